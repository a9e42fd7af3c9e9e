//! Mutations of a valid command line: a bad flag value, an unknown flag, a
//! flag given twice, a required argument left out, a bad file argument.

use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::file_mutations::typo;
use super::templates::{Line, Template};
use super::Expect;

/// Bad flag values. The first five are never valid for a flag that is not a
/// path (`-o`, `--out`).
const BAD_FLAG_VALUES: &[&str] = &[
    "",
    "nan",
    "inf",
    "-inf",
    "abc",
    "0",
    "-1",
    "1e300",
    "-1e300",
    "1e-300",
    "99999999999999999999",
    "18446744073709551616",
    "1,,2",
];

const NEVER_VALID_FLAG_VALUES: usize = 5;

const PATH_FLAGS: &[&str] = &["-o", "--out"];

type CommandMutation = fn(&Template, &mut Line, &mut ChaCha8Rng) -> Option<(String, Expect)>;

const COMMAND_MUTATIONS: &[(u32, CommandMutation)] = &[
    (6, bad_flag_value),
    (1, unknown_flag),
    (1, flag_twice),
    (1, drop_required),
    (1, bad_positional),
];

pub fn mutate_command(template: &Template, rng: &mut ChaCha8Rng) -> (Line, String, Expect) {
    loop {
        let (_, mutation) = COMMAND_MUTATIONS
            .choose_weighted(rng, |m| m.0)
            .expect("weights");
        let mut line = Line::of(template);
        if let Some((what, expect)) = mutation(template, &mut line, rng) {
            return (line, what, expect);
        }
    }
}

/// The flags of a command that take a value: those of the valid line and
/// the others it takes.
pub fn valued_flags(template: &Template) -> Vec<&'static str> {
    let valued = template.flags.iter().filter(|(_, v)| v.is_some());
    let mut names: Vec<&str> = valued.map(|(f, _)| *f).collect();
    names.extend(template.extra.iter().map(|(f, _)| *f));
    names
}

/// A valued flag of the line, or one of the command's other flags, gets a
/// bad value.
fn bad_flag_value(
    template: &Template,
    line: &mut Line,
    rng: &mut ChaCha8Rng,
) -> Option<(String, Expect)> {
    let flag = *valued_flags(template).choose(rng)?;
    set_bad_value(template, line, flag, rng)
}

/// The valid line of `template` with a bad value for `flag`.
pub fn bad_value_of(
    template: &Template,
    flag: &str,
    rng: &mut ChaCha8Rng,
) -> (Line, String, Expect) {
    loop {
        let mut line = Line::of(template);
        if let Some((what, expect)) = set_bad_value(template, &mut line, flag, rng) {
            return (line, what, expect);
        }
    }
}

fn set_bad_value(
    template: &Template,
    line: &mut Line,
    flag: &str,
    rng: &mut ChaCha8Rng,
) -> Option<(String, Expect)> {
    let pick = rng.gen_range(0..BAD_FLAG_VALUES.len());
    let value = BAD_FLAG_VALUES[pick].to_string();
    // a path starting with `-` reads as a flag in any command line
    if PATH_FLAGS.contains(&flag) && value.starts_with('-') {
        return None;
    }
    let added = !line.has(flag);
    match line.flags.iter_mut().find(|(f, _)| f == flag) {
        Some(entry) => entry.1 = Some(value.clone()),
        None => line.flags.push((flag.into(), Some(value.clone()))),
    }
    let never_valid = value.is_empty()
        || (pick < NEVER_VALID_FLAG_VALUES && !PATH_FLAGS.contains(&flag))
        || (added && excludes_a_flag_of(template, line, flag));
    let expect = if never_valid {
        Expect::Refusal
    } else {
        Expect::Anything
    };
    let verb = if added { "added" } else { "set" };
    Some((format!("{flag} {verb} to `{value}`"), expect))
}

fn excludes_a_flag_of(template: &Template, line: &Line, flag: &str) -> bool {
    template
        .exclusive
        .iter()
        .any(|&(a, b)| (a == flag && line.has(b)) || (b == flag && line.has(a)))
}

/// `--bogus` or a misspelt flag of the command.
fn unknown_flag(
    template: &Template,
    line: &mut Line,
    rng: &mut ChaCha8Rng,
) -> Option<(String, Expect)> {
    let known: Vec<&str> = template
        .flags
        .iter()
        .map(|(f, _)| *f)
        .chain(template.extra.iter().map(|(f, _)| *f))
        .chain(["--help", "--version"])
        .collect();
    let long: Vec<&str> = known
        .iter()
        .copied()
        .filter(|f| f.starts_with("--"))
        .collect();
    let flag = match long.choose(rng) {
        Some(f) if rng.gen_bool(0.7) => format!("--{}", typo(&f[2..], rng)),
        _ => "--bogus".into(),
    };
    if known.contains(&flag.as_str()) {
        return None;
    }
    line.flags.push((flag.clone(), Some("1".into())));
    Some((format!("unknown flag `{flag} 1`"), Expect::Refusal))
}

/// A flag given twice: refused unless its repeats add values.
fn flag_twice(
    template: &Template,
    line: &mut Line,
    rng: &mut ChaCha8Rng,
) -> Option<(String, Expect)> {
    let (flag, value) = line.flags.choose(rng)?.clone();
    let expect = if template.repeatable.contains(&flag.as_str()) || value.is_none() {
        Expect::Anything
    } else {
        Expect::Refusal
    };
    line.flags.push((flag.clone(), value));
    Some((format!("{flag} given twice"), expect))
}

fn drop_required(
    template: &Template,
    line: &mut Line,
    rng: &mut ChaCha8Rng,
) -> Option<(String, Expect)> {
    let mut choices: Vec<&str> = template.required.to_vec();
    if template.positional.is_some() {
        choices.push("the file argument");
    }
    let dropped = *choices.choose(rng)?;
    if dropped == "the file argument" {
        line.positional = None;
    } else {
        line.flags.retain(|(f, _)| f != dropped);
    }
    Some((format!("{dropped} left out"), Expect::Refusal))
}

/// The file argument: empty, missing, a directory, or the wrong kind of file.
fn bad_positional(
    template: &Template,
    line: &mut Line,
    rng: &mut ChaCha8Rng,
) -> Option<(String, Expect)> {
    let old = template.positional?;
    let new = *["", "nan", "missing.toml", ".", "run.h5", "s.toml", "p.toml"]
        .iter()
        .filter(|&&p| p != old)
        .copied()
        .collect::<Vec<_>>()
        .choose(rng)?;
    line.positional = Some(new.into());
    let expect = if new.is_empty() {
        Expect::Refusal
    } else {
        Expect::Failure
    };
    Some((format!("file argument `{old}` -> `{new}`"), expect))
}
