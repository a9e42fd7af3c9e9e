//! The cases of a seed: every base input unmutated, then mutated scenarios,
//! protocols, command lines and the basin scenario's own files. Each case
//! depends only on the seed and its index.

use std::sync::OnceLock;

use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::base_inputs::{
    AuxFiles, AMONTONS_PROTOCOL, BASIN_FILES, PROTOCOLS, SCENARIOS, SMALL_SCENARIO,
};
use super::basin_files::{fixed_mutants, random_mutant, BasinMutant, Content};
use super::command_lines::{bad_value_of, mutate_command, valued_flags};
use super::file_mutations::mutate_file;
use super::templates::{Line, Template, TEMPLATES};
use super::text::strings;
use super::Expect;

/// The seed of every case (`FLOE_FUZZ_SEED=N` explores other cases).
const SEED: u64 = 0xF10E_2026;

/// Mutated cases of each family, after the base inputs (the basin files
/// also get every fixed mutation of `basin_files`).
const SCENARIO_CASES: usize = 350;
const PROTOCOL_CASES: usize = 100;
const COMMAND_CASES: usize = 100;
const RANDOM_BASIN_FILE_CASES: usize = 40;

/// What a case mutates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Family {
    Base,
    Scenario,
    Protocol,
    CommandLine,
    /// The basin scenario's NetCDF and GeoJSON files, and its keys naming
    /// them.
    BasinFile,
}

/// One run of floe: its input files, its command line, what it must do.
pub struct Case {
    pub index: usize,
    pub family: Family,
    /// The mutation, for the failure message.
    pub what: String,
    /// Files written into the working directory; none may change.
    pub files: Vec<(String, Vec<u8>)>,
    /// Directories made in the working directory (where a file is expected).
    pub dirs: Vec<String>,
    /// The file the mutation changed, printed on failure.
    pub mutated: Option<usize>,
    pub args: Vec<String>,
    pub expect: Expect,
    /// Text an exit-2 message must hold besides its location: the file or
    /// key the mutation is about.
    pub names: Option<String>,
}

/// The fixtures every command-line case gets: a scenario, a finished run of
/// it, a protocol.
pub struct Fixtures {
    pub run_h5: Vec<u8>,
}

impl Fixtures {
    pub fn files(&self) -> Vec<(String, Vec<u8>)> {
        vec![
            ("s.toml".into(), SMALL_SCENARIO.into()),
            ("run.h5".into(), self.run_h5.clone()),
            ("p.toml".into(), AMONTONS_PROTOCOL.into()),
        ]
    }
}

/// `SEED`, or `FLOE_FUZZ_SEED` when set (decimal or 0x-hex).
pub fn seed() -> u64 {
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
pub fn case_rng(index: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed());
    rng.set_stream(index as u64);
    rng
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

pub fn all_cases(fixtures: &Fixtures) -> Vec<Case> {
    let mut cases = base_cases(fixtures);
    for _ in 0..SCENARIO_CASES {
        let index = cases.len();
        let (name, text, files) = SCENARIOS[index % SCENARIOS.len()];
        let mut case = file_case(index, Family::Scenario, name, text, "case.toml");
        case.files.extend(aux(files));
        cases.push(case);
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
    for mutant in fixed_mutants() {
        let index = cases.len();
        cases.push(basin_case(index, mutant));
    }
    for _ in 0..RANDOM_BASIN_FILE_CASES {
        let index = cases.len();
        let mutant = random_mutant(&mut case_rng(index));
        cases.push(basin_case(index, mutant));
    }
    cases
}

/// A scenario's auxiliary files as case files.
fn aux(files: AuxFiles) -> impl Iterator<Item = (String, Vec<u8>)> {
    files.iter().map(|(n, b)| (n.to_string(), b.to_vec()))
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
            dirs: Vec::new(),
            mutated: None,
            args,
            expect: Expect::Success,
            names: None,
        });
    };
    for (name, text, files) in SCENARIOS {
        let mut all = vec![("case.toml".into(), text.as_bytes().to_vec())];
        all.extend(aux(files));
        push(format!("scenario `{name}` unmutated"), all, run_args());
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
        dirs: Vec::new(),
        mutated: Some(0),
        args,
        expect: mutant.expect,
        names: None,
    }
}

/// The basin scenario run with one of its files (or the key naming it)
/// mutated; an exit 2 must also name that file or key.
fn basin_case(index: usize, mutant: BasinMutant) -> Case {
    let mut files = vec![("case.toml".to_string(), mutant.scenario.into_bytes())];
    let (mut dirs, mut mutated) = (Vec::new(), None);
    for (name, bytes) in BASIN_FILES {
        match &mutant.change {
            Some((changed, content)) if changed == name => match content {
                Content::Bytes(b) => {
                    mutated = Some(files.len());
                    files.push((name.to_string(), b.clone()));
                }
                Content::Missing => {}
                Content::Directory => dirs.push(name.to_string()),
            },
            _ => files.push((name.to_string(), bytes.to_vec())),
        }
    }
    Case {
        index,
        family: Family::BasinFile,
        what: format!("basin {}", mutant.what),
        files,
        dirs,
        mutated: mutated.or(mutant.change.is_none().then_some(0)),
        args: run_args(),
        expect: mutant.expect,
        names: (!mutant.names.is_empty()).then_some(mutant.names),
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
        dirs: Vec::new(),
        mutated: None,
        args: line.args(template),
        expect,
        names: None,
    }
}
