//! `strata bench`: the benchmark suite (`crate::bench`) as a table and JSON.

use std::io::Write;

use anyhow::{Context, Result};

use crate::bench::{COMPARISONS, Options, run_suite, table};
use crate::cli::{BenchArgs, IntegratorName};
use crate::commands::output::write_text;
use crate::commands::{check_output_ext, progress_bar};

/// Runs `strata bench`.
pub fn bench(args: &BenchArgs) -> Result<()> {
    if let Some(path) = &args.json {
        // Probes the directory with a file of our own: an existing report
        // is left alone until the new one replaces it.
        check_output_ext(path, "json", "--json")?;
    }
    let options = Options {
        repetitions: args.repetitions as usize,
        min_time: std::time::Duration::from_millis(args.min_time_ms),
        group: args.group,
        integrator: IntegratorName::integrator(args.integrator),
    };
    let bar = progress_bar(
        args.group
            .map_or(COMPARISONS, crate::bench::Group::comparisons),
        "{spinner} {pos}/{len} {wide_msg}",
    );
    let report = run_suite(options, &|name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    if let Some(path) = &args.json {
        write_text(path, &serde_json::to_string_pretty(&report)?)?;
    }
    // The table is the result here: a full disk is an error, a reader
    // that went away (a closed pipe) is not.
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{}", table(&report).trim_end()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("writing the table"),
        _ => Ok(()),
    }
}
