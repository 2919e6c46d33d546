//! Every flag of the command line: the clap types. Their doc comments are the
//! help texts (`solscope help`, `solscope COMMAND --help`), so only `//`
//! comments are added to them here.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};
use solscope_engine::TuneOptions;

/// Largest `--max-input-mib` (1 TiB).
const MAX_INPUT_MIB: u64 = 1 << 20;

// The whole command line: a command, or a plan to open in the app.
#[derive(Parser, Debug)]
#[command(
    name = "solscope",
    version,
    about = "Explainable scheduling for rover activity plans",
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    // The command (none: open the app).
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Plan to open in the app (default: the bundled plan).
    pub plan: Option<PathBuf>,
}

/// The input size limit of the commands that read files.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct InputLimit {
    /// Largest input file read (plan, actuals, Monte Carlo parts), in MiB
    /// (default: 32). The app reads up to 32 MiB.
    #[arg(long, value_name = "MIB", value_parser = clap::value_parser!(u64).range(1..=MAX_INPUT_MIB))]
    pub max_input_mib: Option<u64>,
}

impl InputLimit {
    /// The size limit on the files a command reads, in bytes (the app reads
    /// up to [`solscope_engine::MAX_PLAN_BYTES`], File > Open included).
    pub fn bytes(self) -> Result<usize, solscope_engine::Error> {
        match self.max_input_mib {
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

/// Where a command's output goes: standard output, or `--output FILE`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct OutputFile {
    /// Write the output to FILE instead of standard output, whole or not at
    /// all: into a new file beside it, renamed over it once complete (a
    /// failed or killed run leaves FILE as it was). Nothing is printed on
    /// standard output.
    #[arg(long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

// The commands; each variant's doc comment is its help text, each one's flags
// are in its own struct below.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Schedule a plan and print the schedule JSON (solscope.schedule/1).
    Schedule(ScheduleArgs),
    /// Explain why activities failed (all failed or skipped ones, or the one named)
    /// and print the explanation JSON (solscope.explain/1).
    Explain(ExplainArgs),
    /// Execute a plan as the onboard scheduler would, with actual durations that
    /// differ from the predicted ones, and print the execution JSON
    /// (solscope.execution/1).
    Execute(ExecuteArgs),
    /// Run many executions with durations drawn from the plan's duration_models
    /// and print the summary JSON (solscope.montecarlo/1). Run indices are the
    /// unit of work: --shard I/K runs every K-th of them (from I) and prints their
    /// records (solscope.montecarlo-runs/1); `solscope montecarlo merge PARTS...`
    /// combines the parts into exactly the summary one machine prints.
    #[command(args_conflicts_with_subcommands = true)]
    Montecarlo(MontecarloArgs),
    /// Schedule a plan and print its flexible (dispatchable) form: per activity the
    /// start bounds [lb, ub], the free slack, start conditions, and the minimum
    /// dispatchable network and dynamic controllability (solscope.flex/1).
    Flex(FlexArgs),
    /// Search the priorities (the greedy order) that complete more of what matters
    /// over the executions the plan's duration_models make likely, confirm them on
    /// a held-out sample and print the tuning JSON (solscope.tuning/1): the
    /// changes, why each helps, and the edits. Ctrl+C stops the search and prints
    /// the best order found so far, marked as stopped early.
    Tune(TuneArgs),
    /// Validate a plan and print its warnings.
    Check(CheckArgs),
    /// Write a random plan (every feature) to standard output.
    Generate(GenerateArgs),
    /// Render the app's view of a plan to a PNG, offscreen (software rendering).
    Screenshot(ScreenshotArgs),
}

impl Command {
    /// The command's `--output FILE`, if it has the flag and it was given.
    pub fn output(&self) -> Option<&std::path::Path> {
        let output = match self {
            Command::Schedule(a) => &a.output,
            Command::Explain(a) => &a.output,
            Command::Execute(a) => &a.output,
            Command::Montecarlo(a) => match &a.merge {
                Some(MonteCarloCommand::Merge { output, .. }) => output,
                None => &a.output,
            },
            Command::Flex(a) => &a.output,
            Command::Tune(a) => &a.output,
            Command::Check(a) => &a.output,
            Command::Generate(a) => &a.output,
            Command::Screenshot(_) => return None,
        };
        output.output.as_deref()
    }
}

// `solscope schedule`.
#[derive(clap::Args, Debug)]
pub struct ScheduleArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
}

// `solscope explain`.
#[derive(clap::Args, Debug)]
pub struct ExplainArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
    /// Explain this activity (by id), whatever its outcome.
    #[arg(long)]
    pub activity: Option<String>,
    /// Print planner-facing text instead of JSON.
    #[arg(long)]
    pub text: bool,
    /// Skip suggestions (each is verified by rescheduling the edited plan, which
    /// dominates the time on large plans).
    #[arg(long)]
    pub no_suggestions: bool,
}

// `solscope execute`.
#[derive(clap::Args, Debug)]
pub struct ExecuteArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
    /// Actual durations (solscope.actuals/1 JSON); without it and without
    /// --sample every activity runs exactly its duration.
    #[arg(long, conflicts_with = "sample")]
    pub actuals: Option<PathBuf>,
    /// Draw the actual durations from the plan's duration_models with this seed.
    #[arg(long)]
    pub sample: Option<u64>,
    /// Also write the actual durations used to this file (solscope.actuals/1).
    #[arg(long, value_name = "FILE")]
    pub write_actuals: Option<PathBuf>,
    /// With --sample: the Monte Carlo run index to replay (its durations are
    /// stream RUN of the seed).
    #[arg(long, default_value_t = 0, requires = "sample")]
    pub run: u64,
    /// How activities are started: rescheduling every cycle (replan), by the
    /// flexible schedule's conditions (dispatch), or at their scheduled times
    /// (fixed).
    #[arg(long, value_enum, default_value_t = Policy::Replan)]
    pub policy: Policy,
}

// `solscope montecarlo` (and `solscope montecarlo merge`).
#[derive(clap::Args, Debug)]
pub struct MontecarloArgs {
    // `merge PARTS...` instead of a campaign.
    #[command(subcommand)]
    pub merge: Option<MonteCarloCommand>,
    /// The plan file (solscope.plan/1 JSON).
    pub plan: Option<PathBuf>,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
    /// Number of runs in the campaign (one process runs at most 100000 of them;
    /// --shard splits more).
    #[arg(long, default_value_t = 1000)]
    pub runs: u64,
    /// Campaign seed: run i draws its durations from stream i of this seed
    /// (`solscope execute PLAN --sample SEED --run I` replays it).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print one CSV row per run instead of the summary.
    #[arg(long)]
    pub csv: bool,
    /// Run only the runs whose index is I modulo K (0 <= I < K) and print their
    /// records.
    #[arg(long, value_name = "I/K")]
    pub shard: Option<String>,
    /// How activities are started (the same seed draws the same durations
    /// under every policy, so campaigns compare run by run).
    #[arg(long, value_enum, default_value_t = Policy::Replan)]
    pub policy: Policy,
}

/// `solscope montecarlo merge`.
#[derive(Subcommand, Debug)]
pub enum MonteCarloCommand {
    /// Combine shard outputs (solscope.montecarlo-runs/1) into the summary.
    Merge {
        /// The parts, in any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        #[command(flatten)]
        input: InputLimit,
        #[command(flatten)]
        output: OutputFile,
        /// Print one CSV row per run instead of the summary.
        #[arg(long)]
        csv: bool,
    },
}

// `solscope flex`.
#[derive(clap::Args, Debug)]
pub struct FlexArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
    /// Print planner-facing text instead of JSON.
    #[arg(long)]
    pub text: bool,
    /// Also compute the free slack of every activity (one re-check of the
    /// schedule after each activity's step: seconds on large plans).
    #[arg(long)]
    pub free_slack: bool,
}

// `solscope tune`. The defaults are the engine's (`TuneOptions::default()`):
// a tuning of the bundled plan (70 activities, one order scored in about 20 ms
// per run) takes about 20 s on two cores.
#[derive(clap::Args, Debug)]
pub struct TuneArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
    /// Runs of the tuning sample, on which the search scores each order (at
    /// least 1). The defaults (20 runs, 40 held out, budget 60) tune the bundled
    /// plan in about 20 s on two cores; more runs and a larger budget search
    /// longer and better.
    #[arg(long, default_value_t = TuneOptions::DEFAULT_RUNS)]
    pub runs: u64,
    /// Seed of the tuning sample (run i draws the durations `montecarlo --seed
    /// SEED` draws in run i).
    #[arg(long, default_value_t = TuneOptions::DEFAULT_SEED)]
    pub seed: u64,
    /// Runs of the held-out sample the result is confirmed on (at least --runs).
    #[arg(long, default_value_t = TuneOptions::DEFAULT_CONFIRM_RUNS)]
    pub confirm_runs: u64,
    /// Seed of the held-out sample (not --seed).
    #[arg(long, default_value_t = TuneOptions::DEFAULT_CONFIRM_SEED)]
    pub confirm_seed: u64,
    /// Orders the search may score on the tuning sample, the original's
    /// included (at least 1).
    #[arg(long, value_name = "EVALS", default_value_t = TuneOptions::DEFAULT_BUDGET)]
    pub budget: u64,
    /// Keep this activity's priority (and place); repeat for more.
    #[arg(long, value_name = "ID")]
    pub pin: Vec<String>,
    /// Also write the tuned plan (the input with only priorities changed) to
    /// this file, whole or not at all.
    #[arg(long, value_name = "FILE")]
    pub write_plan: Option<PathBuf>,
}

// `solscope check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    /// On an invalid plan, say every error found in one pass (one `error:`
    /// line each, the first the one said without this), not only the first.
    #[arg(long)]
    pub all_errors: bool,
    #[command(flatten)]
    pub input: InputLimit,
    #[command(flatten)]
    pub output: OutputFile,
}

// `solscope generate`.
#[derive(clap::Args, Debug)]
pub struct GenerateArgs {
    /// Number of activities.
    #[arg(long, default_value_t = 300)]
    pub activities: usize,
    /// Number of sols (at least 1).
    #[arg(long, default_value_t = 1)]
    pub sols: usize,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Shape of the plan.
    #[arg(long, value_enum, default_value_t = Profile::Standard)]
    pub profile: Profile,
    /// Give this share (0 to 1) of the activities that can have one a
    /// `duration_model`, drawn from the seed: arm work and drives run 0.6 to 1.6
    /// times their predicted duration, the others 0.8 to 1.25 times (fixed
    /// durations only; not communication passes or sleeps). Without it, no
    /// activity has one.
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true)]
    pub uncertain: Option<f64>,
    #[command(flatten)]
    pub output: OutputFile,
}

// `solscope screenshot`.
#[derive(clap::Args, Debug)]
pub struct ScreenshotArgs {
    /// The plan file (solscope.plan/1 JSON).
    pub plan: PathBuf,
    #[command(flatten)]
    pub input: InputLimit,
    /// Output PNG file.
    #[arg(long)]
    pub out: PathBuf,
    /// Step to show (default: the last).
    #[arg(long)]
    pub step: Option<usize>,
    /// Activity id to select.
    #[arg(long)]
    pub select: Option<String>,
    /// Plot probe time (plan seconds): lists the consumers then.
    #[arg(long)]
    pub probe: Option<i64>,
    /// Window size in points, WxH.
    #[arg(long, default_value = "1600x1000")]
    pub size: String,
}

/// The `--profile` of `solscope generate`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Profile {
    /// The plans the scheduler's speed was tuned on (the default).
    Standard,
    /// A real multi-sol tactical plan's shapes: activities without windows or with
    /// one window per sol, long expanding activities, night work, tight energy,
    /// data and handover limits. Most, not all, activities schedule.
    Realistic,
    /// The realistic shapes on a battery near its minimum for days: most
    /// activities fail, most of them on the battery or handover minimum.
    Starved,
}

impl From<Profile> for solscope_engine::Profile {
    fn from(p: Profile) -> Self {
        match p {
            Profile::Standard => solscope_engine::Profile::Standard,
            Profile::Realistic => solscope_engine::Profile::Realistic,
            Profile::Starved => solscope_engine::Profile::Starved,
        }
    }
}

/// The `--policy` of `solscope execute` and `solscope montecarlo`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Policy {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Command {
        let cli = Cli::try_parse_from(std::iter::once("solscope").chain(args.iter().copied()));
        match cli.map(|c| c.command) {
            Ok(Some(command)) => command,
            other => panic!("{args:?}: {other:?}"),
        }
    }

    #[test]
    fn the_input_limit_is_32_mib_unless_given() {
        let Command::Schedule(args) = parse(&["schedule", "p.json"]) else {
            panic!("not schedule")
        };
        assert_eq!(
            args.input.bytes().ok(),
            Some(solscope_engine::MAX_PLAN_BYTES)
        );
        assert_eq!(solscope_engine::MAX_PLAN_BYTES, 32 << 20);
        let Command::Montecarlo(args) =
            parse(&["montecarlo", "merge", "a.json", "--max-input-mib", "3"])
        else {
            panic!("not montecarlo")
        };
        let Some(MonteCarloCommand::Merge {
            input, parts, csv, ..
        }) = args.merge
        else {
            panic!("not merge")
        };
        assert_eq!(input.bytes().ok(), Some(3 << 20));
        assert_eq!(parts, [PathBuf::from("a.json")]);
        assert!(!csv);
        assert!(
            Cli::try_parse_from(["solscope", "check", "p.json", "--max-input-mib", "0"]).is_err()
        );
    }
}
