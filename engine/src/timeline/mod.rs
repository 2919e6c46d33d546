//! Timelines: the flight design's core abstraction. Each kind answers "at which
//! start times can this candidate go without violating my constraints" as sorted
//! disjoint integer intervals.

mod intervals;

pub use intervals::{Interval, IntervalSet};
