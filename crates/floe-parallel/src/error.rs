//! What can go wrong in setting up a distributed run.

use floe_dem::DemError;

/// Why a world could not be spread over the processes.
#[derive(Debug, thiserror::Error)]
pub enum ParallelError {
    /// Each process owns at least one free floe.
    #[error("{processes} processes for {floes} free floes: each process needs a floe; run with at most {floes} processes (mpirun -np {floes})")]
    MoreProcessesThanFloes {
        /// Processes asked for.
        processes: usize,
        /// Free floes in the world.
        floes: usize,
    },
    /// A subdomain narrower than the largest floe: the halo would span
    /// several subdomains, and a floe could be owned where it hardly is.
    #[error("subdomain {rank} is {} by {}, narrower than the largest floe ({diameter_m:.0} m across): run with fewer processes", extent(*width_m), extent(*height_m))]
    SubdomainTooSmall {
        /// The process whose subdomain it is.
        rank: usize,
        /// Its width, m.
        width_m: f64,
        /// Its height, m.
        height_m: f64,
        /// The largest free floe's bounding diameter, m.
        diameter_m: f64,
    },
    /// The engine refused the part of the world (a bug if it happens: the
    /// whole was valid).
    #[error(transparent)]
    Dem(#[from] DemError),
    /// A message between processes could not be read.
    #[error("a message between processes could not be read: {0}")]
    Wire(String),
}

/// A subdomain's side for a message: metres, or unbounded (an open side).
fn extent(m: f64) -> String {
    if m.is_finite() {
        format!("{m:.0} m")
    } else {
        "unbounded".into()
    }
}
