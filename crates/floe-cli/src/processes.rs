//! Whether `floe run` is one process of an MPI job (`mpirun -np K`,
//! `srun`), and starting MPI when it is.
//!
//! MPI is behind the cargo feature `mpi` (`make` builds with it; a plain
//! `cargo build` does not, for machines without an MPI library). A build
//! without it refuses to run as one of several processes rather than let
//! each write the same file.

/// The number of processes the launcher started, from its environment
/// (Open MPI, MPICH and Intel MPI's PMI, PMIx), if any.
pub fn launched_processes() -> Option<usize> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.trim().parse::<usize>().ok())
        .or_else(|| std::env::var("PMIX_RANK").ok().map(|_| 2))
}

/// Refuses a command other than `floe run` started as one of several
/// processes: each would do the whole work and write the same files.
pub fn refuse_several() -> Result<(), crate::CliError> {
    match launched_processes() {
        Some(n) if n > 1 => Err(crate::CliError::Usage(format!(
            "started as one of {n} processes (mpirun): only `floe run` spreads over \
             processes; run this command without mpirun"
        ))),
        _ => Ok(()),
    }
}

/// Whether this is a process of an MPI job other than the first (which
/// alone talks to the user).
pub fn is_other_than_first() -> bool {
    ["OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.trim().parse::<usize>().ok())
        .is_some_and(|rank| rank > 0)
}

/// MPI for this process, when it is one of several; `Ok(None)` for a lone
/// process.
#[cfg(feature = "mpi")]
pub fn start() -> Result<Option<floe_parallel::mpi_comm::Mpi>, crate::CliError> {
    if launched_processes().is_none() {
        return Ok(None);
    }
    floe_parallel::mpi_comm::Mpi::initialize()
        .map(Some)
        .map_err(crate::CliError::Usage)
}

/// Refuses to run as one of several processes in a build without MPI.
#[cfg(not(feature = "mpi"))]
pub fn start() -> Result<Option<std::convert::Infallible>, crate::CliError> {
    match launched_processes() {
        Some(n) if n > 1 => Err(crate::CliError::Usage(format!(
            "started as one of {n} processes (mpirun), but this floe was built without MPI: \
             build it with `make build` or `cargo build --release --features floe-cli/mpi` \
             (see docs/hpc.md), or run it without mpirun"
        ))),
        _ => Ok(None),
    }
}
