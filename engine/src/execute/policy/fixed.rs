//! The fixed policy: every activity at its scheduled time, like a time-tagged
//! sequence, or not at all.

use super::{no_next, scheduled_once};
use crate::error::Error;
use crate::execute::Event;
use crate::execute::sim::{CycleSchedule, Executive, Next, Sim, guard};
use crate::model::Plan;
use crate::scheduler::{Problem, RunOutcomes};

/// The fixed executive of a plan scheduled once.
pub(super) struct Fixed<'a> {
    pub outcomes: &'a RunOutcomes,
}

impl Executive for Fixed<'_> {
    fn schedule<'p>(
        &'p self,
        _: &Problem,
        plan: &'p Plan,
        _: &mut Sim,
    ) -> Result<CycleSchedule<'p>, Error> {
        Ok(scheduled_once(plan, self.outcomes))
    }

    fn next_cycle(&self, problem: &Problem, _: &Sim) -> Next {
        no_next(problem)
    }

    /// Every activity at its scheduled start, in time then step order, if the
    /// guard lets it start then (once the others due at that instant have
    /// started); otherwise it does not run.
    fn start(
        &self,
        problem: &Problem,
        plan: &Plan,
        sim: &mut Sim,
        _: &CycleSchedule<'_>,
        _: &mut Next,
    ) -> Vec<Event> {
        let out = self.outcomes;
        let mut due: Vec<(i64, usize, usize, i64)> = out
            .placements
            .iter()
            .enumerate()
            .filter_map(|(a, p)| p.map(|(s, e)| (s, out.step_of[a], a, e - s)))
            .collect();
        due.sort_unstable();
        let mut events = Vec::new();
        // Activities due at the same time start together: one held back (a
        // required state another sets at that instant, a dependency ending
        // then) is tried again after the others of its instant.
        let mut i = 0;
        while i < due.len() {
            let t = due[i].0;
            let mut group: Vec<(usize, i64)> = due[i..]
                .iter()
                .take_while(|x| x.0 == t)
                .map(|x| (x.2, x.3))
                .collect();
            i += group.len();
            loop {
                let before = group.len();
                let mut held = Vec::new();
                for &(a, planned) in &group {
                    match guard(problem, plan, a, t, &sim.runs) {
                        Some(g) => held.push((a, planned, g)),
                        None => {
                            // Same-time effects apply in the schedule's step
                            // order, as the schedule that placed them assumed.
                            sim.start(problem, plan, a, t, planned, problem.step_of[a]);
                            events.push(Event::Started {
                                activity: a,
                                time: t,
                            });
                        }
                    }
                }
                group = held.iter().map(|&(a, p, _)| (a, p)).collect();
                if group.is_empty() || group.len() == before {
                    for (a, _, g) in held {
                        events.push(Event::Held {
                            activity: a,
                            time: t,
                            guard: g,
                        });
                    }
                    break;
                }
            }
        }
        events
    }
}
