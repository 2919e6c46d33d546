//! The visible time range (plan seconds): zoomed, panned and moved to reveal a
//! span, within the plan's bounds. Where a time is drawn on screen is the
//! gui's (`gui::time_axis`).

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

/// The margin [`TimeAxis::reveal`] leaves on each side, as a share of the span
/// shown.
const REVEAL_MARGIN: f64 = 0.05;

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

    /// Brings `[lo, hi]` into view with a margin, changing the range as little
    /// as it can: nothing when it is wholly visible, a pan keeping the zoom
    /// when it fits, else a zoom out to it (within `bounds`).
    pub fn reveal(&mut self, (lo, hi): (f64, f64), bounds: (f64, f64)) {
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        if lo >= self.start && hi <= self.end {
            return;
        }
        let span = self.span();
        let margin = span * REVEAL_MARGIN;
        if hi - lo + 2.0 * margin <= span {
            // Pan just past it: from the side it lies on.
            self.start = if lo < self.start {
                lo - margin
            } else {
                hi + margin - span
            };
            self.end = self.start + span;
        } else {
            let margin = ((hi - lo) * REVEAL_MARGIN).max(MIN_SPAN);
            *self = Self::new(lo - margin, hi + margin);
        }
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

    #[test]
    fn reveal_pans_or_zooms_out_only_as_far_as_needed() {
        let bounds = (0.0, 100_000.0);
        let mut axis = TimeAxis::new(10_000.0, 20_000.0);
        // Wholly visible: nothing moves.
        axis.reveal((12_000.0, 13_000.0), bounds);
        assert_eq!((axis.start, axis.end), (10_000.0, 20_000.0));
        // Later, fits: a pan keeping the span, the end a margin past it.
        axis.reveal((30_000.0, 31_000.0), bounds);
        assert_eq!((axis.start, axis.end), (21_500.0, 31_500.0));
        // Earlier, cut by the left edge: the start a margin before it.
        axis.reveal((21_000.0, 22_000.0), bounds);
        assert_eq!((axis.start, axis.end), (20_500.0, 30_500.0));
        // Longer than the span: zoomed out to it with a margin.
        axis.reveal((40_000.0, 60_000.0), bounds);
        assert_eq!((axis.start, axis.end), (39_000.0, 61_000.0));
        // Within the bounds at their edges.
        axis.reveal((99_000.0, 100_000.0), bounds);
        assert_eq!((axis.start, axis.end), (78_000.0, 100_000.0));
        axis.reveal((0.0, 100_000.0), bounds);
        assert_eq!((axis.start, axis.end), (0.0, 100_000.0));
    }
}
