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

/// Why a text does not read as a quantity, a length of time or a time of day
/// (the `parse_*` functions beside the printers).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("\"{text}\" is not {expected}")]
pub struct ParseUnitError {
    /// The text read.
    pub text: String,
    /// What it should have been, with an example of it: `a power in W (750.0 W)`.
    pub expected: &'static str,
}

impl ParseUnitError {
    fn new(text: &str, expected: &'static str) -> Self {
        Self {
            text: text.to_string(),
            expected,
        }
    }
}

/// A decimal number in a planner unit, with or without the unit after it
/// (`750.0 W`, `750W`, `750`), times `scale` and rounded to the nearest
/// integer; `None` when it is not one, or out of range.
fn parse_scaled(text: &str, unit: &str, scale: f64, max: f64) -> Option<i128> {
    let text = text.trim();
    let number = text.strip_suffix(unit).unwrap_or(text).trim_end();
    // Only digits, signs, points and exponents: Rust also reads `inf`, `NaN`.
    if number.is_empty()
        || !number
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.' | b'e' | b'E'))
    {
        return None;
    }
    let x = number.parse::<f64>().ok()?;
    let v = (x * scale).round();
    (v.abs() <= max).then_some(v as i128)
}

/// A planner unit of a quantity, with the one rounding rule it is read with
/// (one decimal for each: `474.9 Wh`, `750.0 W`, `16666.7 Mbit`), whatever
/// shows it: a plot's limit line and hover readout, a table, a sentence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// Energy (state of charge) in Wh.
    Wh,
    /// Power in W.
    W,
    /// Data volume in Mbit.
    Mbit,
}

impl Unit {
    /// Its symbol: `Wh`, `W`, `Mbit`.
    pub fn symbol(self) -> &'static str {
        match self {
            Unit::Wh => "Wh",
            Unit::W => "W",
            Unit::Mbit => "Mbit",
        }
    }

    /// How many decimals a value in it is read with.
    pub fn decimals(self) -> usize {
        1
    }

    /// A value in this unit for reading, rounded by its rule: `474.9 Wh` for
    /// `474.8990713381222`.
    pub fn format(self, value: f64) -> String {
        format!("{value:.*} {}", self.decimals(), self.symbol())
    }
}

/// Energy for reading: `1034.2 Wh`.
pub fn format_wh(mj: i128) -> String {
    Unit::Wh.format(wh(mj))
}

/// Energy in Wh with `decimals` decimals: `format_wh_value(1034.25, 0)` is
/// `1034 Wh`.
pub fn format_wh_value(wh: f64, decimals: usize) -> String {
    format!("{wh:.decimals$} Wh")
}

/// Reads an energy as [`format_wh`] and [`format_wh_value`] write it (`1034.2
/// Wh`; the unit may be left out), in mJ, rounded to the nearest.
pub fn parse_wh(text: &str) -> Result<i128, ParseUnitError> {
    // Within i64 mJ: every energy the engine computes fits.
    parse_scaled(text, "Wh", MJ_PER_WH, i64::MAX as f64)
        .ok_or_else(|| ParseUnitError::new(text, "an energy in Wh (1034.2 Wh)"))
}

/// Power for reading: `750.0 W`.
pub fn format_watts(mw: i64) -> String {
    Unit::W.format(watts(mw))
}

/// Reads a power as [`format_watts`] writes it (`750.0 W`; the unit may be left
/// out), in mW, rounded to the nearest.
pub fn parse_watts(text: &str) -> Result<i64, ParseUnitError> {
    parse_scaled(text, "W", MW_PER_W, i64::MAX as f64)
        .and_then(|v| i64::try_from(v).ok())
        .ok_or_else(|| ParseUnitError::new(text, "a power in W (750.0 W)"))
}

/// Data volume for reading: `12.5 Mbit`.
pub fn format_mbit(bit: i128) -> String {
    Unit::Mbit.format(mbit(bit))
}

/// Data volume in Mbit with `decimals` decimals: `format_mbit_value(12.46, 1)`
/// is `12.5 Mbit`.
pub fn format_mbit_value(mbit: f64, decimals: usize) -> String {
    format!("{mbit:.decimals$} Mbit")
}

/// Reads a data volume as [`format_mbit`] and [`format_mbit_value`] write it
/// (`12.5 Mbit`; the unit may be left out), in bit, rounded to the nearest.
pub fn parse_mbit(text: &str) -> Result<i128, ParseUnitError> {
    parse_scaled(text, "Mbit", BIT_PER_MBIT, i64::MAX as f64)
        .ok_or_else(|| ParseUnitError::new(text, "a data volume in Mbit (12.5 Mbit)"))
}

/// Seconds of the local mean solar time clock (LMST) in a sol: a 24-hour
/// clock whose second is `sol_length / 86400` plan seconds.
pub const LMST_SECONDS_PER_SOL: i64 = 86_400;

/// The LMST second of the day (`0..86400`) that `time_of_day` plan seconds
/// after local midnight fall in, in a sol of `sol_length` plan seconds
/// (rounded down: the clock reads `09:45:05` for the whole of that Mars
/// second).
pub fn lmst_of_day(sol_length: i64, time_of_day: i64) -> i64 {
    let len = i128::from(sol_length.max(1));
    let lmst = (i128::from(time_of_day) * i128::from(LMST_SECONDS_PER_SOL)).div_euclid(len);
    i64::try_from(lmst).unwrap_or(if lmst < 0 { i64::MIN } else { i64::MAX })
}

/// The first plan second after local midnight whose LMST second (see
/// [`lmst_of_day`]) is `lmst`, in a sol of `sol_length` plan seconds: what a
/// typed LMST time reads as.
pub fn time_of_day_of_lmst(sol_length: i64, lmst: i64) -> i64 {
    let len = i128::from(sol_length.max(1));
    let n = i128::from(LMST_SECONDS_PER_SOL);
    let plan = (i128::from(lmst) * len + n - 1).div_euclid(n);
    i64::try_from(plan).unwrap_or(if plan < 0 { i64::MIN } else { i64::MAX })
}

/// A time of day in seconds after midnight (LMST seconds for a sol time:
/// see [`lmst_of_day`]) as `hh:mm:ss`.
pub fn format_time_of_day(time_of_day: i64) -> String {
    format!(
        "{:02}:{:02}:{:02}",
        time_of_day / 3600,
        (time_of_day / 60) % 60,
        time_of_day % 60
    )
}

/// Reads `hh:mm:ss` as [`format_time_of_day`] writes any count of seconds
/// (hours unbounded: a document's local time of day in plan seconds runs
/// past 24:00 on a Mars sol), in seconds.
pub(crate) fn parse_clock_seconds(text: &str) -> Result<i64, ParseUnitError> {
    let bad = || ParseUnitError::new(text, "a clock time (14:15:00)");
    let parts: Vec<&str> = text.trim().split(':').collect();
    let [h, m, s] = parts.as_slice() else {
        return Err(bad());
    };
    let n = |x: &str| x.parse::<i64>().ok().filter(|v| *v >= 0);
    match (n(h), n(m), n(s)) {
        (Some(h), Some(m), Some(s)) if m < 60 && s < 60 => h
            .checked_mul(3600)
            .and_then(|x| x.checked_add(m * 60 + s))
            .ok_or_else(bad),
        _ => Err(bad()),
    }
}

/// The LMST clock of plan time `t`, `09:45:05`: its local time of day on the
/// 24-hour Mars clock.
pub fn format_lmst(clock: &LocalTime, t: i64) -> String {
    format_time_of_day(lmst_of_day(clock.sol_length, clock.time_of_day(t)))
}

/// Reads a time of day on a 24-hour clock as [`format_time_of_day`] writes it
/// (`14:15:00`, or `14:15`), in seconds after midnight (LMST seconds for a sol
/// time: [`time_of_day_of_lmst`] gives its plan second). Hours are below 24,
/// minutes and seconds below 60.
pub fn parse_time_of_day(text: &str) -> Result<i64, ParseUnitError> {
    let bad = || ParseUnitError::new(text, "a time of day (14:15 or 14:15:00)");
    let mut parts = text.trim().split(':').map(|p| p.parse::<i64>().ok());
    let (h, m) = (
        parts.next().flatten().ok_or_else(bad)?,
        parts.next().ok_or_else(bad)?.ok_or_else(bad)?,
    );
    let s = match parts.next() {
        Some(s) => s.ok_or_else(bad)?,
        None => 0,
    };
    if parts.next().is_some()
        || !(0..24).contains(&h)
        || !(0..60).contains(&m)
        || !(0..60).contains(&s)
    {
        return Err(bad());
    }
    Ok(h * 3600 + m * 60 + s)
}

/// A signed difference of two times (one minus the other, as an actual start
/// against its predicted one): `on time`, `25 s late`, `25 s early`.
pub fn format_time_difference(seconds: i64) -> String {
    match seconds {
        0 => "on time".into(),
        d if d > 0 => format!("{d} s late"),
        d => format!("{} s early", d.unsigned_abs()),
    }
}

/// Reads a difference of two times as [`format_time_difference`] writes it.
pub fn parse_time_difference(text: &str) -> Result<i64, ParseUnitError> {
    let bad = || ParseUnitError::new(text, "a time difference (on time, 25 s late, 25 s early)");
    let t = text.trim();
    if t == "on time" {
        return Ok(0);
    }
    let (number, late) = match (t.strip_suffix(" s late"), t.strip_suffix(" s early")) {
        (Some(n), _) => (n, true),
        (None, Some(n)) => (n, false),
        (None, None) => return Err(bad()),
    };
    if !number.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    let n = i128::from(number.parse::<u64>().map_err(|_| bad())?);
    i64::try_from(if late { n } else { -n }).map_err(|_| bad())
}

/// Plan time `t` as a planner reads it: its sol and local mean solar time
/// (LMST, see [`lmst_of_day`]), `Sol 413 14:15:00`.
pub fn format_local(clock: &LocalTime, t: i64) -> String {
    format!("Sol {} {}", clock.sol(t), format_lmst(clock, t))
}

/// Plan time `t` in sol and LMST, with the plan second it is (what the JSON
/// documents hold): `Sol 413 14:15:00 (t=600)`.
pub fn format_plan_time(clock: &LocalTime, t: i64) -> String {
    format!("{} (t={t})", format_local(clock, t))
}

/// Plan time `t` as the sentences inside the JSON documents (notes,
/// `why.text`) have always written it: the sol, the local time of day in plan
/// seconds after local midnight as `hh:mm:ss` (past `24:00` on a Mars sol), and
/// the plan second, `Sol 412 24:38:35 (t=112714)`. Kept so that the documents
/// stay as they were; what a planner reads (text outputs, the app) goes
/// through [`lmst_sentence`], which says the same time in LMST.
pub fn format_document_time(clock: &LocalTime, t: i64) -> String {
    format!(
        "Sol {} {} (t={t})",
        clock.sol(t),
        format_time_of_day(clock.time_of_day(t))
    )
}

/// `text` with every time written as [`format_document_time`] writes it
/// said as [`format_plan_time`] says it (sol and LMST, with the same plan
/// second): how a document's sentence reads for a planner. Anything else is
/// left as it is.
pub fn lmst_sentence(clock: &LocalTime, text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find("Sol ") {
        out.push_str(&rest[..i]);
        let at = &rest[i..];
        match document_time_at(at) {
            Some((t, len)) => {
                out.push_str(&format_plan_time(clock, t));
                rest = &at[len..];
            }
            None => {
                out.push_str("Sol ");
                rest = &at[4..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// The plan second and length of a time as [`format_document_time`] writes
/// it at the start of `text` (`Sol 412 24:38:35 (t=112714)`), if one is there.
fn document_time_at(text: &str) -> Option<(i64, usize)> {
    let after_sol = text.strip_prefix("Sol ")?;
    let sol_len = after_sol
        .bytes()
        .enumerate()
        .take_while(|&(i, b)| b.is_ascii_digit() || (i == 0 && b == b'-'))
        .count();
    let after_number = after_sol.get(sol_len..)?.strip_prefix(' ')?;
    if sol_len == 0 || after_sol[..sol_len].parse::<i64>().is_err() {
        return None;
    }
    let clock_len = after_number
        .bytes()
        .take_while(|b| b.is_ascii_digit() || *b == b':')
        .count();
    let after_clock = after_number.get(clock_len..)?.strip_prefix(" (t=")?;
    let close = after_clock.find(')')?;
    let t = after_clock[..close].parse::<i64>().ok()?;
    if clock_len < 5 {
        return None;
    }
    let len = text.len() - after_clock.len() + close + 1;
    Some((t, len))
}

/// Reads a time as [`format_local`] and [`format_plan_time`] write it
/// (`Sol 413 14:15:00`, `sol 413 14:15`, with or without the `(t=...)`), or as
/// plan seconds (`600`, `t=600`). A time of day without a sol (`14:15`) is in
/// sol `sol`, and refused without one. An LMST time reads as the first plan
/// second of that Mars second; written with its plan second (as
/// [`format_plan_time`] writes it), as that second. `None` for anything else:
/// hours past 23, minutes or seconds past 59, or a time out of range.
pub fn parse_local(clock: &LocalTime, text: &str, sol: Option<i64>) -> Option<i64> {
    let text = text.trim();
    // The plan time written after a sol time: that second, when the sol time
    // is its own (else the sol time, as typed over it).
    let (text, written) = match text.find(" (t=") {
        Some(i) if text.ends_with(')') => (
            &text[..i],
            text[i + 4..text.len() - 1].trim().parse::<i64>().ok(),
        ),
        _ => (text, None),
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
    let lmst = parse_time_of_day(clock_text).ok()?;
    let len = clock.sol_length.max(1);
    let tod = time_of_day_of_lmst(len, lmst);
    // offset + t = (sol - first_sol) * sol_length + time of day.
    let t = sol
        .checked_sub(clock.first_sol.unwrap_or(0))?
        .checked_mul(len)?
        .checked_add(tod)?
        .checked_sub(clock.offset)?;
    match written {
        Some(w)
            if clock.sol(w) == clock.sol(t) && format_lmst(clock, w) == format_lmst(clock, t) =>
        {
            Some(w)
        }
        _ => Some(t),
    }
}

/// A length of time for reading: `45 s`, `12 min 05 s`, `3 h 07 min` (to the
/// minute from an hour on).
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

/// Reads a length of time as [`format_span`] writes it (`45 s`, `12 min 05 s`,
/// `-3 h 07 min`): hours, minutes and seconds in that order, each at most
/// once, or whole seconds alone (`725`), in seconds.
pub fn parse_span(text: &str) -> Result<i64, ParseUnitError> {
    let bad = || ParseUnitError::new(text, "a length of time (45 s, 12 min 05 s, 3 h 07 min)");
    let t = text.trim();
    let (negative, t) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t),
    };
    let digits = |x: &str| !x.is_empty() && x.bytes().all(|b| b.is_ascii_digit());
    let mut words = t.split_whitespace();
    let mut total: i128 = 0;
    let mut units = 0;
    // The units not yet used, largest first: each may follow only larger ones.
    let mut allowed: &[(&str, i128)] = &[("h", 3600), ("min", 60), ("s", 1)];
    while let Some(number) = words.next() {
        if !digits(number) {
            return Err(bad());
        }
        let n = i128::from(number.parse::<u64>().map_err(|_| bad())?);
        let factor = match words.next() {
            // Whole seconds alone.
            None if units == 0 => 1,
            None => return Err(bad()),
            Some(unit) => {
                let i = allowed
                    .iter()
                    .position(|&(u, _)| u == unit)
                    .ok_or_else(bad)?;
                let factor = allowed[i].1;
                allowed = &allowed[i + 1..];
                factor
            }
        };
        total = n
            .checked_mul(factor)
            .and_then(|x| x.checked_add(total))
            .ok_or_else(bad)?;
        units += 1;
    }
    if units == 0 {
        return Err(bad());
    }
    i64::try_from(if negative { -total } else { total }).map_err(|_| bad())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_read_in_plan_seconds_and_lmst() {
        let clock = LocalTime {
            sol_length: 88_775,
            offset: 64_800,
            first_sol: Some(411),
        };
        // 64,800 plan seconds after local midnight: 64,800 * 86,400 / 88,775
        // Mars seconds, 17:31:06 LMST.
        assert_eq!(format_local(&clock, 0), "Sol 411 17:31:06");
        assert_eq!(format_plan_time(&clock, 600), "Sol 411 17:40:50 (t=600)");
        // Past local midnight the day wraps at the sol length, and the sol counts on.
        assert_eq!(format_local(&clock, 88_775 - 64_800), "Sol 412 00:00:00");
        // The clock never reads 24:00: the sol's last second is 23:59:59.
        assert_eq!(
            format_local(&clock, 88_775 - 64_800 - 1),
            "Sol 411 23:59:59"
        );
        assert_eq!(format_local(&clock, -64_801), "Sol 410 23:59:59");
        let unnamed = LocalTime {
            first_sol: None,
            ..clock
        };
        assert_eq!(format_local(&unnamed, 88_775 * 3), "Sol 3 17:31:06");
        // Noon is half a sol after midnight.
        assert_eq!(
            format_local(&unnamed, 88_775 / 2 + 1 - 64_800),
            "Sol 0 12:00:00"
        );
        // An Earth-length sol reads as plan seconds.
        let earth = LocalTime {
            sol_length: 86_400,
            offset: 0,
            first_sol: None,
        };
        assert_eq!(format_local(&earth, 35_105), "Sol 0 09:45:05");
        assert_eq!(format_time_of_day(86_399), "23:59:59");
        assert_eq!(format_span(45), "45 s");
        assert_eq!(format_span(725), "12 min 05 s");
        assert_eq!(format_span(-3600 * 3 - 420 - 9), "-3 h 07 min");
    }

    #[test]
    fn document_sentences_read_in_lmst() {
        let clock = LocalTime {
            sol_length: 88_775,
            offset: 64_800,
            first_sol: Some(411),
        };
        // The documents keep their clock (past 24:00 on a Mars sol).
        assert_eq!(
            format_document_time(&clock, 23_974),
            "Sol 411 24:39:34 (t=23974)"
        );
        let doc = format!(
            "at the cycle at {} (t=5) the scheduler, then {}–{}. Sol 3 rests; Sol 4 10:00 (t=x)",
            format_document_time(&clock, 23_974),
            format_document_time(&clock, -64_801),
            format_document_time(&clock, 600)
        );
        assert_eq!(
            lmst_sentence(&clock, &doc),
            "at the cycle at Sol 411 23:59:59 (t=23974) (t=5) the scheduler, then \
             Sol 410 23:59:59 (t=-64801)–Sol 411 17:40:50 (t=600). Sol 3 rests; Sol 4 10:00 (t=x)"
        );
    }

    #[test]
    fn lmst_seconds_cover_the_sol_once() {
        for len in [88_775, 86_400, 80_000, 1, 2] {
            assert_eq!(lmst_of_day(len, 0), 0);
            assert!(lmst_of_day(len, len - 1) < LMST_SECONDS_PER_SOL);
            let mut last = -1;
            for tod in 0..len.min(100_000) {
                let m = lmst_of_day(len, tod);
                assert!(m >= last, "{len} {tod}");
                if m != last {
                    // The first plan second of each LMST second is what it
                    // reads back as.
                    assert_eq!(time_of_day_of_lmst(len, m), tod, "{len} {tod}");
                }
                last = m;
            }
        }
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
            // A sol time reads back as the first plan second of its Mars
            // second, which prints the same; with its plan second, exactly.
            let back = parse_local(&clock, &format_local(&clock, t), None).unwrap();
            assert!(back == t || back == t - 1, "{t} -> {back}");
            assert_eq!(format_local(&clock, back), format_local(&clock, t));
            assert_eq!(
                parse_local(&clock, &format_plan_time(&clock, t), None),
                Some(t)
            );
            assert_eq!(parse_local(&clock, &t.to_string(), None), Some(t));
        }
        // A sol time typed over its plan second is read as typed.
        assert_eq!(
            parse_local(&clock, "Sol 412 00:00:00 (t=0)", None),
            Some(88_775 - 64_800)
        );
        assert_eq!(parse_local(&clock, " sol 412 09:45 ", None), Some(60_040));
        assert_eq!(format_local(&clock, 60_040), "Sol 412 09:45:00");
        assert_eq!(format_local(&clock, 60_039), "Sol 412 09:44:59");
        assert_eq!(parse_local(&clock, "t=42", None), Some(42));
        // A time of day alone is in the sol given.
        assert_eq!(parse_local(&clock, "09:45:05", Some(412)), Some(60_045));
        assert_eq!(format_local(&clock, 60_045), "Sol 412 09:45:05");
        assert_eq!(parse_local(&clock, "09:45:05", None), None);
        // 23:59:59 is the last second of the 24-hour Mars clock.
        assert_eq!(
            parse_local(&clock, "Sol 412 23:59:59", None),
            Some(2 * 88_775 - 64_800 - 1)
        );
        for bad in [
            "Sol 412 24:00:00",
            "Sol 412 24:39:34",
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
    fn each_unit_rounds_by_its_one_rule() {
        assert_eq!(Unit::Wh.format(474.8990713381222), "474.9 Wh");
        assert_eq!(Unit::Mbit.format(16666.666666666664), "16666.7 Mbit");
        assert_eq!(Unit::W.format(29.96), "30.0 W");
        assert_eq!(
            Unit::Wh.format(wh(3_600_000 * 1034 + 720_000)),
            format_wh(3_600_000 * 1034 + 720_000)
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

    #[test]
    fn times_of_day_read_back_with_clear_errors() {
        assert_eq!(parse_time_of_day("00:00:00"), Ok(0));
        assert_eq!(parse_time_of_day(" 14:15 "), Ok(14 * 3600 + 15 * 60));
        assert_eq!(parse_time_of_day("23:59:59"), Ok(86_399));
        for bad in [
            "24:00",
            "24:39:34",
            "",
            "14",
            "14:60",
            "14:00:60",
            "-1:00",
            "1:2:3:4",
            "x:00",
            "9223372036854775807:00",
        ] {
            let err = parse_time_of_day(bad).unwrap_err();
            assert_eq!(err.text, bad);
            assert_eq!(
                err.to_string(),
                format!("\"{bad}\" is not a time of day (14:15 or 14:15:00)")
            );
        }
    }

    #[test]
    fn quantities_read_back_rounded_to_the_nearest() {
        assert_eq!(parse_watts("750.0 W"), Ok(750_000));
        assert_eq!(parse_watts("750W"), Ok(750_000));
        assert_eq!(parse_watts(" -1.5 "), Ok(-1_500));
        assert_eq!(parse_watts("0.0004 W"), Ok(0));
        assert_eq!(parse_watts("0.0006 W"), Ok(1));
        assert_eq!(parse_wh("1034.2 Wh"), Ok(3_600_000 * 1034 + 720_000));
        assert_eq!(parse_wh("0 Wh"), Ok(0));
        // A small negative value prints as `-0.0`: it reads back as zero.
        assert_eq!(format_wh(-1), "-0.0 Wh");
        assert_eq!(parse_wh("-0.0 Wh"), Ok(0));
        assert_eq!(parse_mbit("12.5 Mbit"), Ok(12_500_000));
        assert_eq!(format_mbit(12_460_000), "12.5 Mbit");
        assert_eq!(format_mbit(-2_500_000), "-2.5 Mbit");
        assert_eq!(format_mbit_value(12.46, 2), "12.46 Mbit");
        assert_eq!(format_wh_value(1034.4, 0), "1034 Wh");
        assert_eq!(format_wh_value(1034.6, 0), "1035 Wh");
        for (bad, err) in [
            (
                parse_watts("750.0 Wh").map(|_| ()),
                "a power in W (750.0 W)",
            ),
            (parse_watts("inf W").map(|_| ()), "a power in W (750.0 W)"),
            (parse_watts("1e300 W").map(|_| ()), "a power in W (750.0 W)"),
            (parse_wh("NaN").map(|_| ()), "an energy in Wh (1034.2 Wh)"),
            (parse_wh("Wh").map(|_| ()), "an energy in Wh (1034.2 Wh)"),
            (parse_wh("12 W").map(|_| ()), "an energy in Wh (1034.2 Wh)"),
            (
                parse_mbit("1.2.3 Mbit").map(|_| ()),
                "a data volume in Mbit (12.5 Mbit)",
            ),
            (
                parse_mbit("").map(|_| ()),
                "a data volume in Mbit (12.5 Mbit)",
            ),
        ] {
            assert_eq!(bad.map_err(|e| e.expected), Err(err));
        }
    }

    #[test]
    fn spans_read_back_with_clear_errors() {
        assert_eq!(parse_span("45 s"), Ok(45));
        assert_eq!(parse_span("12 min 05 s"), Ok(725));
        assert_eq!(parse_span("12 min"), Ok(720));
        assert_eq!(parse_span("-3 h 07 min"), Ok(-(3 * 3600 + 420)));
        assert_eq!(parse_span("1 h 0 min 9 s"), Ok(3609));
        assert_eq!(parse_span("725"), Ok(725));
        assert_eq!(parse_span("0 s"), Ok(0));
        assert_eq!(parse_span("-0 s"), Ok(0));
        // The largest span, to the minute toward zero.
        assert_eq!(format_span(i64::MIN), "-2562047788015215 h 30 min");
        assert_eq!(parse_span(&format_span(i64::MIN)), Ok(i64::MIN + 8));
        for bad in [
            "",
            "-",
            "s",
            "5 min 3 h",
            "5 s 5 s",
            "5 sec",
            "1 h 5",
            "-5 -5 s",
            "+5 s",
            "5.5 s",
            "99999999999999999999 s",
            "9999999999999999 h",
        ] {
            assert_eq!(
                parse_span(bad).map_err(|e| e.to_string()),
                Err(format!(
                    "\"{bad}\" is not a length of time (45 s, 12 min 05 s, 3 h 07 min)"
                )),
            );
        }
    }

    #[test]
    fn time_differences_read_as_late_or_early() {
        assert_eq!(format_time_difference(0), "on time");
        assert_eq!(format_time_difference(25), "25 s late");
        assert_eq!(format_time_difference(-25), "25 s early");
        assert_eq!(
            format_time_difference(i64::MIN),
            "9223372036854775808 s early"
        );
        assert_eq!(parse_time_difference(" 25 s late"), Ok(25));
        assert_eq!(parse_time_difference("0 s early"), Ok(0));
        for bad in [
            "",
            "late",
            "25 s",
            "-25 s late",
            "25 s  late",
            "9223372036854775808 s late",
        ] {
            assert_eq!(
                parse_time_difference(bad).map_err(|e| e.expected),
                Err("a time difference (on time, 25 s late, 25 s early)")
            );
        }
    }

    proptest::proptest! {
        /// A time of day reads back as the second it was.
        #[test]
        fn time_of_day_round_trips(t in 0i64..86_400) {
            proptest::prop_assert_eq!(parse_time_of_day(&format_time_of_day(t)), Ok(t));
        }

        /// A difference of times reads back exactly.
        #[test]
        fn time_difference_round_trips(d in proptest::num::i64::ANY) {
            proptest::prop_assert_eq!(parse_time_difference(&format_time_difference(d)), Ok(d));
        }

        /// A span reads back exactly below an hour and on whole minutes, and
        /// to the minute (toward zero) above; either way it prints the same.
        #[test]
        fn span_round_trips(s in proptest::num::i64::ANY) {
            let text = format_span(s);
            let back = parse_span(&text);
            proptest::prop_assert_eq!(back.clone().map(format_span), Ok(text.clone()), "{}", s);
            let exact = if s.unsigned_abs() < 3600 { s } else { s - s % 60 };
            proptest::prop_assert_eq!(back, Ok(exact), "{}", text);
        }

        /// A quantity reads back as the fixed-point value of the decimal
        /// printed (within half its last digit of the value printed), which
        /// prints the same (but for a negative value printed as zero).
        #[test]
        fn quantities_round_trip(x in -1_000_000_000_000i64..1_000_000_000_000, decimals in 0usize..4) {
            let printed = format_watts(x);
            let back = parse_watts(&printed);
            proptest::prop_assert!(back.clone().is_ok_and(|v| (v - x).abs() <= 50), "{}", printed);
            if !printed.starts_with("-0.0 ") {
                proptest::prop_assert_eq!(back.map(format_watts), Ok(printed));
            }
            let mj = i128::from(x);
            let printed = format_wh(mj);
            let back = parse_wh(&printed);
            proptest::prop_assert!(back.clone().is_ok_and(|v| (v - mj).abs() <= 180_000), "{}", printed);
            if !printed.starts_with("-0.0 ") {
                proptest::prop_assert_eq!(back.map(format_wh), Ok(printed));
            }
            let printed = format_mbit(mj);
            let back = parse_mbit(&printed);
            proptest::prop_assert!(back.clone().is_ok_and(|v| (v - mj).abs() <= 50_000), "{}", printed);
            if !printed.starts_with("-0.0 ") {
                proptest::prop_assert_eq!(back.map(format_mbit), Ok(printed));
            }
            // With other decimals, from the planner's unit.
            let printed = format_wh_value(wh(mj), decimals);
            let back = parse_wh(&printed).map(|v| format_wh_value(wh(v), decimals));
            if !printed.starts_with('-') || printed.bytes().any(|b| (b'1'..=b'9').contains(&b)) {
                proptest::prop_assert_eq!(back, Ok(printed));
            }
            let printed = format_mbit_value(mbit(mj), decimals);
            let back = parse_mbit(&printed).map(|v| format_mbit_value(mbit(v), decimals));
            if !printed.starts_with('-') || printed.bytes().any(|b| (b'1'..=b'9').contains(&b)) {
                proptest::prop_assert_eq!(back, Ok(printed));
            }
        }
    }
}
