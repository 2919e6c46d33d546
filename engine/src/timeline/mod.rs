//! Timelines: the flight design's core abstraction. Each kind answers "at which
//! start times can this candidate go without violating my constraints" as sorted
//! disjoint integer intervals.
//!
//! - [`StateTimeline`]: a named state's value over time (requirements, effects).
//! - [`UnitTimeline`] / [`atomic_valid`]: unit resources (no overlap).
//! - [`TaggedSpans`]: placed intervals with a tag (UHF), sorted for range queries.
//! - [`claimable_valid`]: sequence engines and peak power (usage under a cap).
//! - [`cumulative_valid`]: a total over a time range (handover data produced).
//! - [`RateTimeline`]: cumulative-rate levels (state of charge, data volume).

mod chunks;
mod intervals;
mod kinds;
mod minimum;
mod rate;
mod step;

pub use intervals::{Interval, IntervalSet};
pub use kinds::{
    StateTimeline, TaggedSpans, UnitTimeline, atomic_valid, claimable_valid, cumulative_valid,
};
pub use rate::RateTimeline;
pub use step::StepFn;

/// A small deterministic generator for the timeline tests: `next(m)` is in
/// `[0, m)`.
#[cfg(test)]
fn xorshift(mut seed: u64) -> impl FnMut(i64) -> i64 {
    move |m: i64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % (m as u64)) as i64
    }
}
