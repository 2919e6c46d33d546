//! `cargo bench`: scheduling, explaining (without and, up to 1,000 activities, with
//! verified suggestions), rebuilding the state at a step, one app
//! frame and edit → rerun → repaint, over generated plans of 100, 1,000 and 10,000
//! activities (1, 3 and 30 sols). Prints a markdown table; results are recorded in
//! docs/performance.md.
//!
//! `cargo bench -- --quick` measures only 100 and 1,000 activities;
//! `--profile standard|realistic|starved` only one generator profile (default: all
//! three);
//! `--sweep N` schedules seeds 1..=N of each size and profile once, explains
//! every failure without suggestions, and reports for each the median and the worst (the plan of a sweep that costs most, not only the seed-1
//! plan the table measures). `--execution` measures executions instead: the bundled
//! plan (nominal and sampled), 1,000 activities of each profile, and a Monte Carlo
//! campaign of 1,000 runs of the bundled plan, then `tune` of the bundled plan with the
//! defaults (the whole and its first improvement); with `--sweep N`, instead, the
//! nominal execution of the 1,000-activity plans of seeds 1..=N of each profile,
//! median and worst. `--flex` measures flexible schedules:
//! the network, bounds, minimum dispatchable network and controllability, and the
//! free slack apart, on 1,000 and 10,000 activities of both profiles (worst of
//! `--sweep N` seeds too when given). `--huge` measures 200,000 activities over 30
//! sols: validation and scheduling, and explaining every failure without
//! suggestions (`explain_each`, as `solscope explain --no-suggestions` streams it),
//! once each (minutes). `--navigation` measures the activity list's search and
//! filters on 1,000 and 10,000 activities: a frame with nothing
//! filtered, a frame with a search or a status and sol filter standing, the
//! frame after the search text changes (the list computed again), and "Next
//! match" with the frame that shows it. `--drag` measures frames while the step
//! slider is dragged across 1,000 and 10,000 activities (60 frames each
//! moving the step, as a slider drag gives one new step per frame; the same with
//! five step changes arriving between two frames; 30 frames zooming the time
//! range in then out; 40 frames panning a one-sol view), with the median and
//! worst frame in wall time and in UI-thread CPU time (the thread's run time,
//! apart from waits for a core), and how long the plots take to catch up with
//! the last step once the drag stops. `--growth` measures
//! how time grows with the plan: 1,000 to 30,000 activities at the same density,
//! the median of 3 seeds (`--sweep N`: N seeds), with the exponent of each size
//! against 1,000.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

#[path = "scale/tuning.rs"]
mod tuning;

use std::time::{Duration, Instant};

use eframe::egui;
use serde_json::json;
use solscope::gui::SolscopeApp;
use solscope::state::Command;
use solscope_engine::{
    ExplainOptions, Outcome, Plan, Profile, explain, generate_plan_with, schedule,
};

/// Median wall time of `runs` calls (at least one).
fn median(runs: usize, mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..runs.max(1))
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect();
    times.sort();
    times[times.len() / 2]
}

fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1000.0)
}

/// Peak resident memory of this process so far (VmHWM), in MB.
fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// One app frame (layout + painting + tessellation, no GPU) on an egui context.
fn frame(ctx: &egui::Context, app: &mut SolscopeApp) {
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(1600.0, 1000.0),
        )),
        ..Default::default()
    };
    let out = ctx.run_ui(input, |ui| app.frame_ui(ui));
    let prims = ctx.tessellate(out.shapes, out.pixels_per_point);
    std::hint::black_box(prims);
}

/// The value following `flag` on the command line.
fn arg(flag: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == flag)
        .and_then(|i| args.get(i + 1).cloned())
}

/// The generator profiles `--profile` names (default: all three). `starved` is
/// the over-subscribed, energy-starved plan, where most placements fail on the
/// battery or handover minimum.
fn chosen_profiles() -> Vec<(&'static str, Profile)> {
    let all = [
        ("standard", Profile::Standard),
        ("realistic", Profile::Realistic),
        ("starved", Profile::Starved),
    ];
    let named: Vec<_> = all
        .into_iter()
        .filter(|(n, _)| arg("--profile").is_some_and(|p| p == *n))
        .collect();
    if named.is_empty() {
        all.to_vec()
    } else {
        named
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let sizes: &[(usize, usize, usize)] = if quick {
        &[(100, 1, 5), (1000, 3, 3)]
    } else {
        &[(100, 1, 5), (1000, 3, 3), (10_000, 30, 1)]
    };
    let profiles = chosen_profiles();
    if std::env::args().any(|a| a == "--execution") {
        match arg("--sweep").and_then(|v| v.parse::<u64>().ok()) {
            Some(seeds) => execution_sweep(&profiles, seeds),
            None => execution(),
        }
        return;
    }
    if std::env::args().any(|a| a == "--tuning") {
        tuning::run(quick);
        return;
    }
    if std::env::args().any(|a| a == "--huge") {
        huge();
        return;
    }
    if std::env::args().any(|a| a == "--navigation") {
        navigation(&profiles, quick);
        return;
    }
    if std::env::args().any(|a| a == "--drag") {
        drag(&profiles, quick);
        return;
    }
    if std::env::args().any(|a| a == "--flex") {
        let seeds = arg("--sweep")
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(1);
        flex(&profiles, quick, seeds);
        return;
    }
    if std::env::args().any(|a| a == "--growth") {
        let seeds = arg("--sweep")
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(3);
        growth(&profiles, seeds);
        return;
    }
    if let Some(n) = arg("--sweep").and_then(|v| v.parse::<u64>().ok()) {
        sweep(&profiles, sizes, n);
        return;
    }
    for (name, profile) in profiles {
        println!("\n### profile {name}\n");
        table(profile, sizes);
    }
    if let Some(mb) = peak_rss_mb() {
        println!("\npeak resident memory of the whole run: {mb:.0} MB");
    }
}

/// 200,000 activities over 30 sols (standard profile, seed 1): validation,
/// scheduling and explaining every failure without suggestions, once each.
fn huge() {
    let plan = generate_plan_with(Profile::Standard, 200_000, 30, 1);
    let t = Instant::now();
    solscope_engine::validate(&plan).expect("a generated plan is valid");
    let validated = t.elapsed();
    let t = Instant::now();
    let sched = schedule(&plan).expect("schedules");
    let scheduled = t.elapsed();
    let t = Instant::now();
    let mut explained = 0usize;
    let opts = ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    solscope_engine::explain_each(&plan, &sched, &opts, &mut |_, _| {}, &mut |_| {
        explained += 1
    })
    .expect("explains");
    let explain_time = t.elapsed();
    println!(
        "| activities | sols | validate | schedule | explanations | explain (no suggestions) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    println!(
        "| 200000 | 30 | {} | {} | {explained} | {} |",
        ms(validated),
        ms(scheduled),
        ms(explain_time)
    );
    if let Some(mb) = peak_rss_mb() {
        println!("\npeak resident memory of the whole run: {mb:.0} MB");
    }
}

/// Growth with the plan's size (`--growth`): 1,000, 3,000, 10,000 and 30,000
/// activities at the same density (3, 9, 30 and 90 sols), the median over
/// seeds `1..=seeds` of scheduling and of explaining every failure without
/// suggestions, and the exponent `k` of `N^k` from 1,000 to each size (the
/// targets: schedule at most N^1.3, explain at most N^1.5, to 30,000).
fn growth(profiles: &[(&str, Profile)], seeds: u64) {
    println!(
        "| profile | activities | sols | seeds | median schedule | exponent | median explain (no suggestions) | exponent |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    for &(name, profile) in profiles {
        let mut base: Option<(f64, f64)> = None;
        for (n, sols) in [(1000, 3), (3000, 9), (10_000, 30), (30_000, 90)] {
            let (mut scheduling, mut explaining) = timed_seeds(profile, n, sols, seeds);
            let (s, _, _) = median_worst(&mut scheduling);
            let (e, _, _) = median_worst(&mut explaining);
            let (s_secs, e_secs) = (s.as_secs_f64(), e.as_secs_f64());
            let (s0, e0) = *base.get_or_insert((s_secs, e_secs));
            let exponent = |t: f64, t0: f64| {
                if n == 1000 {
                    "".to_string()
                } else {
                    format!("N^{:.2}", (t / t0).ln() / (n as f64 / 1000.0).ln())
                }
            };
            println!(
                "| {name} | {n} | {sols} | {seeds} | {} | {} | {} | {} |",
                ms(s),
                exponent(s_secs, s0),
                ms(e),
                exponent(e_secs, e0)
            );
        }
    }
    if let Some(mb) = peak_rss_mb() {
        println!("\npeak resident memory of the whole run: {mb:.0} MB");
    }
}

/// Times, each with its seed.
type SeedTimes = Vec<(Duration, u64)>;

/// Seeds `1..=seeds` of a generated plan, each scheduled once and every
/// failure explained without suggestions: the times of each, with the seed.
fn timed_seeds(profile: Profile, n: usize, sols: usize, seeds: u64) -> (SeedTimes, SeedTimes) {
    let opts = ExplainOptions {
        activity: None,
        no_suggestions: true,
    };
    (1..=seeds)
        .map(|seed| {
            let plan = generate_plan_with(profile, n, sols, seed);
            let t = Instant::now();
            let sched = std::hint::black_box(schedule(&plan).expect("schedules"));
            let scheduled = t.elapsed();
            let t = Instant::now();
            std::hint::black_box(explain(&plan, &sched, &opts).expect("explains"));
            ((scheduled, seed), (t.elapsed(), seed))
        })
        .unzip()
}

/// The median and the worst of timed seeds, with the worst one's seed.
fn median_worst(times: &mut [(Duration, u64)]) -> (Duration, Duration, u64) {
    times.sort();
    let (median, _) = times[times.len() / 2];
    let (worst, seed) = times[times.len() - 1];
    (median, worst, seed)
}

/// Schedules seeds `1..=seeds` of every size once, and explains every failure
/// without suggestions: the median and worst time of each.
fn sweep(profiles: &[(&str, Profile)], sizes: &[(usize, usize, usize)], seeds: u64) {
    println!(
        "| profile | activities | sols | seeds | median schedule | worst schedule (seed) | median explain (no suggestions) | worst explain (seed) |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    for &(name, profile) in profiles {
        for &(n, sols, _) in sizes {
            let (mut scheduling, mut explaining) = timed_seeds(profile, n, sols, seeds);
            let (median, worst, seed) = median_worst(&mut scheduling);
            let (e_median, e_worst, e_seed) = median_worst(&mut explaining);
            println!(
                "| {name} | {n} | {sols} | {seeds} | {} | {} ({seed}) | {} | {} ({e_seed}) |",
                ms(median),
                ms(worst),
                ms(e_median),
                ms(e_worst)
            );
        }
    }
}

/// The table of one profile: seed 1 of every size.
fn table(profile: Profile, sizes: &[(usize, usize, usize)]) {
    println!(
        "| activities | sols | scheduled | schedule | explain all (no suggestions) | explain all (with suggestions) | state at step N/2 | app frame | edit → rerun → repaint |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &(n, sols, runs) in sizes {
        let plan = generate_plan_with(profile, n, sols, 1);
        let mut sched = None;
        let t_schedule = median(runs, || sched = Some(schedule(&plan).expect("schedules")));
        let sched = sched.expect("ran");
        let scheduled = sched
            .steps
            .iter()
            .filter(|s| matches!(s.outcome, Outcome::Scheduled { .. }))
            .count();
        let opts = ExplainOptions {
            activity: None,
            no_suggestions: true,
        };
        let t_explain = median(runs, || {
            std::hint::black_box(explain(&plan, &sched, &opts).expect("explains"));
        });
        // With suggestions (the CLI's default): once, and not at 10,000
        // activities, where it takes minutes (docs/performance.md has the
        // whole-process figures).
        let t_suggest = (n <= 1000).then(|| {
            median(1, || {
                std::hint::black_box(
                    explain(&plan, &sched, &ExplainOptions::default()).expect("explains"),
                );
            })
        });
        let t_state = median(runs, || {
            std::hint::black_box(sched.state_after(n / 2));
        });
        // App: one frame at the last step, and an edit (priority of an activity) then
        // the frame that shows it.
        let text = serde_json::to_string(&plan).expect("json");
        let mut app = SolscopeApp::from_text(&text, None).expect("app");
        // As the desktop app runs: the flexible schedule, explanations and
        // executions on worker threads, not in the frame (the frame and the edit
        // measure what the user waits for).
        app.background = true;
        let ctx = egui::Context::default();
        frame(&ctx, &mut app);
        frame(&ctx, &mut app);
        while app.workers_busy() {
            std::thread::sleep(Duration::from_millis(5));
            frame(&ctx, &mut app);
        }
        let t_frame = median(10, || frame(&ctx, &mut app));
        // The activity of the middle step: the edit changes it in place (its energy
        // rate), so the rerun redoes the second half of the steps, the median case of
        // an edit anywhere in the plan.
        let middle = sched.steps[n / 2].activity;
        let target = format!("activity:{}", plan.activities[middle].id);
        let rate = plan.activities[middle].energy_rate;
        // Each edit starts once the workers of the last one are done (their
        // time is not the user's wait; a frame reaps them).
        let settle = |app: &mut SolscopeApp| {
            while app.workers_busy() {
                std::thread::sleep(Duration::from_millis(5));
                frame(&ctx, app);
            }
        };
        let mut times = Vec::new();
        for flip in 1..=runs.max(1) {
            settle(&mut app);
            let t = Instant::now();
            let mut set = serde_json::Map::new();
            set.insert("energy_rate".into(), json!(rate + (flip % 2) as f64));
            app.apply(Command::Edit {
                target: target.clone(),
                set,
                description: "bench".into(),
            });
            frame(&ctx, &mut app);
            times.push(t.elapsed());
        }
        settle(&mut app);
        times.sort();
        let t_edit = times[times.len() / 2];
        println!(
            "| {n} | {sols} | {scheduled} | {} | {} | {} | {} | {} | {} |",
            ms(t_schedule),
            ms(t_explain),
            t_suggest.map_or_else(|| "not run".to_string(), ms),
            ms(t_state),
            ms(t_frame),
            ms(t_edit)
        );
    }
}

/// Generated plan `(profile, n, sols)`, seed 1, and the app on it as the
/// desktop runs it (derived values on workers).
fn desktop_app(profile: Profile, n: usize, sols: usize) -> (Plan, SolscopeApp) {
    let plan = generate_plan_with(profile, n, sols, 1);
    let text = serde_json::to_string(&plan).expect("json");
    let mut app = SolscopeApp::from_text(&text, None).expect("app");
    app.background = true;
    (plan, app)
}

/// The activity list's search and filters (`--navigation`): frames with them
/// standing and the frame after a change, as the desktop app runs (workers
/// settled first).
fn navigation(profiles: &[(&str, Profile)], quick: bool) {
    use solscope::state::{ListFilter, StatusFilter, UiCommand};
    let sizes: &[(usize, usize)] = if quick {
        &[(1000, 3)]
    } else {
        &[(1000, 3), (10_000, 30)]
    };
    println!(
        "| profile | activities | sols | frame | frame, search standing | frame after a keystroke | Next match + frame | Select (a click) + frame | frame, status + sol filter standing |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &(name, profile) in profiles {
        for &(n, sols) in sizes {
            let (plan, mut app) = desktop_app(profile, n, sols);
            let ctx = egui::Context::default();
            let settle = |app: &mut SolscopeApp| {
                frame(&ctx, app);
                frame(&ctx, app);
                while app.workers_busy() {
                    std::thread::sleep(Duration::from_millis(5));
                    frame(&ctx, app);
                }
            };
            settle(&mut app);
            let t_plain = median(10, || frame(&ctx, &mut app));
            // "s1_" matches every activity of sol 1 (ids are `s<sol>_...`).
            app.apply(Command::SetFilter("s1_".into()));
            settle(&mut app);
            let t_search = median(10, || frame(&ctx, &mut app));
            // Typing: each keystroke changes the text, so the list is computed
            // again in the frame after it.
            let mut flip = false;
            let t_type = median(10, || {
                flip = !flip;
                let text = if flip { "s1_c" } else { "s1_" };
                app.apply(Command::SetFilter(text.into()));
                frame(&ctx, &mut app);
            });
            settle(&mut app);
            let t_next = median(10, || {
                app.apply(UiCommand::NextMatch.into());
                frame(&ctx, &mut app);
            });
            // The same selections by click (what selecting anything costs:
            // the frame derives the selected activity's valid starts).
            let shown = app.list_shown();
            let mut i = 0;
            let t_select = median(10, || {
                i = (i + 1) % shown.len().max(1);
                app.apply(Command::Select(shown.get(i).copied()));
                frame(&ctx, &mut app);
            });
            settle(&mut app);
            app.apply(Command::SetListFilter(ListFilter {
                status: Some(StatusFilter::Scheduled),
                sol: Some(plan.local_time.sol(plan.horizon.start) + 1),
                ..ListFilter::default()
            }));
            settle(&mut app);
            let t_filters = median(10, || frame(&ctx, &mut app));
            println!(
                "| {name} | {n} | {sols} | {} | {} | {} | {} | {} | {} |",
                ms(t_plain),
                ms(t_search),
                ms(t_type),
                ms(t_next),
                ms(t_select),
                ms(t_filters)
            );
        }
    }
}

/// Median and worst of `times`.
fn median_max(times: &mut [Duration]) -> (Duration, Duration) {
    times.sort();
    (times[times.len() / 2], times[times.len() - 1])
}

/// Frames under a scripted step drag and time zoom (`--drag`): each frame's
/// time is the commands given since the last frame applied plus the frame
/// itself (what the desktop app does between two paints). The app runs as the
/// desktop app does (workers on), the flexibility layer shown once its network
/// is in; nothing selected.
fn drag(profiles: &[(&str, Profile)], quick: bool) {
    use solscope::state::TimeAxis;
    let sizes: &[(usize, usize)] = if quick {
        &[(1000, 3)]
    } else {
        &[(1000, 3), (10_000, 30)]
    };
    println!(
        "| profile | activities | sols | drag, 1 step a frame: wall median / worst | UI-thread CPU median / worst | drag, 5 steps a frame: wall | UI CPU | zoom: wall | UI CPU | pan: wall | UI CPU | plots at the last step after |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &(name, profile) in profiles {
        for &(n, sols) in sizes {
            let (plan, mut app) = desktop_app(profile, n, sols);
            // The layer shown (it starts off on large plans).
            if !app.flex_shown() {
                app.apply(Command::Ui(solscope::state::UiCommand::ToggleFlex));
            }
            let ctx = egui::Context::default();
            // The flexible schedule's network first (its free slack may go on
            // on a worker, as in the app).
            let t0 = Instant::now();
            while app.flex().is_none() && t0.elapsed() < Duration::from_secs(120) {
                frame(&ctx, &mut app);
                std::thread::sleep(Duration::from_millis(5));
            }
            frame(&ctx, &mut app);
            let steps = app.analysis.steps();
            // A frame's wall time and its UI-thread CPU time.
            let timed = |app: &mut SolscopeApp, cmds: Vec<Command>| {
                let cpu = thread_run_time();
                let t = Instant::now();
                for c in cmds {
                    app.apply(c);
                }
                frame(&ctx, app);
                let wall = t.elapsed();
                let cpu = match (cpu, thread_run_time()) {
                    (Some(a), Some(b)) => b.saturating_sub(a),
                    _ => Duration::ZERO,
                };
                (wall, cpu)
            };
            // A drag from the first step to the last, one new step a frame.
            let one: Vec<(Duration, Duration)> = (0..60)
                .map(|i| timed(&mut app, vec![Command::SetStep(steps * i / 59)]))
                .collect();
            // Back, with five changes between two frames (a fast pointer, or
            // key repeats): only the last should cost.
            let five: Vec<(Duration, Duration)> = (0..60)
                .map(|i| {
                    let cmds = (0..5)
                        .map(|j| Command::SetStep(steps - (steps * (5 * i + j)) / 299))
                        .collect();
                    timed(&mut app, cmds)
                })
                .collect();
            // How long until what the frame draws is all of the last step's.
            let last = app.ui.nav.step;
            let t = Instant::now();
            while app.step_view.step != last && t.elapsed() < Duration::from_secs(10) {
                frame(&ctx, &mut app);
            }
            let caught_up = t.elapsed();
            // Zoom the time range in about its middle, then out again, at the
            // last step (every bar and the whole profiles drawn).
            app.apply(Command::SetStep(steps));
            let t = Instant::now();
            while app.step_view.step != steps && t.elapsed() < Duration::from_secs(10) {
                frame(&ctx, &mut app);
            }
            let bounds = (plan.horizon.start as f64, plan.horizon.end as f64);
            let zoom: Vec<(Duration, Duration)> = (0..30)
                .map(|i| {
                    let mut axis: TimeAxis = app.ui.nav.axis;
                    let factor = if i < 15 { 1.25 } else { 0.8 };
                    axis.zoom_about((axis.start + axis.end) / 2.0, factor, bounds);
                    timed(&mut app, vec![Command::SetAxis(axis)])
                })
                .collect();
            // Pan a view of one sol across the plan's middle, a twentieth of
            // it a frame (what a drag of the Gantt does), at the last step.
            let mut axis: TimeAxis = app.ui.nav.axis;
            let sol = (bounds.1 - bounds.0) / sols as f64;
            axis.zoom_about((bounds.0 + bounds.1) / 2.0, axis.span() / sol, bounds);
            app.apply(Command::SetAxis(axis));
            frame(&ctx, &mut app);
            let pan: Vec<(Duration, Duration)> = (0..40)
                .map(|i| {
                    let mut axis: TimeAxis = app.ui.nav.axis;
                    let dir = if i < 20 { 1.0 } else { -1.0 };
                    axis.pan(dir * axis.span() / 20.0, bounds);
                    timed(&mut app, vec![Command::SetAxis(axis)])
                })
                .collect();
            let cells: Vec<String> = [one, five, zoom, pan]
                .into_iter()
                .map(|frames| {
                    let (mut wall, mut cpu): (Vec<Duration>, Vec<Duration>) =
                        frames.into_iter().unzip();
                    let (wm, ww) = median_max(&mut wall);
                    let (cm, cw) = median_max(&mut cpu);
                    format!("{} / {} | {} / {}", ms(wm), ms(ww), ms(cm), ms(cw))
                })
                .collect();
            println!(
                "| {name} | {n} | {sols} | {} | {} |",
                cells.join(" | "),
                ms(caught_up)
            );
        }
    }
}

/// Run time of the calling thread so far, in nanoseconds
/// (`/proc/thread-self/schedstat`): a frame's UI-thread CPU time, apart from
/// the time it waited for a core on a loaded machine.
fn thread_run_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = stat.split_whitespace().next()?.parse().ok()?;
    Some(Duration::from_nanos(ns))
}

/// Executions and Monte Carlo (`--execution`).
fn execution() {
    use solscope_engine::{
        Actuals, campaign, campaign_runs, execute, load_plan_file, losses, sample_run, summarize,
    };
    let bundled = load_plan_file(std::path::Path::new("assets/default-plan.json"))
        .expect("bundled plan")
        .plan;
    println!("| plan | activities | what | cycles | time |");
    println!("|---|---:|---|---:|---:|");
    let row = |name: &str, plan: &solscope_engine::Plan, what: &str, actuals: &Actuals, runs| {
        let mut cycles = 0;
        let t = median(runs, || {
            let ex = execute(plan, actuals).expect("execute");
            let lost = losses(plan, &ex).expect("losses");
            cycles = ex.cycles.len();
            std::hint::black_box(lost);
        });
        println!(
            "| {name} | {} | {what} | {cycles} | {} |",
            plan.activities.len(),
            ms(t)
        );
    };
    row("bundled", &bundled, "nominal", &Actuals::nominal(), 5);
    row(
        "bundled",
        &bundled,
        "sampled (seed 1, run 0)",
        &sample_run(&bundled, 1, 0),
        5,
    );
    for (name, profile) in chosen_profiles() {
        let plan = generate_plan_with(profile, 1000, 3, 1);
        row(name, &plan, "nominal", &Actuals::nominal(), 1);
    }
    let c = campaign(&bundled, 1, 1000, "bundled").expect("campaign");
    let indices: Vec<u64> = (0..1000).collect();
    let t = Instant::now();
    let records = campaign_runs(&bundled, &c, &indices, &|| {}, None)
        .expect("runs")
        .expect("not cancelled");
    let runs_time = t.elapsed();
    let t = Instant::now();
    std::hint::black_box(summarize(&c, &records));
    println!(
        "\nMonte Carlo, bundled plan, 1,000 runs on {} threads: runs {}, summary {}",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        ms(runs_time),
        ms(t.elapsed())
    );
    tune_defaults(&bundled);
}

/// One nominal execution (with its losses explained, as `solscope execute`
/// reports them) of the 1,000-activity plan of seeds 1 to `seeds` of each
/// profile, once each: the median and the worst, with the worst plan's cycles.
fn execution_sweep(profiles: &[(&str, Profile)], seeds: u64) {
    use solscope_engine::{Actuals, execute, losses};
    println!(
        "| profile | activities | sols | seeds | median execution | worst execution (seed, cycles) |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for &(name, profile) in profiles {
        let mut times: Vec<(Duration, u64)> = Vec::new();
        // Each seed's cycles, seed 1 first.
        let mut cycles = Vec::new();
        for seed in 1..=seeds {
            let plan = generate_plan_with(profile, 1000, 3, seed);
            let t = Instant::now();
            let ex = execute(&plan, &Actuals::nominal()).expect("execute");
            std::hint::black_box(losses(&plan, &ex).expect("losses"));
            times.push((t.elapsed(), seed));
            cycles.push(ex.cycles.len());
        }
        let (median, worst, seed) = median_worst(&mut times);
        println!(
            "| {name} | 1000 | 3 | {seeds} | {} | {} ({seed}, {}) |",
            ms(median),
            ms(worst),
            cycles[(seed - 1) as usize]
        );
    }
}

/// `tune` of the bundled plan with the defaults, as `solscope tune` runs it:
/// the whole (wall and process CPU time) and when the best score first
/// changed (the first improvement), with the orders scored by then.
fn tune_defaults(plan: &solscope_engine::Plan) {
    use solscope_engine::{Score, TuneOptions, tune};
    // The first best score seen, then when (and after how many orders) it changed.
    type First = (Option<Score>, Option<(Duration, u64)>);
    let first: std::sync::Mutex<First> = std::sync::Mutex::new((None, None));
    let start = Instant::now();
    let cpu = tuning::cpu_time();
    let progress = |evaluations: u64, best: &Score| {
        let mut f = first.lock().unwrap();
        match &f.0 {
            None => f.0 = Some(best.clone()),
            Some(s) if s != best && f.1.is_none() => f.1 = Some((start.elapsed(), evaluations)),
            Some(_) => {}
        }
    };
    let options = TuneOptions {
        progress: Some(&progress),
        ..TuneOptions::default()
    };
    let tuned = tune(plan, &options).expect("tune");
    let (wall, cpu) = (start.elapsed(), tuning::cpu_time() - cpu);
    let improved = match first.lock().unwrap().1 {
        Some((t, n)) => format!("first improvement at {} (after {n} orders)", ms(t)),
        None => "no improvement".to_string(),
    };
    println!(
        "tune, bundled plan, defaults: {} wall, {} CPU, {} orders scored; {improved}",
        ms(wall),
        ms(cpu),
        tuned.evaluations
    );
}

/// Flexible schedules (`--flex`): per size and profile, the median over `seeds`
/// seeds and the worst one, of the network without free slack and of the free
/// slack of every placed activity (up to 1,000 activities; the schedule is not
/// timed).
fn flex(profiles: &[(&str, Profile)], quick: bool, seeds: u64) {
    use solscope_engine::{FlexOptions, flex_with, free_slack_of};
    let sizes: &[(usize, usize)] = if quick {
        &[(1000, 3)]
    } else {
        &[(1000, 3), (10_000, 30)]
    };
    println!(
        "| profile | activities | sols | seeds | network edges | dispatchable edges | bounds + network: median | worst (seed) | free slack: median | worst (seed) |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &(name, profile) in profiles {
        for &(n, sols) in sizes {
            let mut net: Vec<(Duration, u64)> = Vec::new();
            let mut free: Vec<(Duration, u64)> = Vec::new();
            let mut edges = (0, 0);
            for seed in 1..=seeds {
                let plan = generate_plan_with(profile, n, sols, seed);
                let sched = schedule(&plan).expect("schedules");
                let t = Instant::now();
                let f = flex_with(&plan, &sched, FlexOptions { free_slack: false });
                net.push((t.elapsed(), seed));
                if seed == 1 {
                    edges = (f.network_edges, f.dispatchable.len());
                }
                // Free slack is quadratic in the placed activities: at 10,000
                // (seed 1) a sample of 20 placed activities spread over the run,
                // timed one by one, for the estimate of the whole.
                if n > 1000 && seed == 1 {
                    let sample: Vec<usize> = (0..20)
                        .map(|i| f.activities[i * f.activities.len() / 20].activity)
                        .collect();
                    let mut each: Vec<Duration> = sample
                        .iter()
                        .map(|&a| {
                            let t = Instant::now();
                            std::hint::black_box(free_slack_of(&sched, a));
                            t.elapsed()
                        })
                        .collect();
                    let mean = each.iter().sum::<Duration>() / 20;
                    let (med, worst) = median_max(&mut each);
                    eprintln!(
                        "{name} {n}: free slack of 20 sampled activities of {}: median {}, worst {}, mean {} each; the whole, one thread, estimated at {:.0} s",
                        f.activities.len(),
                        ms(med),
                        ms(worst),
                        ms(mean),
                        mean.as_secs_f64() * f.activities.len() as f64
                    );
                }
                if n <= 1000 {
                    let t = Instant::now();
                    for fa in &f.activities {
                        std::hint::black_box(free_slack_of(&sched, fa.activity));
                    }
                    free.push((t.elapsed(), seed));
                }
            }
            let (nm, nw, ns) = median_worst(&mut net);
            let free_cells = if free.is_empty() {
                "not run | not run".to_string()
            } else {
                let (fm, fw, fs) = median_worst(&mut free);
                format!("{} | {} ({fs})", ms(fm), ms(fw))
            };
            println!(
                "| {name} | {n} | {sols} | {seeds} | {} | {} | {} | {} ({ns}) | {free_cells} |",
                edges.0,
                edges.1,
                ms(nm),
                ms(nw),
            );
        }
    }
}
