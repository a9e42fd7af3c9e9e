//! Mutations of a base input file: bad numbers, changed arrays, values of
//! another type, misspelt keys, moved lines, truncation, bad bytes, deep keys
//! and foreign headers; each says what it did and what floe must do.

use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::text::short;
use super::toml_scan::{
    arrays, content_lines, elements, number_tokens, split_lines, statements, toml_type, Array,
};
use super::Expect;

pub struct Mutant {
    pub bytes: Vec<u8>,
    pub what: String,
    pub expect: Expect,
}

impl Mutant {
    pub fn from_lines(lines: &[String], what: String, expect: Expect) -> Mutant {
        Mutant {
            bytes: lines.join("\n").into_bytes(),
            what,
            expect,
        }
    }
}

type FileMutation = fn(&str, &mut ChaCha8Rng) -> Option<Mutant>;

/// The file mutations and their weights (bad numbers are the most common
/// mistake, so they get more cases).
const FILE_MUTATIONS: &[(u32, FileMutation)] = &[
    (5, replace_number),
    (1, swap_integer_and_float),
    (1, add_array_element),
    (1, drop_array_element),
    (2, replace_value_type),
    (2, misspell_key),
    (1, duplicate_line),
    (1, delete_line),
    (1, swap_lines),
    (1, truncate),
    (1, insert_bad_byte),
    (1, insert_dotted_key),
    (1, prepend_magic),
];

pub fn mutate_file(text: &str, rng: &mut ChaCha8Rng) -> Mutant {
    loop {
        let (_, mutation) = FILE_MUTATIONS
            .choose_weighted(rng, |m| m.0)
            .expect("weights");
        if let Some(mutant) = mutation(text, rng) {
            return mutant;
        }
    }
}

/// The replacement numbers. The first four can never be a valid value.
const BAD_NUMBERS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "99999999999999999999",
    "0",
    "-0.0",
    "-1",
    "1e300",
    "-1e300",
    "1e-300",
    "1e12",
    "0.5",
];

const NEVER_VALID_NUMBERS: usize = 4;

fn replace_number(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let &(i, start, end) = number_tokens(&lines).choose(rng)?;
    let pick = rng.gen_range(0..BAD_NUMBERS.len());
    let new = BAD_NUMBERS[pick];
    let old = lines[i][start..end].to_string();
    lines[i].replace_range(start..end, new);
    // nan, inf and integers beyond i64 are never a valid setting
    let expect = if pick < NEVER_VALID_NUMBERS {
        Expect::Refusal
    } else {
        Expect::Anything
    };
    let what = format!("{}:{}: number `{old}` -> `{new}`", i + 1, start + 1);
    Some(Mutant::from_lines(&lines, what, expect))
}

/// `400.0` -> `400`, `3` -> `3.0`.
fn swap_integer_and_float(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let &(i, start, end) = number_tokens(&lines).choose(rng)?;
    let old = lines[i][start..end].to_string();
    let new = if old.contains(['.', 'e', 'E']) {
        format!("{}", old.parse::<f64>().ok()?.round() as i64)
    } else {
        format!("{old}.0")
    };
    lines[i].replace_range(start..end, &new);
    let what = format!("{}:{}: `{old}` -> `{new}`", i + 1, start + 1);
    Some(Mutant::from_lines(&lines, what, Expect::Anything))
}

/// Fixed-length arrays (vectors, boxes) and arrays whose lengths must match
/// (time series) are refused with a changed length.
fn array_expect(array: &Array) -> Expect {
    if array.any_length {
        Expect::Anything
    } else {
        Expect::Refusal
    }
}

fn add_array_element(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let array = arrays(&lines);
    let array = array.choose(rng)?;
    let mut items = elements(&lines[array.line][array.open + 1..array.close]);
    let copy = items.first().cloned().unwrap_or_else(|| "0".into());
    items.push(copy.clone());
    lines[array.line].replace_range(array.open + 1..array.close, &items.join(", "));
    let what = format!(
        "{}:{}: array element `{copy}` added",
        array.line + 1,
        array.open + 1
    );
    Some(Mutant::from_lines(&lines, what, array_expect(array)))
}

fn drop_array_element(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let array = arrays(&lines);
    let array = array.choose(rng)?;
    let mut items = elements(&lines[array.line][array.open + 1..array.close]);
    let dropped = items.pop()?;
    lines[array.line].replace_range(array.open + 1..array.close, &items.join(", "));
    let what = format!(
        "{}:{}: array element `{dropped}` dropped",
        array.line + 1,
        array.open + 1
    );
    Some(Mutant::from_lines(&lines, what, array_expect(array)))
}

/// A value of another type, and the TOML name of that type.
fn other_value(rng: &mut ChaCha8Rng) -> (String, &'static str) {
    match rng.gen_range(0..8) {
        0 => ("\"fuzz\"".into(), "string"),
        1 => ("{ fuzz = 1 }".into(), "table"),
        2 => ("[]".into(), "array"),
        3 => ("true".into(), "boolean"),
        4 => ("[1, \"two\"]".into(), "array"),
        5 => ("1979-05-27T07:32:00Z".into(), "datetime"),
        // deep nesting: the parser must refuse it, not overflow its stack
        6 => {
            let depth = rng.gen_range(100..5000);
            (
                format!("{}{}", "[".repeat(depth), "]".repeat(depth)),
                "array",
            )
        }
        _ => {
            let depth = rng.gen_range(100..5000);
            let open = "{ a = ".repeat(depth);
            (format!("{open}1{}", " }".repeat(depth)), "table")
        }
    }
}

fn replace_value_type(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let &(i, v) = statements(&lines).choose(rng)?;
    let old = lines[i][v..].trim().to_string();
    let (new, new_type) = other_value(rng);
    // a value of another type is refused; one of the same type may be valid
    let expect = if toml_type(&old) == Some(new_type) {
        Expect::Anything
    } else {
        Expect::Refusal
    };
    lines[i].replace_range(v.., &format!(" {new}"));
    let what = format!(
        "{}:{}: value `{old}` -> `{}`",
        i + 1,
        v + 1,
        short(&new, 60)
    );
    Some(Mutant::from_lines(&lines, what, expect))
}

/// A keyboard slip: two letters swapped, one dropped or doubled, or the
/// first capitalised. Never the same key.
pub fn typo(name: &str, rng: &mut ChaCha8Rng) -> String {
    let chars: Vec<char> = name.chars().collect();
    for _ in 0..20 {
        let mut c = chars.clone();
        let k = rng.gen_range(0..c.len());
        match rng.gen_range(0..4) {
            0 if k + 1 < c.len() => c.swap(k, k + 1),
            1 if c.len() > 1 => {
                c.remove(k);
            }
            2 => c.insert(k, c[k]),
            _ => c[0] = c[0].to_ascii_uppercase(),
        }
        let typed: String = c.into_iter().collect();
        if typed != name {
            return typed;
        }
    }
    format!("{name}x")
}

/// Misspells a key of a `key = value` line or a table header.
fn misspell_key(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let i = *content_lines(&lines).choose(rng)?;
    let line = lines[i].clone();
    let (start, end) = match line.find('=') {
        Some(eq) if !line.starts_with('[') => (0, line[..eq].trim_end().len()),
        _ => {
            let start = line.rfind('[')? + 1;
            (start, line.find(']')?)
        }
    };
    let old = &line[start..end];
    let new = typo(old, rng);
    lines[i].replace_range(start..end, &new);
    let what = format!("{}:{}: key `{old}` misspelt `{new}`", i + 1, start + 1);
    Some(Mutant::from_lines(&lines, what, Expect::Refusal))
}

/// The copy follows its line, in the same table: a duplicate key, a
/// duplicate table or an empty array element, all refused.
fn duplicate_line(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let i = *content_lines(&lines).choose(rng)?;
    let copy = lines[i].clone();
    lines.insert(i + 1, copy);
    let what = format!("line {} duplicated", i + 1);
    Some(Mutant::from_lines(&lines, what, Expect::Refusal))
}

fn delete_line(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let i = *content_lines(&lines).choose(rng)?;
    let gone = lines.remove(i);
    let what = format!("line {} `{gone}` deleted", i + 1);
    Some(Mutant::from_lines(&lines, what, Expect::Anything))
}

fn swap_lines(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let content = content_lines(&lines);
    let pair: Vec<usize> = content.choose_multiple(rng, 2).copied().collect();
    let (a, b) = (*pair.first()?, *pair.get(1)?);
    if lines[a] == lines[b] {
        return None;
    }
    lines.swap(a, b);
    let what = format!("lines {} and {} swapped", a + 1, b + 1);
    Some(Mutant::from_lines(&lines, what, Expect::Anything))
}

fn truncate(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let at = rng.gen_range(0..text.len());
    Some(Mutant {
        bytes: text.as_bytes()[..at].to_vec(),
        what: format!("truncated at byte {at} of {}", text.len()),
        expect: Expect::Anything,
    })
}

/// A Latin-1 `é`, a byte never in UTF-8, or a NUL: never valid TOML.
fn insert_bad_byte(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let byte = *[0xE9u8, 0xFF, 0x00].choose(rng)?;
    let at = rng.gen_range(0..=text.len());
    let mut bytes = text.as_bytes().to_vec();
    bytes.insert(at, byte);
    Some(Mutant {
        bytes,
        what: format!("byte {byte:#04x} inserted at byte {at}"),
        expect: Expect::Refusal,
    })
}

/// `fuzz.fuzz.(...).fuzz = 1` on a line of its own: an unknown key, however
/// deep.
fn insert_dotted_key(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let mut lines = split_lines(text);
    let depth = *[2usize, 16, 256, 4096, 30000].choose(rng)?;
    let at = rng.gen_range(0..lines.len());
    lines.insert(at, format!("{} = 1", vec!["fuzz"; depth].join(".")));
    let what = format!("a key {depth} deep inserted before line {}", at + 1);
    Some(Mutant::from_lines(&lines, what, Expect::Refusal))
}

/// A compressed or HDF5 file given where TOML is expected.
fn prepend_magic(text: &str, rng: &mut ChaCha8Rng) -> Option<Mutant> {
    let (name, magic): (&str, &[u8]) = *[
        ("gzip", &b"\x1f\x8b\x08\x00\x00\x00\x00\x00"[..]),
        ("HDF5", &b"\x89HDF\r\n\x1a\n"[..]),
    ]
    .choose(rng)?;
    let mut bytes = magic.to_vec();
    bytes.extend_from_slice(text.as_bytes());
    Some(Mutant {
        bytes,
        what: format!("{name} header prepended"),
        expect: Expect::Refusal,
    })
}
