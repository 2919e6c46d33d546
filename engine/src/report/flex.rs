//! The flexible schedule document (`solscope.flex/1`, docs/format.md section 11).

use serde::Serialize;

use crate::flex::{Bound, Constraint, Controllability, Flex, TimePoint, constraint_line};
use crate::model::Plan;
use crate::timeline::IntervalSet;

/// The value of `format` in every flexible schedule document.
pub const FLEX_FORMAT: &str = "solscope.flex/1";

/// `solscope.flex/1`.
#[derive(Clone, Debug, Serialize)]
pub struct FlexDoc {
    /// Always [`FLEX_FORMAT`].
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
    /// Sizes and the controllability verdict.
    pub summary: FlexSummary,
    /// Every placed activity, in file order.
    pub activities: Vec<FlexEntry>,
    /// The minimum dispatchable network.
    pub dispatchable: Vec<EdgeEntry>,
    /// Dynamic controllability.
    pub controllability: ControllabilityEntry,
}

/// Sizes.
#[derive(Clone, Debug, Serialize)]
pub struct FlexSummary {
    /// Placed activities.
    pub placed: usize,
    /// Edges of the temporal network (distance graph, parallel edges merged).
    pub network_edges: usize,
    /// Edges of the minimum dispatchable network.
    pub dispatchable_edges: usize,
    /// `certain`, `controllable` or `not_controllable`.
    pub controllability: &'static str,
}

/// An event: `{"activity": ID, "at": "start"|"end"}` or `{"at": "origin"}`.
#[derive(Clone, Debug, Serialize)]
pub struct PointEntry {
    /// Activity id (absent for the origin).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub activity: Option<String>,
    /// `start`, `end` or `origin`.
    pub at: &'static str,
}

/// Earliest, scheduled and latest time.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct BoundsEntry {
    /// Earliest.
    pub lb: i64,
    /// Scheduled.
    pub nom: i64,
    /// Latest.
    pub ub: i64,
}

/// A neighbour bound.
#[derive(Clone, Debug, Serialize)]
pub struct BoundEntry {
    /// The neighbour event.
    pub event: PointEntry,
    /// Seconds after it.
    pub offset: i64,
}

/// Start condition: `time >= max(lb, after..., min(nom, ub, within...))`; skip
/// condition: `time >= min(ub, within...)`.
#[derive(Clone, Debug, Serialize)]
pub struct ConditionEntry {
    /// `t >= t(event) + offset`.
    pub after: Vec<BoundEntry>,
    /// `t <= t(event) + offset`.
    pub within: Vec<BoundEntry>,
}

/// A wait.
#[derive(Clone, Debug, Serialize)]
pub struct WaitEntry {
    /// The activity of uncertain duration waited for.
    pub on: String,
    /// Not before `on`'s start plus this, unless `on` has ended.
    pub offset: i64,
}

/// One placed activity.
#[derive(Clone, Debug, Serialize)]
pub struct FlexEntry {
    /// Activity id.
    pub id: String,
    /// Start bounds (total slack `[lb, ub]`).
    pub start: BoundsEntry,
    /// End bounds.
    pub end: BoundsEntry,
    /// Start condition.
    pub condition: ConditionEntry,
    /// Start bounds that hold whatever the uncertain durations (controllable
    /// networks with `duration_model`s only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub controllable: Option<(i64, i64)>,
    /// Waits (controllable networks only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub waits: Vec<WaitEntry>,
    /// Neighbours in the minimum dispatchable network.
    pub neighbours: Vec<String>,
    /// Free slack: starts every scheduler check accepts, others fixed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub free_slack: Option<Vec<(i64, i64)>>,
    /// Starts phase 1 alone accepts, others fixed (superset of `free_slack`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub free_slack_phase1: Option<Vec<(i64, i64)>>,
}

/// A dispatchable edge: `t(to) - t(from) <= max`.
#[derive(Clone, Debug, Serialize)]
pub struct EdgeEntry {
    /// From.
    pub from: PointEntry,
    /// To.
    pub to: PointEntry,
    /// Upper bound.
    pub max: i64,
}

/// A plan constraint named in a verdict.
#[derive(Clone, Debug, Serialize)]
pub struct ConstraintEntry {
    /// `horizon`, `window`, `cutoff`, `duration`, `dependency` or `order`.
    pub kind: &'static str,
    /// The activities it is about.
    pub activities: Vec<String>,
    /// As a planner reads it.
    pub text: String,
}

/// The controllability verdict.
#[derive(Clone, Debug, Serialize)]
pub struct ControllabilityEntry {
    /// `certain`, `controllable` or `not_controllable`.
    pub status: &'static str,
    /// For `not_controllable`: the activities involved.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub activities: Vec<String>,
    /// For `not_controllable`: the constraints that make it so.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<ConstraintEntry>,
}

fn point(plan: &Plan, e: TimePoint) -> PointEntry {
    let id = |a: usize| Some(plan.activities[a].id.clone());
    match e {
        TimePoint::Origin => PointEntry {
            activity: None,
            at: "origin",
        },
        TimePoint::Start(a) => PointEntry {
            activity: id(a),
            at: "start",
        },
        TimePoint::End(a) => PointEntry {
            activity: id(a),
            at: "end",
        },
    }
}

fn bound(plan: &Plan, b: &Bound) -> BoundEntry {
    BoundEntry {
        event: point(plan, b.event),
        offset: b.offset,
    }
}

fn set(s: &IntervalSet) -> Vec<(i64, i64)> {
    s.intervals().iter().map(|iv| (iv.lo, iv.hi)).collect()
}

fn constraint(plan: &Plan, c: &Constraint) -> ConstraintEntry {
    let kind = match c {
        Constraint::Horizon { .. } => "horizon",
        Constraint::Window { .. } => "window",
        Constraint::Cutoff { .. } => "cutoff",
        Constraint::Duration { .. } => "duration",
        Constraint::Dependency { .. } => "dependency",
        Constraint::Order { .. } => "order",
    };
    ConstraintEntry {
        kind,
        activities: c
            .activities()
            .into_iter()
            .map(|a| plan.activities[a].id.clone())
            .collect(),
        text: constraint_line(plan, c),
    }
}

/// The `solscope.flex/1` document of a flexible schedule of `plan`.
pub fn flex_document(plan: &Plan, flex: &Flex, name: &str) -> FlexDoc {
    let status = match flex.controllability {
        Controllability::Certain => "certain",
        Controllability::Controllable { .. } => "controllable",
        Controllability::NotControllable { .. } => "not_controllable",
    };
    let activities = flex
        .activities
        .iter()
        .map(|fa| {
            let (controllable, waits) = match &flex.controllability {
                Controllability::Controllable { tightened, waits } => (
                    tightened
                        .iter()
                        .find(|t| t.0 == fa.activity)
                        .map(|t| (t.1, t.2)),
                    waits
                        .iter()
                        .filter(|w| w.activity == fa.activity)
                        .map(|w| WaitEntry {
                            on: plan.activities[w.on].id.clone(),
                            offset: w.offset,
                        })
                        .collect(),
                ),
                _ => (None, Vec::new()),
            };
            let be = |b: crate::flex::EventBounds| BoundsEntry {
                lb: b.lb,
                nom: b.nom,
                ub: b.ub,
            };
            FlexEntry {
                id: plan.activities[fa.activity].id.clone(),
                start: be(fa.start),
                end: be(fa.end),
                condition: ConditionEntry {
                    after: fa.condition.after.iter().map(|b| bound(plan, b)).collect(),
                    within: fa.condition.within.iter().map(|b| bound(plan, b)).collect(),
                },
                controllable,
                waits,
                neighbours: fa
                    .neighbours
                    .iter()
                    .map(|&b| plan.activities[b].id.clone())
                    .collect(),
                free_slack: fa.free_slack.as_ref().map(set),
                free_slack_phase1: fa.free_slack_phase1.as_ref().map(set),
            }
        })
        .collect();
    let (acts, constraints) = match &flex.controllability {
        Controllability::NotControllable {
            activities,
            constraints,
        } => (
            activities
                .iter()
                .map(|&a| plan.activities[a].id.clone())
                .collect(),
            constraints.iter().map(|c| constraint(plan, c)).collect(),
        ),
        _ => (Vec::new(), Vec::new()),
    };
    FlexDoc {
        format: FLEX_FORMAT,
        plan: name.to_string(),
        summary: FlexSummary {
            placed: flex.activities.len(),
            network_edges: flex.network_edges,
            dispatchable_edges: flex.dispatchable.len(),
            controllability: status,
        },
        activities,
        dispatchable: flex
            .dispatchable
            .iter()
            .map(|e| EdgeEntry {
                from: point(plan, e.from),
                to: point(plan, e.to),
                max: e.max,
            })
            .collect(),
        controllability: ControllabilityEntry {
            status,
            activities: acts,
            constraints,
        },
    }
}
