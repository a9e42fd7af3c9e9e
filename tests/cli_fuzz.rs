//! Seeded fuzz test of bad input to the `floe` binary (issue "Bad numbers and
//! bad bytes: no crash, no hang, nothing silently dropped").
//!
//! From one fixed seed it builds, every run the same:
//! - mutated scenario files, run as
//!   `floe run case.toml -o out.h5 --max-steps 200 -q --threads 1`;
//! - mutated spring-slider protocol files, run as
//!   `floe slider run proto.toml --out out`;
//! - mutated command lines of `run`, `info`, `render`, `compare`, `sweep`
//!   and `slider hold|step|run` (bad flag values, unknown flags, a flag given
//!   twice, a required argument dropped, a bad file argument);
//! - and, first, every unmutated base input, which must run (exit 0).
//!
//! File mutations: a number replaced (0, -0.0, -1, 1e300, -1e300, 1e-300,
//! nan, inf, -inf, 1e12, 99999999999999999999, 0.5), an integer written as a
//! float or the reverse, an array element added or dropped, a value replaced by
//! one of another type, a key misspelt, a line duplicated, deleted or swapped
//! with another, the file truncated, a byte that is not UTF-8 (0xE9, 0xFF) or
//! a NUL inserted, a deeply dotted key inserted, a gzip or HDF5 header
//! prepended.
//!
//! Each case runs the real binary in its own temporary directory with a hard
//! timeout, at most two cases at a time, and must:
//! - exit with 0, 1 or 2: no panic (101), no signal, no hang;
//! - never print "panicked", "RUST_BACKTRACE" or "stack backtrace", nor a
//!   stderr line over 1000 characters;
//! - on exit 2 print exactly one line, `error: ...`, that locates the problem:
//!   `FILE:LINE:COL` of the input, or (command lines) the flag or argument;
//! - on exit 1 end stderr with its only `error: ...` line;
//! - leave its input files byte for byte as they were;
//! - refuse (exit 2) a mutation that can never be valid (a misspelt key, a
//!   duplicated line, a non-finite or unrepresentable number, bytes that are
//!   not TOML, an unknown flag, a flag given twice, ...): nothing is silently
//!   dropped;
//! - on exit 0 print no `inf` or `NaN` (standard output, a slider run's
//!   series.csv): bad numbers in must not come out as non-finite numbers.
//!
//! A failure prints the seed, the case index, the command line and the
//! mutated input, and the test ends with a one-line summary of each failure.
//! Cases depend only on the seed and their index:
//! `FLOE_FUZZ_CASE=N cargo test --release -p floe-cli --test cli_fuzz -- --nocapture`
//! reruns case N alone, `FLOE_FUZZ_SEED=S` draws other cases, and
//! `FLOE_FUZZ_VERBOSE=1` prints every case's mutation and exit.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The seed of every case (`FLOE_FUZZ_SEED=N` explores other cases).
const SEED: u64 = 0xF10E_2026;
const SCENARIO_CASES: usize = 300;
const PROTOCOL_CASES: usize = 100;
const COMMAND_CASES: usize = 100;
/// A case still running after this long is a hang.
const TIMEOUT: Duration = Duration::from_secs(30);
/// Cases run at a time (each floe process uses one thread).
const WORKERS: usize = 2;
/// Longest acceptable line on stderr.
const MAX_LINE_CHARS: usize = 1000;

// ---------------------------------------------------------------------------
// Valid base inputs. Every statement is on one line and has no trailing
// comment, so that the mutations below can find keys, values and numbers by
// simple scanning.

/// Explicit floes: boxes, a triangle, a prescribed floe; Amontons friction.
const BOXES: &str = r#"# explicit floes pushed by wind
title = "boxes"
duration_s = 600.0
dt_s = 0.5
seed = 2

[domain]
size_m = [4000.0, 2000.0]
min_m = [0.0, 0.0]

[[floe]]
box_m = [100.0, 100.0, 900.0, 900.0]
velocity_m_per_s = [0.5, 0.0]

[[floe]]
box_m = [1000.0, 100.0, 1800.0, 900.0]
thickness_m = 1.5

[[floe]]
vertices_m = [[2000.0, 100.0], [2800.0, 100.0], [2400.0, 900.0]]
angular_velocity_rad_per_s = 0.001

[[floe]]
box_m = [3000.0, 1000.0, 3800.0, 1800.0]
prescribed = true
velocity_m_per_s = [-0.1, 0.0]

[ice]
density_kg_per_m3 = 917.0

[friction]
law = "amontons"
mu = 0.5

[wind]
velocity_m_per_s = [10.0, 0.0]

[ocean]
drag_coefficient = 5.5e-3

[output]
snapshot_every_s = 60.0
"#;

/// About 60 diamonds in a periodic channel between walls; rate-and-state.
const DIAMONDS: &str = r#"title = "diamonds in a channel"
duration_s = 300.0
seed = 3

[domain]
size_m = [4000.0, 2000.0]
periodic = [true, false]

[tessellation]
kind = "diamond"
side_m = 400.0
acute_angle_deg = 60.0
jitter_fraction = 0.1
min_area_fraction = 0.3

[ice]
thickness_mean_m = 1.5
thickness_std_m = 0.4

[contact]
youngs_modulus_pa = 6e6
poisson_ratio = 0.3
restitution = 0.5
memory_s = 60.0

# Lishman et al. (2011), tank scale
[friction]
law = "rate-state"
preset = "tank"
a = 0.31
b = 0.382
critical_slip_m = 0.005
state_law = "slip"

[wind]
shear = { y_min_m = 0.0, y_max_m = 2000.0, velocity_at_y_min_m_per_s = [0.0, -2.0], velocity_at_y_max_m_per_s = [15.0, -2.0] }

[ocean]
velocity_m_per_s = [0.1, 0.0]
turning_angle_deg = 20.0

[coriolis]
latitude_deg = 75.0

[[wall]]
side = "bottom"

[[wall]]
side = "top"
velocity_m_per_s = [0.2, 0.0]

[output]
snapshot_every_s = 30.0
observables_every_s = 3.0
checkpoint_every_s = 100.0
"#;

/// About 35 Voronoi floes compressed in a box; rate-dependent friction.
const VORONOI: &str = r#"title = "voronoi box"
duration_s = 200.0
seed = 7

[domain]
size_m = [3000.0, 3000.0]

[tessellation]
kind = "voronoi"
floe_scale_m = 500.0
relax_iterations = 2

[ice]
thickness_range_m = [0.5, 2.0]

[friction]
law = "rate"
mu0 = 0.872
c1 = -0.072
v_star_m_per_s = 1e-5

[wind]
time_series = { times_s = [0.0, 100.0, 200.0], velocities_m_per_s = [[0.0, 0.0], [10.0, 5.0], [0.0, 0.0]] }
envelope = { times_s = [0.0, 50.0], factors = [1.0, 0.5] }

[[wall]]
side = "left"

[[wall]]
side = "right"

[[wall]]
side = "bottom"
velocity_m_per_s = [0.0, 0.1]
inset_m = 100.0

[[wall]]
side = "top"
velocity_m_per_s = [0.0, -0.1]
"#;

/// Nine floes on a doubly periodic grid in a gyre, with Coriolis.
const GRID: &str = r#"title = "grid drift"
duration_s = 3600.0

[domain]
size_m = [30000.0, 30000.0]
min_m = [-15000.0, -15000.0]
periodic = [true, true]

[tessellation]
kind = "grid"
columns = 3
rows = 3
gap_m = 5000.0

[ice]
thickness_m = 2.0
initial_velocity_m_per_s = [0.1, 0.0]

[wind]
gyre = { center_m = [0.0, 0.0], core_radius_m = 5000.0, max_speed_m_per_s = 10.0 }
drag_coefficient = 1.2e-3
density_kg_per_m3 = 1.2

[ocean]
turning_angle_deg = 20.0
sea_surface_tilt = true
rotational_drag = true
relative_to_ice = true

[coriolis]
f_per_s = 1.4e-4

[output]
snapshot_every_s = 600.0
"#;

/// The laboratory double-shear experiment (200 of its steps).
const DOUBLE_SHEAR: &str = r#"title = "lab double shear"
duration_s = 20.0

[domain]
size_m = [2.0, 1.0]

[tessellation]
kind = "double-shear"
block_m = [0.2, 0.1]
side_block_m = [0.6, 0.1]
normal_load_per_face_n = 1000.0
push_velocity_m_per_s = 1e-4

[ice]
thickness_m = 0.1

[contact]
youngs_modulus_pa = 2e8
new_contact_slip_rate_m_per_s = 1e-4

[friction]
law = "rate-state"
preset = "lab"
"#;

const SCENARIOS: &[(&str, &str)] = &[
    ("boxes", BOXES),
    ("diamonds", DIAMONDS),
    ("voronoi", VORONOI),
    ("grid", GRID),
    ("double-shear", DOUBLE_SHEAR),
];

/// Slide, hold, ramp on the lab apparatus (published form).
const LAB_PROTOCOL: &str = r#"# slide-hold-slide, shortened
[apparatus]
preset = "lab"
dt_s = 1e-3

[law]
kind = "rate-state"
form = "published"
state_law = "slip"

[output]
every_s = 0.01

[[segment]]
velocity_m_per_s = 1e-4
duration_s = 5

[[segment]]
velocity_m_per_s = 0
duration_s = 2

[[segment]]
ramp_m_per_s = [1e-4, 1e-3]
duration_s = 2
"#;

/// Every apparatus and law key given explicitly (regularized, aging).
const TANK_PROTOCOL: &str = r#"[apparatus]
preset = "tank"
stiffness_n_per_m = 2e6
normal_load_n = 1e4
dt_s = 2e-3

[law]
kind = "rate-state"
form = "regularized"
state_law = "aging"
mu0 = 0.872
a = 0.31
b = 0.382
v_star_m_per_s = 1e-5
critical_slip_m = 5e-3

[initial]
slip_rate_m_per_s = 8e-3

[[segment]]
velocity_m_per_s = 8e-3
duration_s = 3

[[segment]]
velocity_m_per_s = 0
duration_s = 3
"#;

const AMONTONS_PROTOCOL: &str = r#"[apparatus]
preset = "lab"

[law]
kind = "amontons"
mu = 0.6

[[segment]]
velocity_m_per_s = 1e-4
duration_s = 2

[[segment]]
ramp_m_per_s = [1e-4, 0.0]
duration_s = 1
"#;

const RATE_PROTOCOL: &str = r#"[apparatus]
normal_load_n = 2000.0

[law]
kind = "rate"
mu0 = 0.872
c1 = -0.072
v_floor_m_per_s = 1e-5

[output]
every_s = 0.05

[[segment]]
velocity_m_per_s = 1e-3
duration_s = 4
"#;

const PROTOCOLS: &[(&str, &str)] = &[
    ("lab", LAB_PROTOCOL),
    ("tank", TANK_PROTOCOL),
    ("amontons", AMONTONS_PROTOCOL),
    ("rate", RATE_PROTOCOL),
];

/// The scenario of the command-line cases: two floes, 40 steps, so that
/// `compare` and `sweep` finish in a fraction of a second.
const SMALL_SCENARIO: &str = r#"title = "cli fixture"
duration_s = 20.0
dt_s = 0.5

[domain]
size_m = [2000.0, 1000.0]

[[floe]]
box_m = [100.0, 100.0, 900.0, 900.0]
velocity_m_per_s = [0.5, 0.0]

[[floe]]
box_m = [1000.0, 100.0, 1800.0, 900.0]

[friction]
law = "amontons"
mu = 0.5

[wind]
velocity_m_per_s = [10.0, 0.0]
"#;

// ---------------------------------------------------------------------------
// Cases.

/// What a case's exit must be, beyond the contract every case obeys.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Expect {
    /// Any of 0, 1, 2 (with the matching messages).
    Anything,
    /// Exit 0: an unmutated base input.
    Success,
    /// Exit 2: the input can never be valid.
    Refusal,
    /// Exit 1 or 2: a missing or wrong file.
    Failure,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    Base,
    Scenario,
    Protocol,
    CommandLine,
}

struct Case {
    index: usize,
    family: Family,
    /// The mutation, for the failure message.
    what: String,
    /// Files written into the working directory; none may change.
    files: Vec<(String, Vec<u8>)>,
    /// The file the mutation changed, printed on failure.
    mutated: Option<usize>,
    args: Vec<String>,
    expect: Expect,
}

/// The fixtures every command-line case gets: a scenario, a finished run of
/// it, a protocol.
struct Fixtures {
    run_h5: Vec<u8>,
}

impl Fixtures {
    fn files(&self) -> Vec<(String, Vec<u8>)> {
        vec![
            ("s.toml".into(), SMALL_SCENARIO.into()),
            ("run.h5".into(), self.run_h5.clone()),
            ("p.toml".into(), AMONTONS_PROTOCOL.into()),
        ]
    }
}

/// `SEED`, or `FLOE_FUZZ_SEED` when set (decimal or 0x-hex).
fn seed() -> u64 {
    static CELL: OnceLock<u64> = OnceLock::new();
    *CELL.get_or_init(|| match std::env::var("FLOE_FUZZ_SEED") {
        Ok(v) => match v.strip_prefix("0x") {
            Some(hex) => u64::from_str_radix(hex, 16),
            None => v.parse(),
        }
        .expect("FLOE_FUZZ_SEED is a number"),
        Err(_) => SEED,
    })
}

/// Each case draws from its own stream of the seed, so that it depends only
/// on the seed and its index.
fn case_rng(index: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed());
    rng.set_stream(index as u64);
    rng
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|a| a.to_string()).collect()
}

fn run_args() -> Vec<String> {
    strings(&[
        "run",
        "case.toml",
        "-o",
        "out.h5",
        "--max-steps",
        "200",
        "-q",
        "--threads",
        "1",
    ])
}

fn slider_args() -> Vec<String> {
    strings(&["slider", "run", "proto.toml", "--out", "out"])
}

fn all_cases(fixtures: &Fixtures) -> Vec<Case> {
    let mut cases = base_cases(fixtures);
    for _ in 0..SCENARIO_CASES {
        let index = cases.len();
        let (name, text) = SCENARIOS[index % SCENARIOS.len()];
        cases.push(file_case(index, Family::Scenario, name, text, "case.toml"));
    }
    for _ in 0..PROTOCOL_CASES {
        let index = cases.len();
        let (name, text) = PROTOCOLS[index % PROTOCOLS.len()];
        cases.push(file_case(index, Family::Protocol, name, text, "proto.toml"));
    }
    for k in 0..COMMAND_CASES {
        let index = cases.len();
        cases.push(command_case(index, k, fixtures));
    }
    cases
}

/// Every base input and command line unmutated: they must run, or the
/// mutants would test nothing.
fn base_cases(fixtures: &Fixtures) -> Vec<Case> {
    let mut cases = Vec::new();
    let mut push = |what: String, files, args| {
        let index = cases.len();
        cases.push(Case {
            index,
            family: Family::Base,
            what,
            files,
            mutated: None,
            args,
            expect: Expect::Success,
        });
    };
    for (name, text) in SCENARIOS {
        let files = vec![("case.toml".into(), text.as_bytes().to_vec())];
        push(format!("scenario `{name}` unmutated"), files, run_args());
    }
    for (name, text) in PROTOCOLS {
        let files = vec![("proto.toml".into(), text.as_bytes().to_vec())];
        push(format!("protocol `{name}` unmutated"), files, slider_args());
    }
    for template in TEMPLATES {
        let line = Line::of(template);
        push(
            format!("`{}` unmutated", template.words.join(" ")),
            fixtures.files(),
            line.args(template),
        );
    }
    cases
}

fn file_case(index: usize, family: Family, base: &str, text: &str, file: &str) -> Case {
    let mut rng = case_rng(index);
    let mutant = mutate_file(text, &mut rng);
    let (noun, args) = match family {
        Family::Scenario => ("scenario", run_args()),
        _ => ("protocol", slider_args()),
    };
    Case {
        index,
        family,
        what: format!("{noun} `{base}`: {}", mutant.what),
        files: vec![(file.into(), mutant.bytes)],
        mutated: Some(0),
        args,
        expect: mutant.expect,
    }
}

/// The first command-line cases give each flag of each command a bad value
/// in turn, so that every flag is tried; the others are drawn at random.
fn command_case(index: usize, k: usize, fixtures: &Fixtures) -> Case {
    let mut rng = case_rng(index);
    let every_flag: Vec<(&Template, &str)> = TEMPLATES
        .iter()
        .flat_map(|t| valued_flags(t).into_iter().map(move |f| (t, f)))
        .collect();
    let (template, (line, what, expect)) = match every_flag.get(k) {
        Some(&(template, flag)) => (template, bad_value_of(template, flag, &mut rng)),
        None => {
            let template = TEMPLATES.choose(&mut rng).expect("templates");
            (template, mutate_command(template, &mut rng))
        }
    };
    Case {
        index,
        family: Family::CommandLine,
        what: format!("`{}`: {what}", template.words.join(" ")),
        files: fixtures.files(),
        mutated: None,
        args: line.args(template),
        expect,
    }
}

// ---------------------------------------------------------------------------
// File mutations.

struct Mutant {
    bytes: Vec<u8>,
    what: String,
    expect: Expect,
}

impl Mutant {
    fn from_lines(lines: &[String], what: String, expect: Expect) -> Mutant {
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

fn mutate_file(text: &str, rng: &mut ChaCha8Rng) -> Mutant {
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

fn split_lines(text: &str) -> Vec<String> {
    text.split('\n').map(String::from).collect()
}

/// `key = value` lines: (line index, byte offset of the value).
fn statements(lines: &[String]) -> Vec<(usize, usize)> {
    let mut found = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        if trimmed.starts_with('#') || trimmed.starts_with('[') {
            continue;
        }
        if let Some(eq) = line.find('=') {
            found.push((i, eq + 1));
        }
    }
    found
}

/// Lines that are neither blank nor comments.
fn content_lines(lines: &[String]) -> Vec<usize> {
    (0..lines.len())
        .filter(|&i| {
            let t = lines[i].trim();
            !t.is_empty() && !t.starts_with('#')
        })
        .collect()
}

/// For each byte of `value`: whether it is inside a string literal (the
/// bases use only basic strings without escapes).
fn in_string(value: &str) -> Vec<bool> {
    let mut inside = false;
    value
        .bytes()
        .map(|b| {
            if b == b'"' {
                inside = !inside;
                return true;
            }
            inside
        })
        .collect()
}

/// Number literals in values: (line, start, end).
fn number_tokens(lines: &[String]) -> Vec<(usize, usize, usize)> {
    let is_token_byte = |b: u8| b.is_ascii_alphanumeric() || b"._+-".contains(&b);
    let mut found = Vec::new();
    for (i, v) in statements(lines) {
        let value = &lines[i][v..];
        let quoted = in_string(value);
        let bytes = value.as_bytes();
        let mut j = 0;
        while j < bytes.len() {
            if quoted[j] || !is_token_byte(bytes[j]) {
                j += 1;
                continue;
            }
            let start = j;
            while j < bytes.len() && !quoted[j] && is_token_byte(bytes[j]) {
                j += 1;
            }
            if is_number(&value[start..j]) {
                found.push((i, v + start, v + j));
            }
        }
    }
    found
}

/// A TOML number literal (not `inf` or `nan`, which the bases do not hold).
fn is_number(token: &str) -> bool {
    let digits = token.trim_start_matches(['+', '-']);
    digits.starts_with(|c: char| c.is_ascii_digit()) && digits.parse::<f64>().is_ok()
}

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

/// An array in a value: line, byte offsets of `[` and its `]`, and whether a
/// changed length may still be valid (only a floe's list of vertices).
struct Array {
    line: usize,
    open: usize,
    close: usize,
    any_length: bool,
}

fn arrays(lines: &[String]) -> Vec<Array> {
    let mut found = Vec::new();
    for (i, v) in statements(lines) {
        let value = &lines[i][v..];
        let quoted = in_string(value);
        let key = lines[i][..v - 1].trim();
        let mut first = true;
        for (j, b) in value.bytes().enumerate() {
            if b != b'[' || quoted[j] {
                continue;
            }
            let close = matching_bracket(value, &quoted, j);
            found.push(Array {
                line: i,
                open: v + j,
                close: v + close,
                any_length: key == "vertices_m" && first,
            });
            first = false;
        }
    }
    found
}

fn matching_bracket(value: &str, quoted: &[bool], open: usize) -> usize {
    let mut depth = 0;
    for (j, b) in value.bytes().enumerate().skip(open) {
        match b {
            _ if quoted[j] => {}
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    return j;
                }
            }
            _ => {}
        }
    }
    value.len()
}

/// The elements of an array's inside, split at its own commas.
fn elements(inner: &str) -> Vec<String> {
    let quoted = in_string(inner);
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (j, b) in inner.bytes().enumerate() {
        match b {
            _ if quoted[j] => {}
            b'[' | b'{' => depth += 1,
            b']' | b'}' => depth -= 1,
            b',' if depth == 0 => {
                parts.push(inner[start..j].trim().to_string());
                start = j + 1;
            }
            _ => {}
        }
    }
    parts.push(inner[start..].trim().to_string());
    parts.retain(|p| !p.is_empty());
    parts
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

/// The TOML type of a (simple) value.
fn toml_type(value: &str) -> Option<&'static str> {
    let table: toml::Table = format!("x = {value}").parse().ok()?;
    Some(table["x"].type_str())
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
fn typo(name: &str, rng: &mut ChaCha8Rng) -> String {
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

// ---------------------------------------------------------------------------
// Command lines.

/// A valid command line and what else its command takes.
struct Template {
    words: &'static [&'static str],
    positional: Option<&'static str>,
    /// Flags of the valid line; `None`: a switch.
    flags: &'static [(&'static str, Option<&'static str>)],
    /// Other flags the command takes, with a valid value.
    extra: &'static [(&'static str, &'static str)],
    /// Flags that cannot be left out.
    required: &'static [&'static str],
    /// Flags whose repeats add values (`--hold 1 --hold 2`).
    repeatable: &'static [&'static str],
    /// Pairs of flags that exclude each other.
    exclusive: &'static [(&'static str, &'static str)],
}

const TEMPLATES: &[Template] = &[
    Template {
        words: &["run"],
        positional: Some("s.toml"),
        flags: &[
            ("-o", Some("out.h5")),
            ("--threads", Some("1")),
            ("--max-steps", Some("200")),
            ("-q", None),
        ],
        extra: &[("--step-limit", "1000000")],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["info"],
        positional: Some("run.h5"),
        flags: &[],
        extra: &[],
        required: &[],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["render"],
        positional: Some("run.h5"),
        flags: &[
            ("-o", Some("pictures")),
            ("--snapshot", Some("1")),
            ("--color", Some("speed")),
        ],
        extra: &[("--every", "2")],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[("--snapshot", "--every")],
    },
    Template {
        words: &["compare"],
        positional: Some("s.toml"),
        flags: &[
            ("-o", Some("cmp")),
            ("--laws", Some("amontons,rate")),
            ("--reference-slip-speed", Some("0.01")),
            ("--threads", Some("1")),
            ("-q", None),
        ],
        extra: &[
            ("--amontons-mu", "0.5"),
            ("--profile-bins", "25"),
            ("--slip-jump", "10"),
            ("--slip-min-rate", "0.001"),
        ],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[("--reference-slip-speed", "--amontons-mu")],
    },
    Template {
        words: &["sweep"],
        positional: Some("s.toml"),
        flags: &[
            ("--set", Some("friction.mu=0.3,0.6")),
            ("-o", Some("sweep")),
            ("--threads", Some("1")),
        ],
        extra: &[
            ("--profile-bins", "25"),
            ("--slip-jump", "10"),
            ("--slip-min-rate", "0.001"),
        ],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["slider", "hold"],
        positional: None,
        flags: &[
            ("--preset", Some("lab")),
            ("--hold", Some("1,10")),
            ("--dt", Some("0.001")),
            ("--normal-load", Some("2000")),
        ],
        extra: &[
            ("--step-limit", "100000000"),
            ("--form", "regularized"),
            ("--state-law", "aging"),
        ],
        required: &["--preset"],
        repeatable: &["--hold"],
        exclusive: &[],
    },
    Template {
        words: &["slider", "step"],
        positional: None,
        flags: &[
            ("--preset", Some("tank")),
            ("--from", Some("0.001")),
            ("--to", Some("0.01")),
            ("--dt", Some("0.001")),
            ("--json", None),
        ],
        extra: &[
            ("--normal-load", "10000"),
            ("--step-limit", "100000000"),
            ("--form", "regularized"),
            ("--state-law", "aging"),
        ],
        required: &["--preset", "--from", "--to"],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["slider", "run"],
        positional: Some("p.toml"),
        flags: &[("--out", Some("out"))],
        extra: &[("--step-limit", "100000000")],
        required: &["--out"],
        repeatable: &[],
        exclusive: &[],
    },
];

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

/// A command line being mutated.
#[derive(Clone)]
struct Line {
    positional: Option<String>,
    flags: Vec<(String, Option<String>)>,
}

impl Line {
    fn of(template: &Template) -> Line {
        Line {
            positional: template.positional.map(String::from),
            flags: template
                .flags
                .iter()
                .map(|(f, v)| (f.to_string(), v.map(String::from)))
                .collect(),
        }
    }

    fn args(&self, template: &Template) -> Vec<String> {
        let mut args = strings(template.words);
        args.extend(self.positional.clone());
        for (flag, value) in &self.flags {
            args.push(flag.clone());
            args.extend(value.clone());
        }
        args
    }

    fn has(&self, flag: &str) -> bool {
        self.flags.iter().any(|(f, _)| f == flag)
    }
}

type CommandMutation = fn(&Template, &mut Line, &mut ChaCha8Rng) -> Option<(String, Expect)>;

const COMMAND_MUTATIONS: &[(u32, CommandMutation)] = &[
    (6, bad_flag_value),
    (1, unknown_flag),
    (1, flag_twice),
    (1, drop_required),
    (1, bad_positional),
];

fn mutate_command(template: &Template, rng: &mut ChaCha8Rng) -> (Line, String, Expect) {
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
fn valued_flags(template: &Template) -> Vec<&'static str> {
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
fn bad_value_of(template: &Template, flag: &str, rng: &mut ChaCha8Rng) -> (Line, String, Expect) {
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

// ---------------------------------------------------------------------------
// Running a case.

struct Outcome {
    status: Option<ExitStatus>,
    stderr: String,
    elapsed: Duration,
    /// Input files that differ after the run.
    changed: Vec<String>,
    /// Non-finite numbers in a successful run's standard output or
    /// series.csv: bad numbers in must not come out as inf or NaN.
    bad_output: Vec<String>,
}

fn execute(case: &Case) -> Outcome {
    let dir = tempfile::tempdir().expect("temporary directory");
    let work = dir.path().join("work");
    fs::create_dir(&work).expect("work directory");
    for (name, bytes) in &case.files {
        fs::write(work.join(name), bytes).expect("input file");
    }
    let (status, elapsed) = run_with_timeout(&work, &case.args, dir.path());
    let stderr = fs::read(dir.path().join("stderr")).unwrap_or_default();
    let changed = case
        .files
        .iter()
        .filter(|(name, bytes)| fs::read(work.join(name)).ok().as_ref() != Some(bytes))
        .map(|(name, _)| name.clone())
        .collect();
    let mut bad_output = Vec::new();
    if status.is_some_and(|s| s.success()) {
        let stdout = fs::read(dir.path().join("stdout")).unwrap_or_default();
        let stdout = String::from_utf8_lossy(&stdout);
        bad_output.extend(non_finite_word(&stdout, &case.args));
        if let Some(series) = slider_series(&case.args) {
            bad_output.extend(non_finite_cell(&work.join(series)));
        }
    }
    Outcome {
        status,
        stderr: String::from_utf8_lossy(&stderr).into_owned(),
        elapsed,
        changed,
        bad_output,
    }
}

/// The series.csv that `floe slider run ... --out DIR` writes.
fn slider_series(args: &[String]) -> Option<String> {
    if args.get(..2)? != ["slider", "run"] {
        return None;
    }
    let at = args.iter().rposition(|a| a == "--out" || a == "-o")?;
    Some(format!("{}/series.csv", args.get(at + 1)?))
}

/// `inf` or `NaN` in what a successful command printed (not an argument
/// echoed, such as an output directory called `nan`).
fn non_finite_word(stdout: &str, args: &[String]) -> Option<String> {
    let word = stdout
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-' || c == '+'))
        .find(|w| {
            let lower = w.trim_start_matches(['-', '+']).to_ascii_lowercase();
            let non_finite = lower == "inf" || lower == "infinity" || lower == "nan";
            non_finite && !args.iter().any(|a| a == w)
        })?;
    Some(format!("exit 0 but standard output holds `{word}`"))
}

/// A successful slider run writes only finite numbers: the first cell that
/// is not one, or why the file cannot be read.
fn non_finite_cell(series: &Path) -> Option<String> {
    let Ok(text) = fs::read_to_string(series) else {
        return Some(format!("exit 0 but {} is missing", series.display()));
    };
    for (row, line) in text.lines().enumerate().skip(1) {
        for cell in line.split(',') {
            if !cell.trim().parse::<f64>().is_ok_and(f64::is_finite) {
                return Some(format!(
                    "series.csv row {}: `{cell}` is not a finite number",
                    row + 1
                ));
            }
        }
    }
    None
}

/// Runs floe in `work`, its output in files of `logs` (a pipe nobody reads
/// could block it); `None` if it had to be killed after `TIMEOUT`.
fn run_with_timeout(work: &Path, args: &[String], logs: &Path) -> (Option<ExitStatus>, Duration) {
    let stdout = fs::File::create(logs.join("stdout")).expect("stdout file");
    let stderr = fs::File::create(logs.join("stderr")).expect("stderr file");
    let mut child = Command::new(env!("CARGO_BIN_EXE_floe"))
        .args(args)
        .current_dir(work)
        .env("RUST_BACKTRACE", "1")
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(stderr)
        .spawn()
        .expect("floe starts");
    let start = Instant::now();
    let mut pause = Duration::from_millis(1);
    loop {
        if let Some(status) = child.try_wait().expect("waiting for floe") {
            return (Some(status), start.elapsed());
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return (None, start.elapsed());
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(20));
    }
}

// ---------------------------------------------------------------------------
// Checking a case.

fn problems(case: &Case, out: &Outcome) -> Vec<String> {
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
        Some(1) if !last_is_error || errors != 1 => Some(format!(
            "exit 1 must end stderr with its only `error: ` line ({errors} such lines)"
        )),
        Some(0) if errors > 0 => Some("exit 0 after an `error:` line".into()),
        _ => None,
    };
    found.extend(problem);
}

fn locates(case: &Case, message: &str) -> bool {
    names_file_position(message) || (case.family == Family::CommandLine && names_argument(message))
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

// ---------------------------------------------------------------------------
// Reporting.

struct Failure {
    index: usize,
    report: String,
    summary: String,
}

fn failure(case: &Case, out: &Outcome, found: &[String]) -> Failure {
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
         cargo test --release -p floe-cli --test cli_fuzz -- --nocapture",
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
        let _ = writeln!(report, "input {name}:\n{}", show(bytes));
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

fn short(text: &str, max: usize) -> String {
    let n = text.chars().count();
    if n <= max {
        return text.to_string();
    }
    let head: String = text.chars().take(max).collect();
    format!("{head}... ({} more characters)", n - max)
}

// ---------------------------------------------------------------------------
// The test.

/// Runs the small scenario once, for `info` and `render` to read.
fn fixtures() -> Fixtures {
    let dir = tempfile::tempdir().expect("temporary directory");
    fs::write(dir.path().join("s.toml"), SMALL_SCENARIO).expect("fixture");
    let args = strings(&["run", "s.toml", "-o", "run.h5", "-q", "--threads", "1"]);
    let (status, _) = run_with_timeout(dir.path(), &args, dir.path());
    assert!(
        status.is_some_and(|s| s.success()),
        "the fixture run failed: {}",
        fs::read_to_string(dir.path().join("stderr")).unwrap_or_default()
    );
    Fixtures {
        run_h5: fs::read(dir.path().join("run.h5")).expect("fixture run file"),
    }
}

/// What the cases did: failures, exit codes per family, the slowest case.
#[derive(Default)]
struct Results {
    failures: Vec<Failure>,
    exits: BTreeMap<(String, String), usize>,
    slowest: Duration,
}

impl Results {
    fn record(&mut self, case: &Case, out: &Outcome, found: &[String]) {
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
}

/// Runs the cases on `WORKERS` threads.
fn run_all(cases: &[&Case]) -> Results {
    let next = AtomicUsize::new(0);
    let results = Mutex::new(Results::default());
    std::thread::scope(|scope| {
        for _ in 0..WORKERS {
            scope.spawn(|| {
                while let Some(case) = cases.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let out = execute(case);
                    let found = problems(case, &out);
                    results.lock().unwrap().record(case, &out, &found);
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.failures.sort_by_key(|f| f.index);
    results
}

#[test]
fn bad_input_never_crashes_hangs_or_is_silently_dropped() {
    let start = Instant::now();
    let fixtures = fixtures();
    let cases = all_cases(&fixtures);
    let only: Option<usize> = std::env::var("FLOE_FUZZ_CASE")
        .ok()
        .map(|v| v.parse().expect("FLOE_FUZZ_CASE is a case index"));
    let selected: Vec<&Case> = cases
        .iter()
        .filter(|c| only.is_none_or(|i| c.index == i))
        .collect();
    let results = run_all(&selected);

    let count = |family| selected.iter().filter(|c| c.family == family).count();
    println!(
        "cli_fuzz: seed {:#x}; {} base inputs, {} scenario, {} protocol and {} command-line cases; \
         {} failed; slowest case {:.2} s; wall time {:.1} s",
        seed(),
        count(Family::Base),
        count(Family::Scenario),
        count(Family::Protocol),
        count(Family::CommandLine),
        results.failures.len(),
        results.slowest.as_secs_f64(),
        start.elapsed().as_secs_f64()
    );
    for ((family, exit), n) in &results.exits {
        println!("  {family}: exit {exit} x {n}");
    }
    for f in &results.failures {
        println!("FAILED {}", f.summary);
    }
    assert!(
        results.failures.is_empty(),
        "{} of {} cases failed (seed {:#x}); each is printed above with its input and how to rerun it",
        results.failures.len(),
        selected.len(),
        seed()
    );
}
