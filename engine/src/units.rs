//! Units and time, in one place: the fixed point the scheduler computes in (mW, mJ,
//! bit) against the planner's units (W, Wh, Mbit), and how plan times read (local
//! time of day, and the "plan seconds (hh:mm:ss)" label). Every renderer (the
//! schedule and explanation documents, the explanation text, the app) formats
//! through here, so a number reads the same everywhere.

use crate::model::LocalTime;

/// mW per W.
pub const MW_PER_W: f64 = 1_000.0;
/// mJ per Wh.
pub const MJ_PER_WH: f64 = 3_600_000.0;
/// bit per Mbit (and bit/s per Mbit/s).
pub const BIT_PER_MBIT: f64 = 1_000_000.0;

/// Rounds `x * scale` to the nearest integer (half away from zero): a plan figure
/// in planner units to fixed point.
pub(crate) fn to_fixed(x: f64, scale: f64) -> i64 {
    let v = (x * scale).round();
    if v.is_finite() {
        // Validation bounds every quantity far inside the i64 range.
        v.clamp(i64::MIN as f64, i64::MAX as f64) as i64
    } else {
        0
    }
}

/// Energy in mJ as Wh.
pub fn wh(mj: i128) -> f64 {
    mj as f64 / MJ_PER_WH
}

/// Power in mW as W.
pub fn watts(mw: i64) -> f64 {
    mw as f64 / MW_PER_W
}

/// Data volume in bit as Mbit.
pub fn mbit(bit: i128) -> f64 {
    bit as f64 / BIT_PER_MBIT
}

/// Energy for reading: `1034.2 Wh`.
pub fn format_wh(mj: i128) -> String {
    format!("{:.1} Wh", wh(mj))
}

/// Power for reading: `750.0 W`.
pub fn format_watts(mw: i64) -> String {
    format!("{:.1} W", watts(mw))
}

/// A time of day (seconds after local midnight) as `hh:mm:ss`.
pub fn format_time_of_day(time_of_day: i64) -> String {
    format!(
        "{:02}:{:02}:{:02}",
        time_of_day / 3600,
        (time_of_day / 60) % 60,
        time_of_day % 60
    )
}

/// The local time of day of plan time `t` as `hh:mm:ss`.
pub fn format_local(clock: &LocalTime, t: i64) -> String {
    format_time_of_day(clock.time_of_day(t))
}

/// Plan time `t` with its local time of day: `600 (00:10:00)`.
pub fn format_plan_time(clock: &LocalTime, t: i64) -> String {
    format!("{t} ({})", format_local(clock, t))
}

/// A length of time for reading: `45 s`, `12 min 05 s`, `3 h 07 min`.
pub fn format_span(seconds: i64) -> String {
    let sign = if seconds < 0 { "-" } else { "" };
    let s = seconds.unsigned_abs();
    if s < 60 {
        format!("{sign}{s} s")
    } else if s < 3600 {
        match s % 60 {
            0 => format!("{sign}{} min", s / 60),
            r => format!("{sign}{} min {r:02} s", s / 60),
        }
    } else {
        format!("{sign}{} h {:02} min", s / 3600, (s / 60) % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_read_in_plan_seconds_and_local_time() {
        let clock = LocalTime {
            sol_length: 88_775,
            offset: 64_800,
        };
        assert_eq!(format_local(&clock, 0), "18:00:00");
        assert_eq!(format_plan_time(&clock, 600), "600 (18:10:00)");
        // Past local midnight the day wraps at the sol length.
        assert_eq!(format_local(&clock, 88_775 - 64_800), "00:00:00");
        assert_eq!(format_time_of_day(88_774), "24:39:34");
        assert_eq!(format_span(45), "45 s");
        assert_eq!(format_span(725), "12 min 05 s");
        assert_eq!(format_span(-3600 * 3 - 420 - 9), "-3 h 07 min");
    }

    #[test]
    fn quantities_convert_from_fixed_point() {
        assert_eq!(format_wh(3_600_000 * 1034 + 720_000), "1034.2 Wh");
        assert_eq!(format_watts(750_000), "750.0 W");
        assert_eq!(mbit(-2_500_000), -2.5);
        assert_eq!(to_fixed(1.5, 1.0), 2);
        assert_eq!(to_fixed(-1.5, 1.0), -2);
        assert_eq!(to_fixed(f64::NAN, MW_PER_W), 0);
    }
}
