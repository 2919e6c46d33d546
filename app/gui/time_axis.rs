//! The one place where plan time and screen x are mapped to each other (in `f64`),
//! shared by the Gantt rows and the plots, and where the time ticks are chosen:
//! round LMST times of day, and sol boundaries. The visible range itself,
//! [`TimeAxis`], is state (`crate::state::TimeAxis`: zoom, pan, reveal); the
//! pixel mapping is added to it here, where the pixels are.

use eframe::egui::Rect;
use solscope_engine::{LMST_SECONDS_PER_SOL, LocalTime, format_lmst, time_of_day_of_lmst};

pub use crate::state::TimeAxis;

/// Local-time tick steps (LMST seconds), finest first: a tick sits where the
/// LMST time of day is a multiple of the step, so they restart at every
/// midnight.
const TICK_STEPS: [i64; 13] = [
    10,
    30,
    60,
    300,
    600,
    900,
    1800,
    3600,
    7200,
    10800,
    21600,
    43200,
    i64::MAX,
];

/// One labelled time on an axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// Plan time.
    pub t: f64,
    /// `Sol 412` at a sol boundary, else the local time of day (`14:00`, or
    /// `14:05:30` when the step is under a minute). Empty for a sol boundary
    /// drawn as a line without a label (too many sols to label each).
    pub label: String,
    /// A sol boundary (local midnight).
    pub sol_start: bool,
    /// The step this tick belongs to (the sol length for sol boundaries).
    pub step: f64,
}

/// The label of a tick at plan time `t` on a grid of `step` seconds: `Sol 412`
/// at local midnight, else the LMST time of day, `14:00`, with seconds
/// (`14:05:30`) when the step is under a minute (of LMST). The ruler and the
/// plots' axes both label so.
pub fn tick_label(clock: &LocalTime, t: i64, step: f64) -> String {
    let tod = clock.time_of_day(t);
    let text = format_lmst(clock, t);
    if tod == 0 {
        format!("Sol {}", clock.sol(t))
    } else if step < 60.0 {
        text
    } else {
        text[..5].to_string()
    }
}

/// The ticks of `axis` shown `width` pixels wide, at least `min_gap` pixels
/// apart: the finest round local-time step that keeps them apart, and every sol
/// boundary (labelled every sol, or every few sols when they are too close).
pub fn ticks(axis: &TimeAxis, width: f64, clock: &LocalTime, min_gap: f64) -> Vec<Tick> {
    let per_px = axis.seconds_per_pixel(width);
    let sol = clock.sol_length.max(1);
    // Plan seconds per LMST second.
    let mars = sol as f64 / LMST_SECONDS_PER_SOL as f64;
    let step = TICK_STEPS
        .into_iter()
        .find(|&s| s >= LMST_SECONDS_PER_SOL || (s as f64) * mars / per_px >= min_gap)
        .unwrap_or(i64::MAX);
    let label_every = ((min_gap * per_px) / sol as f64).ceil().max(1.0) as i64;
    let (lo, hi) = (axis.start.floor() as i64, axis.end.ceil() as i64);
    let mut out = Vec::new();
    // The local midnight at or before the start, then one sol at a time.
    let mut midnight = lo - clock.time_of_day(lo);
    while midnight <= hi {
        let number = clock.sol(midnight);
        if midnight >= lo {
            out.push(Tick {
                t: midnight as f64,
                label: if number.rem_euclid(label_every) == 0 {
                    tick_label(clock, midnight, sol as f64)
                } else {
                    String::new()
                },
                sol_start: true,
                step: sol as f64,
            });
        }
        if step < LMST_SECONDS_PER_SOL {
            // The first LMST step in the visible part of this sol.
            let lmst_lo = ((lo - midnight) as f64 / mars).floor().max(0.0) as i64;
            let mut lmst = (lmst_lo.max(step) + step - 1) / step * step;
            while lmst < LMST_SECONDS_PER_SOL {
                let t = midnight + time_of_day_of_lmst(sol, lmst);
                if t > hi {
                    break;
                }
                // No tick whose label would run into the next sol's.
                if t >= lo && (midnight + sol - t) as f64 / per_px >= min_gap {
                    out.push(Tick {
                        t: t as f64,
                        label: tick_label(clock, t, step as f64),
                        sol_start: false,
                        step: step as f64 * mars,
                    });
                }
                lmst += step;
            }
        }
        midnight += sol;
    }
    out
}

/// The pixel side of the visible range: where a time is drawn inside a rect.
impl TimeAxis {
    /// Screen x of plan time `t` inside `rect`.
    pub fn x(&self, t: f64, rect: Rect) -> f64 {
        f64::from(rect.left()) + (t - self.start) / self.span() * f64::from(rect.width())
    }

    /// Plan time at screen x inside `rect`.
    pub fn t(&self, x: f64, rect: Rect) -> f64 {
        self.start + (x - f64::from(rect.left())) / f64::from(rect.width()).max(1.0) * self.span()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::egui::{Rect, pos2};

    fn clock() -> LocalTime {
        LocalTime {
            sol_length: 88_775,
            offset: 64_800,
            first_sol: Some(411),
        }
    }

    #[test]
    fn no_tick_runs_into_a_sol_label() {
        // Around a local midnight at zooms where the last tick step of the
        // sol is shorter than a label.
        for width in [600.0, 1000.0, 1400.0, 2600.0] {
            for span in [20_000.0, 40_000.0, 88_775.0] {
                let axis = TimeAxis::new(23_975.0 - span / 2.0, 23_975.0 + span / 2.0);
                let t = ticks(&axis, width, &clock(), 60.0);
                let px = axis.seconds_per_pixel(width);
                for pair in t.windows(2).filter(|p| p[1].sol_start) {
                    assert!(
                        (pair[1].t - pair[0].t) / px >= 60.0,
                        "{} too close to {} ({width} px, {span} s)",
                        pair[0].label,
                        pair[1].label
                    );
                }
            }
        }
    }

    #[test]
    fn ticks_sit_on_round_local_times_and_sol_boundaries() {
        // Two sols on 1,000 px: hours would be 40 px apart, so every 3 h.
        let axis = TimeAxis::new(0.0, 177_550.0);
        let t = ticks(&axis, 1000.0, &clock(), 60.0);
        let sols: Vec<&str> = t
            .iter()
            .filter(|k| k.sol_start)
            .map(|k| k.label.as_str())
            .collect();
        assert_eq!(sols, ["Sol 412", "Sol 413"]);
        // Plan time 0 is 17:31:06 LMST; 18:00 LMST is 1782 s later.
        assert_eq!((t[0].t, t[0].label.as_str()), (1_782.0, "18:00"), "{t:?}");
        assert_eq!((t[1].t, t[1].label.as_str()), (12_879.0, "21:00"));
        let first_sol = t.iter().position(|k| k.sol_start).expect("a sol");
        assert_eq!(t[first_sol].t, 23_975.0, "local midnight");
        assert_eq!(t[first_sol + 1].label, "03:00");
        for pair in t.windows(2) {
            assert!(pair[1].t > pair[0].t, "sorted: {pair:?}");
            let gap = (pair[1].t - pair[0].t) / axis.seconds_per_pixel(1000.0);
            assert!(gap >= 30.0, "not crowded: {pair:?}");
        }
        // Zoomed to 20 minutes (10:00 to 10:20 LMST): ticks every five
        // minutes, labelled hh:mm.
        let axis = TimeAxis::new(60_965.0, 62_198.0);
        let t = ticks(&axis, 1000.0, &clock(), 60.0);
        assert!(t.iter().all(|k| !k.sol_start));
        assert_eq!(t[0].label, "10:00");
        assert_eq!(t[1].label, "10:05");
        assert_eq!(t.len(), 5, "{t:?}");
        // Thirty sols on 600 px: only sol boundaries, every few labelled.
        let axis = TimeAxis::new(0.0, 30.0 * 88_775.0);
        let t = ticks(&axis, 600.0, &clock(), 60.0);
        assert!(t.iter().all(|k| k.sol_start));
        assert_eq!(t.len(), 30);
        let labelled: Vec<&Tick> = t.iter().filter(|k| !k.label.is_empty()).collect();
        assert!(labelled.len() >= 5 && labelled.len() <= 10, "{labelled:?}");
        for pair in labelled.windows(2) {
            let gap = (pair[1].t - pair[0].t) / axis.seconds_per_pixel(600.0);
            assert!(gap >= 60.0, "labels apart: {pair:?}");
        }
    }

    #[test]
    fn maps_both_ways_and_zooms_about_a_point() {
        let rect = Rect::from_min_max(pos2(100.0, 0.0), pos2(1100.0, 10.0));
        let mut axis = TimeAxis::new(0.0, 88775.0);
        let x = axis.x(44387.5, rect);
        assert!((x - 600.0).abs() < 1e-9);
        assert!((axis.t(x, rect) - 44387.5).abs() < 1e-6);
        axis.zoom_about(44387.5, 4.0, (0.0, 88775.0));
        assert!((axis.span() - 88775.0 / 4.0).abs() < 1e-6);
        assert!(
            (axis.x(44387.5, rect) - 600.0).abs() < 1e-6,
            "the point under the cursor stays"
        );
        axis.pan(-1e9, (0.0, 88775.0));
        assert_eq!(axis.start, 0.0);
        axis.zoom_about(0.0, 1e-9, (0.0, 88775.0));
        assert_eq!((axis.start, axis.end), (0.0, 88775.0));
    }
}
