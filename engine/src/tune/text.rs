//! The sentences of priority tuning, made from its data in one place.

use super::Tuning;
use super::score::{MICRO, Score, ValueMeasure};
use super::why::{ChangeWhy, Moved};
use crate::model::Plan;

/// A share of runs as planners read it: whole percent, `<1%` for a few runs
/// of many, `0%` only for none.
fn share(k: u64, n: u64) -> String {
    if n == 0 {
        return "0%".into();
    }
    let pct = (u128::from(k) * 100 + u128::from(n) / 2) / u128::from(n);
    if pct == 0 && k > 0 {
        "<1%".into()
    } else if pct == 100 && k < n {
        ">99%".into()
    } else {
        format!("{pct}%")
    }
}

/// Why a priority changed, in one sentence: e.g. "moved ahead of drive: it
/// was lost in 31% of runs, to placement/min_soc with drive; now in 4%".
pub fn change_line(plan: &Plan, why: &ChangeWhy) -> String {
    let id = |a: usize| plan.activities.get(a).map_or("?", |x| x.id.as_str());
    let moved = match why.moved {
        Moved::Ahead { of } => format!("moved ahead of {}", id(of)),
        Moved::After { of } => format!("moved after {}", id(of)),
        Moved::Renumbered => "renumbered so that the tuned order is the one the scheduler follows \
             (its order relative to every other activity is unchanged)"
            .to_string(),
    };
    let Some(a) = why.activity else {
        if why.breaking_before != why.breaking_after {
            return format!(
                "{moved}: runs breaking a limit {} → {}",
                share(why.breaking_before, why.runs),
                share(why.breaking_after, why.runs)
            );
        }
        return moved;
    };
    let who = match why.moved {
        Moved::After { of } if of == a => id(a).to_string(),
        _ => "it".to_string(),
    };
    let mut s = format!(
        "{moved}: {who} was lost in {} of runs",
        share(why.lost_before, why.runs)
    );
    if let Some(cause) = &why.cause {
        s.push_str(&format!(", to {cause}"));
        if let Some(c) = why.culprit {
            s.push_str(&format!(" with {}", id(c)));
        }
    }
    s.push_str(&format!("; now in {}", share(why.lost_after, why.runs)));
    if why.cause.is_some() && why.cause_after == 0 && why.lost_after > 0 {
        s.push_str(" (no longer to that cause)");
    }
    s
}

/// A score on a sample of `runs` runs, in the objective's order: e.g. "no run
/// breaks a limit, 40 mandatory completions, value 212.5" (without a `value`
/// in the plan, the value is the completions in the original step order, which
/// has no one number).
pub fn score_line(score: &Score, runs: u64) -> String {
    let breaking = match score.runs_breaking {
        0 => "no run breaks a limit".to_string(),
        k if k == runs => format!("every run breaks a limit ({k})"),
        k => format!("{k} of {runs} runs break a limit ({})", share(k, runs)),
    };
    let mandatory = match score.mandatory_completed {
        1 => "1 mandatory completion".to_string(),
        k => format!("{k} mandatory completions"),
    };
    let value = match &score.value {
        ValueMeasure::Total(v) => format!("value {:.1}", *v as f64 / MICRO as f64),
        ValueMeasure::StepOrder(c) => {
            format!(
                "{} completions in all (compared activity by activity in the original step \
                 order)",
                c.iter().sum::<u64>()
            )
        }
    };
    format!("{breaking}, {mandatory}, {value}")
}

/// Without a `value` in the plan, what decides between the original and the
/// tuned order on the held-out sample after limits and mandatory
/// completions: the first activity in the original step order completed a
/// different number of times, e.g. "first difference in the original step
/// order: uhf_mro_412_pm completes in 38 of 40 runs instead of 34". `None`
/// when the plan has values or no activity differs.
pub fn first_difference_line(plan: &Plan, t: &Tuning) -> Option<String> {
    let (o, n) = (&t.held_out_scores.original, &t.held_out_scores.tuned);
    let (ValueMeasure::StepOrder(a), ValueMeasure::StepOrder(b)) = (&o.value, &n.value) else {
        return None;
    };
    let ((before, after), act) = a
        .iter()
        .zip(b)
        .zip(&t.original)
        .find(|((x, y), _)| x != y)?;
    let id = plan.activities.get(*act).map_or("?", |x| x.id.as_str());
    Some(format!(
        "first difference in the original step order: {id} completes in {after} of {} runs \
         instead of {before}",
        t.held_out.runs
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_score_reads_in_the_objective_s_order() {
        let s = Score {
            runs_breaking: 0,
            mandatory_completed: 40,
            value: ValueMeasure::Total(212_500_000),
            changes: 2,
        };
        assert_eq!(
            score_line(&s, 40),
            "no run breaks a limit, 40 mandatory completions, value 212.5"
        );
        let t = Score {
            runs_breaking: 3,
            mandatory_completed: 1,
            value: ValueMeasure::StepOrder(vec![4, 3]),
            changes: 0,
        };
        assert_eq!(
            score_line(&t, 4),
            "3 of 4 runs break a limit (75%), 1 mandatory completion, \
             7 completions in all (compared activity by activity in the original step order)"
        );
    }

    #[test]
    fn shares_read_as_planners_expect() {
        assert_eq!(share(0, 1000), "0%");
        assert_eq!(share(1, 1000), "<1%");
        assert_eq!(share(310, 1000), "31%");
        assert_eq!(share(999, 1000), ">99%");
        assert_eq!(share(5, 5), "100%");
    }
}
