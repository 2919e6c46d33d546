//! Resource profiles in planner units, as of any step: what the schedule document
//! prints and the app plots.

use serde::Serialize;

use super::Schedule;
use crate::units::{mbit, watts, wh};

/// Resource profiles: `(t, value)` breakpoints in plan seconds and planner units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Profiles {
    /// State of charge (Wh), linear between points.
    pub soc: Vec<(i64, f64)>,
    /// Total peak power (W), constant from each point to the next; the last point
    /// is the horizon end, with the value of the one before.
    pub peak_power: Vec<(i64, f64)>,
    /// Data volume (Mbit), linear between points.
    pub data_volume: Vec<(i64, f64)>,
}

impl Schedule {
    /// The state of charge, peak power and data volume profiles after step `k`
    /// (0 = before step 1).
    pub fn profiles_after(&self, k: usize) -> Profiles {
        let state = self.state_after(k);
        let soc = state
            .soc
            .profile()
            .into_iter()
            .map(|(t, level)| (t, wh(level)))
            .collect();
        // The data timeline stores the volume negated (its floor is the cap);
        // `+ 0.0` turns -0.0 into 0.0.
        let data_volume = state
            .data
            .profile()
            .into_iter()
            .map(|(t, level)| (t, mbit(-level) + 0.0))
            .collect();
        let mut peak_power: Vec<(i64, f64)> = state
            .peak
            .points()
            .iter()
            .map(|&(t, mw)| (t, watts(mw)))
            .collect();
        if let Some(&(_, last)) = peak_power.last() {
            peak_power.push((self.problem.h1, last));
        }
        Profiles {
            soc,
            peak_power,
            data_volume,
        }
    }
}
