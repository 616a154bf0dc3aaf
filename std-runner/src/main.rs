//! `strata`: parses the command line and dispatches to `strata_runner`.

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = strata_runner::cli::Cli::parse();
    match strata_runner::commands::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) if e.is::<strata_runner::commands::Interrupted>() => {
            // The shell's status for a process stopped by SIGINT.
            eprintln!("{e}");
            std::process::ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
