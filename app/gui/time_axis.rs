//! The one place where plan time and screen x are mapped to each other (in `f64`),
//! shared by the Gantt rows and the plots.

use eframe::egui::Rect;

/// The visible time range `[start, end)` in plan seconds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TimeAxis {
    /// First visible plan second.
    pub start: f64,
    /// End of the visible range.
    pub end: f64,
}

/// Shortest visible span (seconds): zooming stops there.
const MIN_SPAN: f64 = 10.0;

impl TimeAxis {
    /// The whole horizon.
    pub fn new(start: f64, end: f64) -> Self {
        Self {
            start,
            end: end.max(start + MIN_SPAN),
        }
    }

    /// Visible span in seconds.
    pub fn span(&self) -> f64 {
        self.end - self.start
    }

    /// Screen x of plan time `t` inside `rect`.
    pub fn x(&self, t: f64, rect: Rect) -> f64 {
        f64::from(rect.left()) + (t - self.start) / self.span() * f64::from(rect.width())
    }

    /// Plan time at screen x inside `rect`.
    pub fn t(&self, x: f64, rect: Rect) -> f64 {
        self.start + (x - f64::from(rect.left())) / f64::from(rect.width()).max(1.0) * self.span()
    }

    /// Seconds per pixel at `width` pixels.
    pub fn seconds_per_pixel(&self, width: f64) -> f64 {
        self.span() / width.max(1.0)
    }

    /// Zooms by `factor` (> 1 zooms in) keeping `t` fixed on screen, within `bounds`.
    pub fn zoom_about(&mut self, t: f64, factor: f64, bounds: (f64, f64)) {
        let factor = if factor.is_finite() && factor > 0.0 {
            factor
        } else {
            1.0
        };
        let span = (self.span() / factor).clamp(MIN_SPAN, bounds.1 - bounds.0);
        let left = (t - self.start) / self.span();
        self.start = t - left * span;
        self.end = self.start + span;
        self.clamp(bounds);
    }

    /// Moves by `dt` seconds within `bounds`.
    pub fn pan(&mut self, dt: f64, bounds: (f64, f64)) {
        self.start += dt;
        self.end += dt;
        self.clamp(bounds);
    }

    /// Keeps the range inside `bounds` without changing its span where possible.
    pub fn clamp(&mut self, (lo, hi): (f64, f64)) {
        let span = self.span().min(hi - lo).max(MIN_SPAN.min(hi - lo));
        if self.start < lo {
            self.start = lo;
        }
        if self.start + span > hi {
            self.start = hi - span;
        }
        self.end = self.start + span;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::egui::{Rect, pos2};

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
