//! The `floe` binary: parse, run, print; one message and a non-zero exit on error.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;
use floe_cli::cli::{execute, Cli};

fn main() -> ExitCode {
    floe_cli::interrupt::ignore_file_size_signal();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    match execute(cli) {
        Ok(out) => {
            if out.is_empty() {
                return ExitCode::SUCCESS;
            }
            match writeln!(std::io::stdout().lock(), "{out}") {
                Ok(()) => ExitCode::SUCCESS,
                // The reader went away (`floe info run.h5 | head`): it has
                // what it wanted; stop quietly.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
                Err(e) => {
                    floe_cli::stderr::line(&format!("error: cannot write to standard output: {e}"));
                    ExitCode::FAILURE
                }
            }
        }
        Err(e) => {
            // Empty: process 0 of an MPI job reports it.
            let message = e.to_string();
            if !message.is_empty() {
                floe_cli::stderr::line(&format!("error: {message}"));
            }
            ExitCode::from(e.exit_code())
        }
    }
}

/// Help and version go to standard output (a closed pipe is fine); a bad
/// command line is one line on standard error and exit code 2.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
    }
    let text = e.render().to_string();
    if e.kind() == ErrorKind::UnknownArgument {
        if let Some(message) = negative_value_hint(&text) {
            let _ = writeln!(
                std::io::stderr().lock(),
                "error: {message} (see floe --help)"
            );
            return ExitCode::from(2);
        }
    }
    // The error and clap's tips (`a similar argument exists: '--force'`),
    // without the usage and help paragraphs.
    let message = text
        .split("\n\n")
        .map(|p| p.lines().map(str::trim).collect::<Vec<_>>().join(" "))
        .filter(|p| p.starts_with("error:") || p.starts_with("tip:"))
        .collect::<Vec<_>>()
        .join("; ");
    let _ = writeln!(std::io::stderr().lock(), "{message} (see floe --help)");
    ExitCode::from(2)
}

/// A value such as `-inf` or `-1e-3` after a flag reads as a flag of its
/// own; name the flag it was meant for.
fn negative_value_hint(clap_message: &str) -> Option<String> {
    let args: Vec<String> = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    args.windows(2).find_map(|pair| {
        let (flag, value) = (&pair[0], &pair[1]);
        let number = value.strip_prefix('-')?.parse::<f64>().is_ok();
        // The value clap took for a flag (it names `-1`, or `-i` of `-inf`).
        let named = clap_message.contains(&format!("'{}", &value[..2]));
        (flag.starts_with("--") && !flag.contains('=') && number && named).then(|| {
            format!(
                "{flag} {value}: a value starting with `-` reads as a flag; write {flag}={value}"
            )
        })
    })
}
