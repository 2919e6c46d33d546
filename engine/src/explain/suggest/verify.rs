//! Verification: a candidate is kept only when the edited plan, rescheduled,
//! places the activity; numeric limits are searched to the least relaxation that
//! does.
//!
//! The run of an edited plan depends on the edit alone, not on the failure that
//! proposed it, and one edit is often proposed for many failures (a blocker moved
//! after them, the loosest value of a plan-wide limit): each distinct edit is
//! rescheduled once and its run answers every failure that asks.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use rayon::prelude::*;

use super::{Candidate, round3};
use crate::edit::{edit_activity, edited, edited_activity, edited_limits};
use crate::explain::Suggestion;
use crate::model::Plan;
use crate::scheduler::{
    Checkpoints, Problem, Schedule, placement_after_edit, placements_if_placed, probe_after_edit,
};
use crate::validate::{ActivityEdits, LIMIT_SECTIONS};

/// Placements by activity index in the run of an edited plan (`None`: not
/// placed, or its step not run).
type Placements = Vec<Option<(i64, i64)>>;

/// The plan's top-level fields that no compiled activity reads (its limits
/// and the number of sequence engines): an edit of these alone leaves every
/// compiled activity as it was. Any other plan field is compiled again in
/// full (a field added to the format later is too, until it is listed here).
const LEAVES_ACTIVITIES: [&str; 6] = [
    "battery",
    "power",
    "sleep",
    "data",
    "handover",
    "sequence_engines",
];

/// An edit's identity: its target and its fields as JSON text.
type EditKey = (String, String);

fn key(c: &Candidate) -> EditKey {
    (
        c.target.clone(),
        serde_json::to_string(&c.set).unwrap_or_default(),
    )
}

/// The plan and run being explained, with the whole runs of edited plans that
/// several failures ask about (each computed once, by the first that asks).
pub(super) struct Runs<'a> {
    pub(super) plan: &'a Plan,
    pub(super) sched: &'a Schedule,
    /// Whether several failures are explained, so that the runs of edits
    /// several of them may ask about are worth keeping whole.
    share: bool,
    /// What is known per edit asked about.
    edits: Mutex<BTreeMap<EditKey, Asked>>,
    /// The plan's context for checking edits of one activity, built on first
    /// use.
    checks: OnceLock<ActivityEdits<'a>>,
    /// States of the run explained to start reruns from, built on first use.
    starts: OnceLock<Checkpoints<'a>>,
}

/// An edit asked about: how many times, and its whole run once computed
/// (`None` inside: no activity is placed, or the edit gives no valid plan).
#[derive(Default)]
struct Asked {
    times: usize,
    run: Arc<OnceLock<Option<Placements>>>,
}

impl<'a> Runs<'a> {
    pub(super) fn new(plan: &'a Plan, sched: &'a Schedule, share: bool) -> Self {
        Self {
            plan,
            sched,
            share,
            edits: Mutex::new(BTreeMap::new()),
            checks: OnceLock::new(),
            starts: OnceLock::new(),
        }
    }

    /// States of the run explained to start reruns from, when several
    /// failures are explained. Building them replays the whole run once;
    /// one failure's few reruns start near its own step and do not repay
    /// that (A/B 0.93 to 1.00 without them, and 25 MB less at 10,000
    /// activities).
    fn starts(&self) -> Option<&Checkpoints<'a>> {
        if !self.share {
            return None;
        }
        Some(self.starts.get_or_init(|| Checkpoints::new(self.sched)))
    }

    /// The plan edited by `c`, compiled sharing the original plan's compiled
    /// activities that the edit leaves alone; `None` when the edit gives no
    /// valid plan. An edit of one activity that keeps its id and the names it
    /// interns is checked and compiled alone, without building the edited
    /// plan (debug builds compare with the edited plan, compiled in full).
    fn edit(&self, c: &Candidate) -> Option<Problem> {
        if !c.set.contains_key("id") {
            if let Some((i, activity)) = edited_activity(self.plan, &c.target, &c.set) {
                let checks = self.checks.get_or_init(|| ActivityEdits::new(self.plan));
                // `Some(None)`: not a valid plan.
                let quick = match checks.check(i, &activity) {
                    Ok(()) => self
                        .sched
                        .problem
                        .with_activity(self.plan, i, &activity)
                        .map(Result::ok),
                    Err(_) => Some(None),
                };
                if let Some(quick) = quick {
                    debug_assert_eq!(
                        quick,
                        edited(self.plan, &c.target, &c.set)
                            .and_then(|p| Problem::compile(&p).ok()),
                        "the edit checked and compiled alone differs"
                    );
                    return quick;
                }
            }
        }
        if c.target == "plan" && c.set.keys().all(|k| LIMIT_SECTIONS.contains(&k.as_str())) {
            let quick = edited_limits(self.plan, &c.set)
                .and_then(|shell| self.sched.problem.with_limits(&shell).ok());
            debug_assert_eq!(
                quick,
                edited(self.plan, &c.target, &c.set).and_then(|p| Problem::compile(&p).ok()),
                "the edit of the limits compiled alone differs"
            );
            return quick;
        }
        let plan = edited(self.plan, &c.target, &c.set)?;
        let edited_activity = match c.target.strip_prefix("activity:") {
            // (An edit that renamed it is compiled in full.)
            Some(id) => plan.activities.iter().position(|a| a.id == id).map(Some),
            None => c
                .set
                .keys()
                .all(|k| LEAVES_ACTIVITIES.contains(&k.as_str()))
                .then_some(None),
        };
        let problem = match edited_activity {
            Some(edited) => Problem::compile_reusing(&plan, &self.sched.problem, edited),
            None => Problem::compile(&plan),
        }
        .ok()?;
        Some(problem)
    }

    /// The whole run of the plan edited by `c`, if one was computed.
    fn known_run(&self, c: &Candidate) -> Option<Arc<OnceLock<Option<Placements>>>> {
        let map = self.edits.lock().unwrap_or_else(PoisonError::into_inner);
        map.get(&key(c))
            .filter(|e| e.run.get().is_some())
            .map(|e| Arc::clone(&e.run))
    }

    /// Whether activity `a` is placed in the run of the plan edited by `c`.
    ///
    /// An edit asked about a second time (the same value of a limit in the
    /// least-relaxation searches of several failures), or `shared` (the loosest
    /// value, which every search that gets that far asks about), is answered
    /// from its whole run, computed once; otherwise the edited plan is run only
    /// up to `a`'s step. With a `chain`, that run starts from the chain's run
    /// (the run of a stricter value of the same limit, up to `a`'s step; the
    /// original run when empty), and when `a` is not placed it becomes the
    /// chain's run.
    fn places(
        &self,
        c: &Candidate,
        a: usize,
        shared: bool,
        chain: Option<&mut Option<Schedule>>,
    ) -> bool {
        let whole = {
            let mut map = self.edits.lock().unwrap_or_else(PoisonError::into_inner);
            let e = map.entry(key(c)).or_default();
            e.times += 1;
            (self.share && (shared || e.times > 1 || e.run.get().is_some()))
                .then(|| Arc::clone(&e.run))
        };
        match whole {
            Some(cell) => {
                let placements = cell.get_or_init(|| {
                    let problem = self.edit(c)?;
                    let all: Vec<usize> = (0..problem.acts.len()).collect();
                    placements_if_placed(self.sched, self.starts(), &problem, &all)
                        .ok()
                        .flatten()
                });
                placed_in(placements.as_ref(), a)
            }
            None => {
                let Some(problem) = self.edit(c) else {
                    return false;
                };
                let Some(chain) = chain else {
                    return placement_after_edit(self.sched, self.starts(), problem, a)
                        .ok()
                        .flatten()
                        .is_some();
                };
                let prev = chain.as_ref().unwrap_or(self.sched);
                match probe_after_edit(prev, self.starts(), problem, a) {
                    Ok((Some(_), _)) => true,
                    Ok((None, run)) => {
                        *chain = Some(run);
                        false
                    }
                    Err(_) => false,
                }
            }
        }
    }

    /// The activities scheduled in the original run that are not in the run of
    /// `placements`.
    fn lost(&self, placements: &[Option<(i64, i64)>]) -> Vec<usize> {
        self.sched
            .steps
            .iter()
            .filter(|s| {
                s.outcome.placement().is_some() && placements.get(s.activity) == Some(&None)
            })
            .map(|s| s.activity)
            .collect()
    }

    /// For each of the activities `asking` (distinct), whether the edit `c`
    /// places it, with the side effects when it does: one run for all of them.
    fn verify(&self, c: &Candidate, asking: &[usize]) -> Vec<Option<Vec<usize>>> {
        let answer = |placements: Option<&Placements>| -> Vec<Option<Vec<usize>>> {
            let Some(placements) = placements else {
                return vec![None; asking.len()];
            };
            let lost = self.lost(placements);
            asking
                .iter()
                .map(|&a| placed_in(Some(placements), a).then(|| lost.clone()))
                .collect()
        };
        if let Some(cell) = self.known_run(c) {
            if let Some(placements) = cell.get() {
                return answer(placements.as_ref());
            }
        }
        let Some(problem) = self.edit(c) else {
            return vec![None; asking.len()];
        };
        if let [a] = asking {
            return vec![side_effects(&problem, *a, self.sched, self.starts())];
        }
        let placements = placements_if_placed(self.sched, self.starts(), &problem, asking)
            .ok()
            .flatten();
        #[cfg(debug_assertions)]
        for &a in asking {
            debug_assert_eq!(
                placed_in(placements.as_ref(), a),
                side_effects(&problem, a, self.sched, self.starts()).is_some(),
                "one run for several activities disagrees with the run for one"
            );
        }
        answer(placements.as_ref())
    }
}

impl Runs<'_> {
    /// The plan edited by `x` and then by `y`, compiled; `None` when either
    /// step gives no valid plan. Edits of limits, and of one activity each
    /// that keep its id, are checked and compiled alone as in [`Runs::edit`];
    /// other pairs build the edited plans (debug builds compare the two).
    fn edit_pair(&self, x: &Candidate, y: &Candidate) -> Option<Problem> {
        let slow = || {
            let once = edited(self.plan, &x.target, &x.set)?;
            let twice = edited(&once, &y.target, &y.set)?;
            Problem::compile(&twice).ok()
        };
        match self.quick_pair(x, y) {
            Some(quick) => {
                debug_assert_eq!(quick, slow(), "the pair checked and compiled alone differs");
                quick
            }
            None => slow(),
        }
    }

    /// [`Runs::edit_pair`] by the quick paths: `Some(None)` when the pair
    /// gives no valid plan, `None` when the quick paths do not apply.
    fn quick_pair(&self, x: &Candidate, y: &Candidate) -> Option<Option<Problem>> {
        let limits = |c: &Candidate| {
            c.target == "plan" && c.set.keys().all(|k| LIMIT_SECTIONS.contains(&k.as_str()))
        };
        let activity =
            |c: &Candidate| c.target.starts_with("activity:") && !c.set.contains_key("id");
        let checks = self.checks.get_or_init(|| ActivityEdits::new(self.plan));
        // An activity edit of the plan, checked: `None` when it is not valid
        // (the activities' checks read only the others' ids, and no limit).
        let checked = |c: &Candidate| {
            edited_activity(self.plan, &c.target, &c.set)
                .filter(|(i, act)| checks.check(*i, act).is_ok())
        };
        let base = &self.sched.problem;
        if limits(x) && limits(y) {
            // Disjoint sections (a pair never edits one field twice), each
            // checked as the slow path does: `x` alone, then both.
            edited_limits(self.plan, &x.set)?;
            let mut both = x.set.clone();
            both.extend(y.set.clone());
            return Some(
                edited_limits(self.plan, &both).and_then(|shell| base.with_limits(&shell).ok()),
            );
        }
        if limits(x) && activity(y) {
            let Some(shell) = edited_limits(self.plan, &x.set) else {
                return Some(None);
            };
            let Some((j, ay)) = checked(y) else {
                return Some(None);
            };
            let p = base.with_limits(&shell).ok()?;
            return p.with_activity(self.plan, j, &ay).map(Result::ok);
        }
        if activity(x) && limits(y) {
            let Some((i, ax)) = checked(x) else {
                return Some(None);
            };
            let p = base.with_activity(self.plan, i, &ax)?.ok()?;
            return Some(
                edited_limits(self.plan, &y.set).and_then(|shell| p.with_limits(&shell).ok()),
            );
        }
        if activity(x) && activity(y) {
            let Some((i, ax)) = checked(x) else {
                return Some(None);
            };
            if x.target == y.target {
                let Some(axy) = edit_activity(&ax, &y.set).filter(|a| checks.check(i, a).is_ok())
                else {
                    return Some(None);
                };
                return base.with_activity(self.plan, i, &axy).map(Result::ok);
            }
            let Some((j, ay)) = checked(y) else {
                return Some(None);
            };
            let p = base.with_activity(self.plan, i, &ax)?.ok()?;
            // The plan after `x`: `y`'s compile reads the others' priorities
            // and names.
            let mut once = self.plan.clone();
            once.activities[i] = ax;
            return p.with_activity(&once, j, &ay).map(Result::ok);
        }
        None
    }

    /// If the plan edited by `x` and then by `y` places activity `a`: the two as
    /// suggestions, with the activities the pair makes fail.
    pub(super) fn verify_pair(
        &self,
        x: &Candidate,
        y: &Candidate,
        a: usize,
    ) -> Option<Vec<Suggestion>> {
        let problem = self.edit_pair(x, y)?;
        let side_effects = side_effects(&problem, a, self.sched, self.starts())?;
        Some(
            [x, y]
                .into_iter()
                .map(|c| Suggestion {
                    description: c.description.clone(),
                    target: c.target.clone(),
                    set: c.set.clone(),
                    side_effects: side_effects.clone(),
                })
                .collect(),
        )
    }
}

fn placed_in(placements: Option<&Placements>, a: usize) -> bool {
    placements.is_some_and(|p| p.get(a).is_some_and(Option::is_some))
}

/// For each failure, its candidates (distinct within the failure) kept when the
/// edited plan places the failed activity, with the activities they make fail;
/// fewest side effects first (stable: candidate order breaks ties).
///
/// Every distinct edit is verified once, for all the failures that propose it,
/// in parallel; the results are collected in edit order and handed back in
/// candidate order, so the output does not depend on the number of threads.
/// A candidate proposed by one failure alone is first checked by running the
/// edited plan only up to the activity's step (the greedy run never looks ahead,
/// so that decides whether it is placed); only one that passes is run to the end
/// for its side effects. Every run reuses the steps of the original run that the
/// edit cannot change.
pub(super) fn verified(
    runs: &Runs<'_>,
    failures: &[(usize, Vec<Candidate>)],
) -> Vec<Vec<Suggestion>> {
    // The distinct edits in order of first appearance, each with the activities
    // asking about it.
    let mut index: BTreeMap<EditKey, usize> = BTreeMap::new();
    let mut edits: Vec<(&Candidate, Vec<usize>)> = Vec::new();
    let mut slots: Vec<Vec<(usize, usize)>> = Vec::with_capacity(failures.len());
    for (a, candidates) in failures {
        let mut mine = Vec::with_capacity(candidates.len());
        for c in candidates {
            let e = *index.entry(key(c)).or_insert_with(|| {
                edits.push((c, Vec::new()));
                edits.len() - 1
            });
            let asking = &mut edits[e].1;
            let slot = match asking.iter().position(|x| x == a) {
                Some(i) => i,
                None => {
                    asking.push(*a);
                    asking.len() - 1
                }
            };
            mine.push((e, slot));
        }
        slots.push(mine);
    }
    let results: Vec<Vec<Option<Vec<usize>>>> = edits
        .par_iter()
        .map(|(c, asking)| runs.verify(c, asking))
        .collect();
    failures
        .iter()
        .zip(slots)
        .map(|((_, candidates), mine)| {
            let mine: Vec<Option<Vec<usize>>> = mine
                .into_iter()
                .map(|(e, slot)| results[e][slot].clone())
                .collect();
            suggestions_of(candidates, &mine)
        })
        .collect()
}

/// [`verified`] for one failure, activity `a`, whose candidates are distinct:
/// per candidate, in order, the side effects when it places `a`.
pub(super) fn verified_each(
    runs: &Runs<'_>,
    a: usize,
    candidates: &[Candidate],
) -> Vec<Option<Vec<usize>>> {
    candidates
        .par_iter()
        .map(|c| runs.verify(c, &[a]).pop().flatten())
        .collect()
}

/// The candidates kept (`results[i]`: `candidates[i]`'s side effects when it
/// places the activity) as suggestions, fewest side effects first (stable:
/// candidate order breaks ties).
pub(super) fn suggestions_of(
    candidates: &[Candidate],
    results: &[Option<Vec<usize>>],
) -> Vec<Suggestion> {
    let mut out: Vec<Suggestion> = candidates
        .iter()
        .zip(results)
        .filter_map(|(c, side_effects)| {
            Some(Suggestion {
                description: c.description.clone(),
                target: c.target.clone(),
                set: c.set.clone(),
                side_effects: side_effects.clone()?,
            })
        })
        .collect();
    out.sort_by_key(|s| s.side_effects.len());
    out
}

/// If activity `a` is placed in the run of the edited plan (compiled:
/// `problem`): the activities
/// scheduled in `before` that are not any more. The steps after `a`'s are run
/// only when it is placed, and only where `a`'s placement can change them
/// ([`placements_if_placed`], which debug builds check against a full run).
fn side_effects(
    problem: &Problem,
    a: usize,
    before: &Schedule,
    starts: Option<&Checkpoints<'_>>,
) -> Option<Vec<usize>> {
    let after = placements_if_placed(before, starts, problem, &[a])
        .ok()
        .flatten()?;
    Some(
        before
            .steps
            .iter()
            .filter(|s| s.outcome.placement().is_some() && after[s.activity].is_none())
            .map(|s| s.activity)
            .collect(),
    )
}

/// The least shortening of a length in whole seconds (from `current`, which
/// fails, down to 0) that makes activity `a` schedule: the largest value below
/// `current` that works, binary-searched (a shorter one relaxes more).
pub(super) fn tune_seconds(
    runs: &Runs<'_>,
    a: usize,
    make: &dyn Fn(i64) -> Candidate,
    current: i64,
) -> Option<Candidate> {
    if current <= 0 {
        return None;
    }
    let loose = make(0);
    let works = |v: i64| {
        let c = make(v);
        let shared = c.same_edit(&loose);
        runs.places(&c, a, shared, None)
    };
    if !works(0) {
        return None;
    }
    // works(good), !works(bad)
    let (mut good, mut bad) = (0, current);
    while bad - good > 1 {
        let mid = good + (bad - good) / 2;
        if works(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(make(good))
}

/// The least relaxation of a numeric plan limit (from `current`, which fails) that
/// makes activity `a` schedule. `needed` is what the failure's numbers call for;
/// knock-on effects on earlier steps can ask for less or more, so the value is
/// binary-searched between `current` and `needed` when `needed` works, else between
/// `needed` and `loosest`, to a resolution of 0.001.
///
/// The loosest value is the same edit for every failure that gets that far, so
/// its whole run is kept and shared. Each value is run from the run of the last
/// value that failed (a relaxation of it, smaller at every halving).
pub(super) fn tune_limit(
    runs: &Runs<'_>,
    a: usize,
    make: &dyn Fn(f64) -> Candidate,
    current: f64,
    needed: f64,
    loosest: f64,
) -> Option<Candidate> {
    let loose = make(loosest);
    let mut chain = None;
    let mut works = |v: f64| {
        let c = make(v);
        let shared = c.same_edit(&loose);
        runs.places(&c, a, shared, Some(&mut chain))
    };
    let (mut bad, mut good) = if works(needed) {
        (current, needed)
    } else if works(loosest) {
        (needed, loosest)
    } else {
        return None;
    };
    for _ in 0..48 {
        let mid = round3((bad + good) / 2.0);
        if (good - bad).abs() <= 0.001 || mid == bad || mid == good {
            break;
        }
        if works(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(make(good))
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;
    use crate::load::load_plan;
    use crate::scheduler::schedule;

    /// A pair of edits compiled by the quick paths is the pair applied to the
    /// plan and compiled in full, for every kind of pair the explainer makes:
    /// limits and limits, limits and an activity either way round, two
    /// activities, one activity twice; valid and not.
    #[test]
    fn pairs_compiled_alone_are_the_full_compile() {
        let plan = load_plan(include_str!("../../../../assets/default-plan.json"))
            .expect("the default plan loads")
            .plan;
        let sched = schedule(&plan).expect("schedules");
        let runs = Runs::new(&plan, &sched, true);
        let b = plan.battery;
        let (first, last) = (&plan.activities[3], &plan.activities[40]);
        let edits = [
            Candidate::plan_section(String::new(), "battery", &b, "min_soc", b.min_soc * 0.5),
            // Invalid: the minimum above the capacity.
            Candidate::plan_section(String::new(), "battery", &b, "min_soc", b.capacity * 2.0),
            Candidate::plan(
                "".into(),
                "power",
                json!({ "rtg": 120.0, "asleep": 20.0, "awake": 150.0, "max_peak": 2000.0 }),
            ),
            Candidate::activity(first, String::new(), "priority", json!(1_000)),
            Candidate::activity(first, String::new(), "windows", json!(null)),
            Candidate::activity(last, String::new(), "priority", json!(0)),
            Candidate::activity(last, String::new(), "energy_rate", json!(1.5)),
            // Invalid: a window ending before it starts.
            Candidate::activity(
                last,
                String::new(),
                "windows",
                json!([{ "start": 500, "end": 100 }]),
            ),
        ];
        let (mut quick, mut valid, mut invalid) = (0, 0, 0);
        for x in &edits {
            for y in &edits {
                if x.target == y.target && x.set.keys().any(|k| y.set.contains_key(k)) {
                    continue;
                }
                let full = edited(&plan, &x.target, &x.set)
                    .and_then(|once| edited(&once, &y.target, &y.set))
                    .and_then(|twice| Problem::compile(&twice).ok());
                if let Some(alone) = runs.quick_pair(x, y) {
                    assert_eq!(
                        alone, full,
                        "{} {:?} then {} {:?}",
                        x.target, x.set, y.target, y.set
                    );
                    quick += 1;
                }
                assert_eq!(runs.edit_pair(x, y), full);
                if full.is_some() {
                    valid += 1;
                } else {
                    invalid += 1;
                }
            }
        }
        assert!(
            quick > 40 && valid > 20 && invalid > 10,
            "{quick} quick, {valid} valid, {invalid} invalid"
        );
    }
}
