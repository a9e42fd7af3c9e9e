//! Every `floe` command that README.md, docs/running.md and docs/hpc.md
//! show in their code blocks is accepted by the command line as written
//! (each synopsis expanded into its forms, placeholders filled in), and the
//! commands floe itself suggests when a run pauses or is interrupted work
//! when run verbatim.

use crate::run_support;

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Parser;
use floe_cli::cli::{self, Cli};
use floe_cli::commands::run::run_output;
use run_support::{code, run_suggestion, suggested_command, text, Case};

/// The documents whose commands are checked.
const DOCUMENTS: [&str; 3] = ["README.md", "docs/running.md", "docs/hpc.md"];

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `floe ...` command lines in a markdown text's code blocks (fenced,
/// or indented by four spaces or more), continuation lines joined, shell
/// comments and background `&` dropped, and `exec`, `mpirun` and `srun`
/// with their own options removed.
fn command_lines(markdown: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    let mut pending = String::new();
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        let code = fenced || line.starts_with("    ");
        if !code && pending.is_empty() {
            continue;
        }
        let trimmed = line.trim();
        if let Some(head) = trimmed.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        pending.push_str(trimmed);
        let whole = std::mem::take(&mut pending);
        if let Some(command) = floe_part(&whole) {
            out.push(command);
        }
    }
    out
}

/// The `floe ...` part of a shell line, if it runs floe.
fn floe_part(line: &str) -> Option<String> {
    let line = line.split(" & ").next().unwrap_or(line);
    let line = match line.find(" #") {
        Some(i) => &line[..i],
        None => line,
    };
    let mut words: Vec<&str> = line.split_whitespace().collect();
    loop {
        match words.first().copied() {
            Some("exec") => {
                words.remove(0);
            }
            Some("mpirun" | "srun") => {
                words.remove(0);
                // The launcher's own options and their values.
                while let Some(w) = words.first() {
                    if *w == "floe" {
                        break;
                    }
                    words.remove(0);
                }
            }
            _ => break,
        }
    }
    (words.first() == Some(&"floe")).then(|| words.join(" "))
}

/// A synopsis' tokens: words, and the brackets `[ ] ( )` and the
/// alternative bar `|` standing alone.
fn tokens(synopsis: &str) -> Vec<String> {
    let mut out = Vec::new();
    for word in synopsis.split_whitespace() {
        let mut current = String::new();
        for c in word.chars() {
            if "[]()".contains(c) {
                if !current.is_empty() {
                    out.push(std::mem::take(&mut current));
                }
                out.push(c.to_string());
            } else {
                current.push(c);
            }
        }
        if !current.is_empty() {
            out.push(current);
        }
    }
    out
}

/// Every form of a synopsis: each optional group `[...]` left out or put in,
/// each alternative `a | b` and `a|b` taken in turn.
fn forms(tokens: &[String]) -> Vec<Vec<String>> {
    let (alternatives, rest) = alternation(tokens);
    assert!(rest.is_empty(), "unbalanced synopsis: {tokens:?}");
    alternatives
}

/// Parses `seq ('|' seq)*` up to a closing bracket; returns the expanded
/// forms and what follows.
fn alternation(mut tokens: &[String]) -> (Vec<Vec<String>>, &[String]) {
    let mut all = Vec::new();
    loop {
        let (forms, rest) = sequence(tokens);
        all.extend(forms);
        match rest.first().map(String::as_str) {
            Some("|") => tokens = &rest[1..],
            _ => return (all, rest),
        }
    }
}

fn sequence(mut tokens: &[String]) -> (Vec<Vec<String>>, &[String]) {
    let mut forms: Vec<Vec<String>> = vec![Vec::new()];
    loop {
        let Some(first) = tokens.first().map(String::as_str) else {
            return (forms, tokens);
        };
        let (choices, rest): (Vec<Vec<String>>, &[String]) = match first {
            "|" | "]" | ")" => return (forms, tokens),
            "[" | "(" => {
                let (mut inner, rest) = alternation(&tokens[1..]);
                let close = if first == "[" { "]" } else { ")" };
                assert_eq!(rest.first().map(String::as_str), Some(close));
                if first == "[" {
                    inner.insert(0, Vec::new());
                }
                (inner, &rest[1..])
            }
            word if word.contains('|') && !word.contains('=') => (
                word.split('|').map(|w| vec![w.to_string()]).collect(),
                &tokens[1..],
            ),
            word => (vec![vec![word.to_string()]], &tokens[1..]),
        };
        forms = forms
            .iter()
            .flat_map(|f| {
                choices.iter().map(move |c| {
                    let mut g = f.clone();
                    g.extend(c.iter().cloned());
                    g
                })
            })
            .collect();
        tokens = rest;
    }
}

/// A concrete value for a placeholder or shell variable; `None` for a word
/// that is not one.
fn fill(word: &str, previous: Option<&str>) -> Option<String> {
    let value = match word {
        "SCENARIO.toml" => "scenario.toml",
        "SHEAR_CELL.toml" => "cell.toml",
        "STEPPED_CELL.toml" => "steps.toml",
        "OUT.h5" => "out.h5",
        "FIELDS.nc" => "fields.nc",
        "OUT.xdmf" => "out.xdmf",
        "DIR" => "dir",
        "MOVIE" | "MOVIE.gif" => "movie.gif",
        "MOVIE.mp4" => "movie.mp4",
        "NAME" => "sea_ice_area_fraction",
        "N" | "K" | "STEPS" => "2",
        "F" => "0.2",
        "M" => "500",
        "T" => "3600",
        "M_PER_S" => "0.01",
        "MU" => "0.4",
        "KEY=V1,V2,..." => "friction.a=0.25,0.31",
        "V1,V2,..." => "0.1,0.2",
        "\"$v.h5\"" => "variant_001.h5",
        "\"$v.toml\"" => "variant_001.toml",
        "\"$SLURM_CPUS_PER_TASK\"" => "4",
        "..." => match previous {
            Some("--set") => "seed=1,2",
            Some("--color") => "theta",
            Some("--laws") => "amontons,rate-state",
            // "floe slider hold|step|run|fit ...": that subcommand's help.
            _ => "--help",
        },
        _ => return None,
    };
    Some(value.to_string())
}

/// A word left unfilled that looks like a placeholder (capitals or a shell
/// variable): the synopsis uses a name this test does not know.
fn looks_like_placeholder(word: &str) -> bool {
    let stem = word.split('.').next().unwrap_or(word);
    word.contains('$')
        || (!stem.is_empty() && stem.chars().all(|c| c.is_ascii_uppercase() || c == '_'))
}

/// The documented commands, as argument lists ready to parse, with the
/// document and the line they came from.
fn documented_commands() -> Vec<(String, Vec<String>)> {
    let mut all = Vec::new();
    for document in DOCUMENTS {
        let markdown = std::fs::read_to_string(repository().join(document)).unwrap();
        for line in command_lines(&markdown) {
            for form in forms(&tokens(&line)) {
                let mut args = Vec::new();
                for word in &form {
                    let previous = args.last().map(String::as_str);
                    let filled = fill(word, previous).unwrap_or_else(|| word.clone());
                    assert!(
                        !looks_like_placeholder(&filled),
                        "{document}: `{line}`: the placeholder `{word}` has no value in this test's fill()"
                    );
                    args.push(filled);
                }
                all.push((format!("{document}: `{line}`"), args));
            }
        }
    }
    all
}

#[test]
fn the_synopsis_parser_expands_options_and_alternatives() {
    let f = forms(&tokens("floe x A [--b N | --c K] (--d|--e) [--f]"));
    let shown: Vec<String> = f.iter().map(|f| f.join(" ")).collect();
    assert_eq!(
        shown,
        [
            "floe x A --d",
            "floe x A --d --f",
            "floe x A --e",
            "floe x A --e --f",
            "floe x A --b N --d",
            "floe x A --b N --d --f",
            "floe x A --b N --e",
            "floe x A --b N --e --f",
            "floe x A --c K --d",
            "floe x A --c K --d --f",
            "floe x A --c K --e",
            "floe x A --c K --e --f",
        ]
    );
    let lines = command_lines(
        "text\n\n    mpirun -np 16 floe run --resume big.h5   # any count\n\n```bash\n    exec srun floe run \"$v.toml\" \\\n        -o x.h5 & pid=$!\n```\n  floe in prose\n",
    );
    assert_eq!(
        lines,
        ["floe run --resume big.h5", "floe run \"$v.toml\" -o x.h5"]
    );
}

#[test]
fn every_documented_command_is_accepted_as_written() {
    let commands = documented_commands();
    // README's synopsis alone gives more than a hundred forms; a count this
    // low would mean the documents' code blocks were not found.
    assert!(commands.len() > 100, "{} commands", commands.len());
    let mut runs = 0;
    for (origin, args) in &commands {
        let parsed = Cli::try_parse_from(args);
        let cli = match parsed {
            Ok(cli) => cli,
            Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelp => continue,
            Err(e) => panic!("{origin}: `{}` is refused:\n{e}", args.join(" ")),
        };
        if let cli::Command::Run(run) = cli.command {
            runs += 1;
            if let Err(e) = run_output(run.output, run.resume) {
                panic!("{origin}: `{}` is refused: {e}", args.join(" "));
            }
        }
    }
    assert!(runs >= 10, "{runs} forms of floe run");
}

/// A sheared channel of small diamonds, a few hundred steps.
const SHORT: &str = include_str!("../data/run_small.toml");

#[test]
fn the_paused_runs_suggestion_continues_it_when_run_verbatim() {
    let case = Case::new(SHORT);
    let out = case.run("paused.h5", &["--max-steps", "20"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let said = format!("{}{}", text(&out.stdout), text(&out.stderr));
    let words = suggested_command(&said);
    assert_eq!(words[..3], ["floe", "run", "--resume"], "{said}");
    let out = run_suggestion(case.dir.path(), &words);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let file = floe_io::RunFile::open(Path::new(&case.path("paused.h5"))).unwrap();
    assert_eq!(file.status().unwrap(), "completed");
}

#[test]
fn resume_takes_the_file_after_it_or_after_output_but_not_two_files() {
    let case = Case::new(SHORT);
    case.run_ok("a.h5", &["--max-steps", "10"]);
    let floe = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_floe"))
            .args(args)
            .current_dir(case.dir.path())
            .output()
            .unwrap()
    };
    let out = floe(&["run", "--resume", "a.h5", "-q", "--max-steps", "10"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let out = floe(&["run", "--resume", "-o", "a.h5", "-q", "--max-steps", "10"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let out = floe(&["run", "--resume", "a.h5", "-o", "a.h5", "-q"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));

    case.run_ok("b.h5", &["--max-steps", "10"]);
    let out = floe(&["run", "--resume", "b.h5", "-o", "a.h5", "-q"]);
    assert_eq!(code(&out), 2, "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("two files"),
        "{}",
        text(&out.stderr)
    );
    let out = floe(&["run", "--resume", "-q"]);
    assert_eq!(code(&out), 2, "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("floe run --resume OUT.h5"),
        "{}",
        text(&out.stderr)
    );
}
