//! Checking one case's outcome against the contract every case obeys and
//! against what its mutation expects.

use std::os::unix::process::ExitStatusExt;

use super::cases::{Case, Family};
use super::runner::{Outcome, TIMEOUT};
use super::Expect;

/// Longest acceptable line on stderr.
const MAX_LINE_CHARS: usize = 1000;

pub fn problems(case: &Case, out: &Outcome) -> Vec<String> {
    let mut found = Vec::new();
    check_exit(case, out, &mut found);
    check_stderr(case, out, &mut found);
    if !out.changed.is_empty() {
        found.push(format!("input modified: {}", out.changed.join(", ")));
    }
    found.extend(out.bad_output.iter().cloned());
    found
}

fn check_exit(case: &Case, out: &Outcome, found: &mut Vec<String>) {
    let Some(status) = out.status else {
        found.push(format!("hang: still running after {TIMEOUT:?}, killed"));
        return;
    };
    let code = status.code();
    match (code, status.signal()) {
        (Some(0..=2), _) => {}
        (Some(101), _) => found.push("exit code 101: a panic".into()),
        (Some(c), _) => found.push(format!("exit code {c}")),
        (None, signal) => found.push(format!("killed by signal {signal:?}")),
    }
    let wrong = match case.expect {
        Expect::Anything => None,
        Expect::Success => (code != Some(0)).then_some("the unmutated input must run (exit 0)"),
        Expect::Refusal => (code != Some(2))
            .then_some("this input is never valid: it must be refused (exit 2), not silently used"),
        Expect::Failure => (code == Some(0)).then_some("this input must fail (exit 1 or 2)"),
    };
    found.extend(wrong.map(String::from));
}

fn check_stderr(case: &Case, out: &Outcome, found: &mut Vec<String>) {
    for marker in ["panicked", "RUST_BACKTRACE", "stack backtrace"] {
        if out.stderr.contains(marker) {
            found.push(format!("stderr contains `{marker}`"));
        }
    }
    if let Some(long) = out.stderr.lines().map(|l| l.chars().count()).max() {
        if long > MAX_LINE_CHARS {
            found.push(format!("a stderr line of {long} characters"));
        }
    }
    let lines: Vec<&str> = out.stderr.trim_end().lines().collect();
    let errors = lines.iter().filter(|l| l.starts_with("error:")).count();
    let last_is_error = lines.last().is_some_and(|l| l.starts_with("error: "));
    let problem = match out.status.and_then(|s| s.code()) {
        Some(2) if lines.len() != 1 || !last_is_error => Some(format!(
            "exit 2 must print one line, `error: ...`; got {} lines",
            lines.len()
        )),
        Some(2) if !locates(case, lines[0]) => Some(match case.family {
            Family::CommandLine => "exit 2 message names no flag, argument or FILE:LINE:COL".into(),
            _ => "exit 2 message has no FILE:LINE:COL".into(),
        }),
        Some(2)
            if case
                .names
                .as_ref()
                .is_some_and(|n| !lines[0].contains(n.as_str())) =>
        {
            Some(format!(
                "exit 2 message does not name `{}`",
                case.names.as_deref().unwrap_or_default()
            ))
        }
        Some(1) if !last_is_error || errors != 1 => Some(format!(
            "exit 1 must end stderr with its only `error: ` line ({errors} such lines)"
        )),
        Some(0) if errors > 0 => Some("exit 0 after an `error:` line".into()),
        _ => None,
    };
    found.extend(problem);
}

fn locates(case: &Case, message: &str) -> bool {
    names_file_position(message)
        || (case.family == Family::CommandLine
            && (names_argument(message) || names_path_given(case, message)))
}

/// `error: PATH: ...` for a PATH on the command line (a missing file).
fn names_path_given(case: &Case, message: &str) -> bool {
    let rest = message.strip_prefix("error: ").unwrap_or(message);
    case.args
        .iter()
        .any(|a| !a.starts_with('-') && rest.starts_with(&format!("{a}: ")))
}

/// `NAME.toml:LINE:COL` (or `.h5`), or sweep's `NAME.toml with KEY=V:LINE:COL`.
fn names_file_position(message: &str) -> bool {
    let names_file = |s: &str| {
        s.ends_with(".toml")
            || s.ends_with(".h5")
            || s.rfind(".toml with ")
                .is_some_and(|k| !s[k..].contains(':'))
    };
    let line_col = |s: &str| {
        let mut parts = s.split(':');
        let line = parts.next().unwrap_or("");
        let col = parts.next().unwrap_or("");
        !line.is_empty()
            && line.bytes().all(|b| b.is_ascii_digit())
            && col.starts_with(|c: char| c.is_ascii_digit())
    };
    message
        .match_indices(':')
        .any(|(i, _)| names_file(&message[..i]) && line_col(&message[i + 1..]))
}

/// A flag (`--name`) or an argument as clap names it (`<FILE>`, `[SCENARIO]`).
/// Not `--help`: clap's messages all end with "(see floe --help)".
fn names_argument(message: &str) -> bool {
    let flag = message.match_indices("--").any(|(i, _)| {
        let name: String = message[i + 2..]
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
            .collect();
        name.starts_with(|c: char| c.is_ascii_alphabetic()) && name != "help"
    });
    let argument = message
        .match_indices(['<', '['])
        .any(|(i, _)| message[i + 1..].starts_with(|c: char| c.is_ascii_uppercase()));
    flag || argument
}
