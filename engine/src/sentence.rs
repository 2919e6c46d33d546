//! Times, ranges of times and lengths of time as the planner-facing sentences
//! say them (`explain/text.rs`, `execute/text.rs`, `flex/text.rs`): one phrasing
//! of each, so the notes of the documents, the `--text` outputs and the app read
//! alike. The numbers themselves are formatted in `units`; this module only puts
//! them in prose.

use crate::model::LocalTime;
use crate::units::{format_document_time, format_span};

/// A time in a sentence: its sol and local time with the plan second it is,
/// `Sol 413 14:15:00 (t=600)`, as the documents write it
/// ([`format_document_time`]; the text outputs and the app say it in LMST
/// through `units::lmst_sentence`).
pub(crate) fn time(clock: &LocalTime, t: i64) -> String {
    format_document_time(clock, t)
}

/// A range of times in a list, both ends included:
/// `Sol 413 14:15:00 (t=600)–Sol 413 14:25:00 (t=1200)` (as in "starts A–B").
pub(crate) fn range(clock: &LocalTime, lo: i64, hi: i64) -> String {
    format!("{}–{}", time(clock, lo), time(clock, hi))
}

/// A range of times, or the one time it is when both ends are the same.
pub(crate) fn range_or_time(clock: &LocalTime, lo: i64, hi: i64) -> String {
    if lo == hi {
        time(clock, lo)
    } else {
        range(clock, lo, hi)
    }
}

/// The bounds an event may happen between, both included: `from A to B` (as in
/// "may start from A to B", what the flexible schedule's start bounds read as).
pub(crate) fn between(clock: &LocalTime, lo: i64, hi: i64) -> String {
    format!("from {} to {}", time(clock, lo), time(clock, hi))
}

/// A length of time for reading (to the minute past an hour): `12 min 05 s`.
pub(crate) fn span(seconds: i64) -> String {
    format_span(seconds)
}

/// The range a length of time may take: `50 min to 1 h 35 min`.
pub(crate) fn spans(min: i64, max: i64) -> String {
    format!("{} to {}", span(min), span(max))
}

/// A length of time to the second, where the exact count matters (an actual
/// duration against its planned one): `6000 s`.
pub(crate) fn seconds(seconds: i64) -> String {
    format!("{seconds} s")
}

/// A signed difference of lengths of time to the second: `+2400 s`, `-5 s`,
/// `0 s`.
pub(crate) fn seconds_delta(delta: i64) -> String {
    let sign = if delta > 0 { "+" } else { "" };
    format!("{sign}{delta} s")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clock() -> LocalTime {
        LocalTime {
            sol_length: 88_775,
            offset: 64_800,
            first_sol: Some(411),
        }
    }

    #[test]
    fn times_and_ranges_read_as_the_documents_print_them() {
        let c = clock();
        assert_eq!(time(&c, 600), "Sol 411 18:10:00 (t=600)");
        assert_eq!(
            range(&c, 0, 600),
            "Sol 411 18:00:00 (t=0)–Sol 411 18:10:00 (t=600)"
        );
        // A range of one time is still a range; `range_or_time` says it once.
        assert_eq!(
            range(&c, 600, 600),
            "Sol 411 18:10:00 (t=600)–Sol 411 18:10:00 (t=600)"
        );
        assert_eq!(range_or_time(&c, 600, 600), "Sol 411 18:10:00 (t=600)");
        assert_eq!(range_or_time(&c, 0, 600), range(&c, 0, 600));
        assert_eq!(
            between(&c, 0, 600),
            "from Sol 411 18:00:00 (t=0) to Sol 411 18:10:00 (t=600)"
        );
    }

    #[test]
    fn lengths_of_time_read_rounded_or_exact() {
        assert_eq!(span(725), "12 min 05 s");
        assert_eq!(spans(3000, 5700), "50 min to 1 h 35 min");
        assert_eq!(seconds(6000), "6000 s");
        assert_eq!(seconds_delta(2400), "+2400 s");
        assert_eq!(seconds_delta(-5), "-5 s");
        assert_eq!(seconds_delta(0), "0 s");
    }
}
