//! `strata`: parses the command line and dispatches to `strata_runner`.

fn main() -> std::process::ExitCode {
    let cli = strata_runner::cli::Cli::parse_with_sources(std::env::args_os())
        .unwrap_or_else(|e| e.exit());
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
