//! `strata bench`: the benchmark suite (`crate::bench`) as a table and JSON.

use std::io::{IsTerminal, Write};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use crate::cli::BenchArgs;
use crate::commands::output::check_json;
use crate::image_io::write_atomic;

/// Runs `strata bench`.
pub fn bench(args: &BenchArgs) -> Result<()> {
    if let Some(path) = &args.json {
        // Probes the directory with a file of our own: an existing report
        // is left alone until the new one replaces it.
        check_json(path, "--json")?;
    }
    let options = crate::bench::Options {
        repetitions: args.repetitions as usize,
        min_time: std::time::Duration::from_millis(args.min_time_ms),
        group: args.group,
    };
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(
            args.group
                .map_or(crate::bench::COMPARISONS, crate::bench::Group::comparisons),
        );
        bar.set_style(
            ProgressStyle::with_template("{spinner} {pos}/{len} {wide_msg}")
                .expect("a valid template"),
        );
        bar
    } else {
        ProgressBar::hidden()
    };
    let report = crate::bench::run_suite(options, &|name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&report)?;
        write_atomic(path, |tmp| Ok(std::fs::write(tmp, &text)?))
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    // The table is the result here: a full disk is an error, a reader
    // that went away (a closed pipe) is not.
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{}", crate::bench::table(&report).trim_end()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("writing the table"),
        _ => Ok(()),
    }
}
