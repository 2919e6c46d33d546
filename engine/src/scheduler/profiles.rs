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
        profiles_of(self, &state, state.soc.profile(), &state.peak)
    }

    /// The profiles after step `k` as they would be had activity `a` also been
    /// placed at `start` for `duration` whatever the peak and energy checks say
    /// (with the awake period and preheats it would bring): what a placement
    /// that failed on `min_soc`, `handover_soc` or `max_peak_power` would have
    /// caused, for showing the violation. The data volume is the one after
    /// step `k`. `None` when the placement is impossible for a structural
    /// reason (it would have no load to show).
    pub fn profiles_if_placed(
        &self,
        k: usize,
        a: usize,
        start: i64,
        duration: i64,
    ) -> Option<Profiles> {
        let state = self.state_after(k);
        let pieces = state.load_if_placed(a, start, duration).ok()?;
        let drain = super::phase2::drain_of_pieces(&pieces);
        let mut peak = state.peak.clone();
        for &(x, y, _, dp) in &pieces {
            peak.add(x, y, dp);
        }
        Some(profiles_of(
            self,
            &state,
            state.soc.profile_with_drain(&drain),
            &peak,
        ))
    }
}

/// [`Profiles`] in planner units from a state of charge profile (mJ), a peak
/// power step function (mW) and `state`'s data volume.
fn profiles_of(
    schedule: &Schedule,
    state: &super::State<'_>,
    soc: Vec<(i64, i128)>,
    peak: &crate::timeline::StepFn,
) -> Profiles {
    let soc = soc.into_iter().map(|(t, level)| (t, wh(level))).collect();
    // The data timeline stores the volume negated (its floor is the cap);
    // `+ 0.0` turns -0.0 into 0.0.
    let data_volume = state
        .data
        .profile()
        .into_iter()
        .map(|(t, level)| (t, mbit(-level) + 0.0))
        .collect();
    let mut peak_power: Vec<(i64, f64)> = peak
        .points()
        .iter()
        .map(|&(t, mw)| (t, watts(mw)))
        .collect();
    if let Some(&(_, last)) = peak_power.last() {
        peak_power.push((schedule.problem.h1, last));
    }
    Profiles {
        soc,
        peak_power,
        data_volume,
    }
}
