//! Onboard replanning (docs/format.md §10): every cycle runs the scheduler
//! again on the plan of what has not started yet, from the executed state, and
//! the dispatcher starts that schedule's activities at their times until the
//! next cycle, behind the guard.

use std::borrow::Cow;

use crate::error::Error;
#[cfg(debug_assertions)]
use crate::execute::cycle::cycle_plan;
#[cfg(debug_assertions)]
use crate::execute::cycle::first_appearance;
use crate::execute::cycle::{Layout, Links, Status, cycle_problem};
use crate::execute::resume::LastRun;
use crate::execute::sim::{CycleSchedule, Executive, Next, Sim, cycle_start, guard, state_values};
use crate::execute::{Event, Trigger};
use crate::model::Plan;
use crate::scheduler::{Problem, run_resuming};

/// The replanning executive of one plan: its cycle period and whether an
/// executing activity's end triggers a cycle.
pub(in crate::execute) struct Replan {
    period: Option<i64>,
    on_end: bool,
    links: Links,
}

impl Replan {
    pub(in crate::execute) fn new(plan: &Plan) -> Self {
        Self {
            period: plan.execution.and_then(|e| e.replan_period),
            on_end: plan.execution.is_none_or(|e| e.replan_on_end),
            links: Links::new(plan),
        }
    }
}

impl Executive for Replan {
    /// The cycle's own plan (the activities not yet started, from the executed
    /// state), scheduled for its outcomes.
    fn schedule<'p>(
        &'p self,
        problem: &Problem,
        plan: &'p Plan,
        sim: &mut Sim,
    ) -> Result<CycleSchedule<'p>, Error> {
        let start = cycle_start(problem, plan, sim);
        let values = state_values(problem, plan, &sim.runs, sim.t);
        let layout = Layout::new(plan, &self.links, sim.t, &sim.status);
        let compiled = cycle_problem(
            problem,
            plan,
            &self.links,
            sim.t,
            &sim.status,
            &values,
            &start,
            &layout,
        )?;
        // Debug builds: the cycle's plan, built and compiled in full, is the
        // one compiled here (but for the numbering of resources, comm kinds
        // and groups), and the one the execution rebuilds later.
        #[cfg(debug_assertions)]
        let (fingerprint, full) = {
            let cp = cycle_plan(
                plan,
                &self.links,
                sim.t,
                &sim.status,
                &values,
                start.clone(),
            );
            debug_assert_eq!(cp.activity_of, layout.activity_of);
            let full = Problem::compile(&cp.plan).ok();
            debug_assert_eq!(
                full.as_ref(),
                Some(&first_appearance(&compiled)),
                "the cycle's problem differs from its plan's compiled in full"
            );
            (crate::execute::sim::fingerprint(&cp.plan), full)
        };
        let last = sim.last_run.take();
        let prior = last
            .as_ref()
            .and_then(|last| last.prior(problem, sim, &layout.activity_of, &compiled));
        let run = run_resuming(&compiled, prior.as_ref());
        sim.kept += run.kept;
        sim.capacity_proved += run.capacity_proved;
        sim.kept_rest += run.kept_rest;
        sim.steps += compiled.order.len();
        drop(prior);
        // Debug builds, one cycle in eight: the numbering of names does not
        // change the run (a cycle keeps the whole plan's).
        #[cfg(debug_assertions)]
        if sim.cycles.len() % 8 == 0
            && let Some(full) = &full
        {
            debug_assert_eq!(
                run_resuming(full, None).outcomes,
                run.outcomes,
                "the cycle's run depends on how its names are numbered"
            );
        }
        let (last, outcomes) = LastRun::of(
            run,
            &layout.activity_of,
            &compiled,
            sim.t,
            plan.activities.len(),
        );
        sim.last_run = Some(last);
        let k = sim.cycles.len();
        for &a in &layout.activity_of {
            if matches!(sim.status[a], Status::Waiting) {
                sim.last_cycle[a] = Some(k);
            }
        }
        Ok(CycleSchedule {
            dropped: layout.dropped(),
            activity_of: layout.activity_of,
            outcomes: Cow::Owned(outcomes),
            start: Some(start),
            #[cfg(debug_assertions)]
            fingerprint,
        })
    }

    /// The next period boundary, or the first end of an executing activity
    /// after the cycle.
    fn next_cycle(&self, problem: &Problem, sim: &Sim) -> Next {
        let (h0, t) = (problem.h0, sim.t);
        let time = self.period.map_or(problem.h1, |p| {
            let done = (t - h0) / p;
            h0.saturating_add(p.saturating_mul(done + 1))
        });
        let mut next = Next {
            time: time.min(problem.h1),
            trigger: Trigger::Period,
        };
        if self.on_end {
            if let Some((end, a)) = sim
                .runs
                .iter()
                .enumerate()
                .filter_map(|(a, r)| r.map(|r| (r.end, a)))
                .filter(|&(end, _)| end > t)
                .min()
            {
                if end < next.time {
                    next = Next {
                        time: end,
                        trigger: Trigger::End(a),
                    };
                }
            }
        }
        next
    }

    /// The cycle's start times before the next cycle, in time then step order;
    /// an activity the guard holds back waits for a later cycle.
    fn start(
        &self,
        problem: &Problem,
        plan: &Plan,
        sim: &mut Sim,
        schedule: &CycleSchedule<'_>,
        next: &mut Next,
    ) -> Vec<Event> {
        let run = &schedule.outcomes;
        // Only starts before the next cycle as it stands can be due (an end
        // below only brings it earlier).
        let mut due: Vec<(i64, usize, usize, i64)> = run
            .placements
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let (s, e) = (*p)?;
                let a = schedule.activity_of[i];
                (s < next.time && matches!(sim.status[a], Status::Waiting)).then_some((
                    s,
                    run.step_of[i],
                    a,
                    e - s,
                ))
            })
            .collect();
        due.sort_unstable();
        let mut events = Vec::new();
        let t = sim.t;
        let mut seq = sim.runs.iter().flatten().count();
        for (s, _, a, planned) in due {
            if s >= next.time {
                break;
            }
            if let Some(guard) = guard(problem, plan, a, s, &sim.runs) {
                events.push(Event::Held {
                    activity: a,
                    time: s,
                    guard,
                });
                continue;
            }
            let end = sim.start(problem, plan, a, s, planned, seq);
            seq += 1;
            events.push(Event::Started {
                activity: a,
                time: s,
            });
            if self.on_end && end > t && end < next.time {
                *next = Next {
                    time: end,
                    trigger: Trigger::End(a),
                };
            }
        }
        events
    }
}
