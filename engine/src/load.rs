//! Reading plans: strict parsing with JSON paths, then semantic validation.

use crate::error::{Error, Warning};
use crate::model::Plan;
use crate::validate::{check_json_shape, validate};

/// A plan that passed strict parsing and semantic validation, with its warnings.
#[derive(Clone, Debug)]
pub struct LoadedPlan {
    /// The plan.
    pub plan: Plan,
    /// Non-fatal remarks, in path order.
    pub warnings: Vec<Warning>,
}

/// Largest plan accepted (bytes): far above any real plan (a generated
/// 10,000-activity plan is about 4 MB), and a bound on the memory loading takes.
pub const MAX_PLAN_BYTES: usize = 32 * 1024 * 1024;

/// Parses and validates a plan from JSON text (a leading UTF-8 byte-order mark is
/// ignored). Errors name the JSON path.
pub fn load_plan(text: &str) -> Result<LoadedPlan, Error> {
    load_plan_limited(text, MAX_PLAN_BYTES)
}

/// [`load_plan`] with another size limit than [`MAX_PLAN_BYTES`] (the command
/// line's `--max-plan-bytes`).
pub fn load_plan_limited(text: &str, limit: usize) -> Result<LoadedPlan, Error> {
    // A UTF-8 byte-order mark (Windows editors write one) is not part of the JSON.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.len() > limit {
        return Err(Error::invalid(
            "$",
            format!(
                "the plan is {} bytes; plans are limited to {limit} bytes",
                text.len()
            ),
        ));
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let typed: Result<Plan, _> = serde_path_to_error::deserialize(&mut *de);
    if typed.is_ok() {
        de.end()
            .map_err(|e| Error::invalid("$", format!("unexpected text after the plan: {e}")))?;
    }
    // serde's derived impls also accept arrays for structs (fields by position);
    // the format does not, and the shape error explains a failed parse better.
    let too_deep = match serde_json::from_str::<serde_json::Value>(text) {
        Ok(doc) => {
            check_json_shape(&doc)?;
            false
        }
        // The typed parse then fails somewhere inside the nesting, with a message
        // about the first value it could not read; the depth is the real cause.
        Err(e) => e.to_string().contains("recursion limit exceeded"),
    };
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
            return Error::invalid(
                path,
                "the JSON is nested more than 128 levels deep (the most a plan may nest)",
            );
        }
        Error::invalid(path, e.into_inner().to_string())
    })?;
    let warnings = validate(&plan)?;
    Ok(LoadedPlan { plan, warnings })
}

/// Reads and loads a plan file (at most [`MAX_PLAN_BYTES`]; see [`read_plan_text`]).
pub fn load_plan_file(path: &std::path::Path) -> Result<LoadedPlan, Error> {
    load_plan(&read_plan_text(path, MAX_PLAN_BYTES)?)
}

/// Reads a plan file's text: at most `limit` bytes are read whatever the file is
/// (a device such as `/dev/zero` or a pipe reports no size, so the limit is
/// enforced on the bytes read, not on the metadata).
pub fn read_plan_text(path: &std::path::Path, limit: usize) -> Result<String, Error> {
    use std::io::Read;
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(u64::try_from(limit).unwrap_or(u64::MAX).saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() > limit {
        return Err(Error::invalid(
            "$",
            format!(
                "{} is larger than {limit} bytes; plans are limited to {limit} bytes",
                path.display()
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("stream did not contain valid UTF-8 ({e})"),
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
            assert!(
                err.to_string().contains("larger than 1048576 bytes"),
                "{err}"
            );
        }
        let path = temp("big", &[b' '; 101]);
        assert!(read_plan_text(&path, 100).is_err());
        assert_eq!(read_plan_text(&path, 101).expect("fits").len(), 101);
        std::fs::remove_file(&path).expect("remove");
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
