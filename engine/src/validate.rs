//! Semantic validation of plans (beyond what serde checks), with JSON paths.
//!
//! [`validate`] walks the plan in document order (the field order of
//! [`Plan`] and [`Activity`]) and stops at the first error, an
//! [`Error::Invalid`] whose `path` names the offending value exactly as
//! `serde_path_to_error` would (`activities[3].windows[0].end`) and whose `reason`
//! quotes the offending numbers (`must be >= start (got 120 < 300)`).
//! [`validate_all`] walks the same checks and goes on after an error, for a
//! view that lists every error of a plan (the app's repair view).
//!
//! # Errors
//!
//! - (`check_json_shape`, on the raw JSON) no array where an object is expected and
//!   no object where an enum string is expected: serde would accept both.
//! - `format` is `solscope.plan/1`.
//! - Times (`horizon`, `local_time.offset`, window `cutoff`s) lie within ±1e10 s;
//!   durations, delays and table/period entries are at most 1e10 s;
//!   `horizon.start < horizon.end` and the horizon is at most 1e9 s long;
//!   `local_time.sol_length > 0`; `local_time.first_sol` is at most 1e6 in
//!   magnitude.
//! - Every number is finite; powers and rates are at most 1e6 (W, Mbit/s) in
//!   magnitude, energies and data volumes at most 1e12 (Wh, Mbit).
//! - Battery: `capacity > 0`, `min_soc >= 0`, `0 <= initial <= capacity`.
//!   Power: `rtg`, `asleep`, `awake`, `max_peak >= 0`. Sleep durations `>= 0`.
//!   Data: `capacity >= 0`, `0 <= initial <= capacity`. Handover: `time` inside
//!   `[horizon.start, horizon.end]`, limits `>= 0`.
//! - States: at least one value, values unique, `initial` among the values.
//! - Thermal zones: a non-empty preheat table with an entry `from == 0`, every
//!   `from` in `[0, sol_length)` and unique (order is free), durations `>= 0`, heater
//!   powers `>= 0`; operable `from`/`to` in `[0, sol_length)`.
//! - Activities: ids non-empty and unique (reported at the second occurrence);
//!   duration `> 0`, or `0 < min <= max`; windows with `start <= end`, inside the
//!   horizon, `preferred` in `[start, end]`, `cutoff > start` (a cutoff may lie past
//!   `end` and past the horizon); `energy_rate`, `peak_power >= 0`; no duplicate
//!   resources or thermal zones; thermal zones, `after` targets and states/values of
//!   requirements and effects exist; no self-dependency; `meets: true` is not
//!   combined with `min_delay`/`max_delay`; delays are `>= 0` (an activity always
//!   starts at or after its dependency's end) and `min_delay <= max_delay`; at most
//!   one requirement per state and one effect per (state, `at`); `group` and
//!   `comm_kind` non-empty when given; `value` (tuning extension) finite, `>= 0`
//!   and at most 1e12.
//!
//! # Warnings
//!
//! Returned in path order of appearance:
//! - an optional activity comes before a mandatory one in step order (path
//!   `activities[i]`);
//! - a value is more precise than the fixed-point resolution (1 mW, 1 mJ, 1 bit,
//!   1 bit/s) and is rounded to its safe side, as the scheduler does (path of the
//!   value);
//! - `"windows": []`: the activity can never be scheduled (path
//!   `activities[i].windows`);
//! - an `after` entry names an activity that comes later in step order, so the
//!   activity can never be scheduled (path `activities[i].after[j]`);
//! - a requirement that neither the state's initial value nor an effect of any
//!   *other* activity can satisfy (an activity's own effects do not count for its
//!   own requirements) (path `activities[i].requires[j]`).

use std::collections::{BTreeMap, HashMap};

use std::fmt::Display;

use serde_json::Value;

use crate::error::{Error, Warning};
use crate::model::{
    Activity, Dependency, Duration, DurationModel, EffectAt, PLAN_FORMAT, Plan, StateDef,
    ThermalZone, Window,
};
use crate::units::{Fixed, Toward, to_fixed};

/// Most periodic scheduling cycles an `execution.replan_period` may give.
pub const MAX_CYCLES: i64 = 100_000;

/// Largest magnitude of any time (plan seconds), and of any duration or delay.
pub(crate) const MAX_TIME: i64 = 10_000_000_000;
/// Largest magnitude of `local_time.first_sol`.
pub(crate) const MAX_SOL_NUMBER: i64 = 1_000_000;
/// Longest allowed horizon, in seconds.
pub(crate) const MAX_HORIZON_LENGTH: i64 = 1_000_000_000;
/// Largest magnitude of a power (W) or data rate (Mbit/s).
pub(crate) const MAX_RATE: f64 = 1e6;
/// Largest magnitude of an energy (Wh) or data volume (Mbit).
pub(crate) const MAX_AMOUNT: f64 = 1e12;
/// Largest activity `value` (tuning extension): a sum of values in millionths
/// over millions of runs stays far inside an `i128`.
pub(crate) const MAX_VALUE: f64 = 1e12;

/// Checks a parsed plan; returns its warnings (in path order) or the first error.
pub fn validate(plan: &Plan) -> Result<Vec<Warning>, Error> {
    let mut v = Validator {
        plan,
        warnings: Vec::new(),
        errors: None,
    };
    v.plan()?;
    Ok(v.warnings)
}

/// The sections of plan-wide limits: no other check reads them (and they read
/// only the horizon besides, which an edit of them leaves as it was), so an edit
/// of these alone leaves the rest of a valid plan valid.
pub(crate) const LIMIT_SECTIONS: [&str; 5] = ["battery", "power", "sleep", "data", "handover"];

/// Checks only the [`LIMIT_SECTIONS`] of a plan whose other parts are known to be
/// valid (an edit of those sections of a valid plan): the first error, as
/// [`validate`] would report it.
pub(crate) fn validate_limits(plan: &Plan) -> Result<(), Error> {
    let mut v = Validator {
        plan,
        warnings: Vec::new(),
        errors: None,
    };
    v.battery()?;
    v.power()?;
    v.sleep()?;
    v.data()?;
    v.handover()
}

/// Every semantic error of a parsed plan, in document order (empty when it is
/// valid): what [`validate`] checks, going on after an error. Each check that
/// fails reports once and the checks that do not depend on it still run (the
/// rest of a window after its `start` failed does not; the next window does),
/// so the first error is the one [`validate`] returns. The checks that need a
/// valid horizon (the execution section's cycle count) are left out while the
/// horizon is invalid.
pub fn validate_all(plan: &Plan) -> Vec<Error> {
    let mut v = Validator {
        plan,
        warnings: Vec::new(),
        errors: Some(Vec::new()),
    };
    // In collecting mode every check's error is kept, so `plan` itself passes.
    let last = v.plan().err();
    let mut errors = v.errors.unwrap_or_default();
    errors.extend(last);
    errors
}

/// The plan's object-valued sections, in the model's field order.
const ROOT_OBJECTS: [&str; 8] = [
    "horizon",
    "local_time",
    "battery",
    "power",
    "sleep",
    "data",
    "handover",
    "execution",
];

/// Rejects JSON shapes that serde's derived impls would quietly accept although the
/// format does not allow them: an array where an object is expected (serde reads
/// `"horizon": [0, 10]` as a struct by field position) and an object where a
/// string-valued enum is expected (`"awake": { "any": null }`). Called by `load_plan`
/// on the raw JSON; walks it in the model's field order and returns the first
/// offending path.
pub(crate) fn check_json_shape(doc: &Value) -> Result<(), Error> {
    let Some(root) = object(doc, "")? else {
        return Ok(());
    };
    // In the field order of the model (Value maps are sorted by key).
    for key in ROOT_OBJECTS {
        if let Some(value) = root.get(key) {
            object(value, key)?;
        }
    }
    for key in ["states", "thermal_zones"] {
        let Some(Value::Object(named)) = root.get(key) else {
            continue;
        };
        for (name, def) in named {
            let path = format!("{key}.{name}");
            if let Some(def) = object(def, &path)?
                && key == "thermal_zones"
            {
                objects(def, &path, "preheat")?;
                objects(def, &path, "operable")?;
            }
        }
    }
    for (path, act) in objects(root, "", "activities")? {
        check_activity_shape(act, &path)?;
    }
    Ok(())
}

/// Whether [`check_json_shape`] could reject `text`: a streaming walk over the
/// same paths that flags any array or object where that check looks for one,
/// without building the document (the `Value` of a 10,000-activity plan costs
/// more than the rest of loading). `false` guarantees the check passes; `true`
/// (also for text that is not JSON, or nested too deeply) sends the caller to the
/// exact check, which names the path.
pub(crate) fn shape_may_fail(text: &str) -> bool {
    use serde::de::DeserializeSeed;
    let de = &mut serde_json::Deserializer::from_str(text);
    Walk(Ctx::Root).deserialize(&mut *de).is_err() || de.end().is_err()
}

/// Where [`Walk`] is: what the value there may be.
#[derive(Clone, Copy)]
enum Ctx {
    /// Anything (walked all the same: the walk must meet serde_json's nesting
    /// and number limits where the exact check's parse does).
    Any,
    /// The plan: an object.
    Root,
    /// Not an array; contents not looked at.
    NoArray,
    /// An array whose elements are in the given context.
    ArrayOf(Elem),
    /// `states` or `thermal_zones` (`true`): an object of definitions.
    Named(bool),
    /// A state (`false`) or zone (`true`) definition: not an array.
    Def(bool),
    /// An activity: not an array.
    Activity,
    /// An effect: not an array.
    Effect,
    /// Not an array and not an object (`awake`, `at`).
    Scalar,
}

/// What an array's elements may be (the contexts an array holds).
#[derive(Clone, Copy)]
enum Elem {
    /// Anything.
    Any,
    /// Not arrays.
    NoArray,
    /// Activities.
    Activity,
    /// Effects.
    Effect,
}

impl Elem {
    fn ctx(self) -> Ctx {
        match self {
            Elem::Any => Ctx::Any,
            Elem::NoArray => Ctx::NoArray,
            Elem::Activity => Ctx::Activity,
            Elem::Effect => Ctx::Effect,
        }
    }
}

/// The walk of [`shape_may_fail`]: fails (with a message nobody reads) where the
/// shape could be wrong.
struct Walk(Ctx);

fn suspect<E: serde::de::Error>() -> E {
    E::custom("shape to check")
}

impl<'de> serde::de::DeserializeSeed<'de> for Walk {
    type Value = ();

    fn deserialize<D: serde::Deserializer<'de>>(self, de: D) -> Result<(), D::Error> {
        de.deserialize_any(self)
    }
}

impl<'de> serde::de::Visitor<'de> for Walk {
    type Value = ();

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let elem = match self.0 {
            Ctx::ArrayOf(elem) => elem,
            Ctx::Any => Elem::Any,
            _ => return Err(suspect()),
        };
        while seq.next_element_seed(Walk(elem.ctx()))?.is_some() {}
        Ok(())
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key_seed(KeyName)? {
            let ctx = match (self.0, key) {
                (Ctx::Scalar, _) => return Err(suspect()),
                (Ctx::Root, Some("activities")) => Ctx::ArrayOf(Elem::Activity),
                (Ctx::Root, Some("states")) => Ctx::Named(false),
                (Ctx::Root, Some("thermal_zones")) => Ctx::Named(true),
                (Ctx::Root, Some(k)) if ROOT_OBJECTS.contains(&k) => Ctx::NoArray,
                (Ctx::Named(zones), _) => Ctx::Def(zones),
                (Ctx::Def(true), Some("preheat" | "operable")) => Ctx::ArrayOf(Elem::NoArray),
                (Ctx::Activity, Some("duration_model")) => Ctx::NoArray,
                (Ctx::Activity, Some("windows" | "after" | "requires")) => {
                    Ctx::ArrayOf(Elem::NoArray)
                }
                (Ctx::Activity, Some("effects")) => Ctx::ArrayOf(Elem::Effect),
                (Ctx::Activity, Some("awake")) | (Ctx::Effect, Some("at")) => Ctx::Scalar,
                _ => Ctx::Any,
            };
            map.next_value_seed(Walk(ctx))?;
        }
        Ok(())
    }
}

/// A map key, kept only when it is one the walk looks at (no allocation for the
/// others: borrowed from the input when it has no escapes).
struct KeyName;

/// The keys it looks at besides [`ROOT_OBJECTS`].
const KEYS: &[&str] = &[
    "activities",
    "states",
    "thermal_zones",
    "preheat",
    "operable",
    "duration_model",
    "windows",
    "after",
    "requires",
    "effects",
    "awake",
    "at",
];

impl<'de> serde::de::DeserializeSeed<'de> for KeyName {
    type Value = Option<&'static str>;

    fn deserialize<D: serde::Deserializer<'de>>(self, de: D) -> Result<Self::Value, D::Error> {
        de.deserialize_str(self)
    }
}

impl<'de> serde::de::Visitor<'de> for KeyName {
    type Value = Option<&'static str>;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a key")
    }

    fn visit_str<E>(self, v: &str) -> Result<Self::Value, E> {
        Ok(ROOT_OBJECTS.iter().chain(KEYS).find(|k| **k == v).copied())
    }
}

/// [`check_json_shape`] for one activity object at `path`.
pub(crate) fn check_activity_shape(act: &Object, path: &str) -> Result<(), Error> {
    if let Some(model) = act.get("duration_model") {
        object(model, &join(path, "duration_model"))?;
    }
    objects(act, path, "windows")?;
    string_enum(act, path, "awake")?;
    objects(act, path, "after")?;
    objects(act, path, "requires")?;
    for (epath, eff) in objects(act, path, "effects")? {
        string_enum(eff, &epath, "at")?;
    }
    Ok(())
}

type Object = serde_json::Map<String, Value>;

fn object<'a>(v: &'a Value, path: &str) -> Result<Option<&'a Object>, Error> {
    match v {
        Value::Array(_) => Err(invalid(
            if path.is_empty() { "$" } else { path },
            "invalid type: array, expected a JSON object",
        )),
        Value::Object(map) => Ok(Some(map)),
        _ => Ok(None), // serde reports other wrong types itself
    }
}
fn join(base: &str, key: &str) -> String {
    if base.is_empty() {
        key.to_string()
    } else {
        format!("{base}.{key}")
    }
}
/// Each element of an array field must be an object; returns them with paths.
fn objects<'a>(map: &'a Object, base: &str, key: &str) -> Result<Vec<(String, &'a Object)>, Error> {
    let mut out = Vec::new();
    if let Some(Value::Array(items)) = map.get(key) {
        for (i, item) in items.iter().enumerate() {
            let path = format!("{}[{i}]", join(base, key));
            if let Some(m) = object(item, &path)? {
                out.push((path, m));
            }
        }
    }
    Ok(out)
}
fn string_enum(map: &Object, base: &str, key: &str) -> Result<(), Error> {
    if let Some(v @ (Value::Object(_) | Value::Array(_))) = map.get(key) {
        let got = if v.is_object() { "object" } else { "array" };
        return Err(invalid(
            join(base, key),
            format!("invalid type: {got}, expected a string"),
        ));
    }
    Ok(())
}

/// The kind of a real-valued quantity: its unit, fixed-point scale and limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Quantity {
    /// W, stored as mW.
    Power,
    /// Wh, stored as mJ.
    Energy,
    /// Mbit, stored as bit.
    DataVolume,
    /// Mbit/s, stored as bit/s.
    DataRate,
}

impl Quantity {
    fn unit(self) -> &'static str {
        match self {
            Quantity::Power => "W",
            Quantity::Energy => "Wh",
            Quantity::DataVolume => "Mbit",
            Quantity::DataRate => "Mbit/s",
        }
    }

    fn internal_unit(self) -> &'static str {
        match self {
            Quantity::Power => "mW",
            Quantity::Energy => "mJ",
            Quantity::DataVolume => "bit",
            Quantity::DataRate => "bit/s",
        }
    }

    /// The fixed-point unit it is stored in.
    fn fixed(self) -> Fixed {
        match self {
            Quantity::Power => Fixed::MilliWatt,
            Quantity::Energy => Fixed::MilliJoule,
            Quantity::DataVolume | Quantity::DataRate => Fixed::Bit,
        }
    }

    /// Internal units per JSON unit.
    fn scale(self) -> f64 {
        match self {
            Quantity::Power => 1e3,
            Quantity::Energy => 3.6e6,
            Quantity::DataVolume | Quantity::DataRate => 1e6,
        }
    }

    fn resolution(self) -> &'static str {
        match self {
            Quantity::Power => "1 mW",
            Quantity::Energy => "1 mJ (1/3600000 Wh)",
            Quantity::DataVolume => "1 bit (1e-6 Mbit)",
            Quantity::DataRate => "1 bit/s (1e-6 Mbit/s)",
        }
    }

    fn max(self) -> f64 {
        match self {
            Quantity::Power | Quantity::DataRate => MAX_RATE,
            Quantity::Energy | Quantity::DataVolume => MAX_AMOUNT,
        }
    }
}

/// Which signs a number may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sign {
    Any,
    NonNegative,
    Positive,
}

/// An activity's `value` (tuning extension): finite, `>= 0`, at most
/// [`MAX_VALUE`]. Tuning sums it over runs in millionths (docs/semantics.md,
/// "Priority tuning"), so it carries no unit and no fixed-point warning.
fn activity_value(path: impl Display, x: f64) -> Result<(), Error> {
    if !x.is_finite() {
        return Err(invalid(
            path,
            format!("must be a finite number (got {})", short(x)),
        ));
    }
    if x < 0.0 {
        return Err(invalid(path, format!("must be >= 0 (got {})", short(x))));
    }
    if x > MAX_VALUE {
        return Err(invalid(
            path,
            format!("must be at most {MAX_VALUE} (got {})", short(x)),
        ));
    }
    Ok(())
}

fn invalid(path: impl Display, reason: impl Into<String>) -> Error {
    Error::invalid(path.to_string(), reason)
}

/// A number as a planner reads it: plain decimals, or scientific notation when
/// plain decimals would run longer than 20 characters (a denormal such as 5e-324
/// has hundreds of digits).
fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() > 20 {
        format!("{x:e}")
    } else {
        plain
    }
}

/// `a, b, c` for an error message listing the allowed names.
fn list<'a>(items: impl IntoIterator<Item = &'a String>) -> String {
    items
        .into_iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ")
}

fn at_name(at: EffectAt) -> &'static str {
    match at {
        EffectAt::Start => "start",
        EffectAt::End => "end",
    }
}

struct Validator<'p> {
    plan: &'p Plan,
    warnings: Vec<Warning>,
    /// `Some` when collecting every error ([`validate_all`]): a failed check is
    /// kept here and the next one runs; `None` stops at the first.
    errors: Option<Vec<Error>>,
}

impl<'p> Validator<'p> {
    /// Runs one check that the following ones do not depend on: its error
    /// stops the walk, or, when collecting, is kept and the walk goes on.
    fn part(&mut self, check: impl FnOnce(&mut Self) -> Result<(), Error>) -> Result<(), Error> {
        match (check(self), &mut self.errors) {
            (Err(e), Some(errors)) => {
                errors.push(e);
                Ok(())
            }
            (result, _) => result,
        }
    }

    fn warn(&mut self, path: impl Display, message: impl Into<String>) {
        self.warnings.push(Warning {
            path: path.to_string(),
            message: message.into(),
        });
    }

    // ----- primitive checks -------------------------------------------------

    /// A finite number of kind `q` with the given sign, within the magnitude limit;
    /// warns when it is finer than the fixed-point resolution, saying the value
    /// the scheduler uses: rounded `toward` its safe side.
    fn number(
        &mut self,
        path: impl Display,
        x: f64,
        q: Quantity,
        sign: Sign,
        toward: Toward,
    ) -> Result<(), Error> {
        if !x.is_finite() {
            return Err(invalid(
                path,
                format!("must be a finite number (got {})", short(x)),
            ));
        }
        match sign {
            Sign::NonNegative if x < 0.0 => {
                return Err(invalid(path, format!("must be >= 0 (got {})", short(x))));
            }
            Sign::Positive if x <= 0.0 => {
                return Err(invalid(path, format!("must be > 0 (got {})", short(x))));
            }
            _ => {}
        }
        if x.abs() > q.max() {
            return Err(invalid(
                path,
                format!(
                    "must be at most {} {} in magnitude (got {})",
                    q.max(),
                    q.unit(),
                    short(x)
                ),
            ));
        }
        // Exact when both sides agree; otherwise the scheduler takes `toward`
        // (docs/semantics.md, "Numbers"), and the warning says what it takes.
        let fixed = to_fixed(x, q.fixed(), toward);
        let other = match toward {
            Toward::Up => Toward::Down,
            Toward::Down => Toward::Up,
        };
        if fixed != to_fixed(x, q.fixed(), other) {
            // 7 mJ has no exact decimal in Wh: its shortest form may read as the
            // figure written; the internal unit then says what changed.
            let mut used = format!("{} {}", short(fixed as f64 / q.scale()), q.unit());
            if short(fixed as f64 / q.scale()) == short(x) {
                used = format!("{fixed} {}", q.internal_unit());
            }
            self.warn(
                path,
                format!(
                    "{} {unit} is more precise than {res} and is rounded {way} to {used} (the safe side)",
                    short(x),
                    unit = q.unit(),
                    res = q.resolution(),
                    way = match toward {
                        Toward::Up => "up",
                        Toward::Down => "down",
                    },
                ),
            );
        }
        Ok(())
    }

    /// A time of the plan: within ±[`MAX_TIME`].
    fn time(&self, path: impl Display, t: i64) -> Result<(), Error> {
        if !(-MAX_TIME..=MAX_TIME).contains(&t) {
            return Err(invalid(
                path,
                format!("must be between -{MAX_TIME} and {MAX_TIME} (got {t})"),
            ));
        }
        Ok(())
    }

    /// A duration or delay: `>= 0` (or `> 0`) and at most [`MAX_TIME`].
    fn length(&self, path: impl Display, d: i64, positive: bool) -> Result<(), Error> {
        if positive && d <= 0 {
            return Err(invalid(path, format!("must be > 0 (got {d})")));
        }
        if d < 0 {
            return Err(invalid(path, format!("must be >= 0 (got {d})")));
        }
        if d > MAX_TIME {
            return Err(invalid(
                path,
                format!("must be at most {MAX_TIME} s (got {d})"),
            ));
        }
        Ok(())
    }

    /// A local time of day: within `[0, sol_length)`.
    fn time_of_day(&self, path: impl Display, t: i64) -> Result<(), Error> {
        let len = self.plan.local_time.sol_length;
        if !(0..len).contains(&t) {
            return Err(invalid(
                path,
                format!("must be a local time of day in [0, {len}) (got {t})"),
            ));
        }
        Ok(())
    }

    fn non_empty(&self, path: impl Display, s: &str) -> Result<(), Error> {
        if s.trim().is_empty() {
            return Err(invalid(path, "must not be empty"));
        }
        Ok(())
    }

    // ----- the plan -----------------------------------------------------------

    fn plan(&mut self) -> Result<(), Error> {
        let plan = self.plan;
        self.part(|_| {
            if plan.format != PLAN_FORMAT {
                return Err(invalid(
                    "format",
                    format!("must be \"{PLAN_FORMAT}\" (got \"{}\")", plan.format),
                ));
            }
            Ok(())
        })?;
        let mut horizon_valid = true;
        self.part(|v| {
            let r = v.horizon();
            horizon_valid = r.is_ok();
            r
        })?;
        self.local_time()?;
        self.battery()?;
        self.power()?;
        self.sleep()?;
        self.data()?;
        self.handover()?;
        if horizon_valid {
            // Counts cycles over the horizon: only over a valid one.
            self.part(|v| v.execution())?;
        }
        for (name, def) in &plan.states {
            self.part(|v| v.state(name, def))?;
        }
        for (name, zone) in &plan.thermal_zones {
            self.zone(name, zone)?;
        }
        self.activities()
    }

    fn horizon(&self) -> Result<(), Error> {
        let h = self.plan.horizon;
        self.time("horizon.start", h.start)?;
        self.time("horizon.end", h.end)?;
        if h.start >= h.end {
            return Err(invalid(
                "horizon.end",
                format!("must be > start (got {} <= {})", h.end, h.start),
            ));
        }
        let len = h.end - h.start;
        if len > MAX_HORIZON_LENGTH {
            return Err(invalid(
                "horizon.end",
                format!("the horizon may be at most {MAX_HORIZON_LENGTH} s long (got {len} s)"),
            ));
        }
        Ok(())
    }

    fn local_time(&mut self) -> Result<(), Error> {
        let lt = self.plan.local_time;
        self.part(|v| v.length("local_time.sol_length", lt.sol_length, true))?;
        self.part(|v| v.time("local_time.offset", lt.offset))?;
        self.part(|_| match lt.first_sol {
            Some(n) if n.abs() > MAX_SOL_NUMBER => Err(invalid(
                "local_time.first_sol",
                format!("a sol number is at most {MAX_SOL_NUMBER} in magnitude (got {n})"),
            )),
            _ => Ok(()),
        })
    }

    fn battery(&mut self) -> Result<(), Error> {
        let b = self.plan.battery;
        self.part(|v| {
            v.number(
                "battery.capacity",
                b.capacity,
                Quantity::Energy,
                Sign::Positive,
                Toward::Down,
            )
        })?;
        self.part(|v| {
            v.number(
                "battery.initial",
                b.initial,
                Quantity::Energy,
                Sign::NonNegative,
                Toward::Down,
            )?;
            if b.initial > b.capacity {
                return Err(invalid(
                    "battery.initial",
                    format!(
                        "must be <= capacity (got {} > {})",
                        short(b.initial),
                        short(b.capacity)
                    ),
                ));
            }
            Ok(())
        })?;
        self.part(|v| {
            v.number(
                "battery.min_soc",
                b.min_soc,
                Quantity::Energy,
                Sign::NonNegative,
                Toward::Up,
            )
        })
    }

    fn power(&mut self) -> Result<(), Error> {
        let p = self.plan.power;
        self.part(|v| {
            v.number(
                "power.rtg",
                p.rtg,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Down,
            )
        })?;
        self.part(|v| {
            v.number(
                "power.asleep",
                p.asleep,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        self.part(|v| {
            v.number(
                "power.awake",
                p.awake,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        if let Some(max_peak) = p.max_peak {
            self.part(|v| {
                v.number(
                    "power.max_peak",
                    max_peak,
                    Quantity::Power,
                    Sign::NonNegative,
                    Toward::Down,
                )
            })?;
        }
        Ok(())
    }

    fn sleep(&mut self) -> Result<(), Error> {
        let s = self.plan.sleep;
        self.part(|v| v.length("sleep.wakeup_duration", s.wakeup_duration, false))?;
        self.part(|v| v.length("sleep.shutdown_duration", s.shutdown_duration, false))?;
        self.part(|v| v.length("sleep.min_awake", s.min_awake, false))?;
        self.part(|v| v.length("sleep.min_sleep", s.min_sleep, false))
    }

    fn data(&mut self) -> Result<(), Error> {
        let d = self.plan.data;
        if let Some(capacity) = d.capacity {
            self.part(|v| {
                v.number(
                    "data.capacity",
                    capacity,
                    Quantity::DataVolume,
                    Sign::NonNegative,
                    Toward::Down,
                )
            })?;
        }
        self.part(|v| {
            v.number(
                "data.initial",
                d.initial,
                Quantity::DataVolume,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        self.part(|_| match d.capacity {
            Some(capacity) if d.initial > capacity => Err(invalid(
                "data.initial",
                format!(
                    "must be <= capacity (got {} > {})",
                    short(d.initial),
                    short(capacity)
                ),
            )),
            _ => Ok(()),
        })
    }

    fn handover(&mut self) -> Result<(), Error> {
        let Some(h) = self.plan.handover else {
            return Ok(());
        };
        let hz = self.plan.horizon;
        self.part(|_| {
            if h.time < hz.start || h.time > hz.end {
                return Err(invalid(
                    "handover.time",
                    format!(
                        "must be inside the horizon [{}, {}] (got {})",
                        hz.start, hz.end, h.time
                    ),
                ));
            }
            Ok(())
        })?;
        if let Some(min_soc) = h.min_soc {
            self.part(|v| {
                v.number(
                    "handover.min_soc",
                    min_soc,
                    Quantity::Energy,
                    Sign::NonNegative,
                    Toward::Up,
                )
            })?;
        }
        if let Some(max) = h.max_data_volume {
            self.part(|v| {
                v.number(
                    "handover.max_data_volume",
                    max,
                    Quantity::DataVolume,
                    Sign::NonNegative,
                    Toward::Down,
                )
            })?;
        }
        Ok(())
    }

    fn state(&self, name: &str, def: &StateDef) -> Result<(), Error> {
        let base = format!("states.{name}");
        if def.values.is_empty() {
            return Err(invalid(
                format!("{base}.values"),
                "must list at least one value",
            ));
        }
        let mut seen: HashMap<&str, usize> = HashMap::new();
        for (i, value) in def.values.iter().enumerate() {
            if let Some(first) = seen.insert(value.as_str(), i) {
                return Err(invalid(
                    format!("{base}.values[{i}]"),
                    format!("duplicate value \"{value}\" (first at {base}.values[{first}])"),
                ));
            }
        }
        if !def.values.contains(&def.initial) {
            return Err(invalid(
                format!("{base}.initial"),
                format!(
                    "unknown value \"{}\" for state \"{name}\" (allowed: {})",
                    def.initial,
                    list(&def.values)
                ),
            ));
        }
        Ok(())
    }

    fn zone(&mut self, name: &str, zone: &ThermalZone) -> Result<(), Error> {
        let base = format!("thermal_zones.{name}");
        self.part(|v| v.preheat_table(&base, zone))?;
        self.part(|v| {
            v.number(
                format_args!("{base}.preheat_power"),
                zone.preheat_power,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        self.part(|v| {
            v.number(
                format_args!("{base}.maintenance_power"),
                zone.maintenance_power,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        for (i, period) in zone.operable.iter().flatten().enumerate() {
            let path = format!("{base}.operable[{i}]");
            self.part(|v| {
                v.time_of_day(format_args!("{path}.from"), period.from)?;
                v.time_of_day(format_args!("{path}.to"), period.to)
            })?;
        }
        Ok(())
    }

    /// A zone's preheat table: rows with distinct `from`s in the sol, one of
    /// them 0.
    fn preheat_table(&self, base: &str, zone: &ThermalZone) -> Result<(), Error> {
        if zone.preheat.is_empty() {
            return Err(invalid(
                format!("{base}.preheat"),
                "must have at least one entry (one with from 0)",
            ));
        }
        let mut seen: HashMap<i64, usize> = HashMap::new();
        for (i, entry) in zone.preheat.iter().enumerate() {
            let path = format!("{base}.preheat[{i}]");
            self.time_of_day(format_args!("{path}.from"), entry.from)?;
            if let Some(first) = seen.insert(entry.from, i) {
                return Err(invalid(
                    format!("{path}.from"),
                    format!(
                        "duplicate from {} (first at {base}.preheat[{first}])",
                        entry.from
                    ),
                ));
            }
            self.length(format_args!("{path}.duration"), entry.duration, false)?;
        }
        if !seen.contains_key(&0) {
            return Err(invalid(
                format!("{base}.preheat"),
                "must have an entry with from 0",
            ));
        }
        Ok(())
    }

    // ----- activities ---------------------------------------------------------

    fn activities(&mut self) -> Result<(), Error> {
        let ctx = ActivityContext::of(&self.plan.activities);
        let acts = &self.plan.activities;
        for (i, a) in acts.iter().enumerate() {
            self.activity(i, a, &ctx)?;
        }
        Ok(())
    }

    fn activity(&mut self, i: usize, a: &Activity, ctx: &ActivityContext<'_>) -> Result<(), Error> {
        let base = format!("activities[{i}]");
        let id = a.id.as_str();

        // id
        self.part(|v| {
            v.non_empty(format_args!("{base}.id"), id)?;
            if let Some(&f) = ctx.first.get(id)
                && f != i
            {
                return Err(invalid(
                    format!("{base}.id"),
                    format!("duplicate id \"{id}\" (first at activities[{f}])"),
                ));
            }
            Ok(())
        })?;

        // step-order warning: optional before mandatory
        if !a.mandatory {
            let later_mandatory = ctx.next_mandatory[ctx.step[i]];
            debug_assert_eq!(
                later_mandatory,
                ctx.order[ctx.step[i]..]
                    .iter()
                    .copied()
                    .find(|&j| self.plan.activities[j].mandatory),
                "next mandatory shortcut"
            );
            if let Some(j) = later_mandatory {
                let other = &self.plan.activities[j];
                self.warn(
                    base.clone(),
                    format!(
                        "optional activity \"{id}\" (step {}, priority {}) comes before \
                         mandatory activity \"{}\" (step {}, priority {}) in step order and \
                         may take what the mandatory one needs",
                        ctx.step[i], a.priority, other.id, ctx.step[j], other.priority
                    ),
                );
            }
        }

        self.part(|v| {
            v.duration(&base, a.duration)?;
            if let Some(m) = a.duration_model {
                v.duration_model(&base, a.duration, m)?;
            }
            Ok(())
        })?;
        if a.windows.as_ref().is_some_and(Vec::is_empty) {
            self.warn(
                format_args!("{base}.windows"),
                format!(
                    "\"{id}\" has an empty list of windows, so it can never be scheduled \
                     (leave out \"windows\" to allow the whole horizon)"
                ),
            );
        }
        for (w, window) in a.windows.iter().flatten().enumerate() {
            self.part(|v| v.window(format_args!("{base}.windows[{w}]"), window))?;
        }
        self.part(|_| unique_names(format_args!("{base}.resources"), &a.resources, "resource"))?;
        self.part(|v| {
            v.number(
                format_args!("{base}.energy_rate"),
                a.energy_rate,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        self.part(|v| {
            v.number(
                format_args!("{base}.peak_power"),
                a.peak_power,
                Quantity::Power,
                Sign::NonNegative,
                Toward::Up,
            )
        })?;
        self.part(|v| {
            v.number(
                format_args!("{base}.data_rate"),
                a.data_rate,
                Quantity::DataRate,
                Sign::Any,
                Toward::Up,
            )
        })?;

        // thermal zones
        for (z, zone) in a.thermal_zones.iter().enumerate() {
            self.part(|v| {
                if !v.plan.thermal_zones.contains_key(zone) {
                    return Err(invalid(
                        format!("{base}.thermal_zones[{z}]"),
                        format!(
                            "unknown thermal zone \"{zone}\" ({})",
                            known(v.plan.thermal_zones.keys(), "thermal zones")
                        ),
                    ));
                }
                Ok(())
            })?;
        }
        self.part(|_| {
            unique_names(
                format_args!("{base}.thermal_zones"),
                &a.thermal_zones,
                "thermal zone",
            )
        })?;

        // dependencies
        for (d, dep) in a.after.iter().enumerate() {
            self.part(|v| v.dependency(format_args!("{base}.after[{d}]"), i, a, dep, ctx))?;
        }

        // requirements
        let mut required: HashMap<&str, usize> = HashMap::new();
        for (r, req) in a.requires.iter().enumerate() {
            let path = format!("{base}.requires[{r}]");
            self.part(|v| {
                let def = v.state_value(&path, &req.state, &req.value)?;
                if let Some(f) = required.insert(req.state.as_str(), r) {
                    return Err(invalid(
                        path,
                        format!(
                            "duplicate requirement on state \"{}\" (first at {base}.requires[{f}]); \
                             at most one per state",
                            req.state
                        ),
                    ));
                }
                let by_other = ctx
                    .setters
                    .get(&(req.state.as_str(), req.value.as_str()))
                    .is_some_and(|who| who.iter().any(|&j| j != i));
                if def.initial != req.value && !by_other {
                    v.warn(
                        path,
                        format!(
                            "state \"{}\" is never \"{}\": it is not the initial value and no \
                             other activity has an effect setting it, so \"{id}\" can never be \
                             scheduled",
                            req.state, req.value
                        ),
                    );
                }
                Ok(())
            })?;
        }

        // effects
        let mut effected: BTreeMap<(&str, EffectAt), usize> = BTreeMap::new();
        for (e, eff) in a.effects.iter().enumerate() {
            let path = format!("{base}.effects[{e}]");
            self.part(|v| {
                v.state_value(&path, &eff.state, &eff.value)?;
                if let Some(f) = effected.insert((eff.state.as_str(), eff.at), e) {
                    return Err(invalid(
                        path,
                        format!(
                            "duplicate effect on state \"{}\" at \"{}\" (first at {base}.effects[{f}])",
                            eff.state,
                            at_name(eff.at)
                        ),
                    ));
                }
                Ok(())
            })?;
        }

        if let Some(kind) = &a.comm_kind {
            self.part(|v| v.non_empty(format_args!("{base}.comm_kind"), kind))?;
        }
        if let Some(group) = &a.group {
            self.part(|v| v.non_empty(format_args!("{base}.group"), group))?;
        }
        if let Some(value) = a.value {
            self.part(|_| activity_value(format_args!("{base}.value"), value))?;
        }
        Ok(())
    }

    fn duration(&self, base: &str, d: Duration) -> Result<(), Error> {
        match d {
            Duration::Fixed(d) => self.length(format_args!("{base}.duration"), d, true),
            Duration::Expanding { min, max } => {
                self.length(format_args!("{base}.duration.min"), min, true)?;
                if max < min {
                    return Err(invalid(
                        format!("{base}.duration.max"),
                        format!("must be >= min (got {max} < {min})"),
                    ));
                }
                self.length(format_args!("{base}.duration.max"), max, true)
            }
        }
    }

    /// An activity's `duration_model` (execution extension): fixed durations only,
    /// `0 < min <= max`.
    fn duration_model(&self, base: &str, d: Duration, m: DurationModel) -> Result<(), Error> {
        if let Duration::Expanding { .. } = d {
            return Err(invalid(
                format!("{base}.duration_model"),
                "an expanding activity cannot have a duration_model (the scheduler picks its duration)",
            ));
        }
        self.length(format_args!("{base}.duration_model.min"), m.min, true)?;
        if m.max < m.min {
            return Err(invalid(
                format!("{base}.duration_model.max"),
                format!("must be >= min (got {} < {})", m.max, m.min),
            ));
        }
        self.length(format_args!("{base}.duration_model.max"), m.max, true)
    }

    /// The `execution` section: a replan period, when given, is positive and
    /// gives at most [`MAX_CYCLES`] periodic cycles over the horizon (each cycle
    /// reschedules the plan: an execution's time must stay bounded).
    fn execution(&self) -> Result<(), Error> {
        if let Some(p) = self.plan.execution.and_then(|e| e.replan_period) {
            self.length("execution.replan_period", p, true)?;
            let h = self.plan.horizon;
            let cycles = (h.end - h.start - 1) / p + 1;
            if cycles > MAX_CYCLES {
                return Err(invalid(
                    "execution.replan_period",
                    format!(
                        "gives {cycles} cycles over the horizon; at most {MAX_CYCLES} (a period of at least {} s)",
                        (h.end - h.start + MAX_CYCLES - 1) / MAX_CYCLES
                    ),
                ));
            }
        }
        Ok(())
    }

    fn window(&self, path: impl Display, w: &Window) -> Result<(), Error> {
        let h = self.plan.horizon;
        if w.start < h.start {
            return Err(invalid(
                format!("{path}.start"),
                format!("must be >= horizon.start (got {} < {})", w.start, h.start),
            ));
        }
        if w.end < w.start {
            return Err(invalid(
                format!("{path}.end"),
                format!("must be >= start (got {} < {})", w.end, w.start),
            ));
        }
        if w.end > h.end {
            return Err(invalid(
                format!("{path}.end"),
                format!("must be <= horizon.end (got {} > {})", w.end, h.end),
            ));
        }
        if let Some(p) = w.preferred
            && (p < w.start || p > w.end)
        {
            return Err(invalid(
                format!("{path}.preferred"),
                format!(
                    "must be within the window [{}, {}] (got {p})",
                    w.start, w.end
                ),
            ));
        }
        if let Some(c) = w.cutoff {
            let cpath = format!("{path}.cutoff");
            if c <= w.start {
                return Err(invalid(
                    cpath,
                    format!("must be > start (got {c} <= {})", w.start),
                ));
            }
            self.time(&cpath, c)?;
        }
        Ok(())
    }

    fn dependency(
        &mut self,
        path: impl Display,
        i: usize,
        a: &Activity,
        dep: &Dependency,
        ctx: &ActivityContext<'_>,
    ) -> Result<(), Error> {
        let target = dep.activity.as_str();
        let Some(&j) = ctx.first.get(target) else {
            return Err(invalid(
                format!("{path}.activity"),
                format!("unknown activity \"{target}\""),
            ));
        };
        if target == a.id {
            return Err(invalid(
                format!("{path}.activity"),
                format!("activity \"{target}\" cannot depend on itself"),
            ));
        }
        if dep.meets {
            for (field, value) in [("min_delay", dep.min_delay), ("max_delay", dep.max_delay)] {
                if value.is_some() {
                    return Err(invalid(
                        format!("{path}.{field}"),
                        "cannot be combined with \"meets\": true",
                    ));
                }
            }
        }
        if let Some(min) = dep.min_delay {
            self.length(format_args!("{path}.min_delay"), min, false)?;
        }
        if let Some(max) = dep.max_delay {
            self.length(format_args!("{path}.max_delay"), max, false)?;
            if let Some(min) = dep.min_delay
                && max < min
            {
                return Err(invalid(
                    format!("{path}.max_delay"),
                    format!("must be >= min_delay (got {max} < {min})"),
                ));
            }
        }
        if ctx.step[j] > ctx.step[i] {
            self.warn(
                path,
                format!(
                    "depends on \"{target}\" (step {}), which comes later in step order than \
                     \"{}\" (step {}), so \"{}\" can never be scheduled",
                    ctx.step[j], a.id, ctx.step[i], a.id
                ),
            );
        }
        Ok(())
    }

    /// Checks that `state` exists and `value` is one of its values.
    fn state_value(
        &self,
        path: impl Display,
        state: &str,
        value: &str,
    ) -> Result<&'p StateDef, Error> {
        let Some(def) = self.plan.states.get(state) else {
            return Err(invalid(
                format!("{path}.state"),
                format!(
                    "unknown state \"{state}\" ({})",
                    known(self.plan.states.keys(), "states")
                ),
            ));
        };
        if !def.values.iter().any(|v| v == value) {
            return Err(invalid(
                format!("{path}.value"),
                format!(
                    "unknown value \"{value}\" for state \"{state}\" (allowed: {})",
                    list(&def.values)
                ),
            ));
        }
        Ok(def)
    }
}

/// Precomputed facts about all activities.
struct ActivityContext<'p> {
    /// Index of the first activity with each id.
    first: HashMap<&'p str, usize>,
    /// Activity indices in step order.
    order: Vec<usize>,
    /// 1-based step of each activity index.
    step: Vec<usize>,
    /// Per step position `k` (0-based): the first mandatory activity at or after
    /// it in step order.
    next_mandatory: Vec<Option<usize>>,
    /// Activities with an effect setting each (state, value).
    setters: HashMap<(&'p str, &'p str), Vec<usize>>,
}

impl<'p> ActivityContext<'p> {
    fn of(acts: &'p [Activity]) -> Self {
        // First occurrence of every id, so that `after` may name later activities
        // and a duplicate is reported where it occurs.
        let mut first: HashMap<&str, usize> = HashMap::new();
        for (i, a) in acts.iter().enumerate() {
            first.entry(a.id.as_str()).or_insert(i);
        }
        // Step order: by (priority, file index); step[i] is 1-based.
        let mut order: Vec<usize> = (0..acts.len()).collect();
        order.sort_by_key(|&i| (acts[i].priority, i));
        let mut step = vec![0usize; acts.len()];
        for (k, &i) in order.iter().enumerate() {
            step[i] = k + 1;
        }
        // Which activities set each (state, value).
        let mut setters: HashMap<(&str, &str), Vec<usize>> = HashMap::new();
        for (i, a) in acts.iter().enumerate() {
            for e in &a.effects {
                setters
                    .entry((e.state.as_str(), e.value.as_str()))
                    .or_default()
                    .push(i);
            }
        }
        // One pass from the end instead of a scan per optional activity (which
        // took most of the load time of a 200,000-activity plan).
        let mut next_mandatory = vec![None; order.len() + 1];
        for k in (0..order.len()).rev() {
            next_mandatory[k] = if acts[order[k]].mandatory {
                Some(order[k])
            } else {
                next_mandatory[k + 1]
            };
        }
        ActivityContext {
            first,
            order,
            step,
            next_mandatory,
            setters,
        }
    }
}

/// The checks of one activity of a valid plan, for edits of it that keep its
/// id. Another activity's checks read this one only for its id (its priority,
/// effects and `mandatory` only for warnings), so with the id kept they still
/// pass, and the edited plan is valid exactly when the edited activity passes
/// its own checks in the plan's context. The suggestion verifier checks
/// thousands of edits of one activity each (debug builds compare with
/// [`validate`]).
pub(crate) struct ActivityEdits<'p> {
    plan: &'p Plan,
    ctx: ActivityContext<'p>,
}

impl<'p> ActivityEdits<'p> {
    /// The context of `plan`'s activities, built once.
    pub(crate) fn new(plan: &'p Plan) -> Self {
        Self {
            plan,
            ctx: ActivityContext::of(&plan.activities),
        }
    }

    /// Whether `plan` with activity `i` replaced by `a` (the same id) is valid,
    /// as [`validate`] would say: its first error, if any.
    pub(crate) fn check(&self, i: usize, a: &Activity) -> Result<(), Error> {
        debug_assert_eq!(
            self.plan.activities.get(i).map(|x| x.id.as_str()),
            Some(a.id.as_str()),
            "not an edit that keeps the id"
        );
        let mut v = Validator {
            plan: self.plan,
            warnings: Vec::new(),
            errors: None,
        };
        v.activity(i, a, &self.ctx)
    }
}

/// `known: a, b` or `the plan defines no <what>`.
fn known<'a>(names: impl Iterator<Item = &'a String>, what: &str) -> String {
    let names: Vec<&String> = names.collect();
    if names.is_empty() {
        format!("the plan defines no {what}")
    } else {
        format!("known: {}", list(names))
    }
}

/// Rejects a repeated name in a list, at its second occurrence.
fn unique_names(path: impl Display, names: &[String], what: &str) -> Result<(), Error> {
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    for (k, name) in names.iter().enumerate() {
        if let Some(f) = seen.insert(name.as_str(), k) {
            return Err(invalid(
                format!("{path}[{k}]"),
                format!("duplicate {what} \"{name}\" (first at {path}[{f}])"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{Value, json};

    /// A small valid plan exercising every section; no warnings.
    fn base_json() -> Value {
        json!({
            "format": "solscope.plan/1",
            "horizon": { "start": 0, "end": 88775 },
            "local_time": { "sol_length": 88775, "offset": 0 },
            "battery": { "capacity": 1600.0, "initial": 1200.0, "min_soc": 500.0 },
            "power": { "rtg": 110.0, "asleep": 25.0, "awake": 190.0, "max_peak": 900.0 },
            "sleep": { "wakeup_duration": 300, "shutdown_duration": 300, "min_awake": 1800, "min_sleep": 3600 },
            "sequence_engines": 3,
            "data": { "capacity": 8000.0, "initial": 0.0 },
            "handover": { "time": 86000, "min_soc": 900.0, "max_data_volume": 4000.0 },
            "states": { "drill": { "values": ["stowed", "deployed"], "initial": "stowed" } },
            "thermal_zones": { "arm": {
                "preheat": [ { "from": 0, "duration": 3600 }, { "from": 36000, "duration": 1200 } ],
                "preheat_power": 45.0, "maintenance_power": 15.0,
                "operable": [ { "from": 25200, "to": 61200 } ] } },
            "activities": [
                { "id": "unstow", "priority": 1, "duration": 600,
                  "windows": [ { "start": 30000, "end": 40000, "preferred": 35000, "cutoff": 45000 } ],
                  "resources": ["arm"], "thermal_zones": ["arm"], "energy_rate": 40.0,
                  "requires": [ { "state": "drill", "value": "stowed" } ],
                  "effects": [ { "state": "drill", "value": "deployed", "at": "end" } ] },
                { "id": "drill", "priority": 2, "duration": { "min": 600, "max": 2400 },
                  "resources": ["arm", "drill"], "peak_power": 220.0, "data_rate": -0.5,
                  "after": [ { "activity": "unstow", "min_delay": 0, "max_delay": 600 } ],
                  "requires": [ { "state": "drill", "value": "deployed" } ],
                  "effects": [ { "state": "drill", "value": "stowed", "at": "start" },
                               { "state": "drill", "value": "stowed", "at": "end" } ],
                  "comm_kind": "uhf", "group": "g" },
                { "id": "pano", "priority": 3, "mandatory": false, "duration": 100,
                  "after": [ { "activity": "drill", "meets": true } ] }
            ]
        })
    }

    fn push(array: &mut Value, item: Value) {
        array.as_array_mut().expect("an array").push(item);
    }

    fn parse(v: Value) -> Plan {
        serde_json::from_value(v).expect("test plan parses")
    }

    fn with(edit: impl FnOnce(&mut Value)) -> Plan {
        let mut v = base_json();
        edit(&mut v);
        parse(v)
    }

    /// The error of a plan, as `(path, reason)`; `validate_all` leads with it.
    fn err(plan: &Plan) -> (String, String) {
        let all = validate_all(plan);
        match validate(plan) {
            Err(Error::Invalid { path, reason }) => {
                assert_eq!(
                    all.first().map(ToString::to_string),
                    Some(format!("{path}: {reason}")),
                    "validate_all starts with validate's error"
                );
                (path, reason)
            }
            other => panic!("expected an Invalid error, got {other:?}"),
        }
    }

    fn paths(errors: &[Error]) -> Vec<String> {
        errors
            .iter()
            .map(|e| match e {
                Error::Invalid { path, .. } => path.clone(),
                other => panic!("expected Invalid errors, got {other:?}"),
            })
            .collect()
    }

    #[test]
    fn validate_all_lists_every_error_in_document_order() {
        assert!(validate_all(&parse(base_json())).is_empty());
        let plan = with(|v| {
            v["battery"]["initial"] = json!(2000.0);
            v["battery"]["min_soc"] = json!(-1.0);
            v["power"]["rtg"] = json!(-5.0);
            v["states"]["drill"]["initial"] = json!("lost");
            v["thermal_zones"]["arm"]["preheat_power"] = json!(-1.0);
            v["activities"][0]["windows"] = json!([
                { "start": 300, "end": 120 },
                { "start": 400, "end": 500, "preferred": 900 }
            ]);
            v["activities"][0]["energy_rate"] = json!(-40.0);
            v["activities"][0]["thermal_zones"] = json!(["mast"]);
            v["activities"][1]["after"] = json!([{ "activity": "nobody" }]);
            v["activities"][1]["requires"] = json!([{ "state": "drill", "value": "gone" }]);
            v["activities"][2]["id"] = json!("unstow");
            v["activities"][2]["duration"] = json!(0);
        });
        let all = validate_all(&plan);
        assert_eq!(
            paths(&all),
            [
                "battery.initial",
                "battery.min_soc",
                "power.rtg",
                "states.drill.initial",
                "thermal_zones.arm.preheat_power",
                "activities[0].windows[0].end",
                "activities[0].windows[1].preferred",
                "activities[0].energy_rate",
                "activities[0].thermal_zones[0]",
                "activities[1].after[0].activity",
                "activities[1].requires[0].value",
                "activities[2].id",
                "activities[2].duration",
            ]
        );
        assert_eq!(
            all[0].to_string(),
            validate(&plan).expect_err("invalid").to_string()
        );
        assert!(
            all[5]
                .to_string()
                .contains("must be >= start (got 120 < 300)")
        );
    }

    #[test]
    fn validate_all_skips_what_needs_a_valid_horizon() {
        // An inverted horizon of extreme times: no cycle count (it would
        // overflow), every other check still runs.
        let plan = with(|v| {
            v["horizon"] = json!({ "start": i64::MAX, "end": i64::MIN });
            v["execution"] = json!({ "replan_period": 1 });
            v["sleep"]["min_sleep"] = json!(-1);
        });
        let all = paths(&validate_all(&plan));
        assert_eq!(all[..2], ["horizon.start", "sleep.min_sleep"]);
        assert!(!all.iter().any(|p| p.starts_with("execution")), "{all:?}");
        assert!(all.len() > 2, "the activities are still checked: {all:?}");
    }

    fn assert_err(edit: impl FnOnce(&mut Value), path: &str, fragment: &str) {
        let (p, reason) = err(&with(edit));
        assert_eq!(p, path, "reason was: {reason}");
        assert!(
            reason.contains(fragment),
            "reason {reason:?} does not contain {fragment:?}"
        );
    }

    fn warnings(edit: impl FnOnce(&mut Value)) -> Vec<Warning> {
        validate(&with(edit)).expect("plan is valid")
    }

    #[test]
    fn base_plan_is_valid_without_warnings() {
        assert_eq!(validate(&parse(base_json())).unwrap(), vec![]);
    }

    #[test]
    fn spec_example_error_format() {
        let (p, r) = err(&with(|v| {
            v["activities"][0]["windows"][0] = json!({ "start": 300, "end": 120 });
        }));
        assert_eq!(
            format!("{p}: {r}"),
            "activities[0].windows[0].end: must be >= start (got 120 < 300)"
        );
    }

    #[test]
    fn format_string() {
        assert_err(
            |v| v["format"] = json!("solscope.plan/2"),
            "format",
            "solscope.plan/1",
        );
    }

    #[test]
    fn horizon() {
        assert_err(
            |v| v["horizon"] = json!({ "start": 10, "end": 10 }),
            "horizon.end",
            "must be > start (got 10 <= 10)",
        );
        assert_err(
            |v| v["horizon"] = json!({ "start": 10, "end": 5 }),
            "horizon.end",
            "got 5 <= 10",
        );
        assert_err(
            |v| v["horizon"]["start"] = json!(-20_000_000_000i64),
            "horizon.start",
            "between",
        );
        assert_err(
            |v| v["horizon"]["end"] = json!(20_000_000_000i64),
            "horizon.end",
            "between",
        );
        assert_err(
            |v| v["horizon"] = json!({ "start": -1_000_000_000, "end": 1 }),
            "horizon.end",
            "at most 1000000000 s long (got 1000000001 s)",
        );
        // exactly 1e9 long is fine
        let plan = with(|v| {
            v["horizon"] = json!({ "start": 0, "end": 1_000_000_000 });
            v["handover"]["time"] = json!(1000);
        });
        assert!(validate(&plan).is_ok());
    }

    #[test]
    fn local_time() {
        assert_err(
            |v| v["local_time"]["sol_length"] = json!(0),
            "local_time.sol_length",
            "must be > 0 (got 0)",
        );
        assert_err(
            |v| v["local_time"]["sol_length"] = json!(-5),
            "local_time.sol_length",
            "must be > 0",
        );
        assert_err(
            |v| v["local_time"]["offset"] = json!(20_000_000_000i64),
            "local_time.offset",
            "between",
        );
    }

    #[test]
    fn battery() {
        assert_err(
            |v| v["battery"]["capacity"] = json!(0.0),
            "battery.capacity",
            "must be > 0 (got 0)",
        );
        assert_err(
            |v| v["battery"]["initial"] = json!(-1.0),
            "battery.initial",
            "must be >= 0 (got -1)",
        );
        assert_err(
            |v| v["battery"]["initial"] = json!(1700.0),
            "battery.initial",
            "must be <= capacity (got 1700 > 1600)",
        );
        assert_err(
            |v| v["battery"]["min_soc"] = json!(-0.5),
            "battery.min_soc",
            "must be >= 0",
        );
        assert_err(
            |v| v["battery"]["capacity"] = json!(2e12),
            "battery.capacity",
            "at most 1000000000000 Wh",
        );
    }

    #[test]
    fn non_finite_numbers_are_rejected() {
        // JSON cannot carry them, but a Plan built in code can.
        let mut plan = parse(base_json());
        plan.battery.capacity = f64::NAN;
        assert_eq!(
            err(&plan),
            (
                "battery.capacity".into(),
                "must be a finite number (got NaN)".into()
            )
        );
        let mut plan = parse(base_json());
        plan.activities[1].data_rate = f64::NEG_INFINITY;
        assert_eq!(err(&plan).0, "activities[1].data_rate");
        let mut plan = parse(base_json());
        plan.power.rtg = f64::INFINITY;
        assert_eq!(
            err(&plan),
            (
                "power.rtg".into(),
                "must be a finite number (got inf)".into()
            )
        );
    }

    #[test]
    fn power() {
        assert_err(
            |v| v["power"]["rtg"] = json!(-1.0),
            "power.rtg",
            "must be >= 0",
        );
        assert_err(
            |v| v["power"]["asleep"] = json!(-1.0),
            "power.asleep",
            "must be >= 0",
        );
        assert_err(
            |v| v["power"]["awake"] = json!(-1.0),
            "power.awake",
            "must be >= 0",
        );
        assert_err(
            |v| v["power"]["max_peak"] = json!(-1.0),
            "power.max_peak",
            "must be >= 0",
        );
        assert_err(
            |v| v["power"]["awake"] = json!(1.5e6),
            "power.awake",
            "at most 1000000 W in magnitude (got 1500000)",
        );
    }

    #[test]
    fn sleep() {
        for f in [
            "wakeup_duration",
            "shutdown_duration",
            "min_awake",
            "min_sleep",
        ] {
            assert_err(
                |v| v["sleep"][f] = json!(-1),
                &format!("sleep.{f}"),
                "must be >= 0 (got -1)",
            );
        }
        assert_err(
            |v| v["sleep"]["min_sleep"] = json!(20_000_000_000i64),
            "sleep.min_sleep",
            "at most",
        );
    }

    #[test]
    fn data() {
        assert_err(
            |v| v["data"]["capacity"] = json!(-1.0),
            "data.capacity",
            "must be >= 0",
        );
        assert_err(
            |v| v["data"]["initial"] = json!(-1.0),
            "data.initial",
            "must be >= 0",
        );
        assert_err(
            |v| v["data"]["initial"] = json!(9000.0),
            "data.initial",
            "must be <= capacity (got 9000 > 8000)",
        );
        // no capacity: unlimited
        let plan = with(|v| v["data"] = json!({ "initial": 9000.0 }));
        assert!(validate(&plan).is_ok());
    }

    #[test]
    fn handover() {
        assert_err(
            |v| v["handover"]["time"] = json!(90000),
            "handover.time",
            "inside the horizon [0, 88775] (got 90000)",
        );
        assert_err(
            |v| v["handover"]["time"] = json!(-1),
            "handover.time",
            "inside the horizon",
        );
        assert_err(
            |v| v["handover"]["min_soc"] = json!(-1.0),
            "handover.min_soc",
            "must be >= 0",
        );
        assert_err(
            |v| v["handover"]["max_data_volume"] = json!(-1.0),
            "handover.max_data_volume",
            "must be >= 0",
        );
        // the horizon end itself is allowed
        assert!(validate(&with(|v| v["handover"]["time"] = json!(88775))).is_ok());
    }

    #[test]
    fn states() {
        assert_err(
            |v| v["states"]["drill"]["values"] = json!([]),
            "states.drill.values",
            "at least one value",
        );
        assert_err(
            |v| v["states"]["drill"]["values"] = json!(["stowed", "deployed", "stowed"]),
            "states.drill.values[2]",
            "duplicate value \"stowed\" (first at states.drill.values[0])",
        );
        assert_err(
            |v| v["states"]["drill"]["initial"] = json!("open"),
            "states.drill.initial",
            "unknown value \"open\" for state \"drill\" (allowed: stowed, deployed)",
        );
    }

    #[test]
    fn thermal_zones() {
        let z = "thermal_zones.arm";
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat"] = json!([]),
            &format!("{z}.preheat"),
            "at least one entry",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat"] = json!([{ "from": 100, "duration": 10 }]),
            &format!("{z}.preheat"),
            "entry with from 0",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat"][1]["from"] = json!(88775),
            &format!("{z}.preheat[1].from"),
            "[0, 88775) (got 88775)",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat"][1]["from"] = json!(-1),
            &format!("{z}.preheat[1].from"),
            "got -1",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat"] = json!([{ "from": 0, "duration": 1 }, { "from": 500, "duration": 2 }, { "from": 500, "duration": 3 }]),
            &format!("{z}.preheat[2].from"),
            "duplicate from 500 (first at thermal_zones.arm.preheat[1])",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat"][0]["duration"] = json!(-1),
            &format!("{z}.preheat[0].duration"),
            "must be >= 0",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["preheat_power"] = json!(-1.0),
            &format!("{z}.preheat_power"),
            ">= 0",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["maintenance_power"] = json!(-1.0),
            &format!("{z}.maintenance_power"),
            ">= 0",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["operable"][0]["to"] = json!(88775),
            &format!("{z}.operable[0].to"),
            "got 88775",
        );
        assert_err(
            |v| v["thermal_zones"]["arm"]["operable"][0]["from"] = json!(-3),
            &format!("{z}.operable[0].from"),
            "got -3",
        );
        // unsorted tables and wrapping periods are fine
        let plan = with(|v| {
            v["thermal_zones"]["arm"]["preheat"] =
                json!([{ "from": 500, "duration": 2 }, { "from": 0, "duration": 1 }]);
            v["thermal_zones"]["arm"]["operable"] = json!([{ "from": 80000, "to": 1000 }]);
        });
        assert!(validate(&plan).is_ok());
    }

    #[test]
    fn activity_ids() {
        assert_err(
            |v| v["activities"][2]["id"] = json!("unstow"),
            "activities[2].id",
            "duplicate id \"unstow\" (first at activities[0])",
        );
        assert_err(
            |v| v["activities"][0]["id"] = json!(""),
            "activities[0].id",
            "must not be empty",
        );
    }

    #[test]
    fn durations() {
        assert_err(
            |v| v["activities"][0]["duration"] = json!(0),
            "activities[0].duration",
            "must be > 0 (got 0)",
        );
        assert_err(
            |v| v["activities"][0]["duration"] = json!(-5),
            "activities[0].duration",
            "must be > 0 (got -5)",
        );
        assert_err(
            |v| v["activities"][0]["duration"] = json!(20_000_000_000i64),
            "activities[0].duration",
            "at most",
        );
        assert_err(
            |v| v["activities"][1]["duration"] = json!({ "min": 0, "max": 10 }),
            "activities[1].duration.min",
            "must be > 0",
        );
        assert_err(
            |v| v["activities"][1]["duration"] = json!({ "min": 10, "max": 5 }),
            "activities[1].duration.max",
            "must be >= min (got 5 < 10)",
        );
        // min == max is fine
        assert!(
            validate(&with(
                |v| v["activities"][1]["duration"] = json!({ "min": 10, "max": 10 })
            ))
            .is_ok()
        );
    }

    #[test]
    fn windows() {
        let w = "activities[0].windows[0]";
        assert_err(
            |v| v["activities"][0]["windows"][0]["start"] = json!(-1),
            &format!("{w}.start"),
            "must be >= horizon.start (got -1 < 0)",
        );
        assert_err(
            |v| v["activities"][0]["windows"][0]["end"] = json!(88776),
            &format!("{w}.end"),
            "must be <= horizon.end (got 88776 > 88775)",
        );
        assert_err(
            |v| v["activities"][0]["windows"][0]["preferred"] = json!(29999),
            &format!("{w}.preferred"),
            "within the window [30000, 40000] (got 29999)",
        );
        assert_err(
            |v| v["activities"][0]["windows"][0]["preferred"] = json!(40001),
            &format!("{w}.preferred"),
            "got 40001",
        );
        assert_err(
            |v| v["activities"][0]["windows"][0]["cutoff"] = json!(30000),
            &format!("{w}.cutoff"),
            "must be > start (got 30000 <= 30000)",
        );
        assert_err(
            |v| v["activities"][0]["windows"][0]["cutoff"] = json!(20_000_000_000i64),
            &format!("{w}.cutoff"),
            "between",
        );
        // a second window is checked too
        assert_err(
            |v| {
                push(
                    &mut v["activities"][0]["windows"],
                    json!({ "start": 10, "end": 5 }),
                )
            },
            "activities[0].windows[1].end",
            "got 5 < 10",
        );
        // cutoff after end and past the horizon; start == end; preferred at the bounds
        let plan = with(|v| {
            v["activities"][0]["windows"] = json!([
                { "start": 88000, "end": 88775, "cutoff": 90000, "preferred": 88775 },
                { "start": 100, "end": 100, "preferred": 100 }
            ]);
        });
        assert!(validate(&plan).is_ok());
    }

    #[test]
    fn activity_numbers() {
        assert_err(
            |v| v["activities"][0]["energy_rate"] = json!(-1.0),
            "activities[0].energy_rate",
            "must be >= 0 (got -1)",
        );
        assert_err(
            |v| v["activities"][0]["peak_power"] = json!(-1.0),
            "activities[0].peak_power",
            "must be >= 0",
        );
        assert_err(
            |v| v["activities"][0]["data_rate"] = json!(2e6),
            "activities[0].data_rate",
            "at most 1000000 Mbit/s",
        );
        assert_err(
            |v| v["activities"][0]["data_rate"] = json!(-2e6),
            "activities[0].data_rate",
            "in magnitude",
        );
    }

    #[test]
    fn activity_value() {
        assert_err(
            |v| v["activities"][0]["value"] = json!(-0.5),
            "activities[0].value",
            "must be >= 0 (got -0.5)",
        );
        assert_err(
            |v| v["activities"][0]["value"] = json!(2e12),
            "activities[0].value",
            "must be at most 1000000000000",
        );
        let mut plan = with(|v| v["activities"][0]["value"] = json!(1.0));
        plan.activities[0].value = Some(f64::NAN);
        assert_eq!(
            err(&plan),
            (
                "activities[0].value".into(),
                "must be a finite number (got NaN)".into()
            )
        );
        // Zero is a value (nothing gained), and absent stays absent on save.
        let plan = with(|v| v["activities"][0]["value"] = json!(0.0));
        assert!(validate(&plan).is_ok_and(|w| w.is_empty()));
        let back: Value = serde_json::to_value(&plan).expect("json");
        assert_eq!(back["activities"][0]["value"], json!(0.0));
        let plain = parse(base_json());
        let back: Value = serde_json::to_value(&plain).expect("json");
        assert!(back["activities"][0].get("value").is_none());
    }

    #[test]
    fn resources_and_zones() {
        assert_err(
            |v| v["activities"][1]["resources"] = json!(["arm", "drill", "arm"]),
            "activities[1].resources[2]",
            "duplicate resource \"arm\" (first at activities[1].resources[0])",
        );
        assert_err(
            |v| v["activities"][0]["thermal_zones"] = json!(["mast"]),
            "activities[0].thermal_zones[0]",
            "unknown thermal zone \"mast\" (known: arm)",
        );
        assert_err(
            |v| v["activities"][0]["thermal_zones"] = json!(["arm", "arm"]),
            "activities[0].thermal_zones[1]",
            "duplicate thermal zone \"arm\"",
        );
        assert_err(
            |v| {
                v["thermal_zones"] = json!({});
            },
            "activities[0].thermal_zones[0]",
            "the plan defines no thermal zones",
        );
    }

    #[test]
    fn dependencies() {
        let d = "activities[1].after[0]";
        assert_err(
            |v| v["activities"][1]["after"][0]["activity"] = json!("nope"),
            &format!("{d}.activity"),
            "unknown activity \"nope\"",
        );
        assert_err(
            |v| v["activities"][1]["after"][0]["activity"] = json!("drill"),
            &format!("{d}.activity"),
            "cannot depend on itself",
        );
        assert_err(
            |v| v["activities"][1]["after"][0]["meets"] = json!(true),
            &format!("{d}.min_delay"),
            "cannot be combined with \"meets\": true",
        );
        assert_err(
            |v| {
                v["activities"][1]["after"][0] =
                    json!({ "activity": "unstow", "meets": true, "max_delay": 5 })
            },
            &format!("{d}.max_delay"),
            "meets",
        );
        assert_err(
            |v| v["activities"][1]["after"][0]["min_delay"] = json!(-1),
            &format!("{d}.min_delay"),
            "must be >= 0 (got -1)",
        );
        assert_err(
            |v| v["activities"][1]["after"][0]["max_delay"] = json!(-1),
            &format!("{d}.max_delay"),
            "must be >= 0 (got -1)",
        );
        assert_err(
            |v| {
                v["activities"][1]["after"][0] =
                    json!({ "activity": "unstow", "min_delay": 700, "max_delay": 600 })
            },
            &format!("{d}.max_delay"),
            "must be >= min_delay (got 600 < 700)",
        );
        // meets: false with delays is fine
        assert!(
            validate(&with(
                |v| v["activities"][1]["after"][0]["meets"] = json!(false)
            ))
            .is_ok()
        );
    }

    #[test]
    fn requirements_and_effects() {
        assert_err(
            |v| v["activities"][0]["requires"][0]["state"] = json!("mast"),
            "activities[0].requires[0].state",
            "unknown state \"mast\" (known: drill)",
        );
        assert_err(
            |v| v["activities"][0]["requires"][0]["value"] = json!("open"),
            "activities[0].requires[0].value",
            "unknown value \"open\" for state \"drill\" (allowed: stowed, deployed)",
        );
        assert_err(
            |v| {
                push(
                    &mut v["activities"][0]["requires"],
                    json!({ "state": "drill", "value": "stowed" }),
                )
            },
            "activities[0].requires[1]",
            "duplicate requirement on state \"drill\" (first at activities[0].requires[0])",
        );
        assert_err(
            |v| v["activities"][0]["effects"][0]["value"] = json!("open"),
            "activities[0].effects[0].value",
            "unknown value \"open\"",
        );
        assert_err(
            |v| v["activities"][0]["effects"][0]["state"] = json!("mast"),
            "activities[0].effects[0].state",
            "unknown state \"mast\"",
        );
        assert_err(
            |v| v["activities"][1]["effects"][0]["at"] = json!("end"),
            "activities[1].effects[1]",
            "duplicate effect on state \"drill\" at \"end\" (first at activities[1].effects[0])",
        );
        // the default `at` is end
        assert_err(
            |v| {
                push(
                    &mut v["activities"][0]["effects"],
                    json!({ "state": "drill", "value": "stowed" }),
                )
            },
            "activities[0].effects[1]",
            "at \"end\"",
        );
        assert_err(
            |v| {
                v["states"] = json!({});
                v["activities"][0]["requires"] = json!([]);
            },
            "activities[0].effects[0].state",
            "the plan defines no states",
        );
    }

    #[test]
    fn group_and_comm_kind() {
        assert_err(
            |v| v["activities"][1]["group"] = json!(""),
            "activities[1].group",
            "must not be empty",
        );
        assert_err(
            |v| v["activities"][1]["comm_kind"] = json!(" "),
            "activities[1].comm_kind",
            "must not be empty",
        );
    }

    #[test]
    fn first_error_in_document_order() {
        // A duplicate id at activities[2] does not hide an earlier window error.
        let plan = with(|v| {
            v["activities"][2]["id"] = json!("unstow");
            v["activities"][1]["windows"] = json!([{ "start": 5, "end": 1 }]);
        });
        assert_eq!(err(&plan).0, "activities[1].windows[0].end");
    }

    #[test]
    fn warns_optional_before_mandatory() {
        let w = warnings(|v| v["activities"][0]["mandatory"] = json!(false));
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].path, "activities[0]");
        assert!(
            w[0].message
                .contains("optional activity \"unstow\" (step 1"),
            "{}",
            w[0].message
        );
        assert!(
            w[0].message
                .contains("mandatory activity \"drill\" (step 2"),
            "{}",
            w[0].message
        );
        // an optional activity after every mandatory one is fine (pano in the base plan)
        assert!(warnings(|_| {}).is_empty());
        // step order uses priority, then file index
        let w = warnings(|v| {
            v["activities"][2]["priority"] = json!(0);
            v["activities"][2]["after"] = json!([]);
        });
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].path, "activities[2]");
        assert!(
            w[0].message.contains("(step 1, priority 0)"),
            "{}",
            w[0].message
        );
        // equal priorities: file order decides
        let w = warnings(|v| {
            v["activities"][2]["priority"] = json!(1);
            v["activities"][2]["after"] = json!([]);
        });
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].message.contains("(step 2, priority 1)"),
            "{}",
            w[0].message
        );
    }

    #[test]
    fn warns_dependency_on_later_activity() {
        let w = warnings(|v| v["activities"][0]["priority"] = json!(3));
        // unstow is now step 2 (priority ties go by file index), after drill (step 1)
        // which depends on it.
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].path, "activities[1].after[0]");
        assert!(
            w[0].message.contains("depends on \"unstow\" (step 2)"),
            "{}",
            w[0].message
        );
        assert!(
            w[0].message.contains("\"drill\" can never be scheduled"),
            "{}",
            w[0].message
        );
    }

    #[test]
    fn warns_unsatisfiable_requirement() {
        let w = warnings(|v| {
            v["activities"][0]["effects"] = json!([]);
        });
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].path, "activities[1].requires[0]");
        assert!(
            w[0].message
                .contains("state \"drill\" is never \"deployed\""),
            "{}",
            w[0].message
        );
        // only its own effect sets the value: still unsatisfiable
        let w = warnings(|v| {
            v["activities"][0]["effects"] = json!([]);
            v["activities"][1]["effects"] =
                json!([{ "state": "drill", "value": "deployed", "at": "start" }]);
        });
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].path, "activities[1].requires[0]");
        // the initial value satisfies it
        let w = warnings(|v| {
            v["activities"][0]["effects"] = json!([]);
            v["states"]["drill"]["initial"] = json!("deployed");
        });
        assert!(
            w.iter().all(|w| w.path != "activities[1].requires[0]"),
            "{w:?}"
        );
    }

    #[test]
    fn warns_empty_windows() {
        let w = warnings(|v| v["activities"][0]["windows"] = json!([]));
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].path, "activities[0].windows");
        assert!(
            w[0].message.contains("can never be scheduled"),
            "{}",
            w[0].message
        );
    }

    #[test]
    fn the_warning_names_the_value_the_scheduler_uses() {
        // Every figure finer than its resolution, in both directions from it.
        for fine in [0.0004, 0.0006] {
            let plan = with(|v| {
                for (section, field) in [
                    ("battery", "capacity"),
                    ("battery", "initial"),
                    ("battery", "min_soc"),
                    ("power", "rtg"),
                    ("power", "asleep"),
                    ("power", "awake"),
                    ("power", "max_peak"),
                    ("data", "capacity"),
                    ("data", "initial"),
                    ("handover", "min_soc"),
                    ("handover", "max_data_volume"),
                ] {
                    let x = v[section][field].as_f64().expect("a number");
                    v[section][field] = json!(x + fine / 1e3);
                }
                let zone = &mut v["thermal_zones"]["arm"];
                zone["preheat_power"] = json!(45.0 + fine);
                zone["maintenance_power"] = json!(15.0 + fine);
                let act = &mut v["activities"][1];
                act["energy_rate"] = json!(fine);
                act["peak_power"] = json!(220.0 + fine);
                act["data_rate"] = json!(-0.5 - fine / 1e3);
            });
            let warnings = validate(&plan).expect("valid");
            let p = crate::scheduler::Problem::compile(&plan).expect("compiles");
            let (act, zone) = (&p.acts[1], &p.zones[0]);
            let used: [(&str, i128, f64); 16] = [
                ("battery.capacity", p.capacity, 3.6e6),
                ("battery.initial", p.soc0, 3.6e6),
                ("battery.min_soc", p.min_soc, 3.6e6),
                ("power.rtg", p.rtg.into(), 1e3),
                ("power.asleep", p.asleep.into(), 1e3),
                ("power.awake", p.awake.into(), 1e3),
                ("power.max_peak", p.max_peak.unwrap_or(0).into(), 1e3),
                ("data.capacity", p.data_cap.unwrap_or(0), 1e6),
                ("data.initial", p.data0, 1e6),
                ("handover.min_soc", p.handover_soc.unwrap_or(0), 3.6e6),
                (
                    "handover.max_data_volume",
                    p.handover_data.unwrap_or(0),
                    1e6,
                ),
                ("thermal_zones.arm.preheat_power", zone.preheat.into(), 1e3),
                (
                    "thermal_zones.arm.maintenance_power",
                    zone.maintenance.into(),
                    1e3,
                ),
                ("activities[1].energy_rate", act.energy.into(), 1e3),
                ("activities[1].peak_power", act.peak.into(), 1e3),
                ("activities[1].data_rate", act.data.into(), 1e6),
            ];
            for (path, fixed, scale) in used {
                let w = warnings
                    .iter()
                    .find(|w| w.path == path)
                    .unwrap_or_else(|| panic!("no warning at {path}: {warnings:?}"));
                let mut said = w.message.split(" to ").nth(1).unwrap_or("").split(' ');
                let value = said.next().and_then(|x| x.parse::<f64>().ok());
                let value = value.unwrap_or_else(|| panic!("no value in {w}"));
                let internal = ["mW", "mJ", "bit", "bit/s"].contains(&said.next().unwrap_or(""));
                let value = if internal { value } else { value * scale };
                assert_eq!(value.round() as i128, fixed, "{w}");
            }
        }
    }

    #[test]
    fn comparisons_print_short_numbers() {
        assert_err(
            |v| {
                v["battery"]["capacity"] = json!(5e-324);
                v["battery"]["initial"] = json!(1e-323);
            },
            "battery.initial",
            "must be <= capacity (got 1e-323 > 5e-324)",
        );
        assert_err(
            |v| {
                v["data"]["capacity"] = json!(5e-324);
                v["data"]["initial"] = json!(1e-323);
            },
            "data.initial",
            "must be <= capacity (got 1e-323 > 5e-324)",
        );
    }

    #[test]
    fn denormal_values_print_short() {
        let w = warnings(|v| v["activities"][0]["energy_rate"] = json!(5e-324));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].message.starts_with("5e-324 W is more precise"),
            "{}",
            w[0].message
        );
        assert!(w[0].message.len() < 100, "{}", w[0].message);
    }

    #[test]
    fn warns_rounded_values() {
        let w = warnings(|v| {
            v["power"]["rtg"] = json!(110.0004);
            v["activities"][0]["energy_rate"] = json!(40.0015);
            v["activities"][1]["data_rate"] = json!(-0.0000005);
            v["battery"]["initial"] = json!(1200.0000001);
            v["data"]["initial"] = json!(1.23456789);
        });
        let paths: Vec<&str> = w.iter().map(|w| w.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "battery.initial",
                "power.rtg",
                "data.initial",
                "activities[0].energy_rate",
                "activities[1].data_rate"
            ]
        );
        assert!(
            w[1].message
                .contains("110.0004 W is more precise than 1 mW and is rounded down to 110 W"),
            "{}",
            w[1].message
        );
        assert!(
            w[2].message.contains("rounded up to 1.234568 Mbit"),
            "{}",
            w[2].message
        );
        assert!(
            w[3].message.contains("rounded up to 40.002 W"),
            "{}",
            w[3].message
        );
        assert!(w[4].message.contains("1 bit/s"), "{}", w[4].message);
        // values exactly on the resolution do not warn
        let w = warnings(|v| {
            v["power"]["rtg"] = json!(110.001);
            v["battery"]["initial"] = json!(0.1);
            v["activities"][1]["data_rate"] = json!(0.000001);
            v["data"]["initial"] = json!(1234.567891);
            v["activities"][0]["peak_power"] = json!(999999.999);
        });
        assert!(w.is_empty(), "{w:?}");
        // 7 mJ has no exact decimal in Wh: its shortest decimal is a little less,
        // rounded up to 7 mJ, said in mJ since it prints the same in Wh.
        let w = warnings(|v| v["battery"]["min_soc"] = json!(1.0 / 3.6e6 * 7.0));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].message
                .ends_with("is rounded up to 7 mJ (the safe side)"),
            "{}",
            w[0].message
        );
    }

    #[test]
    fn warnings_in_path_order() {
        let w = warnings(|v| {
            v["activities"][0]["mandatory"] = json!(false);
            v["activities"][0]["energy_rate"] = json!(1.0001);
            v["activities"][0]["effects"] = json!([]);
            v["activities"][2]["priority"] = json!(0);
            v["battery"]["min_soc"] = json!(0.0000001);
        });
        let paths: Vec<&str> = w.iter().map(|w| w.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "battery.min_soc",
                "activities[0]",
                "activities[0].energy_rate",
                "activities[1].requires[0]",
                "activities[2]",
                "activities[2].after[0]"
            ]
        );
    }

    fn load_err(text: &str) -> (String, String) {
        match crate::load::load_plan(text) {
            Err(Error::Invalid { path, reason }) => (path, reason),
            other => panic!("expected an Invalid error, got {other:?}"),
        }
    }

    fn shape_err(edit: impl FnOnce(&mut Value)) -> (String, String) {
        let mut v = base_json();
        edit(&mut v);
        load_err(&v.to_string())
    }

    #[test]
    fn shape_rejects_arrays_for_objects() {
        // (JSON pointer of the value to replace, replacement, expected path)
        let cases = [
            ("/horizon", json!([0, 88775]), "horizon"),
            ("/battery", json!([1600.0, 1200.0, 500.0]), "battery"),
            ("/handover", json!([86000]), "handover"),
            (
                "/states/drill",
                json!([["stowed"], "stowed"]),
                "states.drill",
            ),
            (
                "/thermal_zones/arm/preheat/1",
                json!([36000, 1200]),
                "thermal_zones.arm.preheat[1]",
            ),
            (
                "/thermal_zones/arm/operable/0",
                json!([1, 2]),
                "thermal_zones.arm.operable[0]",
            ),
            (
                "/activities/2",
                json!(["x", null, 1, true, 10]),
                "activities[2]",
            ),
            (
                "/activities/0/windows/0",
                json!([30000, 40000]),
                "activities[0].windows[0]",
            ),
            (
                "/activities/1/after/0",
                json!(["unstow"]),
                "activities[1].after[0]",
            ),
            (
                "/activities/0/requires/0",
                json!(["drill", "stowed"]),
                "activities[0].requires[0]",
            ),
            (
                "/activities/0/effects/0",
                json!(["drill", "deployed", "end"]),
                "activities[0].effects[0]",
            ),
        ];
        for (pointer, replacement, path) in cases {
            let (p, r) =
                shape_err(|v| *v.pointer_mut(pointer).expect("pointer exists") = replacement);
            assert_eq!(p, path);
            assert_eq!(r, "invalid type: array, expected a JSON object");
        }
        let (p, r) = load_err(&format!("[{}]", base_json()));
        assert_eq!(
            (p.as_str(), r.as_str()),
            ("$", "invalid type: array, expected a JSON object")
        );
    }

    #[test]
    fn shape_rejects_objects_for_enums() {
        let (p, r) = shape_err(|v| v["activities"][2]["awake"] = json!({ "any": null }));
        assert_eq!(
            (p.as_str(), r.as_str()),
            (
                "activities[2].awake",
                "invalid type: object, expected a string"
            )
        );
        let (p, _) =
            shape_err(|v| v["activities"][0]["effects"][0]["at"] = json!({ "start": null }));
        assert_eq!(p, "activities[0].effects[0].at");
    }

    #[test]
    fn load_plan_paths() {
        // serde errors keep serde_path_to_error's path; the root is `$`
        assert_eq!(load_err("").0, "$");
        assert_eq!(load_err("42").0, "$");
        assert_eq!(
            shape_err(|v| v["activities"][1]["priority"] = json!("high")).0,
            "activities[1].priority"
        );
        assert_eq!(
            shape_err(|v| v["activities"][1]["duration"] = json!(1.5)).0,
            "activities[1].duration"
        );
        assert_eq!(
            shape_err(|v| v["activities"][1]["bogus"] = json!(1)).0,
            "activities[1].bogus"
        );
        let (p, r) = shape_err(|v| {
            v.as_object_mut().unwrap().remove("battery");
        });
        assert_eq!(p, "$");
        assert!(r.contains("missing field `battery`"), "{r}");
        // input ending inside an object key: no `.?` segment
        let text = base_json().to_string();
        let cut = text.find("\"energy_rate\"").unwrap() + 3;
        let (p, r) = load_err(&text[..cut]);
        assert_eq!(p, "activities[0]");
        assert!(r.contains("EOF"), "{r}");
        // semantic errors come from `validate`
        assert_eq!(
            shape_err(|v| v["battery"]["initial"] = json!(2000.0)).0,
            "battery.initial"
        );
    }

    /// The check of one edited activity in the plan's context says what
    /// `validate` says of the whole plan so edited, for edits that keep the
    /// id: edits of every kind the explainer makes, valid and not, on each
    /// activity (some making other activities' warnings change).
    #[test]
    fn activity_edits_agree_with_validate() {
        let plan = parse(base_json());
        let checks = ActivityEdits::new(&plan);
        let edits: Vec<(&str, Value)> = vec![
            ("priority", json!(0)),
            ("priority", json!(9)),
            ("priority", json!(-3)),
            ("mandatory", json!(false)),
            ("mandatory", json!(true)),
            ("duration", json!(60)),
            ("duration", json!(0)),
            ("duration", json!({ "min": 600, "max": 300 })),
            ("duration", json!({ "min": 10, "max": 20000 })),
            ("windows", json!([{ "start": 100, "end": 50 }])),
            (
                "windows",
                json!([{ "start": 100, "end": 5000, "preferred": 200 }]),
            ),
            (
                "windows",
                json!([{ "start": 100, "end": 5000, "preferred": 9000 }]),
            ),
            ("windows", json!([{ "start": 0, "end": 99999 }])),
            ("windows", json!([{ "start": 10, "end": 20, "cutoff": 15 }])),
            ("windows", json!(null)),
            ("after", json!([])),
            ("after", json!([{ "activity": "nobody" }])),
            ("after", json!([{ "activity": "pano" }])),
            (
                "after",
                json!([{ "activity": "unstow", "min_delay": 50, "max_delay": 10 }]),
            ),
            ("group", json!(null)),
            ("peak_power", json!(-1.0)),
            ("peak_power", json!(5000.0)),
            ("energy_rate", json!(1e13)),
            ("requires", json!([{ "state": "drill", "value": "lost" }])),
            ("requires", json!([{ "state": "none", "value": "x" }])),
            (
                "effects",
                json!([{ "state": "drill", "value": "deployed", "at": "start" }]),
            ),
            ("thermal_zones", json!(["nowhere"])),
            ("thermal_zones", json!([])),
            ("sequence_engines", json!(4)),
        ];
        let (mut valid, mut invalid) = (0, 0);
        for i in 0..plan.activities.len() {
            for (field, value) in &edits {
                let edited = with(|v| {
                    let a = v["activities"][i].as_object_mut().expect("an object");
                    if value.is_null() {
                        a.remove(*field);
                    } else {
                        a.insert((*field).to_string(), value.clone());
                    }
                });
                let whole = validate(&edited).is_ok();
                let alone = checks.check(i, &edited.activities[i]).is_ok();
                assert_eq!(alone, whole, "activities[{i}].{field} = {value}");
                if whole {
                    valid += 1;
                } else {
                    invalid += 1;
                }
            }
        }
        assert!(
            valid > 20 && invalid > 20,
            "{valid} valid, {invalid} invalid"
        );
    }
}
