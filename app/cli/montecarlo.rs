//! `solscope montecarlo`: a campaign of executions with drawn durations (the
//! summary, solscope.montecarlo/1; one CSV row per run; or with `--shard I/K`
//! one share's records, solscope.montecarlo-runs/1), and `solscope montecarlo
//! merge`, which combines the shares into exactly the summary one machine prints.

use std::path::PathBuf;

use super::args::{MonteCarloCommand, MontecarloArgs};
use super::failure::{Failure, to_json};
use super::progress::with_progress;
use super::{default_name, load};

/// Most Monte Carlo runs one `montecarlo` process runs (their records are kept
/// until it prints; a few kB each).
const MAX_RECORDS_PER_PROCESS: u64 = 100_000;

/// Most run records `montecarlo merge` holds at once.
const MAX_RECORDS_MERGED: u64 = 1_000_000;

/// The campaign's output, or the merged parts'.
pub fn run(args: &MontecarloArgs) -> Result<String, Failure> {
    match &args.merge {
        Some(MonteCarloCommand::Merge {
            parts, input, csv, ..
        }) => merge(parts, input.bytes()?, *csv),
        None => campaign(args, args.input.bytes()?),
    }
}

/// `solscope montecarlo PLAN`.
fn campaign(args: &MontecarloArgs, limit: usize) -> Result<String, Failure> {
    let Some(plan) = &args.plan else {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "PLAN",
            "a plan file is required (or `merge PARTS...`)",
        )));
    };
    let runs = args.runs;
    let loaded = load(plan, limit)?;
    if runs == 0 || runs > 10_000_000 {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--runs",
            format!("must be between 1 and 10000000 (got {runs})"),
        )));
    }
    let (part, of) = match args.shard.as_deref() {
        None => (0, 1),
        Some(text) => parse_shard(text)?,
    };
    // Every record this process runs is kept until it prints: a bigger
    // share is split into more shards.
    let share = shard_size(part, of, runs);
    if share > MAX_RECORDS_PER_PROCESS {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "--runs",
            format!(
                "{share} runs in one process; at most {MAX_RECORDS_PER_PROCESS}: split the campaign with --shard I/K"
            ),
        )));
    }
    let campaign = solscope_engine::campaign_with(
        &loaded.plan,
        args.seed,
        runs,
        &default_name(plan),
        args.policy.into(),
    )?;
    // A step beyond the address space takes only the first run (if any).
    let step = usize::try_from(of).unwrap_or(usize::MAX);
    let indices: Vec<u64> = (part..runs).step_by(step).collect();
    let records = with_progress(indices.len() as u64, |tick| {
        solscope_engine::campaign_runs(&loaded.plan, &campaign, &indices, tick, None)
    })?
    .unwrap_or_default();
    if args.csv {
        Ok(solscope_engine::runs_csv(&campaign, &records))
    } else if args.shard.is_some() {
        to_json(&solscope_engine::RunsDoc {
            format: solscope_engine::MONTECARLO_RUNS_FORMAT.into(),
            campaign,
            shard: (part, of),
            records,
        })
    } else {
        to_json(&solscope_engine::summarize(&campaign, &records))
    }
}

/// `solscope montecarlo merge PARTS...`.
fn merge(parts: &[PathBuf], limit: usize, csv: bool) -> Result<String, Failure> {
    let mut docs = Vec::with_capacity(parts.len());
    for path in parts {
        let text = solscope_engine::read_plan_text(path, limit)?;
        let name = format!("{}", path.display());
        let doc = solscope_engine::read_runs(&text, &name)?;
        docs.push((name, doc));
    }
    let total: usize = docs.iter().map(|(_, d)| d.records.len()).sum();
    if total as u64 > MAX_RECORDS_MERGED {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "parts",
            format!("{total} records; at most {MAX_RECORDS_MERGED} are merged in one process"),
        )));
    }
    let (campaign, records) = solscope_engine::merge_files(&docs)?;
    if csv {
        Ok(solscope_engine::runs_csv(&campaign, &records))
    } else {
        to_json(&solscope_engine::summarize(&campaign, &records))
    }
}

/// How many of the runs `0..runs` shard `part` of `of` holds (the indices
/// `part, part + of, ...` below `runs`): none when `part >= runs`, which is a
/// shard like any other (it merges as zero records). Needs `of >= 1`.
fn shard_size(part: u64, of: u64, runs: u64) -> u64 {
    match runs.checked_sub(part) {
        None | Some(0) => 0,
        // `left >= 1`: the first index, then one per whole step in the rest.
        Some(left) => (left - 1) / of.max(1) + 1,
    }
}

/// `--shard I/K`.
fn parse_shard(text: &str) -> Result<(u64, u64), Failure> {
    let bad = || {
        Failure::Input(solscope_engine::Error::invalid(
            "--shard",
            format!("expected I/K with 0 <= I < K (got {text})"),
        ))
    };
    let (i, k) = text.split_once('/').ok_or_else(bad)?;
    let (i, k): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        k.trim().parse().map_err(|_| bad())?,
    );
    if k == 0 || i >= k {
        return Err(bad());
    }
    Ok((i, k))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shard_holds_the_indices_below_runs_without_wrapping() {
        // Counted by hand: 10 runs in 32 shards, 3 in 4, 10 in 3.
        assert_eq!(shard_size(0, 32, 10), 1);
        assert_eq!(shard_size(9, 32, 10), 1);
        assert_eq!(shard_size(10, 32, 10), 0);
        assert_eq!(shard_size(11, 32, 10), 0);
        assert_eq!(shard_size(31, 32, 10), 0);
        assert_eq!(shard_size(0, 3, 10), 4);
        assert_eq!(shard_size(1, 3, 10), 3);
        assert_eq!(shard_size(2, 3, 10), 3);
        assert_eq!(shard_size(0, 1, 10), 10);
        assert_eq!(shard_size(0, u64::MAX, u64::MAX), 1);
        assert_eq!(shard_size(u64::MAX - 1, u64::MAX, u64::MAX), 1);
        assert_eq!(shard_size(0, 1, u64::MAX), u64::MAX);
        assert_eq!(shard_size(u64::MAX, u64::MAX, 0), 0);
        // Every shard's size is the number of indices it runs.
        for runs in 0..20u64 {
            for of in 1..25u64 {
                let total: u64 = (0..of).map(|part| shard_size(part, of, runs)).sum();
                assert_eq!(total, runs, "{runs} runs in {of} shards");
                for part in 0..of {
                    let n = (part..runs).step_by(of as usize).count() as u64;
                    assert_eq!(shard_size(part, of, runs), n, "{part}/{of} of {runs}");
                }
            }
        }
    }

    #[test]
    fn shards_are_i_of_k_with_i_below_k() {
        assert_eq!(parse_shard("0/1").ok(), Some((0, 1)));
        assert_eq!(parse_shard(" 3 / 8 ").ok(), Some((3, 8)));
        for bad in ["1/1", "0/0", "2", "a/3", "-1/3", "1/2/3"] {
            let err = parse_shard(bad).err().map(|f| match f {
                Failure::Input(e) => e.to_string(),
                other => format!("{other:?}"),
            });
            assert_eq!(
                err.as_deref(),
                Some(format!("--shard: expected I/K with 0 <= I < K (got {bad})").as_str()),
                "{bad}"
            );
        }
    }
}
