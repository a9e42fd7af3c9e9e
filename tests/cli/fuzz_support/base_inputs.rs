//! The valid base inputs, from `tests/data/fuzz/`. Every statement is on one
//! line and has no trailing comment, so that the mutations can find keys,
//! values and numbers by simple scanning.
//!
//! The first line of each file is a comment saying what the file is for; it
//! is not part of the input. The cases use the text below it, so that line
//! numbers and byte offsets in a case's description count from the file's
//! second line.

/// The text of `tests/data/fuzz/PATH` below its first line.
macro_rules! base {
    ($path:literal) => {
        without_first_line(include_str!(concat!("../../data/fuzz/", $path)))
    };
}

/// Files a scenario reads besides itself: name in the case's directory and
/// bytes.
pub type AuxFiles = &'static [(&'static str, &'static [u8])];

/// The basin scenario's inputs, from `tests/data/fuzz/basin/` (written by
/// `cargo run --release -p floe-basin --example make_fuzz_basin`): a
/// longitude-latitude island (GeoJSON), an hourly longitude-latitude wind
/// (NetCDF-4, that is HDF5) and a steady sea-surface height on the plane's
/// x/y grid (NetCDF-3 classic).
pub const BASIN_FILES: AuxFiles = &[
    (
        "coast.geojson",
        include_bytes!("../../data/fuzz/basin/coast.geojson"),
    ),
    ("wind.nc", include_bytes!("../../data/fuzz/basin/wind.nc")),
    ("ssh.nc", include_bytes!("../../data/fuzz/basin/ssh.nc")),
];

/// The basin scenario (`[map]`, `start_time`, `[[land]]`, gridded `[wind]`,
/// `[ocean] sea_surface_height`); its files are [`BASIN_FILES`].
pub const BASIN_SCENARIO: &str = base!("scenarios/basin.toml");

/// The scenarios mutated into `floe run` cases, with the files each reads.
pub const SCENARIOS: &[(&str, &str, AuxFiles)] = &[
    ("boxes", base!("scenarios/boxes.toml"), &[]),
    ("diamonds", base!("scenarios/diamonds.toml"), &[]),
    ("voronoi", base!("scenarios/voronoi.toml"), &[]),
    ("grid", base!("scenarios/grid.toml"), &[]),
    ("double-shear", base!("scenarios/double_shear.toml"), &[]),
    ("scheduled", base!("scenarios/scheduled.toml"), &[]),
    ("power-law", base!("scenarios/power_law.toml"), &[]),
    ("basin", BASIN_SCENARIO, BASIN_FILES),
];

/// Amontons friction on the lab apparatus; also the `p.toml` of the
/// command-line cases.
pub const AMONTONS_PROTOCOL: &str = base!("protocols/amontons.toml");

/// The protocols mutated into `floe slider run` cases.
pub const PROTOCOLS: &[(&str, &str)] = &[
    ("lab", base!("protocols/lab.toml")),
    ("tank", base!("protocols/tank.toml")),
    ("amontons", AMONTONS_PROTOCOL),
    ("rate", base!("protocols/rate.toml")),
];

/// The scenario of the command-line cases (`s.toml`): two floes, 40 steps,
/// so that `compare` and `sweep` finish in a fraction of a second.
pub const SMALL_SCENARIO: &str = base!("cli_scenario.toml");

/// A data file without its first line, which must be a `#` comment (checked
/// when the test compiles).
const fn without_first_line(file: &'static str) -> &'static str {
    let bytes = file.as_bytes();
    assert!(
        !bytes.is_empty() && bytes[0] == b'#',
        "a fuzz base input starts with a comment line"
    );
    let mut i = 0;
    while bytes[i] != b'\n' {
        i += 1;
    }
    let (_, rest) = bytes.split_at(i + 1);
    match std::str::from_utf8(rest) {
        Ok(text) => text,
        Err(_) => panic!("a fuzz base input is UTF-8"),
    }
}
