//! Robustness: mutated plans (characters dropped, numbers replaced by extreme
//! values, fields swapped) never panic anywhere in load → schedule → explain; an
//! invalid one is an error with a JSON path. A cheap, always-on complement to
//! coverage-guided fuzzing.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use proptest::prelude::*;
use solscope_engine::{Error, ExplainOptions, explain, load_plan, schedule};

const SEEDS: [&str; 3] = [
    include_str!("../../assets/examples/pitfall.json"),
    include_str!("../../assets/examples/drill-sol.json"),
    include_str!("../../assets/tutorial-plan.json"),
];

const EXTREMES: [&str; 12] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "9223372036854775807",
    "-9223372036854775808",
    "1e-300",
    "0.5",
    "3600",
    "88775",
    "\"x\"",
    "null",
];

/// Replaces the `k`-th number token of `text` with `with`.
fn replace_number(text: &str, k: usize, with: &str) -> String {
    let bytes = text.as_bytes();
    let mut i = 0;
    let mut seen = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let starts = (c == b'-' || c.is_ascii_digit())
            && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric() && bytes[i - 1] != b'_');
        if starts {
            let mut j = i + 1;
            while j < bytes.len() && (bytes[j].is_ascii_digit() || b".eE+-".contains(&bytes[j])) {
                j += 1;
            }
            if seen == k {
                return format!("{}{with}{}", &text[..i], &text[j..]);
            }
            seen += 1;
            i = j;
        } else {
            i += 1;
        }
    }
    text.to_string()
}

fn exercise(text: &str) {
    match load_plan(text) {
        Ok(loaded) => {
            let sched = schedule(&loaded.plan).expect("a valid plan schedules");
            let opts = ExplainOptions {
                activity: None,
                no_suggestions: true,
            };
            explain(&loaded.plan, &sched, &opts).expect("explains");
        }
        Err(Error::Invalid { path, reason }) => {
            assert!(!path.is_empty() && !reason.is_empty());
        }
        Err(other) => panic!("unexpected error kind: {other}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn extreme_numbers_never_panic(seed in 0..SEEDS.len(), k in 0usize..200, e in 0..EXTREMES.len()) {
        exercise(&replace_number(SEEDS[seed], k, EXTREMES[e]));
    }

    #[test]
    fn dropped_or_duplicated_text_never_panics(seed in 0..SEEDS.len(), at in 0usize..5000, len in 1usize..40, dup in any::<bool>()) {
        let text = SEEDS[seed];
        let at = at.min(text.len());
        let mut end = (at + len).min(text.len());
        while !text.is_char_boundary(end) { end -= 1; }
        let mut start = at;
        while !text.is_char_boundary(start) { start -= 1; }
        let mutated = if dup {
            format!("{}{}{}", &text[..end], &text[start..end], &text[end..])
        } else {
            format!("{}{}", &text[..start], &text[end..])
        };
        exercise(&mutated);
    }
}
