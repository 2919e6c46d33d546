//! Words for what the views show, shared by the Gantt, the plots, the
//! execution controls, the inspector and the Monte Carlo panel: why a cycle
//! ran, a broken limit, a time difference, a share of runs, an energy.

use solscope_engine::{
    MJ_PER_WH, Trigger, Violation, ViolationKind, format_mbit, format_watts, format_wh,
};

use super::Model;

/// Why a cycle ran.
pub fn trigger_text(m: &Model<'_>, trigger: Trigger) -> String {
    match trigger {
        Trigger::Start => "at the plan start".into(),
        Trigger::Period => "replan period".into(),
        Trigger::End(a) => format!("after {} ended", m.doc.plan.activities[a].id),
    }
}

/// The spec's name of a violated limit.
pub fn kind_name(kind: ViolationKind) -> &'static str {
    match kind {
        ViolationKind::MinSoc => "min_soc",
        ViolationKind::MaxPeakPower => "max_peak_power",
        ViolationKind::DataCapacity => "data_capacity",
        ViolationKind::HandoverSoc => "handover_soc",
    }
}

/// A value of a violated limit's kind, in its planner unit.
fn limit_value(kind: ViolationKind, x: i128) -> String {
    match kind {
        ViolationKind::MinSoc | ViolationKind::HandoverSoc => format_wh(x),
        ViolationKind::MaxPeakPower => format_watts(i64::try_from(x).unwrap_or(i64::MAX)),
        ViolationKind::DataCapacity => format_mbit(x),
    }
}

/// A broken limit in one line: kind, when first broken, worst value, limit.
pub fn violation_text(m: &Model<'_>, v: &Violation) -> String {
    format!(
        "{} broken from {}: worst {} at {} (limit {})",
        kind_name(v.kind),
        m.time(v.time),
        limit_value(v.kind, v.worst.0),
        m.time(v.worst.1),
        limit_value(v.kind, v.limit)
    )
}

/// A value in Wh (a float, as the campaign's summaries give it) for reading.
pub fn wh_text(x: f64) -> String {
    format_wh((x * MJ_PER_WH).round() as i128)
}

/// `k` of `n` as a percentage, never rounded to 0 % or 100 % unless exact.
pub fn percent(k: u64, n: u64) -> String {
    if n == 0 {
        return "–".into();
    }
    if (k * 100) % n == 0 {
        return format!("{}%", k * 100 / n);
    }
    let p = k as f64 * 100.0 / n as f64;
    if p < 0.1 {
        "<0.1%".into()
    } else if p > 99.9 {
        ">99.9%".into()
    } else if !(10.0..=90.0).contains(&p) {
        format!("{p:.1}%")
    } else {
        format!("{p:.0}%")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentages_are_never_rounded_to_none_or_all() {
        assert_eq!(percent(0, 200), "0%");
        assert_eq!(percent(200, 200), "100%");
        assert_eq!(percent(1, 3), "33%");
        assert_eq!(percent(1, 2000), "<0.1%");
        assert_eq!(percent(1999, 2000), ">99.9%");
        assert_eq!(percent(1, 200), "0.5%");
        assert_eq!(percent(199, 200), "99.5%");
        assert_eq!(percent(3, 0), "–");
    }
}
