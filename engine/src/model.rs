//! The plan model: a faithful, strict serde mirror of `solscope.plan/1`.
//!
//! These types hold exactly what the plan file says (numbers as written, ids as
//! strings). Validation beyond types lives in `io`; the scheduler works on a compiled
//! form (`scheduler::Problem`) with interned ids and fixed-point quantities.

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The value of `format` in every plan file.
pub const PLAN_FORMAT: &str = "solscope.plan/1";

/// Default length of a local day: one Mars sol, in seconds.
pub const MARS_SOL: i64 = 88775;

/// A whole plan, as read from a `solscope.plan/1` file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Must be [`PLAN_FORMAT`].
    pub format: String,
    /// Display name; the file name when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Plan bounds.
    pub horizon: Horizon,
    /// Mapping from plan time to local time of day.
    #[serde(default)]
    pub local_time: LocalTime,
    /// Battery limits.
    pub battery: Battery,
    /// Power generation and rover draw.
    pub power: Power,
    /// Wake/sleep rules.
    #[serde(default)]
    pub sleep: Sleep,
    /// Number of sequence engines; unlimited when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sequence_engines: Option<u32>,
    /// Onboard data storage.
    #[serde(default)]
    pub data: Data,
    /// Handover to the next plan (optional section).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub handover: Option<Handover>,
    /// Named state timelines.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub states: BTreeMap<String, StateDef>,
    /// Heated zones.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub thermal_zones: BTreeMap<String, ThermalZone>,
    /// The activities, in file order.
    pub activities: Vec<Activity>,
    /// When the onboard scheduler reruns during execution (execution extension).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub execution: Option<ExecutionSection>,
    /// What a scheduling cycle of an execution starts from; never read from or
    /// written to a file (`execute` builds each cycle's plan with it).
    #[serde(skip)]
    pub cycle: Option<CycleStart>,
}

/// What a scheduling cycle at `horizon.start` starts from besides the plan's own
/// fields (which the cycle's plan sets to the executed values): exact fixed-point
/// figures, the activities still executing, and the awake period and heaters
/// already on.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CycleStart {
    /// State of charge at the cycle (mJ), in place of `battery.initial`.
    pub soc_mj: i128,
    /// Onboard data volume at the cycle (bit), in place of `data.initial`.
    pub data_bit: i128,
    /// Data already produced towards `handover.max_data_volume` (bit).
    pub produced_bit: i128,
    /// Ids of the activities still executing: each is placed first, unchecked,
    /// at its first window's start for its fixed duration, generating nothing.
    pub held: Vec<String>,
    /// The awake period the rover is in, `(start, planned end)`: its start may
    /// lie before `horizon.start` (the wakeup is behind it).
    pub awake: Option<(i64, i64)>,
    /// Heaters on at the cycle, drawing until their planned end.
    pub heaters: Vec<HeaterHold>,
}

/// A heater on when a cycle starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HeaterHold {
    /// The zone.
    pub zone: String,
    /// Its planned end: it draws `power_mw` until then.
    pub end: i64,
    /// Heater power (mW).
    pub power_mw: i64,
    /// The activity whose preheat it is (not yet started). For that activity
    /// starting at `end` the preheat is this one; for the others the zone is on
    /// from the owner's step, as when the owner's preheat was generated. Without
    /// an owner (an activity keeping the zone warm ran into the second before the
    /// cycle) the zone is on from the start.
    pub owner: Option<String>,
}

impl Plan {
    /// This plan without its activities (every plan-wide field as it is, the
    /// cycle start included): cheaper than a clone where the activities are
    /// replaced anyway.
    pub fn without_activities(&self) -> Plan {
        Plan {
            format: self.format.clone(),
            name: self.name.clone(),
            horizon: self.horizon,
            local_time: self.local_time,
            battery: self.battery,
            power: self.power,
            sleep: self.sleep,
            sequence_engines: self.sequence_engines,
            data: self.data,
            handover: self.handover,
            states: self.states.clone(),
            thermal_zones: self.thermal_zones.clone(),
            activities: Vec::new(),
            execution: self.execution,
            cycle: self.cycle.clone(),
        }
    }

    /// Each activity's index in `activities`, by id (ids are unique in a
    /// loaded plan).
    pub(crate) fn index_by_id(&self) -> std::collections::BTreeMap<&str, usize> {
        self.activities
            .iter()
            .enumerate()
            .map(|(i, a)| (a.id.as_str(), i))
            .collect()
    }
}

/// The `execution` section: when scheduling cycles happen while the plan runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExecutionSection {
    /// Seconds between cycles, counted from `horizon.start`; one cycle only when
    /// absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub replan_period: Option<i64>,
    /// Also start a cycle whenever an executing activity ends.
    #[serde(default = "default_true")]
    pub replan_on_end: bool,
}

/// An activity's `duration_model`: the actual duration is an integer in
/// `[min, max]` (uniform when sampled).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DurationModel {
    /// Shortest actual duration (s).
    pub min: i64,
    /// Longest actual duration (s).
    pub max: i64,
}

/// Plan bounds `[start, end)` in plan seconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Horizon {
    /// First second of the plan.
    pub start: i64,
    /// End of the plan (exclusive).
    pub end: i64,
}

/// Local time of day, `(offset + t) mod sol_length`, and the sol number,
/// `first_sol + floor((offset + t) / sol_length)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LocalTime {
    /// Length of a local day in seconds.
    #[serde(default = "default_sol_length")]
    pub sol_length: i64,
    /// Local time of day at plan time 0.
    #[serde(default)]
    pub offset: i64,
    /// The number of the sol that holds plan time 0 (solscope's extension of the
    /// format; 0 when absent). It names sols in what solscope prints and
    /// changes nothing the scheduler decides.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_sol: Option<i64>,
}

fn default_sol_length() -> i64 {
    MARS_SOL
}

impl Default for LocalTime {
    fn default() -> Self {
        Self {
            sol_length: MARS_SOL,
            offset: 0,
            first_sol: None,
        }
    }
}

impl LocalTime {
    /// The sol number of plan time `t`: local midnights start sols, and the sol
    /// holding plan time 0 is `first_sol` (0 when absent).
    pub fn sol(&self, t: i64) -> i64 {
        let len = self.sol_length.max(1);
        let days = (self.offset.saturating_add(t)).div_euclid(len);
        self.first_sol.unwrap_or(0).saturating_add(days)
    }

    /// Local time of day (seconds after local midnight) of plan time `t`.
    pub fn time_of_day(&self, t: i64) -> i64 {
        let len = self.sol_length.max(1);
        (self.offset.saturating_add(t)).rem_euclid(len)
    }
}

/// Battery limits, in Wh.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Battery {
    /// Maximum state of charge.
    pub capacity: f64,
    /// State of charge at `horizon.start`.
    pub initial: f64,
    /// The state of charge may never go below this.
    pub min_soc: f64,
}

/// Power generation and rover draw, in W.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Power {
    /// Power generated continuously.
    pub rtg: f64,
    /// Rover draw while asleep.
    pub asleep: f64,
    /// Rover draw while awake.
    pub awake: f64,
    /// Limit on the total peak power; unlimited when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_peak: Option<f64>,
}

/// Wake/sleep rules, in seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sleep {
    /// Length of the wakeup at the start of every awake period.
    #[serde(default)]
    pub wakeup_duration: i64,
    /// Length of the shutdown at the end of every awake period.
    #[serde(default)]
    pub shutdown_duration: i64,
    /// Minimum length of an awake period (wakeup and shutdown included).
    #[serde(default)]
    pub min_awake: i64,
    /// Minimum length of a sleep between two awake periods.
    #[serde(default)]
    pub min_sleep: i64,
}

/// Onboard data storage, in Mbit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Data {
    /// Storage capacity; unlimited when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity: Option<f64>,
    /// Data volume at `horizon.start`.
    #[serde(default)]
    pub initial: f64,
}

/// Handover limits, which apply only when placing optional activities.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Handover {
    /// Time of the handover to the next plan.
    pub time: i64,
    /// Minimum state of charge at `time` (Wh).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_soc: Option<f64>,
    /// Maximum data produced between `horizon.start` and `time` (Mbit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_data_volume: Option<f64>,
}

/// A named state timeline.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateDef {
    /// Allowed values.
    pub values: Vec<String>,
    /// Value at `horizon.start`.
    pub initial: String,
}

/// A heated zone.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalZone {
    /// Preheat durations keyed by local time of day.
    pub preheat: Vec<PreheatEntry>,
    /// Heater power while preheating (W).
    pub preheat_power: f64,
    /// Heater power while maintaining an activity (W).
    pub maintenance_power: f64,
    /// Local-time periods in which a preheat may start; always when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub operable: Option<Vec<OperablePeriod>>,
}

/// One row of a preheat table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreheatEntry {
    /// Local time of day from which this row applies.
    pub from: i64,
    /// Preheat duration in seconds.
    pub duration: i64,
}

/// A local-time period `from <= tod <= to` (wrapping past midnight when `from > to`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperablePeriod {
    /// First local time of day of the period.
    pub from: i64,
    /// Last local time of day of the period (inclusive).
    pub to: i64,
}

/// One activity of the plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Activity {
    /// Unique identifier.
    pub id: String,
    /// Display name; the id when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Scheduling priority: smaller is scheduled earlier.
    pub priority: i64,
    /// Mandatory or optional.
    #[serde(default = "default_true")]
    pub mandatory: bool,
    /// Fixed or expanding duration.
    pub duration: Duration,
    /// Allowed start windows; the whole horizon when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub windows: Option<Vec<Window>>,
    /// Unit resources held while executing.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub resources: Vec<String>,
    /// Sequence engines held while executing.
    #[serde(default = "default_one")]
    pub sequence_engines: u32,
    /// Average power drawn while executing (W).
    #[serde(default)]
    pub energy_rate: f64,
    /// Peak power drawn while executing (W).
    #[serde(default)]
    pub peak_power: f64,
    /// Data produced while executing (Mbit/s); negative for a downlink.
    #[serde(default)]
    pub data_rate: f64,
    /// Whether the rover must be awake.
    #[serde(default)]
    pub awake: AwakeMode,
    /// Zones to preheat and maintain.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub thermal_zones: Vec<String>,
    /// Dependencies on other activities.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub after: Vec<Dependency>,
    /// State requirements over the whole activity.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub requires: Vec<StateRequirement>,
    /// State effects at the start or end.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<StateEffect>,
    /// Comm kinds this activity may overlap; all when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uhf_interactions: Option<Vec<String>>,
    /// Marks a communication activity of that kind.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub comm_kind: Option<String>,
    /// Single-selection group.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    /// The range of actual durations (execution extension; fixed durations only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_model: Option<DurationModel>,
    /// What completing the activity is worth to the planners (tuning extension;
    /// finite, `>= 0`). Only priority tuning reads it: scheduling and execution
    /// ignore it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
}

fn default_true() -> bool {
    true
}

fn default_one() -> u32 {
    1
}

impl Activity {
    /// The display name (the id when no name is given).
    pub fn display_name(&self) -> &str {
        self.name.as_deref().unwrap_or(&self.id)
    }
}

/// A fixed duration, or an expanding `{ "min": m, "max": M }` one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Duration {
    /// Exactly this many seconds.
    Fixed(i64),
    /// The longest feasible duration in `[min, max]`.
    Expanding {
        /// Shortest acceptable duration.
        min: i64,
        /// Longest wanted duration.
        max: i64,
    },
}

impl Duration {
    /// Shortest duration.
    pub fn min(&self) -> i64 {
        match *self {
            Duration::Fixed(d) => d,
            Duration::Expanding { min, .. } => min,
        }
    }

    /// Longest duration.
    pub fn max(&self) -> i64 {
        match *self {
            Duration::Fixed(d) => d,
            Duration::Expanding { max, .. } => max,
        }
    }
}

impl Serialize for Duration {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        match *self {
            Duration::Fixed(d) => serializer.serialize_i64(d),
            Duration::Expanding { min, max } => {
                let mut map = serializer.serialize_map(Some(2))?;
                map.serialize_entry("min", &min)?;
                map.serialize_entry("max", &max)?;
                map.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for Duration {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct DurationVisitor;

        impl<'de> Visitor<'de> for DurationVisitor {
            type Value = Duration;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(r#"an integer number of seconds or { "min": m, "max": M }"#)
            }

            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Duration, E> {
                Ok(Duration::Fixed(v))
            }

            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Duration, E> {
                i64::try_from(v)
                    .map(Duration::Fixed)
                    .map_err(|_| E::custom(format!("duration {v} is too large")))
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Duration, A::Error> {
                let mut min = None;
                let mut max = None;
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "min" if min.is_none() => min = Some(map.next_value::<i64>()?),
                        "max" if max.is_none() => max = Some(map.next_value::<i64>()?),
                        "min" | "max" => return Err(de::Error::duplicate_field("min/max")),
                        other => return Err(de::Error::unknown_field(other, &["min", "max"])),
                    }
                }
                match (min, max) {
                    (Some(min), Some(max)) => Ok(Duration::Expanding { min, max }),
                    (None, _) => Err(de::Error::missing_field("min")),
                    (_, None) => Err(de::Error::missing_field("max")),
                }
            }
        }

        deserializer.deserialize_any(DurationVisitor)
    }
}

/// An allowed start window.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Window {
    /// Earliest start (inclusive).
    pub start: i64,
    /// Latest start (inclusive).
    pub end: i64,
    /// Preferred start; `start` when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preferred: Option<i64>,
    /// Latest allowed end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff: Option<i64>,
}

impl Window {
    /// The preferred start, defaulting to `start`.
    pub fn preferred_start(&self) -> i64 {
        self.preferred.unwrap_or(self.start)
    }
}

/// Whether an activity needs the rover awake.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AwakeMode {
    /// Executes inside an awake period.
    #[default]
    Required,
    /// A manual sleep: no awake period may overlap it.
    Forbidden,
    /// Either.
    Any,
}

/// A dependency on another activity.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dependency {
    /// The activity that must be placed first.
    pub activity: String,
    /// Start exactly at its end.
    #[serde(default, skip_serializing_if = "is_false")]
    pub meets: bool,
    /// Lower bound on `start - other.end`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_delay: Option<i64>,
    /// Upper bound on `start - other.end`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_delay: Option<i64>,
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A state requirement: the state holds `value` over the whole activity.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateRequirement {
    /// State name.
    pub state: String,
    /// Required value.
    pub value: String,
}

/// A state effect: the state takes `value` at the activity's start or end.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateEffect {
    /// State name.
    pub state: String,
    /// New value.
    pub value: String,
    /// When the effect applies.
    #[serde(default)]
    pub at: EffectAt,
}

/// The point of an activity at which an effect applies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EffectAt {
    /// At the activity's start.
    Start,
    /// At the activity's end.
    #[default]
    End,
}
