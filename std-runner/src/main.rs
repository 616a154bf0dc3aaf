//! `strata`: parses arguments and dispatches to `strata_runner`.

fn main() -> std::process::ExitCode {
    match std::env::args().nth(1).as_deref() {
        None | Some("--version") | Some("-V") => {
            println!("{}", strata_runner::version_line());
            std::process::ExitCode::SUCCESS
        }
        Some(other) => {
            eprintln!("error: unknown command `{other}`: only --version exists in this build");
            std::process::ExitCode::from(2)
        }
    }
}
