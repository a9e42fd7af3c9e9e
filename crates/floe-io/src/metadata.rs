//! What a run file says about its run: the scenario, the program, the
//! domain, and the output options.

/// The simulation domain: an axis-aligned box, periodic or not along each axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainBox {
    /// Lower-left corner, m.
    pub min_m: [f64; 2],
    /// Size along x and y, m.
    pub size_m: [f64; 2],
    /// Whether each axis is periodic.
    pub periodic: [bool; 2],
}

/// Provenance of a run, stored under `/parameters` and `/h5md`.
#[derive(Debug, Clone, PartialEq)]
pub struct RunMetadata {
    /// The scenario file's text, verbatim (a resume rebuilds the run from it).
    pub scenario_toml: String,
    /// Where the scenario file was read from.
    pub scenario_path: String,
    /// floe's version.
    pub floe_version: String,
    /// The git commit floe was built from.
    pub git_commit: String,
    /// The command line of the run.
    pub command_line: Vec<String>,
    /// Worker threads (per process).
    pub threads: usize,
    /// Processes the run began on (`mpirun -np`; 1 for files written
    /// before floe recorded it).
    pub processes: usize,
    /// Who ran it (H5MD `author`).
    pub author: String,
    /// The domain.
    pub domain: DomainBox,
    /// The files the run reads besides the scenario (forcing, coastlines,
    /// ice grids) with their checksums; empty for runs without them and
    /// for files written before floe recorded them.
    pub inputs: Vec<InputRecord>,
}

/// One input file of a run, as recorded in `/parameters`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputRecord {
    /// What it gives (`wind`, `ocean`, `land[0]`...).
    pub role: String,
    /// Its path as the run opened it.
    pub path: String,
    /// Lowercase hex SHA-256 of its content (as `sha256sum` prints).
    pub sha256: String,
}

/// How the bulk arrays are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputOptions {
    /// Deflate (gzip) level 0..=9 of the snapshot and contact arrays; 0: none. Default 4.
    pub deflate_level: u8,
    /// Byte-shuffle before deflating (better ratios on floats). Default true.
    pub shuffle: bool,
    /// Write each floe's time-averaged stress with every snapshot
    /// (`/particles/floes/stress`); the world must compute it. Default false.
    pub floe_stress: bool,
    /// Write the number of bonds (floes frozen together) with the
    /// observables (`/observables/bonds`). Default false.
    pub bonds: bool,
    /// Write ridging's ledger with the observables (`/observables/ridged_volume`,
    /// `ridging_energy_lost`, `ridging_events`). Default false.
    pub ridging: bool,
}

impl Default for OutputOptions {
    fn default() -> Self {
        Self {
            deflate_level: 4,
            shuffle: true,
            floe_stress: false,
            bonds: false,
            ridging: false,
        }
    }
}

/// Where the valid checkpoint of a file stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckpointInfo {
    /// The run's step count at the checkpoint.
    pub step: u64,
    /// Simulated time at the checkpoint, s.
    pub time_s: f64,
}
