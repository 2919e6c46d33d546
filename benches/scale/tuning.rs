//! `cargo bench --bench scale -- --tuning`: `tune` against two baselines, on the
//! bundled plan and on generated realistic plans with duration models.
//!
//! Every order is scored by the engine's own scoring ([`OrderScorer`], the
//! objective of docs/format.md §12, on the samples `tune` uses), so the three
//! differ only in how they pick an order:
//!
//! - `tune` with its defaults ([`TuneOptions::default`]);
//! - a random-restart hill climb over the same orders (swap or move
//!   neighbours, kept when the tuning sample's score improves; after two
//!   batches without improvement, a restart from a random order that keeps the
//!   dependencies), with the same budget of orders scored on the same tuning
//!   sample, the original order counted as `tune` counts it;
//! - the dependency order with mandatory activities (and what they depend on)
//!   first, then the original order: no search.
//!
//! Each is judged on the held-out sample against the original order. Also
//! compiled into `tests/tuning_baselines.rs`, which tests the baselines.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use rayon::prelude::*;
use solscope_engine::{
    OrderScorer, Plan, Profile, Sample, Score, TuneOptions, ValueMeasure, add_duration_models,
    generate_plan_with, load_plan, tune,
};

/// Candidates scored together by the hill climb, as `tune` scores its own.
pub const BATCH: usize = 8;

/// Batches in a row without improvement before the hill climb restarts.
const PATIENCE: usize = 2;

/// Share of the generated plans' eligible activities given a duration model
/// (as `solscope generate --uncertain 0.2`).
pub const UNCERTAIN: f64 = 0.2;

/// SplitMix64: the baselines' own deterministic stream.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A stream for `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x4B1D_C11B_0000_0000)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A random order that keeps every dependency pair (a topological order, each
/// next activity drawn uniformly among those whose predecessors are placed).
pub fn random_order(s: &OrderScorer<'_>, rng: &mut Rng) -> Vec<usize> {
    let n = s.original().len();
    let mut waiting: Vec<usize> = (0..n).map(|a| s.before(a).len()).collect();
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
    for a in 0..n {
        for &b in s.before(a) {
            after[b].push(a);
        }
    }
    let mut ready: Vec<usize> = (0..n).filter(|&a| waiting[a] == 0).collect();
    ready.sort_unstable();
    let mut order = Vec::with_capacity(n);
    while !ready.is_empty() {
        let a = ready.swap_remove(rng.below(ready.len()));
        order.push(a);
        for &c in &after[a] {
            waiting[c] -= 1;
            if waiting[c] == 0 {
                ready.push(c);
            }
        }
    }
    order
}

/// Baseline (b): the dependency order with the mandatory activities, and every
/// activity a mandatory one must follow, first; each part in the original
/// order.
pub fn mandatory_first(plan: &Plan, s: &OrderScorer<'_>) -> Vec<usize> {
    let n = s.original().len();
    let mut rank = vec![0; n];
    for (k, &a) in s.original().iter().enumerate() {
        rank[a] = k;
    }
    // Mandatory activities and, through `before`, what they wait for.
    let mut first = vec![false; n];
    let mut stack: Vec<usize> = (0..n).filter(|&a| plan.activities[a].mandatory).collect();
    while let Some(a) = stack.pop() {
        if !first[a] {
            first[a] = true;
            stack.extend(s.before(a).iter().copied());
        }
    }
    let mut waiting: Vec<usize> = (0..n).map(|a| s.before(a).len()).collect();
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
    for a in 0..n {
        for &b in s.before(a) {
            after[b].push(a);
        }
    }
    let key = |a: usize| (!first[a], rank[a]);
    let mut ready: BTreeSet<((bool, usize), usize)> = (0..n)
        .filter(|&a| waiting[a] == 0)
        .map(|a| (key(a), a))
        .collect();
    let mut order = Vec::with_capacity(n);
    while let Some((_, a)) = ready.pop_first() {
        order.push(a);
        for &c in &after[a] {
            waiting[c] -= 1;
            if waiting[c] == 0 {
                ready.insert((key(c), c));
            }
        }
    }
    order
}

/// What a hill climb found.
#[derive(Clone, Debug)]
pub struct Climb {
    /// The best order (the original when nothing scored better).
    pub best: Vec<usize>,
    /// Its score on the tuning sample.
    pub score: Score,
    /// Orders scored on the tuning sample, the original included.
    pub evaluations: u64,
    /// Restarts from a random order.
    pub restarts: u64,
}

/// A neighbour of `order`: two activities swapped, or one moved to another
/// place; `None` when 64 draws gave no order the rules allow.
fn neighbour(s: &OrderScorer<'_>, order: &[usize], rng: &mut Rng) -> Option<Vec<usize>> {
    let n = order.len();
    if n < 2 {
        return None;
    }
    for _ in 0..64 {
        let (i, j) = (rng.below(n), rng.below(n));
        if i == j {
            continue;
        }
        let mut o = order.to_vec();
        if rng.next() % 2 == 0 {
            o.swap(i, j);
        } else {
            let x = o.remove(i);
            o.insert(j, x);
        }
        if s.allows(&o) {
            return Some(o);
        }
    }
    None
}

/// Baseline (a): random-restart hill climb from the original order, at most
/// `budget` orders scored on `sample` (the original first, `original` its
/// score).
pub fn hill_climb(
    s: &OrderScorer<'_>,
    sample: Sample,
    budget: u64,
    original: Score,
    seed: u64,
) -> Result<Climb, solscope_engine::Error> {
    let mut rng = Rng::new(seed);
    let mut seen: BTreeSet<Vec<usize>> = BTreeSet::new();
    seen.insert(s.original().to_vec());
    let mut current = (s.original().to_vec(), original.clone());
    let mut best = current.clone();
    let mut evaluations = 1u64;
    let mut restarts = 0u64;
    let mut stale = 0usize;
    while evaluations < budget {
        let room = usize::try_from(budget - evaluations).unwrap_or(usize::MAX);
        if stale >= PATIENCE {
            // Restart from a random order that keeps the dependencies.
            let mut start = None;
            for _ in 0..16 {
                let o = random_order(s, &mut rng);
                if s.allows(&o) && !seen.contains(&o) {
                    start = Some(o);
                    break;
                }
            }
            let Some(start) = start else { break };
            let score = s.score(&start, sample)?;
            seen.insert(start.clone());
            evaluations += 1;
            restarts += 1;
            stale = 0;
            if score > best.1 {
                best = (start.clone(), score.clone());
            }
            current = (start, score);
            continue;
        }
        let mut batch: Vec<Vec<usize>> = Vec::new();
        for _ in 0..BATCH * 4 {
            if batch.len() >= BATCH.min(room) {
                break;
            }
            if let Some(o) = neighbour(s, &current.0, &mut rng)
                && !seen.contains(&o)
                && !batch.contains(&o)
            {
                batch.push(o);
            }
        }
        if batch.is_empty() {
            stale = PATIENCE;
            continue;
        }
        let scores: Vec<Score> = batch
            .par_iter()
            .map(|o| s.score(o, sample))
            .collect::<Result<_, _>>()?;
        evaluations += batch.len() as u64;
        let mut pick: Option<usize> = None;
        for (i, sc) in scores.iter().enumerate() {
            seen.insert(batch[i].clone());
            if *sc > current.1 && pick.is_none_or(|p| *sc > scores[p]) {
                pick = Some(i);
            }
        }
        match pick {
            Some(i) => {
                current = (batch[i].clone(), scores[i].clone());
                stale = 0;
                if current.1 > best.1 {
                    best = current.clone();
                }
            }
            None => stale += 1,
        }
    }
    Ok(Climb {
        best: best.0,
        score: best.1,
        evaluations,
        restarts,
    })
}

/// Wall and CPU time (this process, every thread) of `f`.
fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration, Duration) {
    let (t, c) = (Instant::now(), cpu_time());
    let out = f();
    (out, t.elapsed(), cpu_time().saturating_sub(c))
}

/// The CPU time of this process so far (user and system, all threads).
pub fn cpu_time() -> Duration {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return Duration::ZERO;
    };
    // Fields after the command name, which ends at the last ')': utime is
    // field 14, stime 15 (1-based), in clock ticks of 1/100 s.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let tick = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(0)
    };
    Duration::from_millis((tick(11) + tick(12)) * 10)
}

/// The outcome part of a score (breaking runs, mandatory completions, value
/// or completions): what a gain is measured in.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Outcome {
    /// Runs breaking a limit.
    pub breaking: u64,
    /// Mandatory completions.
    pub mandatory: u64,
    /// The value completed when the plan gives values, else the completions.
    pub value: f64,
}

impl Outcome {
    /// The outcome part of `s`.
    pub fn of(s: &Score) -> Self {
        let value = match &s.value {
            ValueMeasure::Total(_) => s.value.total().unwrap_or(0.0),
            ValueMeasure::StepOrder(c) => c.iter().sum::<u64>() as f64,
        };
        Self {
            breaking: s.runs_breaking,
            mandatory: s.mandatory_completed,
            value,
        }
    }
}

/// A gain over the original order on the held-out sample: fewer runs
/// breaking a limit, more mandatory completions, more value (or
/// completions), and the objective's verdict on the outcome (changes aside).
#[derive(Clone, Copy, Debug)]
pub struct Gain {
    /// Runs breaking a limit fewer than the original's.
    pub breaking: i64,
    /// Mandatory completions more than the original's.
    pub mandatory: i64,
    /// Value (or completions) more than the original's.
    pub value: f64,
    /// The objective's comparison with the original, changes aside.
    pub verdict: std::cmp::Ordering,
}

impl Gain {
    /// The gain of `s` over `original`.
    pub fn of(s: &Score, original: &Score) -> Self {
        let (a, o) = (Outcome::of(s), Outcome::of(original));
        Self {
            breaking: o.breaking as i64 - a.breaking as i64,
            mandatory: a.mandatory as i64 - o.mandatory as i64,
            value: a.value - o.value,
            verdict: outcome_cmp(s, original),
        }
    }

    /// Lexicographic order of gains (as the objective orders its items).
    fn key(&self) -> (i64, i64, i64) {
        (
            self.breaking,
            self.mandatory,
            (self.value * 1000.0).round() as i64,
        )
    }

    fn text(&self) -> String {
        let v = match self.verdict {
            std::cmp::Ordering::Greater => "better",
            std::cmp::Ordering::Equal => "same",
            std::cmp::Ordering::Less => "worse",
        };
        format!(
            "{v}: {:+} / {:+} / {:+}",
            -self.breaking, self.mandatory, self.value
        )
    }
}

/// The objective's comparison of two scores, the order changes aside.
pub fn outcome_cmp(a: &Score, b: &Score) -> std::cmp::Ordering {
    let strip = |s: &Score| Score {
        changes: 0,
        ..s.clone()
    };
    strip(a).cmp(&strip(b))
}

/// One method's result on one plan.
#[derive(Clone, Debug)]
pub struct MethodResult {
    /// Its held-out score.
    pub held_out: Score,
    /// Gain over the original on the held-out sample.
    pub gain: Gain,
    /// Wall time.
    pub wall: Duration,
    /// CPU time.
    pub cpu: Duration,
}

/// The three methods on one plan.
#[derive(Clone, Debug)]
pub struct PlanRow {
    /// How the plan is named in the table.
    pub label: String,
    /// Activities, and those with a duration model.
    pub activities: usize,
    /// Activities with a `duration_model`.
    pub models: usize,
    /// The original order's held-out outcome.
    pub original: Outcome,
    /// `tune`, the hill climb, the mandatory-first order.
    pub methods: [MethodResult; 3],
    /// Orders `tune` scored.
    pub tune_evaluations: u64,
    /// Orders the hill climb scored.
    pub climb_evaluations: u64,
    /// Restarts of the hill climb.
    pub restarts: u64,
}

/// The samples and budget of a comparison.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Runs of the tuning sample.
    pub runs: u64,
    /// Runs of the held-out sample.
    pub confirm_runs: u64,
    /// Orders scored on the tuning sample.
    pub budget: u64,
}

impl Settings {
    /// `tune`'s defaults.
    pub fn defaults() -> Self {
        Self {
            runs: TuneOptions::DEFAULT_RUNS,
            confirm_runs: TuneOptions::DEFAULT_CONFIRM_RUNS,
            budget: TuneOptions::DEFAULT_BUDGET,
        }
    }
}

/// Runs the three methods on `plan`.
pub fn compare(
    label: &str,
    plan: &Plan,
    settings: Settings,
) -> Result<PlanRow, solscope_engine::Error> {
    let options = TuneOptions {
        runs: settings.runs,
        confirm_runs: settings.confirm_runs,
        budget: settings.budget,
        ..TuneOptions::default()
    };
    let s = OrderScorer::new(plan);
    let tuning = s.sample(options.seed, options.runs);
    let held = s.sample(options.confirm_seed, options.confirm_runs);
    let (tuned, wall, cpu) = timed(|| tune(plan, &options));
    let tuned = tuned?;
    let original = tuned.held_out_scores.original.clone();
    let tune_result = MethodResult {
        gain: Gain::of(&tuned.held_out_scores.tuned, &original),
        held_out: tuned.held_out_scores.tuned.clone(),
        wall,
        cpu,
    };
    let (climb, wall, cpu) = timed(|| {
        let c = hill_climb(
            &s,
            tuning,
            options.budget,
            tuned.tuning_scores.original.clone(),
            options.seed,
        )?;
        let h = s.score(&c.best, held)?;
        Ok::<_, solscope_engine::Error>((c, h))
    });
    let (climb, climb_held) = climb?;
    assert!(
        climb.score >= tuned.tuning_scores.original,
        "{label}: the hill climb keeps the best order it scored, the original's the first"
    );
    let climb_result = MethodResult {
        gain: Gain::of(&climb_held, &original),
        held_out: climb_held,
        wall,
        cpu,
    };
    let (first, wall, cpu) = timed(|| s.score(&mandatory_first(plan, &s), held));
    let first = first?;
    let first_result = MethodResult {
        gain: Gain::of(&first, &original),
        held_out: first,
        wall,
        cpu,
    };
    Ok(PlanRow {
        label: label.to_string(),
        activities: plan.activities.len(),
        models: plan
            .activities
            .iter()
            .filter(|a| a.duration_model.is_some())
            .count(),
        original: Outcome::of(&original),
        methods: [tune_result, climb_result, first_result],
        tune_evaluations: tuned.evaluations,
        climb_evaluations: climb.evaluations,
        restarts: climb.restarts,
    })
}

/// The generated plan `k` of `activities` activities: realistic, seed `k`,
/// one sol for odd `k` and two for even, with duration models on
/// [`UNCERTAIN`] of its activities.
pub fn generated(activities: usize, k: u64) -> Plan {
    let sols = if k % 2 == 1 { 1 } else { 2 };
    add_duration_models(
        generate_plan_with(Profile::Realistic, activities, sols, k),
        UNCERTAIN,
        k,
    )
}

const METHODS: [&str; 3] = ["tune", "hill climb", "mandatory first"];

fn secs(d: Duration) -> String {
    format!("{:.1} s", d.as_secs_f64())
}

/// The value given after `flag` on the command line.
fn flag_value<T: std::str::FromStr>(flag: &str) -> Option<T> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == flag)?;
    args.get(at + 1)?.parse().ok()
}

/// The `--tuning` table: with `quick`, two generated plans of 100 activities
/// and a smaller budget; else the bundled plan and ten plans each of 100 and
/// 300 activities with `tune`'s defaults. `--plans N` takes N plans of each
/// size, `--size N` only plans of N activities (and not the bundled plan).
/// Rows print as each plan is done.
pub fn run(quick: bool) {
    let plans: Option<u64> = flag_value("--plans");
    let size: Option<usize> = flag_value("--size");
    let (settings, mut sets): (Settings, Vec<(usize, u64)>) = if quick {
        (
            Settings {
                runs: 6,
                confirm_runs: 12,
                budget: 16,
            },
            vec![(100, 2)],
        )
    } else {
        (Settings::defaults(), vec![(100, 10), (300, 10)])
    };
    for set in &mut sets {
        set.1 = plans.unwrap_or(set.1);
    }
    if let Some(n) = size {
        sets = vec![(n, sets.first().map_or(1, |s| s.1))];
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "tuning sample {} runs, held out {} runs, budget {} orders; load average at start: {}",
        settings.runs,
        settings.confirm_runs,
        settings.budget,
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    println!(
        "\neach method: its verdict against the original order on the held-out sample (the objective, changes aside), then the differences in runs breaking a limit / mandatory completions / value (completions when the plan gives no values)\n"
    );
    println!(
        "| plan | activities (models) | original: breaking / mandatory / value | tune | time (CPU) | hill climb | time (CPU) | mandatory first | time (CPU) | orders scored: tune / climb (restarts) |"
    );
    println!("|---|---:|---:|---|---:|---|---:|---|---:|---:|");
    if !quick && size.is_none() {
        let text = include_str!("../../assets/default-plan.json");
        let plan = load_plan(text).expect("the bundled plan loads").plan;
        let row = compare("bundled", &plan, settings).expect("compares");
        print_row(&row);
    }
    for &(n, count) in &sets {
        let mut group: Vec<PlanRow> = Vec::new();
        for k in 1..=count {
            let plan = generated(n, k);
            let sols = if k % 2 == 1 { 1 } else { 2 };
            let row = compare(
                &format!("realistic {n}, {sols} sol, seed {k}"),
                &plan,
                settings,
            )
            .expect("compares");
            print_row(&row);
            group.push(row);
        }
        summary(&format!("{n} activities"), &group);
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "\nload average at the end: {}",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
}

fn print_row(r: &PlanRow) {
    let [t, h, m] = &r.methods;
    println!(
        "| {} | {} ({}) | {} / {} / {} | {} | {} ({}) | {} | {} ({}) | {} | {} ({}) | {} / {} ({}) |",
        r.label,
        r.activities,
        r.models,
        r.original.breaking,
        r.original.mandatory,
        r.original.value,
        t.gain.text(),
        secs(t.wall),
        secs(t.cpu),
        h.gain.text(),
        secs(h.wall),
        secs(h.cpu),
        m.gain.text(),
        secs(m.wall),
        secs(m.cpu),
        r.tune_evaluations,
        r.climb_evaluations,
        r.restarts,
    );
}

/// Median and worst gain of each method over `rows`, how often each is
/// better, the same or worse than the original, and how often `tune` loses to
/// each baseline.
fn summary(name: &str, rows: &[PlanRow]) {
    if rows.is_empty() {
        return;
    }
    println!("\n{name}, {} plans:\n", rows.len());
    println!(
        "| method | median gain | worst gain (plan) | better / same / worse | median time (CPU) |"
    );
    println!("|---|---|---|---:|---:|");
    for (m, method) in METHODS.iter().enumerate() {
        let mut by: Vec<&PlanRow> = rows.iter().collect();
        by.sort_by_key(|r| r.methods[m].gain.key());
        let median = &by[by.len() / 2].methods[m];
        let worst = by[0];
        let count = |o: std::cmp::Ordering| {
            rows.iter()
                .filter(|r| r.methods[m].gain.verdict == o)
                .count()
        };
        let mut walls: Vec<Duration> = rows.iter().map(|r| r.methods[m].wall).collect();
        let mut cpus: Vec<Duration> = rows.iter().map(|r| r.methods[m].cpu).collect();
        walls.sort();
        cpus.sort();
        println!(
            "| {method} | {} | {} ({}) | {} / {} / {} | {} ({}) |",
            median.gain.text(),
            worst.methods[m].gain.text(),
            worst.label,
            count(std::cmp::Ordering::Greater),
            count(std::cmp::Ordering::Equal),
            count(std::cmp::Ordering::Less),
            secs(walls[walls.len() / 2]),
            secs(cpus[cpus.len() / 2]),
        );
    }
    for (m, method) in METHODS.iter().enumerate().skip(1) {
        let lost: Vec<&str> = rows
            .iter()
            .filter(|r| outcome_cmp(&r.methods[0].held_out, &r.methods[m].held_out).is_lt())
            .map(|r| r.label.as_str())
            .collect();
        println!(
            "\ntune held out worse than {method} on {} of {} plans{}",
            lost.len(),
            rows.len(),
            if lost.is_empty() {
                String::new()
            } else {
                format!(": {}", lost.join("; "))
            }
        );
    }
}
