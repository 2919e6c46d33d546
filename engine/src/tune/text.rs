//! The sentences of priority tuning, made from its data in one place.

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_read_as_planners_expect() {
        assert_eq!(share(0, 1000), "0%");
        assert_eq!(share(1, 1000), "<1%");
        assert_eq!(share(310, 1000), "31%");
        assert_eq!(share(999, 1000), ">99%");
        assert_eq!(share(5, 5), "100%");
    }
}
