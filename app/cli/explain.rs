//! `solscope explain`: why activities failed (solscope.explain/1, or text),
//! written as it is made: a large plan's explanation is hundreds of megabytes.

use std::io::Write;
use std::path::Path;

use super::args::ExplainArgs;
use super::failure::Failure;
use super::progress::Progress;

/// Loads and schedules the plan (a failure prints nothing on standard output),
/// then writes the explanations one at a time as the engine hands them on, byte
/// for byte the document `explain_document` would make, with a progress bar on
/// standard error (after a second, on a terminal). With `output`, the same
/// bytes go to that file, which is put in place only once complete.
pub fn run(args: &ExplainArgs, limit: usize, output: Option<&Path>) -> Result<(), Failure> {
    let opts = solscope_engine::ExplainOptions {
        activity: args.activity.clone(),
        no_suggestions: args.no_suggestions,
    };
    let text = args.text;
    let source = solscope_engine::read_plan_text(&args.plan, limit)?;
    let loaded = solscope_engine::load_plan_limited(&source, limit)?;
    super::bounds::heated_search(&loaded.plan)?;
    let schedule = solscope_engine::schedule(&loaded.plan)?;
    if let Some(id) = &opts.activity {
        if !loaded.plan.activities.iter().any(|a| &a.id == id) {
            return Err(solscope_engine::Error::UnknownActivity(id.clone()).into());
        }
    } else if !opts.no_suggestions {
        let failures = schedule
            .steps
            .iter()
            .filter(|s| s.outcome.placement().is_none())
            .count();
        super::bounds::suggested_work(failures, loaded.plan.activities.len())?;
    }
    let progress = Progress::new(schedule.steps.len() as u64);
    let mut file = match output {
        Some(path) => {
            Some(crate::write::WholeFile::create(path).map_err(|e| super::unwritable(path, &e))?)
        }
        None => None,
    };
    let mut stdout;
    let sink: &mut dyn Write = match &mut file {
        Some(f) => f,
        None => {
            stdout = std::io::stdout().lock();
            &mut stdout
        }
    };
    let mut out = std::io::BufWriter::new(sink);
    // Pieces written so far (the header is the first), or the first error.
    let mut written: Result<usize, std::io::Error> = Ok(0);
    let mut write = |piece: &str, written: &mut Result<usize, std::io::Error>| {
        if let Ok(n) = written {
            match out.write_all(piece.as_bytes()) {
                Ok(()) => *n += 1,
                Err(e) => *written = Err(e),
            }
        }
    };
    if !text {
        write(
            "{\n  \"format\": \"solscope.explain/1\",\n  \"explanations\": [",
            &mut written,
        );
    }
    let plan_ref = &loaded.plan;
    let sched_ref = &schedule;
    // The explanations are formatted in parallel as they are handed on (the
    // entry as the whole document's pretty form nests it: two levels, four
    // spaces, in), and written here in order.
    let render = |ex: solscope_engine::Explanation| -> Result<String, String> {
        if text {
            return Ok(solscope_engine::explanation_text(plan_ref, sched_ref, &ex));
        }
        let entry = solscope_engine::explanation_entry(plan_ref, sched_ref, &ex);
        let json = serde_json::to_string_pretty(&entry)
            .map_err(|e| format!("could not write the document as JSON: {e}"))?;
        let mut piece = String::with_capacity(json.len() + json.len() / 8);
        for (i, line) in json.lines().enumerate() {
            if i > 0 {
                piece.push('\n');
            }
            piece.push_str("    ");
            piece.push_str(line);
        }
        Ok(piece)
    };
    let outcome = solscope_engine::explain_rendered(
        plan_ref,
        sched_ref,
        &opts,
        render,
        &mut |done, _| progress.set_position(done as u64),
        &mut |piece| match piece {
            Ok(piece) => {
                if !text {
                    let first = matches!(written, Ok(1));
                    write(if first { "\n" } else { ",\n" }, &mut written);
                }
                write(&piece, &mut written);
            }
            Err(e) => {
                if written.is_ok() {
                    written = Err(std::io::Error::other(e));
                }
            }
        },
    );
    progress.finish();
    outcome?;
    if !text {
        let end = if matches!(written, Ok(1)) {
            "]\n}\n"
        } else {
            "\n  ]\n}\n"
        };
        write(end, &mut written);
    }
    let written = written.and_then(|_| out.flush());
    drop(out);
    match (file, output) {
        (Some(file), Some(path)) => written
            .and_then(|()| file.commit())
            .map_err(|e| super::unwritable(path, &e)),
        _ => written.map_err(Failure::Stdout),
    }
}
