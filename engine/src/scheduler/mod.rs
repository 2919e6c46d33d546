//! The greedy, non-backtracking scheduler and its step trace.
//!
//! One step per activity in `(priority, file index)` order. A step computes the
//! valid start intervals of every phase-1 category, intersects them per window, and
//! runs the exact phase-2 search (`search.rs`) window by window; the first window
//! with a passing start wins, at the passing start nearest its preferred time.

mod problem;
mod search;
mod state;
mod trace;

pub use problem::{BIT_PER_MBIT, MJ_PER_WH, MW_PER_W, Problem};
pub use state::{Placement, State};
pub use trace::*;

use crate::error::Error;
use crate::model::{AwakeMode, Plan};
use crate::timeline::IntervalSet;

/// The result of a scheduling run: the compiled problem and the full step trace.
#[derive(Clone, Debug)]
pub struct Schedule {
    /// The compiled plan the run used.
    pub problem: Problem,
    /// One record per step, `steps[k - 1]` for step k.
    pub steps: Vec<Step>,
    /// Every generated activity that ever existed, with its lifetime in steps.
    pub generated: Vec<Generated>,
}

impl Schedule {
    /// Where activity `act` was placed, if it was.
    pub fn placement(&self, act: usize) -> Option<(i64, i64)> {
        self.steps
            .iter()
            .find(|s| s.activity == act)
            .and_then(|s| match s.outcome {
                Outcome::Scheduled { start, end } => Some((start, end)),
                _ => None,
            })
    }

    /// The step of activity `act`.
    pub fn step_of(&self, act: usize) -> Option<&Step> {
        self.steps.iter().find(|s| s.activity == act)
    }

    /// Rebuilds the state of every timeline after step `k` (0 = before step 1) by
    /// replaying the placements of steps `1..=k`.
    pub fn state_after(&self, k: usize) -> State<'_> {
        let mut state = State::new(&self.problem);
        for step in self.steps.iter().take(k) {
            if let Outcome::Scheduled { start, end } = step.outcome {
                // Re-deriving the generated activities is deterministic, so the replay
                // reproduces the run exactly.
                if let Ok(ev) = state.evaluate(step.activity, start, end - start) {
                    state.apply(step.step, &ev.placement);
                }
            }
        }
        state
    }

    /// The generated activities alive after step `k`.
    pub fn generated_after(&self, k: usize) -> impl Iterator<Item = &Generated> {
        self.generated.iter().filter(move |g| g.alive_after(k))
    }
}

/// Schedules a validated plan.
pub fn schedule(plan: &Plan) -> Result<Schedule, Error> {
    let problem = Problem::compile(plan)?;
    let mut steps = Vec::with_capacity(problem.acts.len());
    let mut generated: Vec<Generated> = Vec::new();
    // Index into `generated` of each current awake period (parallel to state.awake).
    let mut awake_gen: Vec<usize> = Vec::new();
    {
        let mut state = State::new(&problem);
        for (k, &a) in problem.order.iter().enumerate() {
            let step_no = k + 1;
            let mut step = run_step(&state, a, step_no);
            if let Some(placement) = step.1.take() {
                // Record generated activities.
                let act = &problem.acts[a];
                let (s, e) = (placement.start, placement.start + placement.duration);
                if let Some((qa, qb)) = placement.new_awake {
                    for &i in &placement.retire {
                        let g = awake_gen[i];
                        generated[g].retired_at = Some(step_no);
                        step.0.retired.push(g);
                    }
                    let mut kept: Vec<usize> = awake_gen
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| !placement.retire.contains(i))
                        .map(|(_, &g)| g)
                        .collect();
                    let at = state
                        .awake
                        .iter()
                        .enumerate()
                        .filter(|(i, p)| !placement.retire.contains(i) && p.0 < qa)
                        .count();
                    kept.insert(at, generated.len());
                    awake_gen = kept;
                    step.0.added.push(generated.len());
                    generated.push(Generated {
                        kind: GeneratedKind::Awake,
                        start: qa,
                        end: qb,
                        power_mw: problem.awake - problem.asleep,
                        added_at: step_no,
                        retired_at: None,
                    });
                }
                for &z in &act.zones {
                    if let Some(&(_, ps, pe)) = placement.preheats.iter().find(|x| x.0 == z) {
                        step.0.added.push(generated.len());
                        generated.push(Generated {
                            kind: GeneratedKind::Preheat {
                                zone: z,
                                activity: a,
                            },
                            start: ps,
                            end: pe,
                            power_mw: problem.zones[z].preheat,
                            added_at: step_no,
                            retired_at: None,
                        });
                    }
                    step.0.added.push(generated.len());
                    generated.push(Generated {
                        kind: GeneratedKind::Maintenance {
                            zone: z,
                            activity: a,
                        },
                        start: s,
                        end: e,
                        power_mw: problem.zones[z].maintenance,
                        added_at: step_no,
                        retired_at: None,
                    });
                }
                state.apply(step_no, &placement);
            }
            steps.push(step.0);
        }
    }
    Ok(Schedule {
        problem,
        steps,
        generated,
    })
}

/// Runs one step against `state`; returns the record and the placement to apply.
fn run_step(state: &State<'_>, a: usize, step_no: usize) -> (Step, Option<Placement>) {
    let pb = state.pb;
    let act = &pb.acts[a];
    let mut step = Step {
        step: step_no,
        activity: a,
        outcome: Outcome::Failed(FailurePhase::ValidIntervals),
        duration: act.dur_max,
        categories: Vec::new(),
        intersection: IntervalSet::empty(),
        tries: Vec::new(),
        added: Vec::new(),
        retired: Vec::new(),
    };
    if let Some(by) = act.group.and_then(|g| state.group_member[g]) {
        step.outcome = Outcome::Skipped { by };
        return (step, None);
    }
    if let Some(dep) = act.after.iter().find(|d| state.placed[d.target].is_none()) {
        step.outcome = Outcome::Failed(FailurePhase::Dependency { on: dep.target });
        return (step, None);
    }
    let mut any_candidate = false;
    // Longest duration first; record the intervals of the chosen duration, or of
    // the shortest when none fits.
    for d in (act.dur_min..=act.dur_max).rev() {
        let categories = state.phase1(a, d);
        let (wake, shut) = if act.awake == AwakeMode::Required {
            (pb.wake, pb.shut)
        } else {
            (0, 0)
        };
        let others = categories
            .iter()
            .skip(1)
            .fold(IntervalSet::single(pb.h0, pb.h1), |acc, c| {
                acc.intersect(&c.valid)
            });
        let mut union = IntervalSet::empty();
        let mut found = None;
        for w in &act.windows {
            let range = state.window_range(a, w.start, w.end, w.cutoff, d, wake, shut);
            let cand = others.clip(range.lo, range.hi);
            if cand.is_empty() {
                continue;
            }
            any_candidate = true;
            union = union.union(&cand);
            if found.is_none() {
                let (chosen, tries) = state.search(a, d, &cand, w.preferred);
                step.tries.extend(tries);
                found = chosen;
            }
        }
        if found.is_some() || d == act.dur_min {
            step.duration = d;
            step.categories = categories;
            step.intersection = union;
        }
        if let Some(ev) = found {
            let p = ev.placement;
            step.outcome = Outcome::Scheduled {
                start: p.start,
                end: p.start + p.duration,
            };
            return (step, Some(p));
        }
    }
    step.outcome = Outcome::Failed(if any_candidate {
        FailurePhase::Placement
    } else {
        FailurePhase::ValidIntervals
    });
    (step, None)
}
