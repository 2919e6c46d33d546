//! Checks on documents of run records as they are read: a part travels
//! between machines and files, so every record is checked against its
//! campaign header (lengths, indices, enumerations, the shard's runs) before
//! it counts in a summary, and parts merge only when they are shards of one
//! campaign that hold every run exactly once.

use std::collections::BTreeMap;

use super::{Campaign, MONTECARLO_RUNS_FORMAT, RunRecord, RunsDoc};
use crate::error::Error;
use crate::execute::ViolationKind;

/// The names a record's `violations` may hold.
const VIOLATIONS: [ViolationKind; 4] = [
    ViolationKind::MinSoc,
    ViolationKind::MaxPeakPower,
    ViolationKind::DataCapacity,
    ViolationKind::HandoverSoc,
];

/// Where a part's errors are: `name: path` (a file) or `name.path`.
pub(super) struct At<'a> {
    name: &'a str,
    file: bool,
}

impl<'a> At<'a> {
    /// The part read from the file `name`.
    pub(super) fn file(name: &'a str) -> Self {
        At { name, file: true }
    }

    /// The part at JSON path `name` (e.g. `parts[2]`).
    pub(super) fn path(name: &'a str) -> Self {
        At { name, file: false }
    }

    /// An error at `path` inside the part.
    pub(super) fn err(&self, path: impl AsRef<str>, reason: impl Into<String>) -> Error {
        let sep = if self.file { ": " } else { "." };
        Error::invalid(format!("{}{sep}{}", self.name, path.as_ref()), reason)
    }
}

/// Reads a document of run records (a shard's output) from `text`, the
/// contents of the file `name`, and checks it: its format, its campaign header,
/// its shard `[i, k]` with `i < k`, and every record against them (the run
/// belongs to the shard and is below the campaign's runs, in increasing run
/// order; lengths of `durations`, `outcomes` and `spans`; outcome characters;
/// spans present exactly for the activities that ran; violation names; loss and
/// culprit indices). Errors name the file and the JSON path
/// (`part-3.json: records[4].outcomes: ...`).
pub fn read_runs(text: &str, name: &str) -> Result<RunsDoc, Error> {
    let doc: RunsDoc = serde_json::from_str(text).map_err(|e| {
        Error::invalid(
            name,
            format!("not a {MONTECARLO_RUNS_FORMAT} document: {e}"),
        )
    })?;
    check_part(&doc, &At::file(name))?;
    Ok(doc)
}

/// Checks one part: its format, its campaign header, its shard `[i, k]` with
/// `i < k`, and every record against them (the run belongs to the shard and is
/// below the campaign's runs, the records in increasing run order; lengths of
/// `durations`, `outcomes` and `spans`; outcome characters; spans present
/// exactly for the activities that ran; violation names; loss and culprit
/// indices, one loss per activity that was predicted and did not complete).
pub(super) fn check_part(doc: &RunsDoc, at: &At<'_>) -> Result<(), Error> {
    if doc.format != MONTECARLO_RUNS_FORMAT {
        return Err(at.err(
            "format",
            format!(
                "expected \"{MONTECARLO_RUNS_FORMAT}\", found \"{}\"",
                doc.format
            ),
        ));
    }
    check_campaign(&doc.campaign, at)?;
    let (i, k) = doc.shard;
    if i >= k {
        return Err(at.err(
            "shard",
            format!("expected [i, k] with 0 <= i < k (got [{i}, {k}])"),
        ));
    }
    let mut previous: Option<u64> = None;
    for (n, r) in doc.records.iter().enumerate() {
        let here = format!("records[{n}]");
        if r.run >= doc.campaign.runs {
            return Err(at.err(
                format!("{here}.run"),
                format!(
                    "run {} is not below the campaign's {} runs",
                    r.run, doc.campaign.runs
                ),
            ));
        }
        if r.run % k != i {
            return Err(at.err(
                format!("{here}.run"),
                format!("run {} is not in shard [{i}, {k}] (runs i modulo k)", r.run),
            ));
        }
        if let Some(p) = previous
            && p >= r.run
        {
            return Err(at.err(
                format!("{here}.run"),
                format!(
                    "run {} after run {p}: records are in increasing run order",
                    r.run
                ),
            ));
        }
        previous = Some(r.run);
        check_record(&doc.campaign, r, at, &here)?;
    }
    Ok(())
}

/// The campaign header: its per-activity lists agree in length, its uncertain
/// activities are increasing indices of activities, and it has runs.
fn check_campaign(c: &Campaign, at: &At<'_>) -> Result<(), Error> {
    let n = c.activities.len();
    if c.runs == 0 {
        return Err(at.err("campaign.runs", "a campaign has at least one run"));
    }
    for (field, len) in [
        ("mandatory", c.mandatory.len()),
        ("predicted", c.predicted.len()),
    ] {
        if len != n {
            return Err(at.err(
                format!("campaign.{field}"),
                format!("{len} entries for {n} activities"),
            ));
        }
    }
    for (j, p) in c.predicted.iter().enumerate() {
        if let Some((s, e)) = p
            && e < s
        {
            return Err(at.err(
                format!("campaign.predicted[{j}]"),
                format!("ends before it starts ({e} < {s})"),
            ));
        }
    }
    for (j, &u) in c.uncertain.iter().enumerate() {
        if u >= n || (j > 0 && c.uncertain[j - 1] >= u) {
            return Err(at.err(
                format!("campaign.uncertain[{j}]"),
                format!("{u} is not an activity index in increasing order (of {n} activities)"),
            ));
        }
    }
    Ok(())
}

/// One record against its campaign.
fn check_record(c: &Campaign, r: &RunRecord, at: &At<'_>, here: &str) -> Result<(), Error> {
    let n = c.activities.len();
    let len = |field: &str, got: usize, want: usize, of: &str| {
        if got == want {
            Ok(())
        } else {
            Err(at.err(
                format!("{here}.{field}"),
                format!("{got} entries for {want} {of}"),
            ))
        }
    };
    len(
        "durations",
        r.durations.len(),
        c.uncertain.len(),
        "uncertain activities",
    )?;
    len("outcomes", r.outcomes.chars().count(), n, "activities")?;
    len("spans", r.spans.len(), n, "activities")?;
    for (a, (o, span)) in r.outcomes.chars().zip(&r.spans).enumerate() {
        if !matches!(o, 'c' | 'a' | 'n') {
            return Err(at.err(
                format!("{here}.outcomes"),
                format!("character {a} is {o:?}; expected 'c' (completed), 'a' (aborted) or 'n' (not run)"),
            ));
        }
        match span {
            None if o != 'n' => {
                return Err(at.err(
                    format!("{here}.spans[{a}]"),
                    format!("null for an activity that ran (outcome '{o}')"),
                ));
            }
            Some(_) if o == 'n' => {
                return Err(at.err(
                    format!("{here}.spans[{a}]"),
                    "a span for an activity that did not run (outcome 'n')",
                ));
            }
            Some((s, e)) if e < s => {
                return Err(at.err(
                    format!("{here}.spans[{a}]"),
                    format!("ends before it starts ({e} < {s})"),
                ));
            }
            _ => {}
        }
    }
    for (v, name) in r.violations.iter().enumerate() {
        if !VIOLATIONS.iter().any(|k| k.name() == name) {
            let known: Vec<&str> = VIOLATIONS.iter().map(|k| k.name()).collect();
            return Err(at.err(
                format!("{here}.violations[{v}]"),
                format!(
                    "unknown limit {name:?}; expected one of {}",
                    known.join(", ")
                ),
            ));
        }
    }
    let outcomes = r.outcomes.as_bytes();
    let mut seen = vec![false; n];
    for (l, loss) in r.losses.iter().enumerate() {
        let a = loss.activity;
        if a >= n {
            return Err(at.err(
                format!("{here}.losses[{l}].activity"),
                format!("{a} is not an activity index (of {n} activities)"),
            ));
        }
        if c.predicted[a].is_none() || outcomes[a] == b'c' || seen[a] {
            return Err(at.err(
                format!("{here}.losses[{l}].activity"),
                format!(
                    "activity {a} ({}) was not lost in this run, or its loss is listed twice",
                    c.activities[a]
                ),
            ));
        }
        seen[a] = true;
        for (m, &culprit) in loss.culprits.iter().enumerate() {
            if culprit >= n {
                return Err(at.err(
                    format!("{here}.losses[{l}].culprits[{m}]"),
                    format!("{culprit} is not an activity index (of {n} activities)"),
                ));
            }
        }
    }
    Ok(())
}

/// Merges named parts (each checked with [`check_part`]): their headers agree,
/// no run appears twice, and together they hold every run of the campaign.
pub(super) fn merge_at(
    parts: &[(At<'_>, &RunsDoc)],
) -> Result<(super::Campaign, Vec<RunRecord>), Error> {
    let Some((_, first)) = parts.first() else {
        return Err(Error::invalid("parts", "no parts to merge"));
    };
    let mut owner: BTreeMap<u64, usize> = BTreeMap::new();
    let mut records = Vec::new();
    for (p, (at, doc)) in parts.iter().enumerate() {
        check_part(doc, at)?;
        if doc.campaign != first.campaign {
            return Err(at.err(
                "campaign",
                "a part of another campaign (plan, seed, run count or policy differ)",
            ));
        }
        for (n, r) in doc.records.iter().enumerate() {
            if let Some(&q) = owner.get(&r.run) {
                return Err(at.err(
                    format!("records[{n}].run"),
                    format!("run {} appears twice (also in {})", r.run, parts[q].0.name),
                ));
            }
            owner.insert(r.run, p);
        }
        records.extend(doc.records.iter().cloned());
    }
    records.sort_by_key(|r| r.run);
    let runs = first.campaign.runs;
    if let Some(k) = (0..runs)
        .zip(&records)
        .find(|(k, r)| r.run != *k)
        .map(|(k, _)| k)
    {
        return Err(Error::invalid("parts", format!("run {k} is missing")));
    }
    if records.len() as u64 != runs {
        // Every run present is below `runs` and distinct: the first one after
        // them is missing.
        return Err(Error::invalid(
            "parts",
            format!(
                "run {} is missing ({} of {runs} runs present)",
                records.len(),
                records.len()
            ),
        ));
    }
    Ok((first.campaign.clone(), records))
}

#[cfg(test)]
mod tests {
    use super::super::{LossRecord, merge_parts};
    use super::*;
    use crate::execute::Policy;

    /// A campaign of two activities (the second uncertain) and `runs` runs.
    fn campaign(runs: u64) -> Campaign {
        Campaign {
            plan: "p".into(),
            plan_hash: "0".into(),
            seed: 1,
            runs,
            activities: vec!["a".into(), "b".into()],
            mandatory: vec![false, false],
            predicted: vec![Some((0, 10)), Some((10, 20))],
            uncertain: vec![1],
            policy: Policy::Replan,
        }
    }

    fn record(run: u64) -> RunRecord {
        RunRecord {
            run,
            durations: vec![12],
            outcomes: "cn".into(),
            spans: vec![Some((0, 10)), None],
            lowest_soc: (0, 0),
            handover_soc: None,
            violations: vec![],
            losses: vec![LossRecord {
                activity: 1,
                cause: "held".into(),
                cycle_time: Some(0),
                culprits: vec![0],
            }],
        }
    }

    /// Runs 0..4 in shards 0/2 and 1/2.
    fn parts() -> Vec<RunsDoc> {
        (0..2)
            .map(|i| RunsDoc {
                format: MONTECARLO_RUNS_FORMAT.into(),
                campaign: campaign(4),
                shard: (i, 2),
                records: vec![record(i), record(i + 2)],
            })
            .collect()
    }

    /// The message of merging `parts` with `edit` applied to the second.
    fn refused(edit: impl Fn(&mut RunsDoc)) -> String {
        let mut parts = parts();
        edit(&mut parts[1]);
        match merge_parts(&parts) {
            Ok(_) => String::new(),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn sound_parts_merge_into_every_run() {
        let merged = merge_parts(&parts()).map(|(_, r)| r.iter().map(|r| r.run).collect());
        assert_eq!(merged.ok(), Some(vec![0u64, 1, 2, 3]));
    }

    #[test]
    fn every_corrupted_record_is_refused_at_its_path() {
        for (edit, want) in [
            (
                (|d: &mut RunsDoc| d.records[1].outcomes = "xn".into()) as fn(&mut RunsDoc),
                "parts[1].records[1].outcomes: character 0 is 'x'",
            ),
            (
                |d| d.records[0].outcomes = "c".into(),
                "parts[1].records[0].outcomes: 1 entries for 2 activities",
            ),
            (
                |d| d.records[0].losses[0].activity = 999_999,
                "parts[1].records[0].losses[0].activity: 999999 is not an activity index",
            ),
            (
                |d| d.records[0].losses[0].culprits = vec![2],
                "parts[1].records[0].losses[0].culprits[0]: 2 is not an activity index",
            ),
            (
                |d| d.records[0].losses[0].activity = 0,
                "parts[1].records[0].losses[0].activity: activity 0 (a) was not lost",
            ),
            (|d| d.shard = (1, 0), "parts[1].shard: expected [i, k]"),
            (
                |d| d.records[0].run = 2,
                "parts[1].records[0].run: run 2 is not in shard [1, 2]",
            ),
            (
                |d| d.records[1].run = 5,
                "parts[1].records[1].run: run 5 is not below",
            ),
            (
                |d| d.records[0].durations.clear(),
                "parts[1].records[0].durations: 0 entries",
            ),
            (
                |d| d.records[0].spans[1] = Some((5, 6)),
                "parts[1].records[0].spans[1]: a span",
            ),
            (
                |d| d.records[0].spans[0] = None,
                "parts[1].records[0].spans[0]: null",
            ),
            (
                |d| d.records[0].violations = vec!["nope".into()],
                "parts[1].records[0].violations[0]",
            ),
            (
                |d| d.records.reverse(),
                "parts[1].records[1].run: run 1 after run 3",
            ),
            (
                |d| d.campaign.seed = 2,
                "parts[1].campaign: a part of another campaign",
            ),
            (
                |d| d.campaign.uncertain = vec![2],
                "parts[1].campaign.uncertain[0]",
            ),
            (
                |d| d.campaign.mandatory.pop().map_or((), drop),
                "parts[1].campaign.mandatory",
            ),
            (|d| d.format = "x".into(), "parts[1].format"),
            (
                |d| d.records.pop().map_or((), drop),
                "parts: run 3 is missing",
            ),
        ] {
            let err = refused(edit);
            assert!(err.starts_with(want), "{want}: {err}");
        }
    }

    #[test]
    fn a_run_in_two_parts_is_refused() {
        let mut parts = parts();
        parts.push(parts[0].clone());
        let err = merge_parts(&parts).err().map(|e| e.to_string());
        assert_eq!(
            err.as_deref(),
            Some("parts[2].records[0].run: run 0 appears twice (also in parts[0])")
        );
    }
}
