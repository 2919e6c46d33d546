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
        Some(MonteCarloCommand::Merge { parts, input, csv }) => merge(parts, input.bytes()?, *csv),
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
    let share = (runs - part).div_ceil(of);
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
    let indices: Vec<u64> = (part..runs).step_by(of as usize).collect();
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
        let doc: solscope_engine::RunsDoc = serde_json::from_str(&text).map_err(|e| {
            solscope_engine::Error::invalid(
                format!("{}", path.display()),
                format!("not a solscope.montecarlo-runs/1 document: {e}"),
            )
        })?;
        docs.push(doc);
    }
    let total: usize = docs.iter().map(|d| d.records.len()).sum();
    if total as u64 > MAX_RECORDS_MERGED {
        return Err(Failure::Input(solscope_engine::Error::invalid(
            "parts",
            format!("{total} records; at most {MAX_RECORDS_MERGED} are merged in one process"),
        )));
    }
    let (campaign, records) = solscope_engine::merge_parts(&docs)?;
    if csv {
        Ok(solscope_engine::runs_csv(&campaign, &records))
    } else {
        to_json(&solscope_engine::summarize(&campaign, &records))
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
