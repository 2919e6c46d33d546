//! The repair view's model: a plan file that does not load, kept as text with
//! every error it has ([`solscope_engine::plan_errors`]), each with its JSON
//! path, until the planner fixes it (then it opens) or leaves (the plan open
//! before stays).
//!
//! [`locate`] finds the text of the value at a JSON path, so an error can be
//! shown and edited where it is.

use std::ops::Range;
use std::path::PathBuf;

/// One error of the plan text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlanError {
    /// JSON path, e.g. `activities[3].windows[0].end` (`$`: the document).
    pub path: String,
    /// Why it is wrong.
    pub reason: String,
}

/// A plan file being repaired.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Repair {
    /// The file it came from (`None`: text from elsewhere).
    pub path: Option<PathBuf>,
    /// Every error of the text as last checked, in the order to fix them.
    pub errors: Vec<PlanError>,
    /// The error looked at.
    pub selected: Option<usize>,
    /// How many times the text was checked (1 when opened).
    pub checks: u32,
    /// The activity ids written in the text as last checked, in file order
    /// (each once): what an unknown `after` target can be replaced by.
    pub ids: Vec<String>,
    /// The text before each replacement made here, the last last (for
    /// [`UiCommand::UndoRepair`](crate::state::UiCommand::UndoRepair)).
    pub undo: Vec<String>,
}

impl Repair {
    /// The repair of `text` (from `path`), checked once.
    pub fn new(path: Option<PathBuf>, text: &str) -> Self {
        Self {
            path,
            errors: check(text),
            selected: None,
            checks: 1,
            ids: activity_ids(text),
            undo: Vec::new(),
        }
    }

    /// The file name shown (`the plan` without a file).
    pub fn file_name(&self) -> String {
        self.path
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or_else(|| "the plan".into(), |n| n.to_string_lossy().into_owned())
    }
}

impl PlanError {
    /// Whether it is an `after` target that names no activity of the plan
    /// (one of the plan's ids can be picked instead).
    pub fn is_unknown_activity(&self) -> bool {
        self.path.ends_with(".activity") && self.reason.starts_with("unknown activity \"")
    }
}

/// The activity ids written in a plan's text, in file order, each once (none
/// when it is not JSON).
pub fn activity_ids(text: &str) -> Vec<String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Ok(doc) = serde_json::from_str::<serde_json::Value>(text) else {
        return Vec::new();
    };
    let mut seen = std::collections::HashSet::new();
    doc.get("activities")
        .and_then(serde_json::Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|a| a.get("id").and_then(serde_json::Value::as_str))
        .filter(|id| seen.insert(*id))
        .map(str::to_string)
        .collect()
}

/// Every error of a plan's text (none when it loads).
pub fn check(text: &str) -> Vec<PlanError> {
    solscope_engine::plan_errors(text)
        .into_iter()
        .map(|e| match e {
            solscope_engine::Error::Invalid { path, reason } => PlanError { path, reason },
            other => PlanError {
                path: "$".into(),
                reason: other.to_string(),
            },
        })
        .collect()
}

/// One step of a JSON path.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Segment {
    Key(String),
    Index(usize),
}

/// The steps of a path as the loader writes it (`activities[3].windows[0].end`,
/// `states.arm.initial`; `$` is the root).
fn segments(path: &str) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut key = String::new();
    let mut chars = path.chars().peekable();
    let flush = |key: &mut String, out: &mut Vec<Segment>| {
        if !key.is_empty() {
            out.push(Segment::Key(std::mem::take(key)));
        }
    };
    while let Some(c) = chars.next() {
        match c {
            '.' => flush(&mut key, &mut out),
            '[' => {
                flush(&mut key, &mut out);
                let mut digits = String::new();
                while let Some(&d) = chars.peek() {
                    chars.next();
                    if d == ']' {
                        break;
                    }
                    digits.push(d);
                }
                match digits.parse() {
                    Ok(i) => out.push(Segment::Index(i)),
                    Err(_) => return out,
                }
            }
            '$' if out.is_empty() && key.is_empty() => {}
            c => key.push(c),
        }
    }
    flush(&mut key, &mut out);
    out
}

/// A forward scan over JSON text (no recursion: the text may nest deeply).
struct Scan<'a> {
    text: &'a str,
    i: usize,
}

impl Scan<'_> {
    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.i).copied()
    }

    fn ws(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.i += 1;
        }
    }

    /// Past a string starting at the quote here; false if it never ends.
    fn string(&mut self) -> bool {
        self.i += 1;
        while let Some(b) = self.peek() {
            self.i += 1;
            match b {
                b'\\' => self.i += 1,
                b'"' => return true,
                _ => {}
            }
        }
        false
    }

    /// Past the value here; false if the text ends inside it.
    fn value(&mut self) -> bool {
        self.ws();
        match self.peek() {
            None => false,
            Some(b'"') => self.string(),
            Some(b'{' | b'[') => {
                let mut depth = 0usize;
                while let Some(b) = self.peek() {
                    match b {
                        b'"' => {
                            if !self.string() {
                                return false;
                            }
                            continue;
                        }
                        b'{' | b'[' => depth += 1,
                        b'}' | b']' => {
                            depth = depth.saturating_sub(1);
                            if depth == 0 {
                                self.i += 1;
                                return true;
                            }
                        }
                        _ => {}
                    }
                    self.i += 1;
                }
                false
            }
            Some(_) => {
                while self
                    .peek()
                    .is_some_and(|b| !matches!(b, b',' | b'}' | b']') && !b.is_ascii_whitespace())
                {
                    self.i += 1;
                }
                true
            }
        }
    }

    /// The span of the value here (to the end of the text if it never ends).
    fn span(&self) -> Range<usize> {
        let mut end = Scan {
            text: self.text,
            i: self.i,
        };
        if end.value() {
            self.i..end.i.min(self.text.len())
        } else {
            self.i..self.text.len()
        }
    }

    /// Inside the object here: moves to the value of member `key`.
    fn member(&mut self, key: &str) -> bool {
        self.i += 1;
        loop {
            self.ws();
            if self.peek() != Some(b'"') {
                return false;
            }
            let from = self.i;
            if !self.string() {
                return false;
            }
            let name: Option<String> = serde_json::from_str(&self.text[from..self.i]).ok();
            self.ws();
            if self.peek() != Some(b':') {
                return false;
            }
            self.i += 1;
            self.ws();
            if name.as_deref() == Some(key) {
                return true;
            }
            if !self.value() {
                return false;
            }
            self.ws();
            if self.peek() != Some(b',') {
                return false;
            }
            self.i += 1;
        }
    }

    /// Inside the array here: moves to element `n`.
    fn element(&mut self, n: usize) -> bool {
        self.i += 1;
        for _ in 0..n {
            self.ws();
            if matches!(self.peek(), Some(b']') | None) || !self.value() {
                return false;
            }
            self.ws();
            if self.peek() != Some(b',') {
                return false;
            }
            self.i += 1;
        }
        self.ws();
        !matches!(self.peek(), Some(b']') | None)
    }
}

/// The byte range of the value at `path` in the JSON `text`: where an error
/// at that path is. A path that goes further than the text (a missing field,
/// text cut short) gives its deepest value there; `None` when the text holds
/// no value at all.
pub fn locate(text: &str, path: &str) -> Option<Range<usize>> {
    let mut scan = Scan { text, i: 0 };
    scan.ws();
    scan.peek()?;
    let mut best = scan.span();
    for seg in segments(path) {
        scan.ws();
        let found = match (&seg, scan.peek()) {
            (Segment::Key(k), Some(b'{')) => scan.member(k),
            (Segment::Index(n), Some(b'[')) => scan.element(*n),
            _ => false,
        };
        if !found {
            break;
        }
        scan.ws();
        best = scan.span();
    }
    Some(best)
}

/// A byte range of `text` as a range of chars (what a text field's cursor
/// counts).
pub fn char_range(text: &str, bytes: &Range<usize>) -> Range<usize> {
    let at = |b: usize| {
        text.get(..b.min(text.len()))
            .map_or(0, |prefix| prefix.chars().count())
    };
    at(bytes.start)..at(bytes.end)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"{ "format": "solscope.plan/1",
  "states": { "arm": { "values": ["a", "b"], "initial": "c" } },
  "activities": [
    { "id": "x", "windows": [ { "start": 5, "end": 1 } ] },
    { "id": "y \"q\"", "after": [ { "activity": "z" } ] }
  ] }"#;

    fn at(path: &str) -> &'static str {
        let span = locate(TEXT, path).expect("a value");
        &TEXT[span]
    }

    #[test]
    fn a_path_finds_its_value() {
        assert_eq!(at("activities[0].windows[0].end"), "1");
        assert_eq!(
            at("activities[0].windows[0]"),
            r#"{ "start": 5, "end": 1 }"#
        );
        assert_eq!(at("activities[1].id"), r#""y \"q\"""#);
        assert_eq!(at("activities[1].after[0].activity"), r#""z""#);
        assert_eq!(at("states.arm.initial"), r#""c""#);
        assert_eq!(at("states.arm.values[1]"), r#""b""#);
        assert_eq!(at("$"), TEXT);
        // Missing: the deepest value on the way.
        assert_eq!(at("activities[0].priority"), at("activities[0]"));
        assert_eq!(at("activities[7].id"), at("activities"));
    }

    #[test]
    fn cut_text_and_deep_nesting_do_not_stop_it() {
        let cut = &TEXT[..TEXT.find("\"end\": 1").expect("end") + 6];
        assert_eq!(
            &cut[locate(cut, "activities[0].windows[0]").expect("value")],
            r#"{ "start": 5, "end":"#,
            "to the end of the text"
        );
        let deep = "[".repeat(100_000);
        assert_eq!(locate(&deep, "activities[0]"), Some(0..deep.len()));
        assert_eq!(locate("  ", "$"), None);
    }

    #[test]
    fn chars_are_counted_for_the_cursor() {
        let text = r#"["é", 12]"#;
        let span = locate(text, "[1]").expect("value");
        assert_eq!(&text[span.clone()], "12");
        assert_eq!(char_range(text, &span), 6..8);
    }
}
