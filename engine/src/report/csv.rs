//! The CSV documents, for spreadsheets: the schedule (one row per activity in
//! step order) and a Monte Carlo campaign's runs (one row per run). Both are
//! written by the one writer here, as RFC 4180 has it: a field holding a comma, a
//! quote, a carriage return or a line feed is quoted, its quotes doubled, and
//! every line (the header's too) ends with CRLF.

use std::borrow::Cow;

use crate::execute::{Campaign, RunRecord};
use crate::model::{LocalTime, Plan};
use crate::scheduler::{Outcome, Schedule};
use crate::units::{format_lmst, wh};

/// The header row of [`schedule_csv`].
const SCHEDULE_HEADER: &str = "step,id,name,status,start,end,duration_s,start_sol,start_local,end_sol,end_local,priority,mandatory";

/// A CSV document being written, row by row.
#[derive(Debug, Default)]
struct Csv {
    text: String,
}

impl Csv {
    /// Appends one row: the fields, each quoted when it must be, separated by
    /// commas and ended with CRLF.
    fn row<S: AsRef<str>>(&mut self, fields: impl IntoIterator<Item = S>) {
        for (i, f) in fields.into_iter().enumerate() {
            if i > 0 {
                self.text.push(',');
            }
            self.text.push_str(&field(f.as_ref()));
        }
        self.text.push_str("\r\n");
    }

    /// The document written.
    fn finish(self) -> String {
        self.text
    }
}

/// One CSV field, quoted when it must be.
fn field(s: &str) -> Cow<'_, str> {
    if s.contains([',', '"', '\n', '\r']) {
        Cow::Owned(format!("\"{}\"", s.replace('"', "\"\"")))
    } else {
        Cow::Borrowed(s)
    }
}

/// Plan time `t` as its sol and LMST time of day, two fields.
fn sol_and_time(clock: &LocalTime, t: i64) -> [String; 2] {
    [clock.sol(t).to_string(), format_lmst(clock, t)]
}

/// The schedule as CSV: one row per activity in step order (`step`, `id`,
/// `name`, `status`, then `start`, `end` and `duration_s` in plan seconds, the
/// sol and local time of day of the start and of the end through the plan's
/// `local_time`, then `priority` and `mandatory`). A failed or skipped activity
/// has empty times.
pub fn schedule_csv(plan: &Plan, schedule: &Schedule) -> String {
    let mut csv = Csv::default();
    csv.row(SCHEDULE_HEADER.split(','));
    for step in &schedule.steps {
        let act = &plan.activities[step.activity];
        let times: [String; 7] = match step.outcome {
            Outcome::Scheduled { start, end } => {
                let [start_sol, start_local] = sol_and_time(&plan.local_time, start);
                let [end_sol, end_local] = sol_and_time(&plan.local_time, end);
                [
                    start.to_string(),
                    end.to_string(),
                    (end - start).to_string(),
                    start_sol,
                    start_local,
                    end_sol,
                    end_local,
                ]
            }
            Outcome::Failed(_) | Outcome::Skipped { .. } => Default::default(),
        };
        let fields = [
            step.step.to_string(),
            act.id.clone(),
            act.name.clone().unwrap_or_default(),
            step.outcome.status().to_string(),
        ]
        .into_iter()
        .chain(times)
        .chain([act.priority.to_string(), act.mandatory.to_string()]);
        csv.row(fields);
    }
    csv.finish()
}

/// A Monte Carlo campaign's runs as CSV, one row per run by run index: the run,
/// its lowest state of charge (Wh) and when, the state of charge at the handover,
/// the limits it broke (`;`-separated), the outcome counts, each uncertain
/// activity's actual duration (`duration:ID`) and each activity's outcome
/// (`outcome:ID`).
pub fn runs_csv(campaign: &Campaign, records: &[RunRecord]) -> String {
    let mut csv = Csv::default();
    let header = [
        "run",
        "lowest_soc_wh",
        "lowest_soc_time",
        "handover_soc_wh",
        "violations",
        "completed",
        "aborted",
        "not_run",
    ]
    .map(String::from)
    .into_iter()
    .chain(
        campaign
            .uncertain
            .iter()
            .map(|&a| format!("duration:{}", campaign.activities[a])),
    )
    .chain(campaign.activities.iter().map(|id| format!("outcome:{id}")));
    csv.row(header);
    let mut records: Vec<&RunRecord> = records.iter().collect();
    records.sort_by_key(|r| r.run);
    for r in records {
        let count = |c: char| r.outcomes.chars().filter(|&x| x == c).count().to_string();
        let row = [
            r.run.to_string(),
            format!("{:.3}", wh(i128::from(r.lowest_soc.0))),
            r.lowest_soc.1.to_string(),
            r.handover_soc
                .map(|x| format!("{:.3}", wh(i128::from(x))))
                .unwrap_or_default(),
            r.violations.join(";"),
            count('c'),
            count('a'),
            count('n'),
        ]
        .into_iter()
        .chain(r.durations.iter().map(i64::to_string))
        .chain(r.outcomes.chars().map(|c| {
            match c {
                'c' => "completed",
                'a' => "aborted",
                _ => "not_run",
            }
            .to_string()
        }));
        csv.row(row);
    }
    csv.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_plan;
    use crate::scheduler::schedule;

    #[test]
    fn fields_with_commas_or_quotes_are_quoted() {
        assert_eq!(field("drill"), "drill");
        assert_eq!(field("a, b"), "\"a, b\"");
        assert_eq!(field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }

    #[test]
    fn fields_with_a_line_break_are_quoted() {
        assert_eq!(field("two\r\nlines"), "\"two\r\nlines\"");
        assert_eq!(field("a\rb"), "\"a\rb\"");
        assert_eq!(field("a\nb"), "\"a\nb\"");
        let mut csv = Csv::default();
        csv.row(["x\ry", "z"]);
        csv.row([""; 2]);
        assert_eq!(csv.finish(), "\"x\ry\",z\r\n,\r\n");
    }

    #[test]
    fn one_row_per_activity_with_its_placement() {
        let text = include_str!("../../../assets/examples/pitfall.json");
        let plan = load_plan(text).expect("plan").plan;
        let schedule = schedule(&plan).expect("schedule");
        let csv = schedule_csv(&plan, &schedule);
        let lines: Vec<&str> = csv.split("\r\n").collect();
        assert_eq!(lines[0], SCHEDULE_HEADER);
        assert_eq!(lines.len(), plan.activities.len() + 2, "{csv}");
        assert!(lines[1].starts_with("1,A,"), "{}", lines[1]);
        assert!(lines[1].contains(",scheduled,0,"), "{}", lines[1]);
        assert!(lines[2].starts_with("2,B,"), "{}", lines[2]);
        assert!(lines[2].contains(",failed,,,,,,,,"), "{}", lines[2]);
        // The bundled plan names its sols: plan time 0 is sol 411 at 18:00.
        let plan = load_plan(include_str!("../../../assets/default-plan.json"))
            .expect("plan")
            .plan;
        assert_eq!(sol_and_time(&plan.local_time, 600), ["411", "17:40:50"]);
        assert_eq!(sol_and_time(&plan.local_time, 88_775), ["412", "17:31:06"]);
    }

    #[test]
    fn one_row_per_run_in_run_order() {
        let campaign = Campaign {
            plan: "p".into(),
            plan_hash: "0".into(),
            seed: 1,
            runs: 2,
            activities: vec!["drive".into(), "a,b".into()],
            mandatory: vec![true, false],
            predicted: vec![Some((0, 10)), None],
            uncertain: vec![0],
            policy: Default::default(),
        };
        let record = |run: u64, outcomes: &str| RunRecord {
            run,
            durations: vec![7 + run as i64],
            outcomes: outcomes.into(),
            spans: vec![None, None],
            lowest_soc: (3_600_000, 42),
            handover_soc: None,
            violations: vec!["min_soc".into(), "handover_soc".into()],
            losses: Vec::new(),
        };
        let csv = runs_csv(&campaign, &[record(1, "an"), record(0, "cc")]);
        assert_eq!(
            csv,
            "run,lowest_soc_wh,lowest_soc_time,handover_soc_wh,violations,completed,aborted,\
             not_run,duration:drive,outcome:drive,\"outcome:a,b\"\r\n\
             0,1.000,42,,min_soc;handover_soc,2,0,0,7,completed,completed\r\n\
             1,1.000,42,,min_soc;handover_soc,0,1,1,8,aborted,not_run\r\n"
        );
    }
}
