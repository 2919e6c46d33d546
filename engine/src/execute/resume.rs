//! What a replanning cycle keeps of the cycle before it (docs/semantics.md,
//! "Execution: cycles that keep the cycle before"): when everything between
//! the two cycles went as the earlier one planned, the later cycle's scheduler
//! run may keep an activity's earlier outcome without searching it, where the
//! differences between the two runs can only take starts away from it.
//!
//! Between a cycle at `t0` and the next at `t1` the later run differs from
//! the earlier one, before a waiting activity `j`'s step, by:
//!
//! - the activities that started in between and came after `j` in the earlier
//!   run's step order (now held first, or ended and in the executed state),
//!   and those that ran longer than the earlier run held them: each only adds
//!   load, busy time and data unless it gives `j` starts (`gives_starts`).
//!   Through a shared heating zone alone it gives starts only up to its end
//!   and the longest preheat of `j`'s zones after it: the step keeps its
//!   outcome when no start up to there passes that it would choose over it
//!   (`Prior::heat_until`);
//! - the executed state of charge and data at `t1` (checked against the
//!   earlier run's levels there: never more charge, never less data), and a
//!   handover passed (then nothing is kept);
//! - the awake period and heaters the rover is in at `t1`, which the earlier
//!   run's later steps generated: more load (the plan's powers are checked
//!   non-negative), and for the awake period, a difference the scheduler
//!   side judges per step (`scheduler::resume`).
//!
//! An activity that started in between as placed and ended at `t1`, earlier
//! than planned, gives back what it would have drawn, held and produced
//! after `t1`, which can give a start to any step after its own in the
//! earlier run's order: those steps are searched. The steps before its own
//! never saw it there, so to them it is one more activity that started in
//! between (its effects now in the executed state), and the run's loads are
//! still among the earlier run's final loads (it ran for less). Any other
//! end earlier than planned, and an activity the guard held back (its load
//! before `t1` not drawn: more charge at `t1`), keep nothing.

use super::sim::Sim;
use crate::model::{AwakeMode, EffectAt};
use crate::scheduler::{
    Before, Placement, Prior, Problem, Resumed, RunOutcomes, gives_starts, gives_starts_unheated,
    shares_zone,
};
use crate::timeline::RateTimeline;

/// The latest cycle's run, as the next cycle's run reads it.
#[derive(Clone, Debug)]
pub(super) struct LastRun {
    /// The cycle's time.
    t: i64,
    /// Its placements, by activity of its plan, and its step order.
    placed: Vec<Option<Placement>>,
    order: Vec<usize>,
    /// Its plan's index of each plan activity (`usize::MAX`: not in it),
    /// and that activity's step index there.
    index: Vec<usize>,
    pos: Vec<usize>,
    /// The state of charge and data timeline after it (from its time on:
    /// a run that ended as the run before kept the run before's), whether
    /// its peak went over the limit, and its awake periods after it.
    soc: RateTimeline,
    data: RateTimeline,
    peak_over: bool,
    awake: Vec<(i64, i64)>,
    /// Its awake periods at its start.
    awake_start: Vec<(i64, i64)>,
    /// The heaters its plan found on that kept their zone warm for every
    /// activity (no owner): `(zone, end, power)`.
    warm: Vec<(usize, i64, i64)>,
    /// Whether its plan still had a handover to keep.
    handover: bool,
}

impl LastRun {
    /// What the run `run` of the cycle at `t` (its activities the plan's
    /// `activity_of`, compiled as `cycle`) leaves for the next cycle, and the
    /// run's outcomes.
    pub(super) fn of(
        run: Resumed,
        activity_of: &[usize],
        cycle: &Problem,
        t: i64,
        n: usize,
    ) -> (Self, RunOutcomes) {
        let mut index = vec![usize::MAX; n];
        let mut pos = vec![usize::MAX; n];
        for (k, &i) in cycle.order.iter().enumerate() {
            let a = activity_of[i];
            index[a] = i;
            pos[a] = k;
        }
        let last = Self {
            t,
            placed: run.placed,
            order: cycle.order.clone(),
            index,
            pos,
            soc: run.soc,
            data: run.data,
            peak_over: run.peak_over,
            awake: run.outcomes.awake.clone(),
            awake_start: cycle.awake0.into_iter().collect(),
            warm: warm(cycle),
            handover: cycle.handover_time.is_some(),
        };
        (last, run.outcomes)
    }

    /// The run's outcome for plan activity `a`.
    fn before(&self, a: usize) -> Before<'_> {
        match self.placed.get(self.index[a]) {
            None => Before::Unknown,
            Some(None) => Before::Failed,
            Some(Some(p)) => Before::Placed(p),
        }
    }

    /// What the run of the cycle at `sim.t` (its activities the plan's
    /// `activity_of`, compiled as `cycle`) may keep of this one; `None` when
    /// nothing can be kept.
    /// `problem` is the whole plan's.
    pub(super) fn prior(
        &self,
        problem: &Problem,
        sim: &Sim,
        activity_of: &[usize],
        cycle: &Problem,
    ) -> Option<Prior<'_>> {
        let (t0, t1) = (self.t, sim.t);
        if !restrictive(problem) || (self.handover && cycle.handover_time.is_none()) {
            return None;
        }
        // The state of charge never higher than the earlier run had at `t1`,
        // which never went under the minimum before `t1`; no peak over the
        // limit anywhere (a check of every start).
        let level = self.soc.level_at(t1);
        let lowest_before = self.soc.lowest_on(t0, t1);
        if cycle.soc0 > level || lowest_before < problem.min_soc {
            return None;
        }
        if self.peak_over {
            return None;
        }
        // Never less data stored than the earlier run had at `t1` (its
        // timeline holds `-D`), or no activity producing data is kept.
        let stored = self.data.level_at(t1);
        let data_ok = -cycle.data0 <= stored;
        // What ran in between, against the earlier run: `(activity, its step
        // there, how it ran against the earlier run)`.
        let mut extras: Vec<(usize, usize, Ran)> = Vec::new();
        for (x, r) in sim.runs.iter().enumerate() {
            let Some(r) = r else { continue };
            if r.start >= t0 {
                // Started as the earlier run placed it.
                let Before::Placed(p) = self.before(x) else {
                    return None;
                };
                if p.start != r.start || p.start + p.duration != r.planned_end {
                    return None;
                }
                let ran = if r.end <= t1 && r.end != r.planned_end {
                    // Ended earlier than planned: only at `t1` (the cycle
                    // its end triggered), as a producer or a load, not a
                    // downlink (one that stops early leaves more data).
                    if r.end != t1 || r.end > r.planned_end || problem.acts[x].data < 0 {
                        return None;
                    }
                    Ran::Shorter
                } else if r.end > t1 && r.planned_end <= t1 {
                    Ran::Longer
                } else {
                    Ran::AsHeld
                };
                extras.push((x, self.pos[x], ran));
            } else if r.end > t0 {
                // Executing at `t0`: the earlier run held it until `held`.
                let held = r.planned_end.max(t0 + 1);
                let now = if r.end <= t1 {
                    r.end
                } else {
                    r.planned_end.max(t1 + 1)
                };
                if r.end <= t1 && r.end < held {
                    return None;
                }
                if now != held {
                    extras.push((x, 0, Ran::Longer));
                }
            }
        }
        if effect_ties(problem, sim, self, t0, t1) {
            return None;
        }
        let none_longer = extras.iter().all(|&(_, _, ran)| ran != Ran::Longer);
        let none_shorter = extras.iter().all(|&(_, _, ran)| ran != Ran::Shorter);
        // Everything the earlier run placed before `t1` started (the guard
        // held nothing back).
        let started = |x: usize| sim.runs[x].is_some();
        let waiting_before =
            |x: usize| matches!(self.before(x), Before::Placed(p) if t0 <= p.start && p.start < t1);
        if (0..self.index.len()).any(|x| waiting_before(x) && !started(x)) {
            return None;
        }
        // A kept placement's loads, with those of the steps before it, are
        // among the earlier run's final loads (every step so far came out
        // as there, and nothing ran longer than held): from the same charge
        // at `t1`, its levels are at least that run's final levels, which
        // keep the minimum; the handover minimum binds optional activities
        // only, and is proved apart.
        let energy_proved =
            cycle.soc0 == level && none_longer && self.soc.lowest_from(t1) >= cycle.min_soc;
        let final_handover = match (cycle.handover_time, cycle.handover_soc) {
            (Some(at), Some(min)) => self.soc.level_at(at) >= min,
            _ => true,
        };
        // Where the earlier run's final level at the handover does not keep
        // the handover minimum, a kept optional placement keeps it when this
        // run's loads from `t1` on, up to and with its step, are the earlier
        // run's at the same step, from the same level at `t1` (then its check
        // comes out as there, where it passed). They are (`energy_proved`:
        // the same level at `t1`, nothing longer than held) for the steps
        // after every activity that started in between, in the earlier run's
        // step order, when no placement after the step that has not started
        // generated anything before `t1`: an awake period (merged or not,
        // such as a wakeup) or a preheat. The earlier run's level at `t1` at
        // that step is then its final one, the period the rover is in and
        // the heaters on at `t1` are that step's, and from `t1` on this run
        // has those steps' placements and the rest of the activities that
        // started before `t1`.
        let same_loads_after = extras
            .iter()
            .map(|&(_, pos, _)| pos)
            .chain(
                (0..self.index.len())
                    .filter(|&x| sim.runs[x].is_none())
                    .filter(|&x| match self.before(x) {
                        Before::Placed(p) => {
                            p.new_awake.is_some_and(|(from, _)| from < t1)
                                || p.preheats.iter().any(|&(_, from, _)| from < t1)
                        }
                        _ => false,
                    })
                    .map(|x| self.pos[x]),
            )
            .max();
        // A kept placement that stores data fits the store again when this
        // run, at its step, stores no more than a run in which it fitted,
        // at every time from `t1` on. Data stored grows with the data stored
        // at `t1` and with what producers add, and shrinks with downlinks (a
        // capped integrator is monotone in each), and this run starts from
        // no more than the earlier run's final level at `t1`. Two runs it
        // fitted in serve:
        // - the earlier run at the kept step's turn: from `t1` on, this
        //   run's loads up to the step are that step's plus the extras after
        //   it in step order, and the earlier run's level at `t1` there is
        //   the final one less what those extras produced before `t1`; so
        //   when no extra after the step produces data;
        // - the earlier run's final placements, which keep the store within
        //   its capacity everywhere (each producer was checked against all
        //   placed before it, and downlinks only take data away): this run's
        //   loads up to the step are among them but for the placements after
        //   it that have not started; so when none of those is a downlink.
        // Either way nothing may run longer than held. (The handover data
        // limit, a sum of what was produced, is checked as ever.)
        let data_at_most = -cycle.data0 >= stored && none_longer;
        // The step of the latest downlink the earlier run placed that has not
        // started.
        let last_downlink = (0..self.index.len())
            .filter(|&x| sim.runs[x].is_none() && problem.acts[x].data < 0)
            .filter(|&x| matches!(self.before(x), Before::Placed(_)))
            .map(|x| self.pos[x])
            .max();
        let awake_reach = self
            .awake
            .iter()
            .filter(|&&(a, _)| a <= t1)
            .map(|&(_, b)| b)
            .chain(cycle.awake0.map(|(_, b)| b))
            .fold(t1, i64::max);
        // A manual sleep that ran where a start of this run can reach (its
        // wakeup from the awake period the rover is in or from the cycle,
        // merged `min_sleep` further): the run before saw it, this one
        // does not.
        let reach_back = cycle
            .awake0
            .map_or(t1, |(w, _)| w.min(t1))
            .saturating_sub(cycle.wake + cycle.min_sleep.max(1));
        let no_sleep_near = !sim.runs.iter().enumerate().any(|(x, r)| {
            r.is_some_and(|r| r.start < t1 && r.end > reach_back)
                && problem.acts[x].awake == AwakeMode::Forbidden
        });
        // A heater that keeps its zone warm for every activity now but did not
        // in the earlier run (its owner started since, at another time than
        // the preheat was for) can spare an activity of the zone its preheat.
        let warmer: Vec<usize> = warm(cycle)
            .into_iter()
            .filter(|&(_, end, _)| end > t1)
            .filter(|h| !self.warm.contains(h))
            .map(|(z, _, _)| z)
            .collect();
        // From the step after every activity that started in between and
        // every placement not started that generated something before `t1`
        // (in the earlier run's step order), this run's state is the earlier
        // run's at the same step, from `t1` on, once every step before came
        // out as there: the same loads from the same levels at `t1` (nothing
        // ran longer than held, the same charge and data stored, and the
        // same data produced: everything in between ran as placed), the
        // same awake period and heaters at `t1` (the earlier run's at that
        // step: no later one generated anything before `t1`; no heater
        // warmer now), and no manual sleep within reach before `t1`. The
        // scheduler side checks the awake periods where a start can reach.
        let same_from = (cycle.soc0 == level
            && -cycle.data0 == stored
            && none_longer
            && none_shorter
            && no_sleep_near
            && warmer.is_empty())
        .then(|| same_loads_after.map_or(0, |k| k + 1));
        // When each activity that started in between ends in this run (no
        // earlier than the cycle): a held one, its held span's end. Its
        // heaters demand nothing after it.
        let ends: Vec<i64> = extras
            .iter()
            .map(|&(x, _, _)| {
                let held = activity_of.binary_search(&x).ok();
                held.filter(|&i| cycle.acts[i].held)
                    .map_or(t1, |i| cycle.held_span(i).1.max(t1))
            })
            .collect();
        let mut before = Vec::with_capacity(activity_of.len());
        let mut may_keep = Vec::with_capacity(activity_of.len());
        let mut heat_until = Vec::with_capacity(activity_of.len());
        let mut pos = Vec::with_capacity(activity_of.len());
        let mut data_proved = Vec::with_capacity(activity_of.len());
        let mut handover_proved = Vec::with_capacity(activity_of.len());
        for (i, &j) in activity_of.iter().enumerate() {
            let act = &problem.acts[j];
            before.push(self.before(j));
            pos.push(self.pos[j]);
            handover_proved
                .push(final_handover || same_loads_after.is_none_or(|k| k < self.pos[j]));
            data_proved.push(
                data_at_most
                    && (last_downlink.is_none_or(|k| k < self.pos[j])
                        || extras
                            .iter()
                            .all(|&(x, pos, _)| pos < self.pos[j] || problem.acts[x].data <= 0)),
            );
            // An activity that started in between and now comes before `j`
            // (or runs longer) gives it nothing but through a shared heating
            // zone: its heater, on to its end, can spare `j` a preheat at a
            // start up to that end, or share `j`'s heating demand at a start
            // whose preheat begins before it (the longest preheat of `j`'s
            // zones earlier); at no later start can it give `j` anything.
            let mut heat: Option<i64> = None;
            let preheat = longest_preheat(problem, j);
            let mut unheated = |x: usize, end: i64| {
                if gives_starts_unheated(problem, x, j) {
                    return false;
                }
                if shares_zone(problem, x, j) {
                    let until = end.saturating_add(preheat);
                    heat = Some(heat.map_or(until, |h| h.max(until)));
                }
                true
            };
            let kept_through = extras
                .iter()
                .zip(&ends)
                .all(|(&(x, pos, ran), &end)| match ran {
                    Ran::AsHeld => pos <= self.pos[j] || unheated(x, end),
                    Ran::Longer => unheated(x, end),
                    Ran::Shorter => pos > self.pos[j] && !gives_starts(problem, x, j),
                });
            may_keep.push(
                !cycle.acts[i].held
                    && (data_ok || act.data <= 0)
                    && !act.zones.iter().any(|z| warmer.contains(z))
                    && kept_through,
            );
            heat_until.push(heat);
        }
        Some(Prior {
            before,
            may_keep,
            heat_until,
            pos,
            energy_proved,
            handover_proved,
            data_proved,
            awake_reach,
            no_sleep_near,
            awake_start: &self.awake_start,
            placed_before: &self.placed,
            order_before: &self.order,
            same_from,
            soc_before: &self.soc,
            data_before: &self.data,
        })
    }
}

/// The longest preheat any of activity `j`'s zones' tables gives.
fn longest_preheat(problem: &Problem, j: usize) -> i64 {
    problem.acts[j]
        .zones
        .iter()
        .map(|&z| problem.zones[z].longest_preheat())
        .max()
        .unwrap_or(0)
}

/// How an activity that ran between two cycles ran, against the earlier
/// cycle's run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ran {
    /// As the earlier run placed or held it, as far as `t1` tells.
    AsHeld,
    /// Longer than the earlier run held it: more load, busy time and data.
    Longer,
    /// Ended at `t1`, earlier than the earlier run placed it to.
    Shorter,
}

/// Whether an activity that started before `t1` has a state effect at or
/// after `t0` at the very time another activity the earlier run placed (at
/// `t0`) has one on the same state. A run orders effects at one instant by
/// step, the later step's value winning; the next cycle instead folds those
/// that took place into its starting values (the executed order) and places
/// the activities still executing first, so such a tie can come out the
/// other way there, and a state value no longer follows from the earlier
/// run's.
fn effect_ties(problem: &Problem, sim: &Sim, last: &LastRun, t0: i64, t1: i64) -> bool {
    let effect_times = |a: usize, start: i64, end: i64| {
        problem.acts[a]
            .effects
            .iter()
            .map(move |e| (e.state, if e.at == EffectAt::Start { start } else { end }))
    };
    // Where the started activities' effects fell or fall, in either cycle's
    // plan: `(state, time, activity)`, sorted.
    let mut started: Vec<(usize, i64, usize)> = Vec::new();
    for (x, r) in sim.runs.iter().enumerate() {
        let Some(r) = r else { continue };
        if r.end < t0 || problem.acts[x].effects.is_empty() {
            continue;
        }
        let ends = [
            r.end,
            r.planned_end,
            r.planned_end.max(t0 + 1),
            r.planned_end.max(t1 + 1),
        ];
        started.extend(
            ends.iter()
                .flat_map(|&end| effect_times(x, r.start, end))
                .filter(|&(_, t)| t >= t0)
                .map(|(state, t)| (state, t, x)),
        );
    }
    if started.is_empty() {
        return false;
    }
    started.sort_unstable();
    started.dedup();
    (0..last.index.len()).any(|y| {
        let Before::Placed(p) = last.before(y) else {
            return false;
        };
        effect_times(y, p.start, p.start + p.duration).any(|(state, t)| {
            let from = started.partition_point(|&(s, u, _)| (s, u) < (state, t));
            started[from..]
                .iter()
                .take_while(|&&(s, u, _)| (s, u) == (state, t))
                .any(|&(_, _, x)| x != y)
        })
    })
}

/// The heaters `cycle`'s plan found on that keep their zone warm for every
/// activity: `(zone, end, power)`.
fn warm(cycle: &Problem) -> Vec<(usize, i64, i64)> {
    cycle
        .heaters
        .iter()
        .filter(|h| h.owner.is_none())
        .map(|h| (h.zone, h.end, h.power))
        .collect()
}

/// Whether every load the plan can add is a load (never charge given back,
/// never less peak): activities' energy and peak, being awake against
/// asleep, heaters.
fn restrictive(problem: &Problem) -> bool {
    problem.awake >= problem.asleep
        && problem
            .zones
            .iter()
            .all(|z| z.preheat >= 0 && z.maintenance >= 0)
        && problem.acts.iter().all(|a| a.energy >= 0 && a.peak >= 0)
}

#[cfg(test)]
mod tests {
    use super::super::sim::Sim;
    use super::super::{Actuals, Execution, Replan, execute, sample_run};
    use crate::generate::{Profile, add_duration_models, generate_plan_with};
    use crate::model::Plan;
    use crate::scheduler::{Problem, run_outcomes};

    fn bundled() -> Plan {
        crate::load::load_plan(include_str!("../../../assets/default-plan.json"))
            .expect("the bundled plan loads")
            .plan
    }

    /// What [`kept_in`] counts over its runs.
    #[derive(Default)]
    struct Counts {
        /// Steps kept from the cycle before, and steps run.
        kept: usize,
        steps: usize,
        /// Kept placements whose data store check the earlier run proved.
        capacity_proved: usize,
        /// Kept steps that were the earlier run's last steps.
        kept_rest: usize,
        /// Steps kept in cycles an end earlier than planned triggered.
        kept_after_early_end: usize,
    }

    /// Runs `runs` sampled executions of `plan` (seed 1) cycle by cycle and
    /// checks that every cycle fails exactly the activities a full scheduler
    /// run of its plan fails (debug builds also check each kept step against
    /// the full step).
    fn kept_in(plan: &Plan, runs: u64) -> Counts {
        let problem = Problem::compile(plan).expect("compiles");
        let mut counts = Counts::default();
        for run in 0..runs {
            let actuals = sample_run(plan, 1, run);
            let mut sim = Sim::new(&problem, plan, &actuals);
            let replan = Replan::new(plan);
            loop {
                let early = match sim.trigger {
                    super::super::Trigger::End(x) => {
                        sim.runs[x].is_some_and(|r| r.end < r.planned_end)
                    }
                    _ => false,
                };
                let kept = sim.kept;
                let more = sim.cycle(&problem, plan, &replan).expect("a cycle runs");
                if early {
                    counts.kept_after_early_end += sim.kept - kept;
                }
                if !more {
                    break;
                }
            }
            counts.kept += sim.kept;
            counts.steps += sim.steps;
            counts.capacity_proved += sim.capacity_proved;
            counts.kept_rest += sim.kept_rest;
            let execution = sim.finish(problem.clone(), plan);
            for (k, cycle) in execution.cycles.iter().enumerate() {
                let cp = execution.cycle_plan(plan, k).expect("a cycle plan");
                let full = run_outcomes(&cp.plan).expect("schedules");
                let failed: Vec<usize> = (0..cp.activity_of.len())
                    .filter(|&i| full.placements[i].is_none())
                    .map(|i| cp.activity_of[i])
                    .collect();
                assert_eq!(cycle.failed(), failed.as_slice(), "run {run}, cycle {k}");
            }
        }
        counts
    }

    /// Sampled executions of the bundled plan keep most of their cycles'
    /// steps from the cycle before, many as the cycle before's last steps,
    /// and come out as full runs would.
    #[test]
    fn replanning_cycles_of_the_bundled_plan_keep_most_steps() {
        let Counts {
            kept,
            steps,
            kept_rest,
            kept_after_early_end,
            ..
        } = kept_in(&bundled(), 6);
        assert!(
            kept_after_early_end > 0,
            "no step was kept in a cycle an early end triggered"
        );
        assert!(
            kept * 2 > steps,
            "only {kept} of {steps} steps were kept from the cycle before"
        );
        assert!(
            kept_rest * 4 > steps,
            "only {kept_rest} of {steps} steps were the cycle before's last steps"
        );
    }

    /// Generated plans of every profile with duration models (thermal zones
    /// with heaters left on, states, downlinks, sleep rules): cycles that keep
    /// steps come out as full runs would. The realistic 200-activity plan of
    /// seed 5 has a heater left on by an activity that started earlier than
    /// its preheat was for: the zone is warm for everyone from then on, which
    /// gives another activity of the zone a start it did not have. Some kept
    /// placements skip their data store check on the earlier run's proof.
    #[test]
    fn replanning_cycles_of_generated_plans_come_out_as_full_runs() {
        let (mut kept, mut capacity_proved, mut kept_rest, mut early) = (0, 0, 0, 0);
        for (profile, activities, seed) in [
            (Profile::Standard, 120, 1),
            (Profile::Standard, 120, 2),
            (Profile::Realistic, 120, 1),
            (Profile::Realistic, 200, 5),
            (Profile::Starved, 120, 1),
            (Profile::Starved, 120, 2),
        ] {
            let plan = generate_plan_with(profile, activities, 1, seed);
            for counts in [
                kept_in(&plan, 1),
                kept_in(&add_duration_models(plan, 0.3, seed), 2),
            ] {
                kept += counts.kept;
                capacity_proved += counts.capacity_proved;
                kept_rest += counts.kept_rest;
                early += counts.kept_after_early_end;
            }
        }
        assert!(kept > 0, "no step was kept");
        assert!(capacity_proved > 0, "no data store check was proved");
        assert!(kept_rest > 0, "no cycle kept the cycle before's last steps");
        assert!(
            early > 0,
            "no step was kept in a cycle an early end triggered"
        );
    }

    /// Whether the second cycle of `plan`'s execution with its planned
    /// durations keeps any step from the first.
    fn keeps_at_second_cycle(plan: &Plan) -> bool {
        let problem = Problem::compile(plan).expect("compiles");
        let actuals = Actuals::nominal();
        let mut sim = Sim::new(&problem, plan, &actuals);
        let replan = Replan::new(plan);
        assert!(sim.cycle(&problem, plan, &replan).expect("a cycle runs"));
        let before = sim.kept;
        assert!(sim.cycle(&problem, plan, &replan).expect("a cycle runs"));
        sim.kept > before
    }

    /// A heater shared with an activity that started since the cycle before
    /// gives a start only up to its end and a preheat after it. X (second in
    /// step order, in the arm zone) runs from 0 to 2,500 s needing no preheat
    /// (the table's first row); J (first) needs a 1,000 s preheat from 2,000 s
    /// of local time on, which may start only from 5,000 to 6,000 s: the first
    /// cycle places J at 6,000 s. At the cycle at 1,000 s (W's end) X's heater
    /// is on. With J's window from 2,000 s, J there needs no preheat and moves
    /// to it; from 2,600 s no start near the cycle passes, and the cycle keeps
    /// J at 6,000 s without searching it.
    #[test]
    fn a_heater_started_since_gives_starts_only_near_its_end() {
        for (from, start, kept) in [(2000, 2000, false), (2600, 6000, true)] {
            let json = format!(
                r#"{{
                  "format": "solscope.plan/1",
                  "horizon": {{ "start": 0, "end": 20000 }},
                  "local_time": {{ "sol_length": 88775, "offset": 0 }},
                  "battery": {{ "capacity": 2000.0, "initial": 1500.0, "min_soc": 100.0 }},
                  "power": {{ "rtg": 200.0, "asleep": 20.0, "awake": 20.0 }},
                  "thermal_zones": {{
                    "arm": {{
                      "preheat": [ {{ "from": 0, "duration": 0 }}, {{ "from": 2000, "duration": 1000 }} ],
                      "preheat_power": 40.0, "maintenance_power": 10.0,
                      "operable": [ {{ "from": 5000, "to": 6000 }} ]
                    }}
                  }},
                  "activities": [
                    {{ "id": "J", "priority": 1, "duration": 500, "awake": "any",
                      "thermal_zones": ["arm"], "windows": [ {{ "start": {from}, "end": 7000 }} ] }},
                    {{ "id": "X", "priority": 2, "duration": 2500, "awake": "any",
                      "thermal_zones": ["arm"], "windows": [ {{ "start": 0, "end": 0 }} ] }},
                    {{ "id": "W", "priority": 3, "duration": 1000, "awake": "any",
                      "windows": [ {{ "start": 0, "end": 0 }} ] }}
                  ]
                }}"#
            );
            let plan = crate::load::load_plan(&json).expect("the plan loads").plan;
            assert_eq!(
                keeps_at_second_cycle(&plan),
                kept,
                "J kept at the cycle (window from {from})"
            );
            let ex = execute(&plan, &Actuals::nominal()).expect("executes");
            assert_eq!(ex.cycles[1].time, 1000);
            assert_eq!(ex.activities[0].actual.map(|(s, _)| s), Some(start));
            kept_in(&plan, 1);
        }
    }

    /// A step placed as before inside the awake period the rover is in at the
    /// cycle comes out as before, though it generates no period now. J (first
    /// in step order, awake) runs at 1,000 s, its period from its wakeup at
    /// 700 s; at the cycle at W's end (800 s) the rover is in that period, and
    /// J, searched (its awake need reaches the cycle), lands where it was: K,
    /// after it, is kept.
    #[test]
    fn a_step_inside_the_awake_period_at_the_cycle_comes_out_as_before() {
        let json = r#"{
          "format": "solscope.plan/1",
          "horizon": { "start": 0, "end": 20000 },
          "battery": { "capacity": 2000.0, "initial": 1500.0, "min_soc": 100.0 },
          "power": { "rtg": 200.0, "asleep": 20.0, "awake": 50.0 },
          "sleep": { "wakeup_duration": 300, "shutdown_duration": 300, "min_awake": 0, "min_sleep": 0 },
          "activities": [
            { "id": "J", "priority": 1, "duration": 500, "awake": "required",
              "windows": [ { "start": 1000, "end": 1000 } ] },
            { "id": "W", "priority": 2, "duration": 800, "awake": "any",
              "windows": [ { "start": 0, "end": 0 } ] },
            { "id": "K", "priority": 3, "duration": 100, "awake": "any",
              "windows": [ { "start": 5000, "end": 5000 } ] }
          ]
        }"#;
        let plan = crate::load::load_plan(json).expect("the plan loads").plan;
        assert!(
            keeps_at_second_cycle(&plan),
            "K is not kept at the cycle at 800 s"
        );
        let ex = execute(&plan, &Actuals::nominal()).expect("executes");
        assert_eq!(ex.cycles[1].time, 800);
        assert_eq!(ex.activities[0].actual, Some((1000, 1500)));
        kept_in(&plan, 1);
    }

    /// Executes the plan `json` (whose first activity is J) with its planned
    /// durations; checks that the first cycle places J and the cycle at
    /// 1,000 s does not (the earlier run's proof does not hold there), and
    /// that every cycle comes out as a full run would.
    fn j_not_kept_at_1000(json: &str) -> Execution {
        let plan = crate::load::load_plan(json).expect("the plan loads").plan;
        let ex = execute(&plan, &Actuals::nominal()).expect("executes");
        assert_eq!(ex.cycles[1].time, 1000);
        assert!(!ex.cycles[0].did_not_place(0), "the first cycle places J");
        assert!(
            ex.cycles[1].did_not_place(0),
            "the cycle at 1,000 s keeps J"
        );
        kept_in(&plan, 1);
        ex
    }

    /// State effects at one instant: Y (first in step order) sets `s` to `b`
    /// at its start at 1,000 s, X (second) sets it to `c` at its end at
    /// 1,000 s, and the earlier run's later step, X's, wins the tie; Z
    /// (last) needs `need` at 2,000 s, W (third) runs `w` seconds from 0.
    /// At the cycle at X's end (`w` 50) X's effect is among the starting
    /// values and Y's, placed, wins; at the cycle at W's end (`w` 500) X
    /// still executes, is placed first, and Y's wins again. Either way Z's
    /// outcome is not the earlier run's, and every cycle must come out as a
    /// full run would.
    #[test]
    fn effects_tied_at_one_instant_are_not_kept_across_cycles() {
        for (w, need) in [(50, "c"), (500, "c"), (500, "b")] {
            let json = format!(
                r#"{{
                  "format": "solscope.plan/1",
                  "horizon": {{ "start": 0, "end": 10000 }},
                  "battery": {{ "capacity": 1000.0, "initial": 500.0, "min_soc": 100.0 }},
                  "power": {{ "rtg": 10.0, "asleep": 10.0, "awake": 10.0 }},
                  "states": {{ "s": {{ "values": ["a", "b", "c"], "initial": "a" }} }},
                  "activities": [
                    {{ "id": "Y", "priority": 1, "duration": 100, "awake": "any",
                      "windows": [ {{ "start": 1000, "end": 1000 }} ],
                      "effects": [ {{ "state": "s", "value": "b", "at": "start" }} ] }},
                    {{ "id": "X", "priority": 2, "duration": 1000, "awake": "any",
                      "windows": [ {{ "start": 0, "end": 0 }} ],
                      "effects": [ {{ "state": "s", "value": "c", "at": "end" }} ] }},
                    {{ "id": "W", "priority": 3, "duration": {w}, "awake": "any",
                      "windows": [ {{ "start": 0, "end": 0 }} ] }},
                    {{ "id": "Z", "priority": 4, "duration": 100, "awake": "any",
                      "windows": [ {{ "start": 2000, "end": 2000 }} ],
                      "requires": [ {{ "state": "s", "value": "{need}" }} ] }}
                  ]
                }}"#
            );
            let plan = crate::load::load_plan(&json).expect("the plan loads").plan;
            let ex = execute(&plan, &Actuals::nominal()).expect("executes");
            assert!(ex.cycles.len() > 1, "w {w}: a single cycle");
            assert_eq!(
                ex.cycles[0].did_not_place(3),
                need == "b",
                "w {w}, need {need}: the first cycle's outcome for Z"
            );
            kept_in(&plan, 1);
        }
    }

    /// A producer's placement is checked against the data store again when
    /// the earlier run's proof does not hold. J (first in step order) fitted
    /// at 5,000 s in the first cycle's run beside X's 90 Mbit (0 to 1,000 s)
    /// because L's downlink (2,000 s, after J in step order) made room. At
    /// the cycle at X's end, J's step comes before L's, and the 90 Mbit
    /// stored with J's 50 overflow the 100 Mbit store: J fails there, and the
    /// cycle at L's end places it again.
    #[test]
    fn a_kept_producer_is_checked_against_data_produced_in_between() {
        let ex = j_not_kept_at_1000(
            r#"{
              "format": "solscope.plan/1",
              "horizon": { "start": 0, "end": 10000 },
              "battery": { "capacity": 1000.0, "initial": 900.0, "min_soc": 100.0 },
              "power": { "rtg": 100.0, "asleep": 10.0, "awake": 60.0 },
              "data": { "capacity": 100.0, "initial": 0.0 },
              "activities": [
                { "id": "J", "priority": 1, "duration": 1000, "data_rate": 0.05,
                  "windows": [ { "start": 5000, "end": 5000 } ] },
                { "id": "L", "priority": 2, "duration": 1000, "data_rate": -0.06,
                  "windows": [ { "start": 2000, "end": 2000 } ] },
                { "id": "X", "priority": 3, "duration": 1000, "data_rate": 0.09,
                  "windows": [ { "start": 0, "end": 0 } ] }
              ]
            }"#,
        );
        let times: Vec<i64> = ex.cycles.iter().map(|c| c.time).collect();
        assert_eq!(times, [0, 1000, 3000, 6000]);
        assert_eq!(ex.activities[0].actual, Some((5000, 6000)));
    }

    /// An optional placement is checked against the handover minimum again
    /// when the earlier run's proof does not hold. J (optional, first in step
    /// order) fitted at 5,000 s in the first cycle's run, leaving 550 Wh at
    /// the handover; X (mandatory, exempt from the handover minimum) then
    /// took the level there to 450 Wh, under the 500 Wh minimum. At the cycle
    /// at X's end, X's drain is behind the rover and J's step sees it: J fails
    /// on the handover minimum.
    #[test]
    fn a_kept_optional_placement_is_checked_against_the_handover_minimum() {
        let ex = j_not_kept_at_1000(
            r#"{
              "format": "solscope.plan/1",
              "horizon": { "start": 0, "end": 10000 },
              "battery": { "capacity": 1000.0, "initial": 650.0, "min_soc": 100.0 },
              "power": { "rtg": 60.0, "asleep": 60.0, "awake": 60.0 },
              "handover": { "time": 9000, "min_soc": 500.0 },
              "activities": [
                { "id": "J", "priority": 1, "duration": 1000, "energy_rate": 360.0,
                  "mandatory": false, "windows": [ { "start": 5000, "end": 5000 } ] },
                { "id": "X", "priority": 2, "duration": 1000, "energy_rate": 360.0,
                  "windows": [ { "start": 0, "end": 0 } ] }
              ]
            }"#,
        );
        assert_eq!(ex.cycles.len(), 2);
        assert_eq!(ex.activities[0].actual, None);
    }
}
