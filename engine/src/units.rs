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

/// A fixed-point unit: `10^decimals * factor` of it make one planner unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Fixed {
    /// mW per W (and mW·s = mJ per W·s).
    MilliWatt,
    /// mJ per Wh: `10^5 * 36`.
    MilliJoule,
    /// bit per Mbit (and bit/s per Mbit/s).
    Bit,
}

impl Fixed {
    /// `(decimals, factor)`: one planner unit is `10^decimals * factor` of this.
    fn parts(self) -> (i32, i128) {
        match self {
            Fixed::MilliWatt => (3, 1),
            Fixed::MilliJoule => (5, 36),
            Fixed::Bit => (6, 1),
        }
    }
}

/// Which way a plan figure is rounded to fixed point: the safe side for what it
/// is (docs/semantics.md, "Numbers"): loads up, supplies down, a lower limit up,
/// an upper limit down, so that the scheduler never accepts what exact
/// arithmetic on the plan's decimals would refuse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Toward {
    /// The least integer not below the exact value.
    Up,
    /// The greatest integer not above the exact value.
    Down,
}

/// A plan figure in planner units to fixed point, rounded `toward` the given side
/// from its exact decimal value (the shortest decimal that reads back as `x`,
/// i.e. the number as the planner wrote it). Exact figures are not rounded at all.
pub(crate) fn to_fixed(x: f64, unit: Fixed, toward: Toward) -> i64 {
    if !x.is_finite() {
        return 0;
    }
    let (decimals, factor) = unit.parts();
    let pow = 10f64.powi(decimals);
    // Fast path: `x` reads back as a decimal of at most `decimals` places, `q`
    // of them (unique: within 2^50 an ulp of `x * pow` is below 1/4, and two such
    // decimals are a whole unit apart), so the value is exactly `q * factor`.
    let q = (x * pow).round();
    let v = if q.abs() < (1u64 << 50) as f64 && q / pow == x {
        i128::from(q as i64) * factor
    } else {
        exact_scaled(x, decimals, factor, toward)
    };
    // Validation bounds every quantity far inside the i64 range.
    v.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64
}

/// `x * 10^decimals * factor` rounded `toward`, from `x`'s shortest decimal form
/// (`m * 10^e` with `m` an integer of at most 17 digits).
fn exact_scaled(x: f64, decimals: i32, factor: i128, toward: Toward) -> i128 {
    let text = format!("{x:e}");
    let (mantissa, exp) = text.split_once('e').unwrap_or((text.as_str(), "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits = format!("{int}{frac}");
    let m: i128 = digits.parse().unwrap_or(0);
    let frac_len = i32::try_from(frac.len()).unwrap_or(0);
    // x = m * 10^(exp - frac_len); scaled: m * factor * 10^(exp - frac_len + decimals).
    let num = m * factor;
    let e = exp - frac_len + decimals;
    if e >= 0 {
        return 10i128
            .checked_pow(e.unsigned_abs())
            .and_then(|p| num.checked_mul(p))
            .unwrap_or(if num < 0 { i128::MIN } else { i128::MAX });
    }
    let Some(den) = 10i128.checked_pow(e.unsigned_abs()) else {
        // |num| < 10^24 (17 digits times at most 36): the value is strictly
        // between -1 and 1.
        return match (toward, num.cmp(&0)) {
            (Toward::Up, std::cmp::Ordering::Greater) => 1,
            (Toward::Down, std::cmp::Ordering::Less) => -1,
            _ => 0,
        };
    };
    let (quot, rem) = (num.div_euclid(den), num.rem_euclid(den));
    match toward {
        Toward::Down => quot,
        Toward::Up if rem == 0 => quot,
        Toward::Up => quot + 1,
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

/// Plan time `t` as a planner reads it: its sol and local time of day,
/// `Sol 413 14:15:00`.
pub fn format_local(clock: &LocalTime, t: i64) -> String {
    format!(
        "Sol {} {}",
        clock.sol(t),
        format_time_of_day(clock.time_of_day(t))
    )
}

/// Plan time `t` in sol and local time, with the plan second it is (what the
/// JSON documents hold): `Sol 413 14:15:00 (t=600)`.
pub fn format_plan_time(clock: &LocalTime, t: i64) -> String {
    format!("{} (t={t})", format_local(clock, t))
}

/// Reads a time as [`format_local`] and [`format_plan_time`] write it
/// (`Sol 413 14:15:00`, `sol 413 14:15`, with or without the `(t=...)`), or as
/// plan seconds (`600`, `t=600`). A time of day without a sol (`14:15`) is in
/// sol `sol`, and refused without one. `None` for anything else: hours past the
/// sol's length, minutes or seconds past 59, or a time out of range.
pub fn parse_local(clock: &LocalTime, text: &str, sol: Option<i64>) -> Option<i64> {
    let text = text.trim();
    // The plan time written after a sol time is the same time: read the sol time.
    let text = match text.find(" (t=") {
        Some(i) if text.ends_with(')') => &text[..i],
        _ => text,
    };
    let plain = text.strip_prefix("t=").unwrap_or(text).trim();
    if let Ok(t) = plain.parse::<i64>() {
        return Some(t);
    }
    let (sol, clock_text) = match text
        .strip_prefix("Sol ")
        .or_else(|| text.strip_prefix("sol "))
    {
        Some(rest) => {
            let rest = rest.trim_start();
            let end = rest.find(' ')?;
            (rest[..end].parse::<i64>().ok()?, rest[end..].trim())
        }
        None => (sol?, text),
    };
    let mut parts = clock_text.split(':').map(|p| p.parse::<i64>().ok());
    let (h, m) = (parts.next()??, parts.next()??);
    let s = match parts.next() {
        Some(s) => s?,
        None => 0,
    };
    if parts.next().is_some() || h < 0 || !(0..60).contains(&m) || !(0..60).contains(&s) {
        return None;
    }
    let tod = h * 3600 + m * 60 + s;
    let len = clock.sol_length.max(1);
    if tod >= len {
        return None;
    }
    // offset + t = (sol - first_sol) * sol_length + time of day.
    sol.checked_sub(clock.first_sol.unwrap_or(0))?
        .checked_mul(len)?
        .checked_add(tod)?
        .checked_sub(clock.offset)
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
            first_sol: Some(411),
        };
        assert_eq!(format_local(&clock, 0), "Sol 411 18:00:00");
        assert_eq!(format_plan_time(&clock, 600), "Sol 411 18:10:00 (t=600)");
        // Past local midnight the day wraps at the sol length, and the sol counts on.
        assert_eq!(format_local(&clock, 88_775 - 64_800), "Sol 412 00:00:00");
        assert_eq!(
            format_local(&clock, 88_775 - 64_800 - 1),
            "Sol 411 24:39:34"
        );
        assert_eq!(format_local(&clock, -64_801), "Sol 410 24:39:34");
        let unnamed = LocalTime {
            first_sol: None,
            ..clock
        };
        assert_eq!(format_local(&unnamed, 88_775 * 3), "Sol 3 18:00:00");
        assert_eq!(format_time_of_day(88_774), "24:39:34");
        assert_eq!(format_span(45), "45 s");
        assert_eq!(format_span(725), "12 min 05 s");
        assert_eq!(format_span(-3600 * 3 - 420 - 9), "-3 h 07 min");
    }

    #[test]
    fn sol_times_read_back_as_written() {
        let clock = LocalTime {
            sol_length: 88_775,
            offset: 64_800,
            first_sol: Some(411),
        };
        for t in [
            -200_000, -1, 0, 1, 23_974, 23_975, 59_080, 177_550, 3_000_000,
        ] {
            assert_eq!(parse_local(&clock, &format_local(&clock, t), None), Some(t));
            assert_eq!(
                parse_local(&clock, &format_plan_time(&clock, t), None),
                Some(t)
            );
            assert_eq!(parse_local(&clock, &t.to_string(), None), Some(t));
        }
        assert_eq!(
            parse_local(&clock, " sol 412 09:45 ", None),
            Some(59_080 - 5)
        );
        assert_eq!(parse_local(&clock, "t=42", None), Some(42));
        // A time of day alone is in the sol given.
        assert_eq!(parse_local(&clock, "09:45:05", Some(412)), Some(59_080));
        assert_eq!(parse_local(&clock, "09:45:05", None), None);
        // 24:39:34 is the last second of a Mars sol; 24:39:35 is the next sol.
        assert!(parse_local(&clock, "Sol 412 24:39:34", None).is_some());
        for bad in [
            "Sol 412 24:39:35",
            "Sol 412 10:60",
            "Sol 412 10:00:60",
            "Sol x 10:00",
            "Sol 412",
            "1e3",
            "Sol 412 10:00:00:00",
            "Sol 412 -1:00",
        ] {
            assert_eq!(parse_local(&clock, bad, Some(412)), None, "{bad}");
        }
        assert_eq!(
            parse_local(&clock, "Sol 9223372036854775807 10:00", None),
            None
        );
    }

    #[test]
    fn quantities_convert_from_fixed_point() {
        assert_eq!(format_wh(3_600_000 * 1034 + 720_000), "1034.2 Wh");
        assert_eq!(format_watts(750_000), "750.0 W");
        assert_eq!(mbit(-2_500_000), -2.5);
        assert_eq!(to_fixed(f64::NAN, Fixed::MilliWatt, Toward::Up), 0);
    }

    #[test]
    fn exact_figures_are_not_rounded() {
        for t in [Toward::Up, Toward::Down] {
            assert_eq!(to_fixed(0.1, Fixed::MilliWatt, t), 100);
            assert_eq!(to_fixed(-2.5, Fixed::MilliWatt, t), -2500);
            assert_eq!(to_fixed(1000.5, Fixed::MilliJoule, t), 3_601_800_000);
            assert_eq!(to_fixed(0.00001, Fixed::MilliJoule, t), 36);
            assert_eq!(to_fixed(1.000001, Fixed::Bit, t), 1_000_001);
            assert_eq!(to_fixed(123_456.789, Fixed::MilliWatt, t), 123_456_789);
        }
    }

    #[test]
    fn finer_figures_round_toward_the_side_asked() {
        assert_eq!(to_fixed(0.1234, Fixed::MilliWatt, Toward::Up), 124);
        assert_eq!(to_fixed(0.1234, Fixed::MilliWatt, Toward::Down), 123);
        assert_eq!(to_fixed(-0.1234, Fixed::MilliWatt, Toward::Up), -123);
        assert_eq!(to_fixed(-0.1234, Fixed::MilliWatt, Toward::Down), -124);
        // 1 mJ is 1/3600000 Wh: 0.000001 Wh is 3.6 mJ.
        assert_eq!(to_fixed(0.000001, Fixed::MilliJoule, Toward::Up), 4);
        assert_eq!(to_fixed(0.000001, Fixed::MilliJoule, Toward::Down), 3);
        assert_eq!(
            to_fixed(999.9999999, Fixed::MilliJoule, Toward::Up),
            3_600_000_000
        );
        assert_eq!(
            to_fixed(999.9999999, Fixed::MilliJoule, Toward::Down),
            3_599_999_999
        );
        // Far below the resolution, and denormal.
        assert_eq!(to_fixed(1e-300, Fixed::MilliWatt, Toward::Up), 1);
        assert_eq!(to_fixed(1e-300, Fixed::MilliWatt, Toward::Down), 0);
        assert_eq!(to_fixed(-5e-324, Fixed::Bit, Toward::Down), -1);
        assert_eq!(to_fixed(-5e-324, Fixed::Bit, Toward::Up), 0);
        // Large figures with a fraction below the resolution.
        assert_eq!(
            to_fixed(1e9 + 0.0005, Fixed::MilliWatt, Toward::Up),
            1_000_000_000_001
        );
        assert_eq!(
            to_fixed(1e9 + 0.0005, Fixed::MilliWatt, Toward::Down),
            1_000_000_000_000
        );
    }

    #[test]
    fn the_fast_path_agrees_with_the_exact_one() {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let m = (x % 2_000_000_000) as i64 - 1_000_000_000;
            let k = (x >> 40) % 9;
            let v = m as f64 / 10f64.powi(k as i32);
            for unit in [Fixed::MilliWatt, Fixed::MilliJoule, Fixed::Bit] {
                let (d, f) = unit.parts();
                for t in [Toward::Up, Toward::Down] {
                    assert_eq!(
                        i128::from(to_fixed(v, unit, t)),
                        exact_scaled(v, d, f, t),
                        "{v} {unit:?} {t:?}"
                    );
                }
            }
        }
    }
}
