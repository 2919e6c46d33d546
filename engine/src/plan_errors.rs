//! Every error of a plan's text in one pass ([`plan_errors`]).

use std::collections::HashSet;

use serde::de::DeserializeOwned;
use serde_json::Value;

use crate::error::Error;
use crate::load::{MAX_PLAN_BYTES, parse_plan, planner_words};
use crate::model::{Activity, Plan};
use crate::validate::{check_activity_shape, check_json_shape, validate_all};

/// Every error of a plan's text (at most [`MAX_PLAN_BYTES`]), in the order a
/// planner fixes them; empty exactly when [`load_plan`](crate::load_plan)
/// accepts it, and otherwise led by the error `load_plan` gives.
///
/// A plan that parses gets every semantic error ([`validate_all`]). One that
/// does not is read again piece by piece when it is a JSON object: the plan
/// without its activities, then each activity on its own, and inside each of
/// them field by field (a value of the wrong type is reported, then read as a
/// stand-in of the right type so the fields after it are read too). The
/// semantic checks then run on what did parse: on the whole plan when its
/// plan-wide part parsed (the activities that did not parse left out, their
/// ids still known), else only the references between activities (`after`
/// targets), so an unknown id shows up beside the type errors.
pub fn plan_errors(text: &str) -> Vec<Error> {
    match parse_plan(text, MAX_PLAN_BYTES) {
        Ok(plan) => validate_all(&plan),
        Err(first) => {
            // The text parse names the position too: the same error read from
            // the piece has the same path.
            let first_path = path(&first);
            let mut errors = vec![first];
            for e in piecewise_errors(text.strip_prefix('\u{feff}').unwrap_or(text)) {
                if path(&e) != first_path {
                    errors.push(e);
                }
            }
            errors
        }
    }
}

/// The path of an [`Error::Invalid`].
fn path(e: &Error) -> Option<String> {
    match e {
        Error::Invalid { path, .. } => Some(path.clone()),
        _ => None,
    }
}

/// The errors of a plan read piece by piece (see [`plan_errors`]): none when
/// the text is not a JSON object.
fn piecewise_errors(text: &str) -> Vec<Error> {
    let Ok(Value::Object(mut root)) = serde_json::from_str::<Value>(text) else {
        return Vec::new();
    };
    let activities = root.remove("activities");
    let mut errors = Vec::new();
    // The plan without its activities (an empty list stands in for them).
    root.insert("activities".into(), Value::Array(Vec::new()));
    let shell = Value::Object(root);
    let shell: Option<Plan> = match check_json_shape(&shell) {
        Err(e) => {
            errors.push(e);
            None
        }
        // Only a part read with no error is the file's (see `read_all`).
        Ok(()) => {
            let before = errors.len();
            read_all(shell, "", &mut errors).filter(|_| errors.len() == before)
        }
    };
    let acts = match activities {
        Some(Value::Array(acts)) => acts,
        _ => Vec::new(),
    };
    // Every id written, parsed or not: a reference to one of them is no error
    // of the activity that makes it.
    let ids: HashSet<&str> = acts
        .iter()
        .filter_map(|a| a.get("id").and_then(Value::as_str))
        .collect();
    // The activities read whole (with their index in the file).
    let mut parsed: Vec<(usize, Activity)> = Vec::new();
    for (i, act) in acts.iter().enumerate() {
        let base = format!("activities[{i}]");
        if let Some(obj) = act.as_object()
            && let Err(e) = check_activity_shape(obj, &base)
        {
            errors.push(e);
            continue;
        }
        let before = errors.len();
        let read: Option<Activity> = read_all(act.clone(), &base, &mut errors);
        match read {
            Some(a) if errors.len() == before => parsed.push((i, a)),
            _ => {}
        }
    }
    let whole: HashSet<usize> = parsed.iter().map(|(i, _)| *i).collect();
    match shell {
        Some(mut plan) => {
            let index: Vec<usize> = parsed.iter().map(|(i, _)| *i).collect();
            plan.activities = parsed.into_iter().map(|(_, a)| a).collect();
            for e in validate_all(&plan) {
                if let Some(e) = in_file(e, &index, &ids) {
                    errors.push(e);
                }
            }
        }
        None => {
            for (i, a) in &parsed {
                unknown_targets(*i, a, &ids, &mut errors);
            }
        }
    }
    // The activities that did not parse whole: their readable `after` targets.
    for (i, act) in acts.iter().enumerate() {
        if !whole.contains(&i) {
            unknown_targets_in_json(i, act, &ids, &mut errors);
        }
    }
    errors
}

/// A semantic error of the plan made of the activities that parsed (activity
/// `k` of it is `index[k]` of the file) as the file's error: its paths and the
/// activity it names renumbered, or none when it only says that an activity
/// which did not parse is missing.
fn in_file(e: Error, index: &[usize], ids: &HashSet<&str>) -> Option<Error> {
    let Error::Invalid { path, reason } = e else {
        return Some(e);
    };
    if let Some(target) = unknown_activity(&reason)
        && ids.contains(target)
    {
        return None;
    }
    Some(Error::invalid(
        renumber(&path, index),
        renumber(&reason, index),
    ))
}

/// The id an "unknown activity" reason names.
fn unknown_activity(reason: &str) -> Option<&str> {
    reason
        .strip_prefix("unknown activity \"")?
        .split('"')
        .next()
}

/// `text` with every `activities[k]` written as `activities[index[k]]`.
fn renumber(text: &str, index: &[usize]) -> String {
    const KEY: &str = "activities[";
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(KEY) {
        let (head, tail) = rest.split_at(at + KEY.len());
        out.push_str(head);
        let digits = tail.bytes().take_while(u8::is_ascii_digit).count();
        match tail[..digits]
            .parse::<usize>()
            .ok()
            .and_then(|k| index.get(k))
        {
            Some(i) => out.push_str(&i.to_string()),
            None => out.push_str(&tail[..digits]),
        }
        rest = &tail[digits..];
    }
    out.push_str(rest);
    out
}

/// The reason for an `after` target that names no activity, as the semantic
/// check gives it.
fn unknown_target(i: usize, k: usize, target: &str) -> Error {
    Error::invalid(
        format!("activities[{i}].after[{k}].activity"),
        format!("unknown activity \"{target}\""),
    )
}

/// The `after` targets of a parsed activity (file index `i`) that name no id.
fn unknown_targets(i: usize, a: &Activity, ids: &HashSet<&str>, errors: &mut Vec<Error>) {
    for (k, dep) in a.after.iter().enumerate() {
        if !ids.contains(dep.activity.as_str()) {
            errors.push(unknown_target(i, k, &dep.activity));
        }
    }
}

/// The `after` targets written as strings in an activity that did not parse
/// (file index `i`) that name no id.
fn unknown_targets_in_json(i: usize, act: &Value, ids: &HashSet<&str>, errors: &mut Vec<Error>) {
    let Some(after) = act.get("after").and_then(Value::as_array) else {
        return;
    };
    for (k, dep) in after.iter().enumerate() {
        if let Some(target) = dep.get("activity").and_then(Value::as_str)
            && !ids.contains(target)
        {
            errors.push(unknown_target(i, k, target));
        }
    }
}

/// Most values of one piece stood in for before it is given up: far above
/// the fields of any piece of a plan.
const MAX_STAND_INS: usize = 256;

/// Reads `value` as a `T`, going on past each error: the error is kept (its
/// path under `base`), the value at its path is replaced by a stand-in of the
/// type wanted (or an unknown field dropped), and the piece is read again.
/// The result (when it reads at last) holds stand-ins wherever an error was
/// kept: only a piece read with no error is the file's.
fn read_all<T: DeserializeOwned>(value: Value, base: &str, errors: &mut Vec<Error>) -> Option<T> {
    let from = errors.len();
    let read = read_each::<T>(value, base, errors);
    // Found in the order the fields are read (by name); listed in the
    // format's (the model's) field order, as the text parse finds them.
    let order = field_order::<T>();
    let rank = |e: &Error| {
        let Error::Invalid { path, reason } = e else {
            return order.len();
        };
        let inner = path.strip_prefix(base).unwrap_or(path);
        let field = quoted(reason, "missing field `")
            .filter(|_| inner.is_empty() || inner == "$")
            .or_else(|| inner.trim_start_matches('.').split(['.', '[']).next())
            .unwrap_or("");
        order
            .iter()
            .position(|f| *f == field)
            .unwrap_or(order.len())
    };
    errors[from..].sort_by_key(rank);
    read
}

/// The field names of struct `T` in the order it declares them (none when
/// `T` is not a struct).
fn field_order<T: DeserializeOwned>() -> &'static [&'static str] {
    use serde::de::{Error as _, value::Error as Stop};
    /// A deserializer that only notes the fields a struct asks for.
    struct Fields(&'static [&'static str]);
    impl<'de> serde::Deserializer<'de> for &mut Fields {
        type Error = Stop;
        fn deserialize_any<V: serde::de::Visitor<'de>>(self, _: V) -> Result<V::Value, Stop> {
            Err(Stop::custom("not a struct"))
        }
        fn deserialize_struct<V: serde::de::Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Stop> {
            self.0 = fields;
            Err(Stop::custom("fields noted"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
            byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map
            enum identifier ignored_any
        }
    }
    let mut fields = Fields(&[]);
    // Never read: the deserializer stops at the struct's field list.
    let _stopped = T::deserialize(&mut fields).is_err();
    fields.0
}

/// [`read_all`] in the order serde reads the fields.
fn read_each<T: DeserializeOwned>(
    mut value: Value,
    base: &str,
    errors: &mut Vec<Error>,
) -> Option<T> {
    // The paths (inside the piece) of stand-ins put in for fields that were
    // missing: an error there is the stand-in's, not the file's.
    let mut stood_in: HashSet<String> = HashSet::new();
    // Each error once: the same one again means the stand-in did not help.
    let mut seen: HashSet<(String, String)> = HashSet::new();
    for _ in 0..MAX_STAND_INS {
        let err = match serde_path_to_error::deserialize::<_, T>(&value) {
            Ok(t) => return Some(t),
            Err(err) => err,
        };
        let steps: Vec<Step> = err.path().iter().map(Step::of).collect();
        let inner = err.path().to_string();
        let reason = err.into_inner().to_string();
        if !seen.insert((inner.clone(), reason.clone()))
            || steps.iter().any(|s| matches!(s, Step::Other))
        {
            return None;
        }
        if !stood_in.contains(&inner) {
            let path = joined(base, &inner);
            let words = planner_words(&path, &reason);
            errors.push(Error::invalid(path, words));
        }
        if let Some(field) = quoted(&reason, "missing field `") {
            let Some(Value::Object(obj)) = at_mut(&mut value, &steps) else {
                return None;
            };
            obj.insert(field.to_string(), Value::from(1));
            let path = if inner.is_empty() || inner == "." {
                field.to_string()
            } else {
                format!("{inner}.{field}")
            };
            stood_in.insert(path);
            continue;
        }
        if reason.starts_with("unknown field `") {
            let (last, parent) = steps.split_last()?;
            let (Step::Key(key), Some(Value::Object(obj))) = (last, at_mut(&mut value, parent))
            else {
                return None;
            };
            obj.remove(key);
            continue;
        }
        let stand_in = stand_in(&reason)?;
        *at_mut(&mut value, &steps)? = stand_in;
    }
    None
}

/// One step of a serde path.
enum Step {
    Key(String),
    Index(usize),
    Other,
}

impl Step {
    fn of(s: &serde_path_to_error::Segment) -> Self {
        match s {
            serde_path_to_error::Segment::Map { key } => Step::Key(key.clone()),
            serde_path_to_error::Segment::Seq { index } => Step::Index(*index),
            _ => Step::Other,
        }
    }
}

/// The value at `steps` inside `value`.
fn at_mut<'v>(value: &'v mut Value, steps: &[Step]) -> Option<&'v mut Value> {
    steps.iter().try_fold(value, |v, s| match s {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
        Step::Other => None,
    })
}

/// A piece's inner path under `base` (`$` for the root).
fn joined(base: &str, inner: &str) -> String {
    let inner = if inner == "." { "" } else { inner };
    match (base.is_empty(), inner.is_empty()) {
        (true, true) => "$".into(),
        (true, false) => inner.into(),
        (false, true) => base.into(),
        (false, false) if inner.starts_with('[') => format!("{base}{inner}"),
        (false, false) => format!("{base}.{inner}"),
    }
}

/// The text between `prefix` and the next backtick in `reason`.
fn quoted<'r>(reason: &'r str, prefix: &str) -> Option<&'r str> {
    reason.strip_prefix(prefix)?.split('`').next()
}

/// A value of the type a serde reason says it expected.
fn stand_in(reason: &str) -> Option<Value> {
    if reason.starts_with("unknown variant `") {
        // "expected `a`", "expected `a` or `b`", "expected one of `a`, `b`".
        let expected = reason.split(", expected ").nth(1)?;
        return expected.split('`').nth(1).map(Value::from);
    }
    let expected = reason.rsplit(", expected ").next()?;
    let has = |words: &[&str]| words.iter().any(|w| expected.contains(w));
    Some(
        if has(&[
            "i64", "i32", "u32", "u64", "usize", "integer", "f64", "number",
        ]) {
            Value::from(1)
        } else if has(&["string"]) {
            Value::from("")
        } else if has(&["bool"]) {
            Value::from(false)
        } else if has(&["sequence", "array", "list"]) {
            Value::Array(Vec::new())
        } else if has(&["struct", "map", "object"]) {
            Value::Object(serde_json::Map::new())
        } else {
            return None;
        },
    )
}

#[cfg(test)]
mod tests;
