//! `solscope`: explainable scheduling workstation for rover activity plans.
//!
//! `solscope [PLAN]` opens the desktop app (on the bundled default plan without an
//! argument). Command line: `solscope schedule|explain|execute|montecarlo|flex|check PLAN`, and
//! `solscope screenshot PLAN --out FILE.png` for headless rendering. Invalid input
//! prints a path-named message on standard error, nothing on standard output, and
//! exits with status 2.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

#[derive(Parser, Debug)]
#[command(
    name = "solscope",
    version,
    about = "Explainable scheduling for rover activity plans",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Plan to open in the app (default: the bundled plan).
    plan: Option<PathBuf>,
}

/// The input size limit of the commands that read files.
#[derive(clap::Args, Debug, Clone, Copy)]
struct InputLimit {
    /// Largest input file read (plan, actuals, Monte Carlo parts), in MiB
    /// (default: 32). The app and `screenshot` read up to 32 MiB.
    #[arg(long, value_name = "MIB", value_parser = clap::value_parser!(u64).range(1..=MAX_INPUT_MIB))]
    max_input_mib: Option<u64>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Schedule a plan and print the schedule JSON (solscope.schedule/1).
    Schedule {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        #[command(flatten)]
        input: InputLimit,
    },
    /// Explain why activities failed (all failed or skipped ones, or the one named)
    /// and print the explanation JSON (solscope.explain/1).
    Explain {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        #[command(flatten)]
        input: InputLimit,
        /// Explain this activity (by id), whatever its outcome.
        #[arg(long)]
        activity: Option<String>,
        /// Print planner-facing text instead of JSON.
        #[arg(long)]
        text: bool,
        /// Skip suggestions (each is verified by rescheduling the edited plan, which
        /// dominates the time on large plans).
        #[arg(long)]
        no_suggestions: bool,
    },
    /// Execute a plan as the onboard scheduler would, with actual durations that
    /// differ from the predicted ones, and print the execution JSON
    /// (solscope.execution/1).
    Execute {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        #[command(flatten)]
        input: InputLimit,
        /// Actual durations (solscope.actuals/1 JSON); without it and without
        /// --sample every activity runs exactly its duration.
        #[arg(long, conflicts_with = "sample")]
        actuals: Option<PathBuf>,
        /// Draw the actual durations from the plan's duration_models with this seed.
        #[arg(long)]
        sample: Option<u64>,
        /// Also write the actual durations used to this file (solscope.actuals/1).
        #[arg(long, value_name = "FILE")]
        write_actuals: Option<PathBuf>,
        /// With --sample: the Monte Carlo run index to replay (its durations are
        /// stream RUN of the seed).
        #[arg(long, default_value_t = 0, requires = "sample")]
        run: u64,
        /// How activities are started: rescheduling every cycle (replan), by the
        /// flexible schedule's conditions (dispatch), or at their scheduled times
        /// (fixed).
        #[arg(long, value_enum, default_value_t = Policy::Replan)]
        policy: Policy,
    },
    /// Run many executions with durations drawn from the plan's duration_models
    /// and print the summary JSON (solscope.montecarlo/1). Run indices are the
    /// unit of work: --shard I/K runs every K-th of them (from I) and prints their
    /// records (solscope.montecarlo-runs/1); `solscope montecarlo merge PARTS...`
    /// combines the parts into exactly the summary one machine prints.
    #[command(args_conflicts_with_subcommands = true)]
    Montecarlo {
        #[command(subcommand)]
        merge: Option<MonteCarloCommand>,
        /// The plan file (solscope.plan/1 JSON).
        plan: Option<PathBuf>,
        #[command(flatten)]
        input: InputLimit,
        /// Number of runs in the campaign (one process runs at most 100000 of them;
        /// --shard splits more).
        #[arg(long, default_value_t = 1000)]
        runs: u64,
        /// Campaign seed: run i draws its durations from stream i of this seed
        /// (`solscope execute PLAN --sample SEED --run I` replays it).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Print one CSV row per run instead of the summary.
        #[arg(long)]
        csv: bool,
        /// Run only the runs whose index is I modulo K (0 <= I < K) and print their
        /// records.
        #[arg(long, value_name = "I/K")]
        shard: Option<String>,
        /// How activities are started (the same seed draws the same durations
        /// under every policy, so campaigns compare run by run).
        #[arg(long, value_enum, default_value_t = Policy::Replan)]
        policy: Policy,
    },
    /// Schedule a plan and print its flexible (dispatchable) form: per activity the
    /// start bounds [lb, ub], the free slack, start conditions, and the minimum
    /// dispatchable network and dynamic controllability (solscope.flex/1).
    Flex {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        #[command(flatten)]
        input: InputLimit,
        /// Print planner-facing text instead of JSON.
        #[arg(long)]
        text: bool,
        /// Also compute the free slack of every activity (one re-check of the
        /// schedule after each activity's step: seconds on large plans).
        #[arg(long)]
        free_slack: bool,
    },
    /// Validate a plan and print its warnings.
    Check {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        #[command(flatten)]
        input: InputLimit,
    },
    /// Write a random plan (every feature) to standard output.
    Generate {
        /// Number of activities.
        #[arg(long, default_value_t = 300)]
        activities: usize,
        /// Number of sols (at least 1).
        #[arg(long, default_value_t = 1)]
        sols: usize,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Shape of the plan.
        #[arg(long, value_enum, default_value_t = Profile::Standard)]
        profile: Profile,
    },
    /// Render the app's view of a plan to a PNG, offscreen (software rendering).
    Screenshot {
        /// The plan file (solscope.plan/1 JSON).
        plan: PathBuf,
        /// Output PNG file.
        #[arg(long)]
        out: PathBuf,
        /// Step to show (default: the last).
        #[arg(long)]
        step: Option<usize>,
        /// Activity id to select.
        #[arg(long)]
        select: Option<String>,
        /// Plot probe time (plan seconds): lists the consumers then.
        #[arg(long)]
        probe: Option<i64>,
        /// Window size in points, WxH.
        #[arg(long, default_value = "1600x1000")]
        size: String,
    },
}

impl Command {
    /// The size limit on the files this command reads, in bytes (the app and
    /// `screenshot` read up to [`solscope_engine::MAX_PLAN_BYTES`], and so does
    /// File > Open in the app).
    fn input_limit(&self) -> Result<usize, solscope_engine::Error> {
        let input = match self {
            Command::Schedule { input, .. }
            | Command::Explain { input, .. }
            | Command::Execute { input, .. }
            | Command::Flex { input, .. }
            | Command::Check { input, .. }
            | Command::Montecarlo {
                merge: Some(MonteCarloCommand::Merge { input, .. }),
                ..
            }
            | Command::Montecarlo {
                merge: None, input, ..
            } => *input,
            Command::Generate { .. } | Command::Screenshot { .. } => {
                return Ok(solscope_engine::MAX_PLAN_BYTES);
            }
        };
        match input.max_input_mib {
            None => Ok(solscope_engine::MAX_PLAN_BYTES),
            Some(mib) => usize::try_from(mib << 20).map_err(|_| {
                solscope_engine::Error::invalid(
                    "--max-input-mib",
                    format!("{mib} MiB is more than this machine can address"),
                )
            }),
        }
    }
}

/// `solscope montecarlo merge`.
#[derive(Subcommand, Debug)]
enum MonteCarloCommand {
    /// Combine shard outputs (solscope.montecarlo-runs/1) into the summary.
    Merge {
        /// The parts, in any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        #[command(flatten)]
        input: InputLimit,
        /// Print one CSV row per run instead of the summary.
        #[arg(long)]
        csv: bool,
    },
}

/// The `--profile` of `solscope generate`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Profile {
    /// The plans the scheduler's speed was tuned on (the default).
    Standard,
    /// A real multi-sol tactical plan's shapes: activities without windows or with
    /// one window per sol, long expanding activities, night work, tight energy,
    /// data and handover limits. Most, not all, activities schedule.
    Realistic,
}

impl From<Profile> for solscope_engine::Profile {
    fn from(p: Profile) -> Self {
        match p {
            Profile::Standard => solscope_engine::Profile::Standard,
            Profile::Realistic => solscope_engine::Profile::Realistic,
        }
    }
}

/// The `--policy` of `solscope execute` and `solscope montecarlo`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Policy {
    /// The onboard scheduler reschedules at every cycle (the default).
    Replan,
    /// The flexible schedule, executed by its start and skip conditions.
    Dispatch,
    /// Every activity at its scheduled time, skipped if it cannot start then.
    Fixed,
}

impl From<Policy> for solscope_engine::Policy {
    fn from(p: Policy) -> Self {
        match p {
            Policy::Replan => solscope_engine::Policy::Replan,
            Policy::Dispatch => solscope_engine::Policy::Dispatch,
            Policy::Fixed => solscope_engine::Policy::Fixed,
        }
    }
}

/// Exit status for invalid input.
const EXIT_INVALID: u8 = 2;

/// Largest `--max-input-mib` (1 TiB).
const MAX_INPUT_MIB: u64 = 1 << 20;

/// Most Monte Carlo runs one `montecarlo` process runs (their records are kept
/// until it prints; a few kB each).
const MAX_RECORDS_PER_PROCESS: u64 = 100_000;

/// Most run records `montecarlo merge` holds at once.
const MAX_RECORDS_MERGED: u64 = 1_000_000;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let Some(command) = cli.command else {
        return run_app(cli.plan.as_deref());
    };
    if let Command::Screenshot {
        plan,
        out,
        step,
        select,
        probe,
        size,
    } = command
    {
        return screenshot(&plan, &out, step, select, probe, &size);
    }
    let limit = match command.input_limit() {
        Ok(limit) => limit,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_INVALID);
        }
    };
    let result = match command {
        // An explanation is written as it is made (a large plan's is hundreds
        // of megabytes), once the plan has loaded and scheduled.
        Command::Explain {
            plan,
            activity,
            text,
            no_suggestions,
            ..
        } => {
            let opts = solscope_engine::ExplainOptions {
                activity,
                no_suggestions,
            };
            return explain_streamed(&plan, limit, &opts, text);
        }
        command => run(command, limit),
    };
    match result {
        Ok(text) => {
            let mut out = std::io::stdout().lock();
            match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
                Ok(()) => ExitCode::SUCCESS,
                // A reader that stopped early (`| head`) wants no more: not news.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::FAILURE,
                Err(e) => {
                    eprintln!("error: could not write the output to standard output: {e}");
                    ExitCode::FAILURE
                }
            }
        }
        Err(Failure::Input(err)) => {
            eprintln!("error: {err}");
            ExitCode::from(EXIT_INVALID)
        }
        Err(Failure::Output(what)) => {
            eprintln!("error: {what}");
            ExitCode::FAILURE
        }
    }
}

/// `solscope explain`: loads and schedules the plan (a failure prints nothing on
/// standard output), then writes the explanations one at a time as the engine
/// hands them on, byte for byte the document `explain_document` would make, with
/// a progress bar on standard error (after a second, on a terminal).
fn explain_streamed(
    plan: &std::path::Path,
    limit: usize,
    opts: &solscope_engine::ExplainOptions,
    text: bool,
) -> ExitCode {
    use std::io::IsTerminal;
    let prepared = (|| -> Result<_, solscope_engine::Error> {
        let source = solscope_engine::read_plan_text(plan, limit)?;
        let loaded = solscope_engine::load_plan_limited(&source, limit)?;
        let schedule = solscope_engine::schedule(&loaded.plan)?;
        if let Some(id) = &opts.activity {
            if !loaded.plan.activities.iter().any(|a| &a.id == id) {
                return Err(solscope_engine::Error::UnknownActivity(id.clone()));
            }
        }
        Ok((loaded, schedule))
    })();
    let (loaded, schedule) = match prepared {
        Ok(x) => x,
        Err(err) => {
            eprintln!("error: {err}");
            return ExitCode::from(EXIT_INVALID);
        }
    };
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(schedule.steps.len() as u64),
        indicatif::ProgressDrawTarget::hidden(),
    );
    let started = std::time::Instant::now();
    let terminal = std::io::stderr().is_terminal();
    let mut shown = false;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    // Pieces written so far (the header is the first), or the first error.
    let mut written: Result<usize, std::io::Error> = Ok(0);
    let mut write = |piece: &str, written: &mut Result<usize, std::io::Error>| {
        if let Ok(n) = written {
            match out.write_all(piece.as_bytes()) {
                Ok(()) => *n += 1,
                Err(e) => *written = Err(e),
            }
        }
    };
    if !text {
        write(
            "{\n  \"format\": \"solscope.explain/1\",\n  \"explanations\": [",
            &mut written,
        );
    }
    let plan_ref = &loaded.plan;
    let sched_ref = &schedule;
    // The explanations are formatted in parallel as they are handed on (the
    // entry as the whole document's pretty form nests it: two levels, four
    // spaces, in), and written here in order.
    let render = |ex: solscope_engine::Explanation| -> Result<String, String> {
        if text {
            return Ok(solscope_engine::explanation_text(plan_ref, sched_ref, &ex));
        }
        let entry = solscope_engine::explanation_entry(plan_ref, sched_ref, &ex);
        let json = serde_json::to_string_pretty(&entry)
            .map_err(|e| format!("could not write the document as JSON: {e}"))?;
        let mut piece = String::with_capacity(json.len() + json.len() / 8);
        for (i, line) in json.lines().enumerate() {
            if i > 0 {
                piece.push('\n');
            }
            piece.push_str("    ");
            piece.push_str(line);
        }
        Ok(piece)
    };
    let outcome = solscope_engine::explain_rendered(
        plan_ref,
        sched_ref,
        opts,
        render,
        &mut |done, _| {
            bar.set_position(done as u64);
            if terminal && !shown && started.elapsed() > std::time::Duration::from_secs(1) {
                shown = true;
                bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            }
        },
        &mut |piece| match piece {
            Ok(piece) => {
                if !text {
                    let first = matches!(written, Ok(1));
                    write(if first { "\n" } else { ",\n" }, &mut written);
                }
                write(&piece, &mut written);
            }
            Err(e) => {
                if written.is_ok() {
                    written = Err(std::io::Error::other(e));
                }
            }
        },
    );
    bar.finish_and_clear();
    if let Err(err) = outcome {
        eprintln!("error: {err}");
        return ExitCode::from(EXIT_INVALID);
    }
    if !text {
        let end = if matches!(written, Ok(1)) {
            "]\n}\n"
        } else {
            "\n  ]\n}\n"
        };
        write(end, &mut written);
    }
    match written.and_then(|_| out.flush()) {
        Ok(()) => ExitCode::SUCCESS,
        // A reader that stopped early (`| head`) wants no more: not news.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: could not write the output to standard output: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Why a command printed nothing.
#[derive(Debug)]
enum Failure {
    /// The input is invalid (exit status 2).
    Input(solscope_engine::Error),
    /// The output could not be made (exit status 1).
    Output(String),
}

impl From<solscope_engine::Error> for Failure {
    fn from(e: solscope_engine::Error) -> Self {
        Failure::Input(e)
    }
}

/// Opens the desktop app.
fn run_app(plan: Option<&std::path::Path>) -> ExitCode {
    let app = match solscope::gui::SolscopeApp::open_or_default(plan) {
        Ok(app) => app,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_INVALID);
        }
    };
    match solscope::gui::run(app) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: the window could not be opened: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `solscope screenshot`.
fn screenshot(
    plan: &std::path::Path,
    out: &std::path::Path,
    step: Option<usize>,
    select: Option<String>,
    probe: Option<i64>,
    size: &str,
) -> ExitCode {
    if let Some(code) = solscope::screenshot::rerun_with_runtime_dir() {
        return code;
    }
    let parsed = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse::<f32>().ok()?, h.trim().parse::<f32>().ok()?)))
        .filter(|(w, h)| (100.0..=8000.0).contains(w) && (100.0..=8000.0).contains(h));
    let Some((w, h)) = parsed else {
        eprintln!("error: --size: expected WxH between 100 and 8000 (got {size})");
        return ExitCode::from(EXIT_INVALID);
    };
    let text = match solscope_engine::read_plan_text(plan, solscope_engine::MAX_PLAN_BYTES) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_INVALID);
        }
    };
    let app = match solscope::gui::SolscopeApp::from_text(&text, Some(plan.to_path_buf())) {
        Ok(app) => app,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_INVALID);
        }
    };
    let view = solscope::screenshot::View {
        step,
        select,
        probe,
    };
    match solscope::screenshot::render_png(app, eframe::egui::vec2(w, h), &view, out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs a command to completion and returns everything it prints on standard output,
/// so that nothing is printed when it fails.
fn run(command: Command, limit: usize) -> Result<String, Failure> {
    let load = |plan: &std::path::Path| {
        let text = solscope_engine::read_plan_text(plan, limit)?;
        solscope_engine::load_plan_limited(&text, limit)
    };
    match command {
        Command::Schedule { plan, .. } => {
            let loaded = load(&plan)?;
            let schedule = solscope_engine::schedule(&loaded.plan)?;
            let doc = solscope_engine::schedule_document(&loaded, &schedule, &default_name(&plan));
            to_json(&doc)
        }
        Command::Execute {
            plan,
            actuals,
            sample,
            write_actuals,
            run,
            policy,
            ..
        } => {
            let loaded = load(&plan)?;
            let actuals = match (actuals, sample) {
                (Some(path), _) => {
                    let text = solscope_engine::read_plan_text(&path, limit)?;
                    solscope_engine::load_actuals(&text, &loaded.plan).map_err(|e| match e {
                        solscope_engine::Error::Invalid { path: p, reason } => {
                            solscope_engine::Error::invalid(
                                format!("{}: {p}", path.display()),
                                reason,
                            )
                        }
                        other => other,
                    })?
                }
                (None, Some(seed)) => solscope_engine::sample_run(&loaded.plan, seed, run),
                (None, None) => solscope_engine::Actuals::nominal(),
            };
            let options = solscope_engine::ExecuteOptions {
                policy: policy.into(),
                ..Default::default()
            };
            let execution = solscope_engine::execute_with(&loaded.plan, &actuals, options)?;
            let losses = solscope_engine::losses(&loaded.plan, &execution)?;
            let doc = solscope_engine::execution_document(
                &loaded.plan,
                &execution,
                &actuals,
                &losses,
                &default_name(&plan),
            );
            let out = to_json(&doc)?;
            if let Some(path) = write_actuals {
                let text = to_json(&actuals)?;
                std::fs::write(&path, text).map_err(|e| {
                    Failure::Output(format!("{}: could not write: {e}", path.display()))
                })?;
            }
            Ok(out)
        }
        Command::Montecarlo {
            merge: Some(MonteCarloCommand::Merge { parts, csv, .. }),
            ..
        } => {
            let mut docs = Vec::with_capacity(parts.len());
            for path in &parts {
                let text = solscope_engine::read_plan_text(path, limit)?;
                let doc: solscope_engine::RunsDoc = serde_json::from_str(&text).map_err(|e| {
                    solscope_engine::Error::invalid(
                        format!("{}", path.display()),
                        format!("not a solscope.montecarlo-runs/1 document: {e}"),
                    )
                })?;
                docs.push(doc);
            }
            let total: usize = docs.iter().map(|d| d.records.len()).sum();
            if total as u64 > MAX_RECORDS_MERGED {
                return Err(Failure::Input(solscope_engine::Error::invalid(
                    "parts",
                    format!(
                        "{total} records; at most {MAX_RECORDS_MERGED} are merged in one process"
                    ),
                )));
            }
            let (campaign, records) = solscope_engine::merge_parts(&docs)?;
            if csv {
                Ok(solscope_engine::runs_csv(&campaign, &records))
            } else {
                to_json(&solscope_engine::summarize(&campaign, &records))
            }
        }
        Command::Montecarlo {
            merge: None,
            plan,
            runs,
            seed,
            csv,
            shard,
            policy,
            ..
        } => {
            let Some(plan) = plan else {
                return Err(Failure::Input(solscope_engine::Error::invalid(
                    "PLAN",
                    "a plan file is required (or `merge PARTS...`)",
                )));
            };
            let loaded = load(&plan)?;
            if runs == 0 || runs > 10_000_000 {
                return Err(Failure::Input(solscope_engine::Error::invalid(
                    "--runs",
                    format!("must be between 1 and 10000000 (got {runs})"),
                )));
            }
            let (part, of) = match shard.as_deref() {
                None => (0, 1),
                Some(text) => parse_shard(text)?,
            };
            // Every record this process runs is kept until it prints: a bigger
            // share is split into more shards.
            let share = (runs - part).div_ceil(of);
            if share > MAX_RECORDS_PER_PROCESS {
                return Err(Failure::Input(solscope_engine::Error::invalid(
                    "--runs",
                    format!(
                        "{share} runs in one process; at most {MAX_RECORDS_PER_PROCESS}: split the campaign with --shard I/K"
                    ),
                )));
            }
            let campaign = solscope_engine::campaign_with(
                &loaded.plan,
                seed,
                runs,
                &default_name(&plan),
                policy.into(),
            )?;
            let indices: Vec<u64> = (part..runs).step_by(of as usize).collect();
            let records = with_progress(indices.len() as u64, |tick| {
                solscope_engine::campaign_runs(&loaded.plan, &campaign, &indices, tick, None)
            })?
            .unwrap_or_default();
            if csv {
                Ok(solscope_engine::runs_csv(&campaign, &records))
            } else if shard.is_some() {
                to_json(&solscope_engine::RunsDoc {
                    format: solscope_engine::MONTECARLO_RUNS_FORMAT.into(),
                    campaign,
                    shard: (part, of),
                    records,
                })
            } else {
                to_json(&solscope_engine::summarize(&campaign, &records))
            }
        }
        // Written by `main` itself: `screenshot` and `explain_streamed`.
        Command::Screenshot { .. } | Command::Explain { .. } => Ok(String::new()),
        Command::Generate {
            activities,
            sols,
            seed,
            profile,
        } => {
            if activities > 1_000_000 || sols > 1000 {
                return Err(Failure::Input(solscope_engine::Error::invalid(
                    "--activities/--sols",
                    "at most 1000000 activities and 1000 sols",
                )));
            }
            if sols == 0 {
                return Err(Failure::Input(solscope_engine::Error::invalid(
                    "--sols",
                    "must be at least 1 (got 0)",
                )));
            }
            let plan = solscope_engine::generate_plan_with(profile.into(), activities, sols, seed);
            to_json(&plan)
        }
        Command::Flex {
            plan,
            text,
            free_slack,
            ..
        } => {
            let loaded = load(&plan)?;
            let sched = solscope_engine::schedule(&loaded.plan)?;
            let opts = solscope_engine::FlexOptions { free_slack };
            let flex = solscope_engine::flex_with(&loaded.plan, &sched, opts);
            if text {
                Ok(solscope_engine::flex_text(&loaded.plan, &flex))
            } else {
                to_json(&solscope_engine::flex_document(
                    &loaded.plan,
                    &flex,
                    &default_name(&plan),
                ))
            }
        }
        Command::Check { plan, .. } => {
            let loaded = load(&plan)?;
            let mut out = String::new();
            for w in &loaded.warnings {
                out.push_str(&format!("warning: {w}\n"));
            }
            out.push_str(&format!(
                "ok: {} is a valid plan with {} activities and {} warning(s)\n",
                plan.display(),
                loaded.plan.activities.len(),
                loaded.warnings.len()
            ));
            Ok(out)
        }
    }
}

/// `--shard I/K`.
fn parse_shard(text: &str) -> Result<(u64, u64), Failure> {
    let bad = || {
        Failure::Input(solscope_engine::Error::invalid(
            "--shard",
            format!("expected I/K with 0 <= I < K (got {text})"),
        ))
    };
    let (i, k) = text.split_once('/').ok_or_else(bad)?;
    let (i, k): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        k.trim().parse().map_err(|_| bad())?,
    );
    if k == 0 || i >= k {
        return Err(bad());
    }
    Ok((i, k))
}

/// Runs `work` with a progress bar on standard error, shown once the work has
/// taken a second and only when standard error is a terminal.
fn with_progress<T>(total: u64, work: impl FnOnce(&(dyn Fn() + Sync)) -> T) -> T {
    use std::io::IsTerminal;
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(total),
        indicatif::ProgressDrawTarget::hidden(),
    );
    let started = std::time::Instant::now();
    let shown = std::sync::atomic::AtomicBool::new(false);
    let terminal = std::io::stderr().is_terminal();
    let tick = || {
        bar.inc(1);
        if terminal
            && started.elapsed() > std::time::Duration::from_secs(1)
            && !shown.swap(true, std::sync::atomic::Ordering::Relaxed)
        {
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
    };
    let out = work(&tick);
    bar.finish_and_clear();
    out
}

/// The plan's display name when the file does not give one: the file name.
fn default_name(path: &std::path::Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The document as pretty JSON with a final newline.
fn to_json<T: serde::Serialize>(value: &T) -> Result<String, Failure> {
    serde_json::to_string_pretty(value)
        .map(|text| text + "\n")
        .map_err(|e| Failure::Output(format!("could not write the document as JSON: {e}")))
}
