//! Priority tuning of the open plan (the engine's `tune`): the panel's
//! settings as typed ([`TuneText`], starting from the command line's
//! defaults) and as read ([`TuneSettings`]), the result the panel shows
//! ([`TuneResult`]: the engine's tuning with the tuned plan's predicted
//! schedule and each change's reason as a sentence), and the search on a
//! worker (`cache`: one at a time, with its progress; Cancel keeps the best
//! order found so far, which the engine still confirms on the held-out
//! sample). A result belongs to the plan revision it ran on: an edit (its
//! own Apply included) retires it.

mod cache;

use std::sync::atomic::AtomicBool;

use serde_json::{Map, Value};
use solscope_engine::{Error, Plan, Score, Stop, TuneOptions, TuneProgress, Tuning};

pub use cache::TuneCache;

/// Runs of the tuning sample the panel proposes (as `solscope tune`).
pub const DEFAULT_RUNS: u64 = 20;
/// Seed of the tuning sample the panel proposes (as `solscope tune`).
pub const DEFAULT_SEED: u64 = 1;
/// Runs of the held-out sample the panel proposes (as `solscope tune`).
pub const DEFAULT_CONFIRM_RUNS: u64 = 40;
/// Seed of the held-out sample the panel proposes (as `solscope tune`).
pub const DEFAULT_CONFIRM_SEED: u64 = 2;
/// Orders the search may score, as the panel proposes (as `solscope tune`).
pub const DEFAULT_BUDGET: u64 = 60;

/// The panel's settings as typed (runtime text buffers, like the Monte Carlo
/// panel's).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TuneText {
    /// Runs of the tuning sample.
    pub runs: String,
    /// Seed of the tuning sample.
    pub seed: String,
    /// Runs of the held-out sample.
    pub confirm_runs: String,
    /// Seed of the held-out sample.
    pub confirm_seed: String,
    /// Orders the search may score.
    pub budget: String,
    /// Ids of the activities that keep their priority, separated by commas
    /// or spaces.
    pub pinned: String,
}

impl Default for TuneText {
    fn default() -> Self {
        Self {
            runs: DEFAULT_RUNS.to_string(),
            seed: DEFAULT_SEED.to_string(),
            confirm_runs: DEFAULT_CONFIRM_RUNS.to_string(),
            confirm_seed: DEFAULT_CONFIRM_SEED.to_string(),
            budget: DEFAULT_BUDGET.to_string(),
            pinned: String::new(),
        }
    }
}

impl TuneText {
    /// The settings typed, or what is wrong with a field (named by its
    /// label). Whether they fit together (held-out runs at least the runs,
    /// another seed, known pinned ids) the engine says when the search starts.
    pub fn parse(&self) -> Result<TuneSettings, String> {
        let number = |text: &str, label: &str| {
            text.trim()
                .parse::<u64>()
                .map_err(|_| format!("{label}: enter a whole number from 0 to {}", u64::MAX))
        };
        Ok(TuneSettings {
            runs: number(&self.runs, RUNS_LABEL)?,
            seed: number(&self.seed, SEED_LABEL)?,
            confirm_runs: number(&self.confirm_runs, CONFIRM_RUNS_LABEL)?,
            confirm_seed: number(&self.confirm_seed, CONFIRM_SEED_LABEL)?,
            budget: number(&self.budget, BUDGET_LABEL)?,
            pinned: self
                .pinned
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect(),
        })
    }
}

/// The label of the tuning sample's runs field.
pub const RUNS_LABEL: &str = "Tuning runs";
/// The label of the tuning sample's seed field.
pub const SEED_LABEL: &str = "Tuning seed";
/// The label of the held-out sample's runs field.
pub const CONFIRM_RUNS_LABEL: &str = "Held-out runs";
/// The label of the held-out sample's seed field.
pub const CONFIRM_SEED_LABEL: &str = "Held-out seed";
/// The label of the budget field.
pub const BUDGET_LABEL: &str = "Budget";
/// The label of the pinned ids field.
pub const PINNED_LABEL: &str = "Pinned ids";

/// What one search runs (the engine's [`TuneOptions`] without the worker's
/// cancel flag and progress).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TuneSettings {
    /// Runs of the tuning sample.
    pub runs: u64,
    /// Seed of the tuning sample.
    pub seed: u64,
    /// Runs of the held-out sample.
    pub confirm_runs: u64,
    /// Seed of the held-out sample.
    pub confirm_seed: u64,
    /// Orders the search may score.
    pub budget: u64,
    /// Ids of the activities that keep their priority.
    pub pinned: Vec<String>,
}

impl Default for TuneSettings {
    fn default() -> Self {
        Self {
            runs: DEFAULT_RUNS,
            seed: DEFAULT_SEED,
            confirm_runs: DEFAULT_CONFIRM_RUNS,
            confirm_seed: DEFAULT_CONFIRM_SEED,
            budget: DEFAULT_BUDGET,
            pinned: Vec::new(),
        }
    }
}

/// A tuning as the panel shows it.
#[derive(Clone, Debug)]
pub struct TuneResult {
    /// What it ran.
    pub settings: TuneSettings,
    /// The engine's result.
    pub tuning: Tuning,
    /// Per plan activity, where the tuned plan's predicted schedule places
    /// it (`None`: not placed).
    pub tuned_placements: Vec<Option<(i64, i64)>>,
    /// Per change (in the order of `tuning.changes`), why, in one sentence.
    pub reasons: Vec<String>,
}

impl TuneResult {
    /// Tunes `plan` with `settings`; `cancel` stops the search (the best
    /// order found so far is kept and confirmed), `progress` hears of each
    /// batch of orders scored. A plan in which no activity can move is an
    /// error: there is nothing to tune.
    pub fn of(
        plan: &Plan,
        settings: &TuneSettings,
        cancel: Option<&AtomicBool>,
        progress: Option<TuneProgress<'_>>,
    ) -> Result<Self, String> {
        let options = TuneOptions {
            runs: settings.runs,
            seed: settings.seed,
            confirm_runs: settings.confirm_runs,
            confirm_seed: settings.confirm_seed,
            budget: settings.budget,
            pinned: settings.pinned.clone(),
            cancel,
            progress,
        };
        let tuning = solscope_engine::tune(plan, &options).map_err(field_named)?;
        if tuning.movable == 0 {
            return Err(
                "No activity can move (every one is pinned, alone, or fixed in the \
                        step order by its dependencies): there is nothing to tune"
                    .into(),
            );
        }
        let schedule = solscope_engine::schedule(&tuning.tuned_plan)
            .map_err(|e| format!("The tuned plan could not be scheduled: {e}"))?;
        let tuned_placements = (0..plan.activities.len())
            .map(|a| schedule.step_of(a).and_then(|s| s.outcome.placement()))
            .collect();
        let reasons = tuning
            .changes
            .iter()
            .map(|c| solscope_engine::change_line(plan, &c.why))
            .collect();
        Ok(Self {
            settings: settings.clone(),
            tuning,
            tuned_placements,
            reasons,
        })
    }

    /// The search stopped before it finished (cancelled, or the budget ran
    /// out), as the command line's `stopped_early` says: the result is the
    /// best order found until then, confirmed on the held-out sample all the
    /// same.
    pub fn stopped_early(&self) -> bool {
        self.tuning.stop != Stop::Finished
    }

    /// The edit that gives `plan` (the plan tuned) the tuned priorities and
    /// changes nothing else: its activities, each priority changed set, with
    /// a description naming every move. `None` when no priority changes.
    pub fn edit(&self, plan: &Plan) -> Option<(Map<String, Value>, String)> {
        if self.tuning.changes.is_empty() {
            return None;
        }
        let mut activities = plan.activities.clone();
        let mut moves = Vec::new();
        for c in &self.tuning.changes {
            let a = activities.get_mut(c.activity)?;
            a.priority = c.after;
            moves.push(format!("{} {} → {}", a.id, c.before, c.after));
        }
        let mut set = Map::new();
        set.insert("activities".into(), serde_json::to_value(activities).ok()?);
        let description = format!("Tuned priorities: {}", moves.join(", "));
        Some((set, description))
    }
}

/// The engine's option names as the panel's field labels.
fn field_named(e: Error) -> String {
    match e {
        Error::Invalid { path, reason } => {
            let label = match path.as_str() {
                "runs" => RUNS_LABEL,
                "confirm_runs" => CONFIRM_RUNS_LABEL,
                "confirm_seed" => CONFIRM_SEED_LABEL,
                "budget" => BUDGET_LABEL,
                p if p.starts_with("pinned[") => PINNED_LABEL,
                _ => return format!("Tuning failed: {path}: {reason}"),
            };
            format!("{label}: {reason}")
        }
        other => format!("Tuning failed: {other}"),
    }
}

/// A search running.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TuneRunning {
    /// Orders scored so far.
    pub evaluations: u64,
    /// The budget.
    pub budget: u64,
    /// Runs of the tuning sample (what the best score is over).
    pub runs: u64,
    /// The best score so far (none before the original order is scored).
    pub best: Option<Score>,
    /// Cancel was asked for: the best order so far is being confirmed.
    pub cancelling: bool,
    /// Seconds since it started.
    pub seconds: u64,
}

/// What the views read of tuning for one frame.
#[derive(Clone, Debug, Default)]
pub struct TuneModel<'a> {
    /// The panel is shown.
    pub open: bool,
    /// The Gantt shows the tuned schedule over the original one.
    pub overlay: bool,
    /// The last tuning of the plan as it is, or why it failed.
    pub result: Option<&'a Result<TuneResult, String>>,
    /// The search running, if any.
    pub running: Option<TuneRunning>,
    /// A tuning finished on an earlier revision of the plan (no longer
    /// shown).
    pub stale: bool,
    /// The plan was edited while a search ran: it was stopped, nothing kept.
    pub interrupted: bool,
}

impl TuneModel<'_> {
    /// The tuning shown, when it succeeded.
    pub fn ok(&self) -> Option<&TuneResult> {
        self.result.and_then(|r| r.as_ref().ok())
    }

    /// The tuned placements to draw on the Gantt (the toggle is on and a
    /// result of the plan as it is exists).
    pub fn overlay(&self) -> Option<&TuneResult> {
        self.ok().filter(|_| self.overlay)
    }
}

#[cfg(test)]
mod tests;
