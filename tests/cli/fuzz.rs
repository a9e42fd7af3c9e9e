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
//! - the basin scenario (`[map]`, `start_time`, `[[land]]` from GeoJSON,
//!   gridded `[wind]` and `[ocean] sea_surface_height` from NetCDF-4 and
//!   NetCDF-3 files) with one of its files mutated: missing, a directory,
//!   empty, cut short, garbage, another kind of file, bytes changed at
//!   random; a GeoJSON with broken JSON, NaN or huge coordinates, other
//!   geometry types, no features, holes, crossing edges; and its `file`,
//!   `variables`, `projection` and `start_time` values changed. An exit 2
//!   must also name the file or key;
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
//! `FLOE_FUZZ_CASE=N cargo test --release -p floe-cli --test cli fuzz:: -- --nocapture`
//! reruns case N alone, `FLOE_FUZZ_SEED=S` draws other cases, and
//! `FLOE_FUZZ_VERBOSE=1` prints every case's mutation and exit.
//!
//! The base inputs are in `tests/data/fuzz/`; the mutations, the cases, the
//! running and the checking in `tests/cli/fuzz_support/`.

use crate::fuzz_support;

use std::time::Instant;

use fuzz_support::{all_cases, fixtures, run_all, seed, Case};

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
    results.print_summary(&selected, start.elapsed());
    assert!(
        results.failures.is_empty(),
        "{} of {} cases failed (seed {:#x}); each is printed above with its input and how to rerun it",
        results.failures.len(),
        selected.len(),
        seed()
    );
}
