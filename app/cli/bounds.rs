//! The command line's limits on valid plans whose work would grow with
//! something other than what the command reports (docs/format.md, "Limits of
//! the command line"): each refuses the plan at once, path-named, exit status 2,
//! instead of running for minutes.

use solscope_engine::{Duration, Error, Plan};

/// The most sols the duration searches of expanding activities heated in a zone
/// with operable periods may cover in all (each such activity counts the sols
/// its windows span, the whole horizon without windows).
pub const HEATED_SEARCH_SOLS_MAX: i64 = 20_000;

/// The most `failures × activities` for which `explain` verifies suggestions
/// for every failure: each failure's candidate edits are verified by
/// rescheduling the plan, so the work grows with both.
pub const SUGGESTED_WORK_MAX: u64 = 4_000_000;

/// Sols of `[lo, hi]` (one at least), for a sol of `sol_length` seconds.
fn sols(lo: i64, hi: i64, sol_length: i64) -> i64 {
    let len = i128::from(hi) - i128::from(lo);
    let n = len.max(0) / i128::from(sol_length.max(1)) + 1;
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// Refuses a plan whose expanding activities heated in zones with operable
/// periods would search their durations over more than
/// [`HEATED_SEARCH_SOLS_MAX`] sols in all: a duration that fits nowhere is
/// checked sol by sol (each operable period cuts the starts), over the span
/// of the activity's windows, for every duration the search tries. Named at
/// the `duration` of the activity that crosses the limit.
pub fn heated_search(plan: &Plan) -> Result<(), Error> {
    let zoned = |names: &[String]| {
        names.iter().any(|z| {
            plan.thermal_zones
                .get(z)
                .is_some_and(|zone| zone.operable.is_some())
        })
    };
    let (h0, h1) = (plan.horizon.start, plan.horizon.end);
    let sol_length = plan.local_time.sol_length;
    let mut total: i64 = 0;
    for (i, act) in plan.activities.iter().enumerate() {
        if !matches!(act.duration, Duration::Expanding { .. }) || !zoned(&act.thermal_zones) {
            continue;
        }
        let (lo, hi) = match act.windows.as_deref() {
            Some([]) => continue,
            Some(ws) => (
                ws.iter().map(|w| w.start).min().unwrap_or(h0).max(h0),
                ws.iter().map(|w| w.end).max().unwrap_or(h1).min(h1),
            ),
            None => (h0, h1),
        };
        let own = sols(lo, hi, sol_length);
        total = total.saturating_add(own);
        if total > HEATED_SEARCH_SOLS_MAX {
            return Err(Error::invalid(
                format!("activities[{i}].duration"),
                format!(
                    "expanding activities heated in a zone with operable periods search their \
                     duration over every sol their windows span, at most {HEATED_SEARCH_SOLS_MAX} \
                     sols in all; \"{}\" brings the plan to {total} ({own} of its own): give it \
                     windows over fewer sols, or a fixed duration",
                    act.id
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses to verify suggestions for `failures` failures of a plan of
/// `activities` activities when `failures × activities` passes
/// [`SUGGESTED_WORK_MAX`]. Named at `activities`.
pub fn suggested_work(failures: usize, activities: usize) -> Result<(), Error> {
    let work = (failures as u64).saturating_mul(activities as u64);
    if work <= SUGGESTED_WORK_MAX {
        return Ok(());
    }
    Err(Error::invalid(
        "activities",
        format!(
            "{failures} of the {activities} activities fail; explain verifies suggestions by \
             rescheduling the plan for each failure, for at most {SUGGESTED_WORK_MAX} failures \
             times activities (here {work}): use --no-suggestions, or --activity ID for one \
             failure"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sols_count_every_sol_touched() {
        assert_eq!(sols(0, 0, 88775), 1);
        assert_eq!(sols(0, 88774, 88775), 1);
        assert_eq!(sols(0, 88775, 88775), 2);
        assert_eq!(sols(0, 1_000_000_000, 88775), 11_265);
        assert_eq!(sols(10, 5, 88775), 1);
    }

    #[test]
    fn suggested_work_refuses_past_the_limit_only() {
        assert!(suggested_work(2_000, 2_000).is_ok());
        let err = suggested_work(2_001, 2_000).unwrap_err().to_string();
        assert!(
            err.starts_with("activities: 2001 of the 2000 activities fail"),
            "{err}"
        );
    }
}
