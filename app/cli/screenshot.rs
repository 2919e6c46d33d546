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
    check_out(&args.out)?;
    let limit = args.input.bytes()?;
    let text = solscope_engine::read_plan_text(&args.plan, limit)?;
    let app = crate::gui::SolscopeApp::from_text_limited(&text, Some(args.plan.clone()), limit)?;
    // What names nothing in the plan is invalid input, as in every command.
    if let Some(id) = &args.select {
        if !app.doc.plan.activities.iter().any(|a| &a.id == id) {
            return Err(solscope_engine::Error::UnknownActivity(id.clone()).into());
        }
    }
    let steps = app.analysis.steps();
    if let Some(k) = args.step.filter(|&k| k > steps) {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--step",
            format!("must be between 0 and {steps}, the plan's steps (got {k})"),
        )));
    }
    let view = crate::gui::screenshot::View {
        step: args.step,
        select: args.select.clone(),
        probe: args.probe,
    };
    crate::gui::screenshot::render_png(app, eframe::egui::vec2(w, h), &view, &args.out)
        .map_err(Failure::Output)?;
    Ok(ExitCode::SUCCESS)
}

/// `--out` must name a PNG file in a directory that exists: checked before
/// anything is opened or rendered, so that a wrong name costs nothing and
/// leaves any file there as it was.
fn check_out(out: &std::path::Path) -> Result<(), Failure> {
    let png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--out",
            format!(
                "{}: screenshots are written as PNG only: the file name must end in .png",
                out.display()
            ),
        )));
    }
    crate::write::check_target(out)
        .map_err(|e| Failure::Output(format!("{}: could not write: {e}", out.display())))
}
