//! Reading plans: strict parsing with JSON paths, then semantic validation.

use serde::Deserialize;

use crate::error::{Error, Warning};
use crate::model::Plan;
use crate::validate::{check_json_shape, shape_may_fail, validate};

/// A plan that passed strict parsing and semantic validation, with its warnings.
#[derive(Clone, Debug)]
pub struct LoadedPlan {
    /// The plan.
    pub plan: Plan,
    /// Non-fatal remarks, in path order.
    pub warnings: Vec<Warning>,
}

/// Largest input file read (bytes), 32 MiB: far above any real plan (a generated
/// 10,000-activity plan is about 4 MB), and a bound on the memory loading takes.
/// The command line's `--max-input-mib` raises it.
pub const MAX_PLAN_BYTES: usize = 32 * 1024 * 1024;

/// A size limit as a planner reads it: `32 MiB` when it is a whole number of MiB,
/// else in bytes.
fn limit_text(limit: usize) -> String {
    const MIB: usize = 1024 * 1024;
    if limit >= MIB && limit % MIB == 0 {
        format!("{} MiB", limit / MIB)
    } else {
        format!("{limit} bytes")
    }
}

/// Parses and validates a plan from JSON text (a leading UTF-8 byte-order mark is
/// ignored). Errors name the JSON path.
pub fn load_plan(text: &str) -> Result<LoadedPlan, Error> {
    load_plan_limited(text, MAX_PLAN_BYTES)
}

/// [`load_plan`] with another size limit than [`MAX_PLAN_BYTES`] (the command
/// line's `--max-input-mib`).
pub fn load_plan_limited(text: &str, limit: usize) -> Result<LoadedPlan, Error> {
    let plan = parse_plan(text, limit)?;
    let warnings = validate(&plan)?;
    Ok(LoadedPlan { plan, warnings })
}

/// The parse half of [`load_plan_limited`]: size, JSON, shape and types, no
/// semantic validation.
pub(crate) fn parse_plan(text: &str, limit: usize) -> Result<Plan, Error> {
    // A UTF-8 byte-order mark (Windows editors write one) is not part of the JSON.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.len() > limit {
        return Err(Error::invalid(
            "$",
            format!(
                "the plan is {} bytes, larger than {}; plans are limited to {}",
                text.len(),
                limit_text(limit),
                limit_text(limit)
            ),
        ));
    }
    let text = &*read_underflow_as_smallest(text);
    // A plan that parses is read without tracking the path (a third faster on
    // large plans); one that does not is read again with it, for the error's
    // path. The tracker is a transparent wrapper: both reads accept the same
    // texts and build the same plan.
    let quick = {
        let de = &mut serde_json::Deserializer::from_str(text);
        Plan::deserialize(&mut *de)
            .ok()
            .filter(|_| de.end().is_ok())
    };
    #[cfg(debug_assertions)]
    if let Some(plan) = &quick {
        let de = &mut serde_json::Deserializer::from_str(text);
        let tracked: Result<Plan, _> = serde_path_to_error::deserialize(&mut *de);
        debug_assert!(
            tracked.is_ok_and(|t| &t == plan) && de.end().is_ok(),
            "the plan read without its path differs from the one read with it"
        );
    }
    let typed: Result<Plan, _> = match quick {
        Some(plan) => Ok(plan),
        None => {
            let de = &mut serde_json::Deserializer::from_str(text);
            let typed = serde_path_to_error::deserialize(&mut *de);
            if typed.is_ok() {
                de.end().map_err(|e| {
                    Error::invalid("$", format!("unexpected text after the plan: {e}"))
                })?;
            }
            typed
        }
    };
    // serde's derived impls also accept arrays for structs (fields by position);
    // the format does not, and the shape error explains a failed parse better.
    // The streaming walk rules the check out for almost every plan without
    // building the document; the exact check runs when it cannot.
    let suspect = shape_may_fail(text);
    let too_deep = match suspect.then(|| serde_json::from_str::<serde_json::Value>(text)) {
        None => false,
        Some(Ok(doc)) => {
            check_json_shape(&doc)?;
            false
        }
        // The typed parse then fails somewhere inside the nesting, with a message
        // about the first value it could not read; the depth is the real cause.
        Some(Err(e)) => e.to_string().contains("recursion limit exceeded"),
    };
    #[cfg(debug_assertions)]
    if !suspect {
        let doc = serde_json::from_str::<serde_json::Value>(text);
        debug_assert!(
            doc.is_ok_and(|doc| check_json_shape(&doc).is_ok()),
            "the shape walk passed a plan the shape check rejects"
        );
    }
    let plan = typed.map_err(|e| {
        // Drop trailing unknown segments (`activities[3].?` when the input ends
        // inside an object key); the root is `$`.
        let path = e.path().to_string();
        let mut path = path.as_str();
        while let Some(p) = path.strip_suffix('?') {
            path = p.strip_suffix('.').unwrap_or(p);
        }
        let path = if path.is_empty() || path == "." {
            "$"
        } else {
            path
        };
        if too_deep {
            // A plan is an object: a path into a top-level array names nothing.
            let path = if path.starts_with('[') { "$" } else { path };
            // No value of a plan is an array of arrays: the path ends at the
            // value that should not have been one (`activities[0]`, not the
            // `activities[0][0]` the typed parse reached).
            let path = path.find("][").map_or(path, |i| &path[..=i]);
            return Error::invalid(path, NESTED_TOO_DEEPLY);
        }
        let reason = planner_words(path, &e.into_inner().to_string());
        Error::invalid(path, reason)
    })?;
    Ok(plan)
}

/// The integer fields that do not count seconds.
const NOT_SECONDS: [&str; 4] = ["priority", "sequence_engines", "first_sol", "power_mw"];

/// The reason serde gives for a value of the wrong type (`invalid type: string
/// "high", expected i64`) in the planner's words (`must be a whole number (got
/// the text "high")`), for the field at `path`; other reasons as they are.
pub(crate) fn planner_words(path: &str, reason: &str) -> String {
    // Read from text, serde adds the position; the path names the place.
    let at_line = reason
        .rfind(" at line ")
        .filter(|&i| {
            let tail = &reason[i + " at line ".len()..];
            tail.split_once(" column ").is_some_and(|(l, c)| {
                [l, c]
                    .iter()
                    .all(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
            })
        })
        .map_or(reason, |i| &reason[..i]);
    let body = at_line
        .strip_prefix("invalid type: ")
        .or_else(|| at_line.strip_prefix("invalid value: "));
    let Some((got, expected)) = body.and_then(|b| b.rsplit_once(", expected ")) else {
        return reason.to_string();
    };
    let field = path
        .rsplit(['.', '['])
        .next()
        .unwrap_or(path)
        .trim_end_matches(']');
    let seconds = !NOT_SECONDS.contains(&field) && field.parse::<usize>().is_err();
    let unsigned = ["u32", "u64", "usize"].contains(&expected);
    let wanted = match expected {
        "i64" | "i32" | "u32" | "u64" | "usize" => {
            let what = if seconds {
                "a whole number of seconds"
            } else {
                "a whole number"
            };
            if unsigned {
                format!("{what} >= 0")
            } else {
                what.to_string()
            }
        }
        "f64" | "f32" => "a number".into(),
        "a string" => "text in double quotes".into(),
        "a boolean" => "true or false".into(),
        "a sequence" => "a list [ … ]".into(),
        "a map" => "an object { … }".into(),
        e if e.starts_with("struct ") => "an object { … }".into(),
        e => match e.strip_prefix("an integer number of seconds") {
            Some(rest) => format!("a whole number of seconds{rest}"),
            None => e.to_string(),
        },
    };
    format!("must be {wanted} (got {})", value_words(got))
}

/// The value serde names (`string "high"`, ``floating point `1.5` ``) as a
/// planner reads it (`the text "high"`, `1.5`).
fn value_words(got: &str) -> String {
    if let Some(s) = got.strip_prefix("string ") {
        return format!("the text {s}");
    }
    for kind in ["floating point ", "integer ", "boolean "] {
        if let Some(v) = got.strip_prefix(kind) {
            return v.trim_matches('`').to_string();
        }
    }
    match got {
        "sequence" => "a list".into(),
        "map" => "an object".into(),
        "unit value" => "null".into(),
        other => other.to_string(),
    }
}

/// The text with every number literal too small for a 64-bit float but not zero
/// (`1e-400`, which the JSON parser reads as 0) written as the smallest float of
/// its sign (`5e-324`): it is then rounded to the fixed-point resolution on the
/// safe side, with the warning any tiny value gets, instead of silently
/// becoming 0. Borrowed unchanged when there is none (almost always).
fn read_underflow_as_smallest(text: &str) -> std::borrow::Cow<'_, str> {
    let bytes = text.as_bytes();
    let mut out: Option<String> = None;
    // Bytes of `text` copied into `out` so far.
    let mut copied = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'"' => {
                // Skip the string, escapes included.
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            b'-' | b'0'..=b'9' => {
                let start = i;
                while i < bytes.len()
                    && matches!(bytes[i], b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9')
                {
                    i += 1;
                }
                let token = &text[start..i];
                // Only an exponent or a long fraction can underflow.
                let may_underflow = token.len() > 300 || token.contains(['e', 'E']);
                let underflows = may_underflow
                    && token.parse::<f64>().is_ok_and(|x| x == 0.0)
                    && token
                        .split(['e', 'E'])
                        .next()
                        .is_some_and(|m| m.bytes().any(|b| matches!(b, b'1'..=b'9')));
                if underflows {
                    let o = out.get_or_insert_with(|| String::with_capacity(text.len()));
                    o.push_str(&text[copied..start]);
                    o.push_str(if token.starts_with('-') {
                        "-5e-324"
                    } else {
                        "5e-324"
                    });
                    copied = i;
                }
            }
            _ => i += 1,
        }
    }
    match out {
        None => std::borrow::Cow::Borrowed(text),
        Some(mut o) => {
            o.push_str(&text[copied..]);
            std::borrow::Cow::Owned(o)
        }
    }
}

/// The reason given for JSON nested past serde_json's recursion limit.
const NESTED_TOO_DEEPLY: &str =
    "nested too deeply: the JSON nests 128 levels or more here (a plan nests at most 5)";

/// Reads and loads a plan file (at most [`MAX_PLAN_BYTES`]; see [`read_plan_text`]).
pub fn load_plan_file(path: &std::path::Path) -> Result<LoadedPlan, Error> {
    load_plan(&read_plan_text(path, MAX_PLAN_BYTES)?)
}

/// Reads an input file's text (a plan, actuals, Monte Carlo parts): at most
/// `limit` bytes are read whatever the file is (a device such as `/dev/zero` or a
/// pipe reports no size, so the limit is enforced on the bytes read, not on the
/// metadata). A leading UTF-8 byte-order mark is dropped. Text that is not UTF-8
/// is invalid input at `$`; a file that cannot be read is an I/O error.
pub fn read_plan_text(path: &std::path::Path, limit: usize) -> Result<String, Error> {
    use std::io::Read;
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    let file = open_input(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(u64::try_from(limit).unwrap_or(u64::MAX).saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() > limit {
        return Err(Error::invalid(
            "$",
            format!(
                "{} is larger than {}, the input size limit (--max-input-mib raises it)",
                path.display(),
                limit_text(limit)
            ),
        ));
    }
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(Error::invalid(
            "$",
            format!(
                "{} is UTF-16 text (it starts with a UTF-16 byte-order mark); save it as UTF-8",
                path.display()
            ),
        ));
    }
    let bom = if bytes.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    bytes.drain(..bom);
    if bom > 0 && bytes.starts_with(b"\xEF\xBB\xBF") {
        return Err(Error::invalid(
            "$",
            format!(
                "{} starts with two byte-order marks; a UTF-8 file has at most one",
                path.display()
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        Error::invalid(
            "$",
            format!(
                "{} is not UTF-8 text (invalid byte at offset {})",
                path.display(),
                bom + e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// How long [`read_plan_text`] waits for a named pipe (FIFO) to get a writer.
const FIFO_WAIT: std::time::Duration = std::time::Duration::from_secs(5);

/// Opens an input file for reading. Opening a named pipe waits until
/// something opens it for writing, which may be never: it waits at most
/// [`FIFO_WAIT`], then says so (a pipe a writer already holds, such as a
/// shell's `<(...)`, opens at once).
fn open_input(path: &std::path::Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::FileTypeExt;
    if !std::fs::metadata(path)?.file_type().is_fifo() {
        return std::fs::File::open(path);
    }
    let (tx, rx) = std::sync::mpsc::channel();
    let fifo = path.to_path_buf();
    std::thread::spawn(move || {
        if tx.send(std::fs::File::open(&fifo)).is_err() {
            // The receiver is gone only when the wait timed out: the file
            // closes here, unread.
        }
    });
    match rx.recv_timeout(FIFO_WAIT) {
        Ok(opened) => opened,
        Err(_) => {
            // Release the waiting open by being its writer for an instant (a
            // waiting reader lets a writer open at once), off this thread in
            // case the reader left in the meantime.
            let fifo = path.to_path_buf();
            std::thread::spawn(move || {
                if std::fs::OpenOptions::new().write(true).open(&fifo).is_err() {
                    // Nothing waits for this answer: the caller has its error.
                }
            });
            Err(std::io::Error::new(
                std::io::ErrorKind::TimedOut,
                format!(
                    "a named pipe that nothing opened for writing within {} s",
                    FIFO_WAIT.as_secs()
                ),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shape_walk_clears_real_plans_and_flags_every_shape_the_check_rejects() {
        for plan in [
            include_str!("../../assets/default-plan.json"),
            include_str!("../../assets/tutorial-plan.json"),
            include_str!("../../assets/examples/drill-sol.json"),
        ] {
            assert!(!shape_may_fail(plan), "a valid plan needs no Value");
        }
        let base =
            r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":10},"activities":[ACT]}"#;
        let act = r#"{"id":"a","priority":1,"duration":1,"windows":[{"start":0,"end":5}],"effects":[{"state":"s","value":"v","at":"end"}]}"#;
        assert!(!shape_may_fail(&base.replace("ACT", act)));
        for (from, to) in [
            (r#"{"start":0,"end":10}"#, "[0, 10]"),
            (r#"{"start":0,"end":5}"#, "[0, 5]"),
            (r#""at":"end""#, r#""at":{"end":null}"#),
            (r#""at":"end""#, r#""at":["end"]"#),
            (r#""duration":1,"#, r#""duration":1,"awake":{"any":null},"#),
            (
                r#""duration":1,"#,
                r#""duration":1,"duration_model":[1,2],"#,
            ),
            (r#""duration":1,"#, r#""duration":1,"after":[["b"]],"#),
        ] {
            let text = base.replace("ACT", act).replacen(from, to, 1);
            assert!(shape_may_fail(&text), "{text}");
            let doc: serde_json::Value = serde_json::from_str(&text).expect("json");
            assert!(check_json_shape(&doc).is_err(), "{text}");
        }
        assert!(shape_may_fail(&format!("[{}]", base.replace("ACT", act))));
        assert!(shape_may_fail(&base.replace("ACT", &format!("[{act}]"))));
        assert!(shape_may_fail(
            r#"{"thermal_zones":{"z":{"preheat":[[1]]}}}"#
        ));
        assert!(shape_may_fail(r#"{"states":{"s":[1]}}"#));
        assert!(!shape_may_fail(r#"{"states":{"s":{"values":["a"]}}}"#));
    }

    fn temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let path =
            std::env::temp_dir().join(format!("solscope-load-{}-{name}", std::process::id()));
        std::fs::write(&path, bytes).expect("write temp file");
        path
    }

    #[test]
    fn reading_stops_at_the_limit_whatever_the_file() {
        // A device reports size 0 and never ends.
        let zero = std::path::Path::new("/dev/zero");
        if zero.exists() {
            let err = read_plan_text(zero, 1 << 20).expect_err("must stop");
            assert_eq!(
                err.to_string(),
                "$: /dev/zero is larger than 1 MiB, the input size limit (--max-input-mib raises it)"
            );
        }
        let path = temp("big", &[b' '; 101]);
        let err = read_plan_text(&path, 100).expect_err("one byte too many");
        assert!(err.to_string().contains("larger than 100 bytes"), "{err}");
        assert_eq!(read_plan_text(&path, 101).expect("fits").len(), 101);
        std::fs::remove_file(&path).expect("remove");
    }

    #[test]
    fn the_reader_drops_a_byte_order_mark_and_names_other_encodings() {
        let path = temp("bom", b"\xEF\xBB\xBF{}");
        assert_eq!(read_plan_text(&path, 100).expect("reads"), "{}");
        std::fs::remove_file(&path).expect("remove");
        let path = temp("utf16", b"\xFF\xFE{\0}\0");
        let err = read_plan_text(&path, 100).expect_err("UTF-16");
        assert!(err.to_string().starts_with("$: "), "{err}");
        assert!(err.to_string().contains("is UTF-16 text"), "{err}");
        std::fs::remove_file(&path).expect("remove");
        let path = temp("latin1", b"\xEF\xBB\xBF{\"a\":\"\xE9\"}");
        let err = read_plan_text(&path, 100).expect_err("Latin-1");
        assert!(
            err.to_string()
                .contains("is not UTF-8 text (invalid byte at offset 9)"),
            "{err}"
        );
        std::fs::remove_file(&path).expect("remove");
    }

    #[test]
    fn deep_nesting_is_named_with_its_path() {
        let deep = "[".repeat(100_000);
        let err = load_plan(&deep).expect_err("too deep");
        assert!(err.to_string().starts_with("$: nested too deeply"), "{err}");
        let inside = format!(r#"{{"format":"solscope.plan/1","activities":[{{"id":{deep}"#);
        let err = load_plan(&inside).expect_err("too deep");
        assert!(
            err.to_string()
                .starts_with("activities[0].id: nested too deeply"),
            "{err}"
        );
        let in_list = format!(r#"{{"format":"solscope.plan/1","activities":{deep}"#);
        let err = load_plan(&in_list).expect_err("too deep");
        assert!(
            err.to_string()
                .starts_with("activities[0]: nested too deeply"),
            "{err}"
        );
    }

    #[test]
    fn numbers_below_the_smallest_float_are_read_as_it() {
        let text = r#"{"a": 1e-400, "b": "1e-400", "c": -0.5e-999, "d": 0e-999, "e": 2.5e-10}"#;
        assert_eq!(
            read_underflow_as_smallest(text),
            r#"{"a": 5e-324, "b": "1e-400", "c": -5e-324, "d": 0e-999, "e": 2.5e-10}"#
        );
        let long = format!("[0.{}1]", "0".repeat(400));
        assert_eq!(read_underflow_as_smallest(&long), "[5e-324]");
        let plain = r#"{"a": "x\"1e-400", "b": 3}"#;
        assert!(matches!(
            read_underflow_as_smallest(plain),
            std::borrow::Cow::Borrowed(_)
        ));
    }

    #[test]
    fn the_text_limit_is_said_in_mib() {
        let err = load_plan_limited(&" ".repeat(2 << 20), 1 << 20).expect_err("too big");
        assert!(err.to_string().contains("larger than 1 MiB"), "{err}");
    }

    #[test]
    fn a_byte_order_mark_is_accepted() {
        let plan = r#"{"format":"solscope.plan/1","horizon":{"start":0,"end":100},
            "battery":{"capacity":10.0,"initial":5.0,"min_soc":1.0},
            "power":{"rtg":10.0,"asleep":1.0,"awake":2.0},"activities":[]}"#;
        let with_bom = format!("\u{feff}{plan}");
        assert_eq!(
            load_plan(&with_bom).expect("loads").plan,
            load_plan(plan).expect("loads").plan
        );
    }
}
