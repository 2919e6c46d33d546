//! `solscope screenshot`: the app's view of a plan rendered to a PNG, offscreen,
//! by the headless renderer ([`crate::gui::screenshot`]).

use std::process::ExitCode;

use super::args::ScreenshotArgs;
use super::failure::Failure;

/// Renders the view asked for to `--out`; the exit status is the child's when
/// the renderer runs again in a child process (see
/// [`crate::gui::screenshot::rerun_with_runtime_dir`]).
pub fn run(args: &ScreenshotArgs) -> Result<ExitCode, Failure> {
    if let Some(code) = crate::gui::screenshot::rerun_with_runtime_dir() {
        return Ok(code);
    }
    let size = &args.size;
    let parsed = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse::<f32>().ok()?, h.trim().parse::<f32>().ok()?)))
        .filter(|(w, h)| (100.0..=8000.0).contains(w) && (100.0..=8000.0).contains(h));
    let Some((w, h)) = parsed else {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--size",
            format!("expected WxH between 100 and 8000 (got {size})"),
        )));
    };
    let text = solscope_engine::read_plan_text(&args.plan, solscope_engine::MAX_PLAN_BYTES)?;
    let app = crate::gui::SolscopeApp::from_text(&text, Some(args.plan.clone()))?;
    let view = crate::gui::screenshot::View {
        step: args.step,
        select: args.select.clone(),
        probe: args.probe,
    };
    crate::gui::screenshot::render_png(app, eframe::egui::vec2(w, h), &view, &args.out)
        .map_err(Failure::Output)?;
    Ok(ExitCode::SUCCESS)
}
