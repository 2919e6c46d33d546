//! The `solscope.schedule/1` document.

use serde::Serialize;

use crate::load::LoadedPlan;
use crate::scheduler::{Generated, GeneratedKind, Profiles, Schedule};
use crate::units::watts;

/// `solscope.schedule/1` document; see the spec. Built by [`schedule_document`].
#[derive(Clone, Debug, Serialize)]
pub struct ScheduleDoc {
    /// Always `solscope.schedule/1`.
    pub format: &'static str,
    /// Plan name.
    pub plan: String,
    /// Every activity, in step order.
    pub activities: Vec<ActivityEntry>,
    /// Generated activities alive at the end: awake periods by start, then heating
    /// by zone and start.
    pub generated: Vec<GeneratedEntry>,
    /// Loader warnings, as `path: message`.
    pub warnings: Vec<String>,
    /// Resource profiles as breakpoints.
    pub profiles: Profiles,
}

/// One activity's outcome in a schedule document.
#[derive(Clone, Debug, Serialize)]
pub struct ActivityEntry {
    /// Activity id.
    pub id: String,
    /// `scheduled`, `failed` or `skipped`.
    pub status: &'static str,
    /// Its step.
    pub step: usize,
    /// Start, when scheduled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<i64>,
    /// End, when scheduled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end: Option<i64>,
}

/// One generated activity in a schedule document.
#[derive(Clone, Debug, Serialize)]
pub struct GeneratedEntry {
    /// `awake`, `preheat` or `maintenance`.
    pub kind: &'static str,
    /// Zone name (heating only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zone: Option<String>,
    /// The activity heated for (heating only).
    #[serde(rename = "for", skip_serializing_if = "Option::is_none")]
    pub for_activity: Option<String>,
    /// Start.
    pub start: i64,
    /// End.
    pub end: i64,
    /// Heater power in W (heating only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub power: Option<f64>,
    /// The step that created it (solscope addition).
    pub step: usize,
}

/// Builds the schedule document of a run.
pub fn schedule_document(
    loaded: &LoadedPlan,
    schedule: &Schedule,
    default_name: &str,
) -> ScheduleDoc {
    let plan = &loaded.plan;
    let problem = &schedule.problem;
    let activities = schedule
        .steps
        .iter()
        .map(|st| {
            let placement = st.outcome.placement();
            ActivityEntry {
                id: plan.activities[st.activity].id.clone(),
                status: st.outcome.status(),
                step: st.step,
                start: placement.map(|(start, _)| start),
                end: placement.map(|(_, end)| end),
            }
        })
        .collect();
    let last = schedule.steps.len();
    let mut alive: Vec<&Generated> = schedule.generated_after(last).collect();
    let key = |g: &Generated| match g.kind {
        GeneratedKind::Awake => (0, 0, g.start, 0, 0),
        GeneratedKind::Preheat { zone, activity } => (1, zone, g.start, 0, activity),
        GeneratedKind::Maintenance { zone, activity } => (1, zone, g.start, 1, activity),
    };
    alive.sort_by_key(|g| key(g));
    let generated = alive
        .into_iter()
        .map(|g| {
            let (kind, heat) = match g.kind {
                GeneratedKind::Awake => ("awake", None),
                GeneratedKind::Preheat { zone, activity } => ("preheat", Some((zone, activity))),
                GeneratedKind::Maintenance { zone, activity } => {
                    ("maintenance", Some((zone, activity)))
                }
            };
            GeneratedEntry {
                kind,
                zone: heat.map(|(z, _)| problem.zone_names[z].clone()),
                for_activity: heat.map(|(_, a)| plan.activities[a].id.clone()),
                start: g.start,
                end: g.end,
                power: heat.map(|_| watts(g.power_mw)),
                step: g.added_at,
            }
        })
        .collect();
    ScheduleDoc {
        format: "solscope.schedule/1",
        plan: plan
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string()),
        activities,
        generated,
        warnings: loaded.warnings.iter().map(ToString::to_string).collect(),
        profiles: schedule.profiles_after(last),
    }
}
