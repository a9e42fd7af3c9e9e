//! What the cases did: a report of each failure, exit codes per family, the
//! slowest case.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::os::unix::process::ExitStatusExt;
use std::time::Duration;

use super::cases::{seed, Case, Family};
use super::runner::Outcome;
use super::text::short;

pub struct Failure {
    pub index: usize,
    pub report: String,
    pub summary: String,
}

pub fn failure(case: &Case, out: &Outcome, found: &[String]) -> Failure {
    let code = match out.status {
        Some(s) => format!("{:?} (signal {:?})", s.code(), s.signal()),
        None => "killed after the timeout".into(),
    };
    let mut report = String::new();
    let _ = writeln!(
        report,
        "=== case {} of seed {:#x} ({:?}): {}",
        case.index,
        seed(),
        case.family,
        case.what
    );
    let _ = writeln!(
        report,
        "reproduce: FLOE_FUZZ_SEED={:#x} FLOE_FUZZ_CASE={} \
         cargo test --release -p floe-cli --test cli fuzz:: -- --nocapture",
        seed(),
        case.index
    );
    let _ = writeln!(report, "command: floe {}", shell_words(&case.args));
    let _ = writeln!(
        report,
        "exit: {code}, after {:.2} s",
        out.elapsed.as_secs_f64()
    );
    for problem in found {
        let _ = writeln!(report, "problem: {problem}");
    }
    let _ = writeln!(report, "stderr:\n{}", show(out.stderr.as_bytes()));
    if let Some(k) = case.mutated {
        let (name, bytes) = &case.files[k];
        let _ = writeln!(report, "input {name}:\n{}", show_file(bytes));
    }
    let last = out.stderr.lines().last().unwrap_or("");
    let summary = format!(
        "case {} ({:?}) {}: {} | stderr: {}",
        case.index,
        case.family,
        case.what,
        found.join("; "),
        short(last, 200)
    );
    Failure {
        index: case.index,
        report,
        summary,
    }
}

fn shell_words(args: &[String]) -> String {
    let quote = |a: &String| {
        if !a.is_empty()
            && a.bytes()
                .all(|b| b.is_ascii_alphanumeric() || b"-_.,=/".contains(&b))
        {
            a.clone()
        } else {
            format!("'{a}'")
        }
    };
    args.iter().map(quote).collect::<Vec<_>>().join(" ")
}

/// A text file as [`show`] gives it; a binary one (a NetCDF file) as its
/// length and first bytes.
fn show_file(bytes: &[u8]) -> String {
    let text = std::str::from_utf8(bytes).is_ok_and(|t| !t.contains('\0'));
    if text || bytes.is_empty() {
        return show(bytes);
    }
    let head: Vec<String> = bytes.iter().take(32).map(|b| format!("{b:02x}")).collect();
    format!("({} bytes, binary) {} ...", bytes.len(), head.join(" "))
}

/// Bytes as text: control bytes and bytes that are not UTF-8 as `\xNN`,
/// long lines shortened.
fn show(bytes: &[u8]) -> String {
    let mut text = String::new();
    for chunk in bytes.utf8_chunks() {
        for c in chunk.valid().chars() {
            if c.is_control() && c != '\n' && c != '\t' {
                let _ = write!(text, "\\x{:02X}", c as u32);
            } else {
                text.push(c);
            }
        }
        for b in chunk.invalid() {
            let _ = write!(text, "\\x{b:02X}");
        }
    }
    text.lines()
        .map(|l| short(l, 400))
        .collect::<Vec<_>>()
        .join("\n")
}

/// What the cases did: failures, exit codes per family, the slowest case.
#[derive(Default)]
pub struct Results {
    pub failures: Vec<Failure>,
    pub exits: BTreeMap<(String, String), usize>,
    pub slowest: Duration,
}

impl Results {
    pub fn record(&mut self, case: &Case, out: &Outcome, found: &[String]) {
        let exit = match out.status {
            Some(s) => format!("{:?}", s.code()),
            None => "timeout".into(),
        };
        if std::env::var_os("FLOE_FUZZ_VERBOSE").is_some() {
            let last = out.stderr.lines().last().unwrap_or("");
            println!(
                "case {} {:?} {}: exit {exit}, {:.2} s: {}",
                case.index,
                case.family,
                case.what,
                out.elapsed.as_secs_f64(),
                short(last, 160)
            );
        }
        *self
            .exits
            .entry((format!("{:?}", case.family), exit))
            .or_default() += 1;
        self.slowest = self.slowest.max(out.elapsed);
        if !found.is_empty() {
            let f = failure(case, out, found);
            println!("{}", f.report);
            self.failures.push(f);
        }
    }

    /// The summary line, exit codes per family, and one line per failure.
    pub fn print_summary(&self, cases: &[&Case], wall: Duration) {
        let count = |family| cases.iter().filter(|c| c.family == family).count();
        println!(
            "cli fuzz: seed {:#x}; {} base inputs, {} scenario, {} protocol, {} command-line \
             and {} basin-file cases; {} failed; slowest case {:.2} s; wall time {:.1} s",
            seed(),
            count(Family::Base),
            count(Family::Scenario),
            count(Family::Protocol),
            count(Family::CommandLine),
            count(Family::BasinFile),
            self.failures.len(),
            self.slowest.as_secs_f64(),
            wall.as_secs_f64()
        );
        for ((family, exit), n) in &self.exits {
            println!("  {family}: exit {exit} x {n}");
        }
        for f in &self.failures {
            println!("FAILED {}", f.summary);
        }
    }
}
