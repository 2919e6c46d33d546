//! Blame: which placed activities hold what the failed activity needed, and the
//! energy and peak-power queries the app's plots use.

use serde::Serialize;

use super::{Culprit, Explanation, Phase};
use crate::scheduler::{Category, GeneratedKind, Phase2Reason, ReasonKind, Schedule, State};
use crate::timeline::IntervalSet;

/// One consumer of energy or peak power.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Consumer {
    /// The activity (for heating: the activity heated for); `None` for the rover's
    /// awake draw.
    pub activity: Option<usize>,
    /// `activity`, `preheat`, `maintenance` or `awake`.
    pub kind: &'static str,
    /// Zone index for heating.
    pub zone: Option<usize>,
    /// Energy used in the range (mJ), or peak power at the instant (mW).
    pub amount: i64,
}

/// One power draw after some step.
struct Load {
    kind: &'static str,
    activity: Option<usize>,
    zone: Option<usize>,
    start: i64,
    end: i64,
    energy_mw: i64,
    peak_mw: i64,
}

/// Everything drawing power after step `k` (activities, awake periods, heating).
fn loads(sched: &Schedule, k: usize) -> Vec<Load> {
    let problem = &sched.problem;
    let mut out = Vec::new();
    for st in sched.steps.iter().take(k) {
        if let Some((start, end)) = st.outcome.placement() {
            let act = &problem.acts[st.activity];
            out.push(Load {
                kind: "activity",
                activity: Some(st.activity),
                zone: None,
                start,
                end,
                energy_mw: act.energy,
                peak_mw: act.peak,
            });
        }
    }
    for g in sched.generated_after(k) {
        let (kind, activity, zone) = match g.kind {
            GeneratedKind::Awake => ("awake", None, None),
            GeneratedKind::Preheat { zone, activity } => ("preheat", Some(activity), Some(zone)),
            GeneratedKind::Maintenance { zone, activity } => {
                ("maintenance", Some(activity), Some(zone))
            }
        };
        out.push(Load {
            kind,
            activity,
            zone,
            start: g.start,
            end: g.end,
            energy_mw: g.power_mw,
            peak_mw: g.power_mw,
        });
    }
    out
}

/// Energy used on `[from, t)` after step `k`, ranked (largest first; ties by
/// activity). With `since_full`, `from` is the last time at or before `t` that the
/// battery was full (else the plan start). Heating is listed per demand (a zone
/// heater draws the largest demand, so overlapping demands of one zone are counted
/// once each here, as upper bounds).
pub fn energy_consumers(
    sched: &Schedule,
    k: usize,
    t: i64,
    since_full: bool,
) -> (i64, Vec<Consumer>) {
    let problem = &sched.problem;
    let from = if since_full {
        let state = sched.state_after(k);
        last_full_before(&state, t).unwrap_or(problem.h0)
    } else {
        problem.h0
    };
    let mut out: Vec<Consumer> = loads(sched, k)
        .into_iter()
        .filter_map(|l| {
            let overlap = (l.end.min(t) - l.start.max(from)).max(0);
            let amount = l.energy_mw.saturating_mul(overlap);
            (amount > 0).then_some(Consumer {
                activity: l.activity,
                kind: l.kind,
                zone: l.zone,
                amount,
            })
        })
        .collect();
    rank(&mut out);
    (from, out)
}

/// Largest amount first; ties by activity, then kind (deterministic).
fn rank(list: &mut [Consumer]) {
    list.sort_by(|a, b| {
        b.amount
            .cmp(&a.amount)
            .then(a.activity.cmp(&b.activity))
            .then(a.kind.cmp(b.kind))
    });
}

/// Peak-power users at instant `t` after step `k`, ranked by their peak.
pub fn peak_users(sched: &Schedule, k: usize, t: i64) -> Vec<Consumer> {
    let mut out: Vec<Consumer> = loads(sched, k)
        .into_iter()
        .filter(|l| l.start <= t && t < l.end && l.peak_mw > 0)
        .map(|l| Consumer {
            activity: l.activity,
            kind: l.kind,
            zone: l.zone,
            amount: l.peak_mw,
        })
        .collect();
    rank(&mut out);
    out
}

/// The last time at or before `t` that the state of charge was at capacity.
fn last_full_before(state: &State<'_>, t: i64) -> Option<i64> {
    state.soc.last_at_cap(t)
}

/// What a culprit is blamed for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Blame {
    /// It is the dependency target that did not schedule (phase `dependency`).
    Dependency,
    /// It is the group member that was scheduled (phase `group`).
    Group,
    /// Its placement narrows this phase-1 category (phase `valid_intervals`).
    Constraint(Category),
    /// It contributes to this phase-2 reason (phase `placement`).
    Reason(ReasonKind),
}

impl Blame {
    /// The spec's name: the phase, category or reason kind.
    pub fn name(self) -> &'static str {
        match self {
            Blame::Dependency => "dependency",
            Blame::Group => "group",
            Blame::Constraint(c) => c.name(),
            Blame::Reason(r) => r.name(),
        }
    }
}

/// How many energy consumers an energy failure blames: the largest ones since the
/// battery was last full. On a long plan with the battery never full again that
/// would otherwise be every placed activity (thousands), which tells a planner
/// nothing; the app's energy plot lists them all.
pub const ENERGY_CULPRITS: usize = 10;

/// How many data producers a `data_volume` conflict blames: the ones that
/// produced the most before the blocked span ends (every producer before it
/// would make an explanation per failure as long as the plan, and a document
/// quadratic in it, when the data store fills).
pub const DATA_CULPRITS: usize = 10;

/// The activities a run places, by the charge their whole placement draws
/// (mJ: energy rate times duration), largest first (ties by activity): the
/// energy culprits at any step of the run are ranked from it, stopping once
/// no later activity can draw more than the ones found, instead of a scan of
/// every placement since the battery was last full.
#[derive(Debug)]
pub(crate) struct EnergyRank(Vec<(i64, usize)>);

impl EnergyRank {
    /// The ranking of `sched`'s placements (a state of its replay holds a
    /// prefix of them, each where the run put it).
    pub(crate) fn new(sched: &crate::scheduler::Schedule) -> Self {
        let acts = &sched.problem.acts;
        let mut all: Vec<(i64, usize)> = sched
            .steps
            .iter()
            .filter_map(|st| {
                st.outcome
                    .placement()
                    .map(|(s, e)| (acts[st.activity].energy.saturating_mul(e - s), st.activity))
            })
            .collect();
        all.sort_by(energy_order);
        Self(all)
    }

    /// The [`ENERGY_CULPRITS`] activities placed in `state` drawing the most
    /// charge within `[from, t)`, largest first (ties by activity). A
    /// placement draws at most its whole charge, so the walk down the ranking
    /// stops at the first activity whose whole charge is below the last one
    /// kept, or not positive.
    fn top_users(&self, state: &State<'_>, from: i64, t: i64) -> Vec<(i64, usize)> {
        let mut top: Vec<(i64, usize)> = Vec::with_capacity(ENERGY_CULPRITS + 1);
        for &(whole, x) in &self.0 {
            let full = top.len() == ENERGY_CULPRITS;
            if whole <= 0 || (full && top.last().is_some_and(|l| whole < l.0)) {
                break;
            }
            let Some(u) = draw_within(state, x, from, t) else {
                continue;
            };
            let at = top.partition_point(|p| energy_order(p, &u).is_lt());
            top.insert(at, u);
            top.truncate(ENERGY_CULPRITS);
        }
        top
    }
}

/// Energy users in order: the largest first, ties by activity (a total order).
fn energy_order(p: &(i64, usize), q: &(i64, usize)) -> std::cmp::Ordering {
    q.0.cmp(&p.0).then(p.1.cmp(&q.1))
}

/// The charge (mJ) activity `x`, placed in `state`, draws within `[from, t)`
/// with `x`, when positive.
fn draw_within(state: &State<'_>, x: usize, from: i64, t: i64) -> Option<(i64, usize)> {
    let (s, e) = state.placed[x]?;
    let c = state.problem.acts[x]
        .energy
        .saturating_mul((e.min(t) - s.max(from)).max(0));
    (c > 0).then_some((c, x))
}

/// [`EnergyRank::top_users`] by a scan of every placement overlapping
/// `[from, t)` (the debug builds' check of the ranking).
fn top_users_by_scan(state: &State<'_>, from: i64, t: i64) -> Vec<(i64, usize)> {
    let mut users: Vec<(i64, usize)> = state
        .placed_overlapping_unordered(from, t)
        .filter_map(|x| draw_within(state, x, from, t))
        .collect();
    users.sort_by(energy_order);
    users.truncate(ENERGY_CULPRITS);
    users
}

/// The culprits of an explained failure, from the state at its failure step
/// (energy culprits ranked by `rank`, the run's [`EnergyRank`]).
pub(crate) fn culprits(state: &State<'_>, ex: &Explanation, rank: &EnergyRank) -> Vec<Culprit> {
    let problem = state.problem;
    let a = ex.activity;
    let act = &problem.acts[a];
    let mut out: Vec<Culprit> = Vec::new();
    let mut seen: std::collections::HashSet<(usize, Blame)> = std::collections::HashSet::new();
    let mut push = |x: usize, blame: Blame| {
        if x != a && seen.insert((x, blame)) {
            out.push(Culprit {
                activity: x,
                step: problem.step_of[x],
                blame,
            });
        }
    };
    match ex.phase {
        Some(Phase::Dependency) | Some(Phase::Group) => {
            if let Some(x) = ex.blocked_by {
                push(
                    x,
                    if ex.phase == Some(Phase::Group) {
                        Blame::Group
                    } else {
                        Blame::Dependency
                    },
                );
            }
        }
        Some(Phase::ValidIntervals) => {
            let d = ex.duration;
            // For category X of a minimal conflict C, the starts the other members of
            // C allow are non-empty (minimality) and X blocks all of them: blame what
            // X's timeline holds over that span.
            let mut blamed: Vec<(Category, i64, i64)> = Vec::new();
            for conflict in &ex.conflicts {
                for &cat in conflict {
                    let others = ex
                        .categories
                        .iter()
                        .filter(|c| c.category != cat && conflict.contains(&c.category))
                        .fold(IntervalSet::single(problem.h0, problem.h1), |acc, c| {
                            acc.intersect(&c.valid)
                        });
                    if let (Some(lo), Some(hi)) = (others.first(), others.intervals().last()) {
                        blamed.push((cat, lo, hi.hi.saturating_add(d)));
                    }
                }
            }
            let mut producers: Vec<(i64, usize)> = Vec::new();
            for (cat, span_lo, span_hi) in blamed {
                let overlaps = |(s, e): (i64, i64)| s < span_hi && span_lo < e;
                let blame = Blame::Constraint(cat);
                // The placed activities this category can blame, in activity
                // order: those overlapping the span where only overlap counts (an
                // index query, not a scan of every activity), else all placed.
                let candidates: Vec<usize> = match cat {
                    Category::Execution => Vec::new(),
                    Category::UnitResource | Category::SequenceEngines | Category::Uhf => {
                        state.placed_overlapping(span_lo, span_hi)
                    }
                    _ => (0..state.placed.len())
                        .filter(|&x| state.placed[x].is_some())
                        .collect(),
                };
                for x in candidates {
                    let Some(iv) = state.placed[x] else { continue };
                    let other = &problem.acts[x];
                    let hit = match cat {
                        Category::Execution => false,
                        Category::Dependency => act.after.iter().any(|dep| dep.target == x),
                        Category::UnitResource => {
                            overlaps(iv)
                                && other.resources.iter().any(|r| act.resources.contains(r))
                        }
                        Category::SequenceEngines => overlaps(iv) && other.engines > 0,
                        Category::StateRequirement => act.requires.iter().any(|req| {
                            // Effects setting another value inside the span, or the one
                            // in force when the span begins.
                            let changes = state.states[req.state].effects();
                            let last_before = changes.iter().rev().find(|c| c.time <= span_lo);
                            changes.iter().any(|c| {
                                c.owner == x
                                    && c.value != req.value
                                    && ((span_lo < c.time && c.time < span_hi)
                                        || last_before
                                            .is_some_and(|l| l.owner == x && l.time == c.time))
                            })
                        }),
                        Category::StateEffect => {
                            other.requires.iter().any(|r| {
                                act.effects
                                    .iter()
                                    .any(|e| e.state == r.state && e.value != r.value)
                            }) && iv.1 > span_lo
                        }
                        Category::DataVolume => other.data > 0 && iv.0 < span_hi,
                        Category::Uhf => {
                            overlaps(iv)
                                && (other.comm.is_some_and(|k| !act.allows(k))
                                    || act.comm.is_some_and(|k| !other.allows(k)))
                        }
                    };
                    if hit {
                        if cat == Category::DataVolume {
                            let produced = other.data.saturating_mul(iv.1.min(span_hi) - iv.0);
                            producers.push((produced, x));
                        } else {
                            push(x, blame);
                        }
                    }
                }
                // The producers that produced the most, largest first (ties by
                // activity), as the energy users are ranked.
                producers.sort_by(energy_order);
                for (_, x) in producers.drain(..).take(DATA_CULPRITS) {
                    push(x, blame);
                }
            }
        }
        Some(Phase::Placement) => {
            // Energy reasons of one kind at one time blame the same consumers
            // (for the same reason kind): ranked once.
            let mut energy_at: std::collections::HashSet<(i64, Blame)> =
                std::collections::HashSet::new();
            for r in &ex.reasons {
                let kind = Blame::Reason(r.reason.kind());
                match r.reason {
                    Phase2Reason::ForcedSleep { sleep: Some(x) }
                    | Phase2Reason::MinSleep { sleep: x }
                    | Phase2Reason::MinAwake { sleep: Some(x) } => push(x, kind),
                    Phase2Reason::MaxPeakPower { at, .. } => {
                        for x in state.placed_overlapping(at, at.saturating_add(1)) {
                            if problem.acts[x].peak > 0 {
                                push(x, kind);
                            }
                        }
                    }
                    Phase2Reason::MinSoc { .. } | Phase2Reason::HandoverSoc { .. } => {
                        let t = match r.reason {
                            Phase2Reason::MinSoc { at, .. } => at,
                            _ => problem.handover_time.unwrap_or(problem.h1),
                        };
                        if !energy_at.insert((t, kind)) {
                            continue;
                        }
                        let from = last_full_before(state, t).unwrap_or(problem.h0);
                        let users = rank.top_users(state, from, t);
                        debug_assert_eq!(
                            users,
                            top_users_by_scan(state, from, t),
                            "energy culprits from the ranking"
                        );
                        for (_, x) in users {
                            push(x, kind);
                        }
                    }
                    _ => {}
                }
            }
        }
        None => {}
    }
    out
}
