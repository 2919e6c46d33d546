//! The schedule as CSV (File → Export schedule CSV…): one row per activity in
//! step order, for spreadsheets. Times are plan seconds and, in columns of
//! their own, the sol number and local time of day (`local_time`, through the
//! engine's `units`).

use solscope_engine::{LocalTime, Outcome, Plan, Schedule, format_time_of_day};

/// The header row.
pub const CSV_HEADER: &str = "step,id,name,status,start,end,duration_s,start_sol,start_local,end_sol,end_local,priority,mandatory";

/// Plan time `t` as its sol and local time of day, two fields.
fn sol_and_time(clock: &LocalTime, t: i64) -> [String; 2] {
    [
        clock.sol(t).to_string(),
        format_time_of_day(clock.time_of_day(t)),
    ]
}

/// The schedule as CSV (RFC 4180: a field with a comma, quote or line break is
/// quoted, its quotes doubled; lines end with CRLF). A failed or skipped
/// activity has empty times.
pub fn schedule_csv(plan: &Plan, schedule: &Schedule) -> String {
    let mut out = String::new();
    out.push_str(CSV_HEADER);
    out.push_str("\r\n");
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
        let row: Vec<String> = fields.map(|f| field(&f)).collect();
        out.push_str(&row.join(","));
        out.push_str("\r\n");
    }
    out
}

/// One CSV field, quoted when it must be.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_with_commas_or_quotes_are_quoted() {
        assert_eq!(field("drill"), "drill");
        assert_eq!(field("a, b"), "\"a, b\"");
        assert_eq!(field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }

    #[test]
    fn one_row_per_activity_with_its_placement() {
        let text = include_str!("../../assets/examples/pitfall.json");
        let plan = solscope_engine::load_plan(text).expect("plan").plan;
        let schedule = solscope_engine::schedule(&plan).expect("schedule");
        let csv = schedule_csv(&plan, &schedule);
        let lines: Vec<&str> = csv.split("\r\n").collect();
        assert_eq!(lines[0], CSV_HEADER);
        assert_eq!(lines.len(), plan.activities.len() + 2, "{csv}");
        assert!(lines[1].starts_with("1,A,"), "{}", lines[1]);
        assert!(lines[1].contains(",scheduled,0,"), "{}", lines[1]);
        assert!(lines[2].starts_with("2,B,"), "{}", lines[2]);
        assert!(lines[2].contains(",failed,,,,,,,,"), "{}", lines[2]);
        // The bundled plan names its sols: plan time 0 is sol 411 at 18:00.
        let plan = solscope_engine::load_plan(include_str!("../../assets/default-plan.json"))
            .expect("plan")
            .plan;
        assert_eq!(sol_and_time(&plan.local_time, 600), ["411", "18:10:00"]);
        assert_eq!(sol_and_time(&plan.local_time, 88_775), ["412", "18:00:00"]);
    }
}
