//! The one error type of the DEM engine.

use thiserror::Error;

/// Everything that can go wrong in `floe-dem`.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DemError {
    /// A parameter is outside its physical range.
    #[error("{name} = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Parameter name, with its unit suffix as in the API.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// A polygon is not a usable floe (fewer than 3 vertices, not convex, zero area).
    #[error("floe {index}: {reason}")]
    InvalidFloe {
        /// Floe index.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// A floe cannot be added, removed or changed as asked (a duplicate or
    /// unknown id, a floe the engine cannot step, a partner missing).
    #[error("floe id {id}: {reason}")]
    FloeEdit {
        /// Global id of the floe.
        id: u64,
        /// What is wrong.
        reason: String,
    },
    /// Floe arrays that do not make a set (lengths differ, ids not
    /// strictly increasing, bad vertex offsets).
    #[error("invalid floe arrays: {reason}")]
    InvalidFloeColumns {
        /// What is wrong.
        reason: String,
    },
    /// The contact model cannot be used (a friction law whose state does
    /// not fit a contact).
    #[error("invalid contact model: {reason}")]
    InvalidModel {
        /// What is wrong.
        reason: String,
    },
    /// The time step is above the stability limit of the explicit integrator.
    #[error("dt = {dt_s} s is above the stable limit {limit_s:.3e} s ({reason})")]
    UnstableTimeStep {
        /// Requested step, s.
        dt_s: f64,
        /// Largest stable step, s.
        limit_s: f64,
        /// Which floe and contact stiffness set the limit.
        reason: String,
    },
    /// An iterative solver did not reach its tolerance.
    #[error("{what} did not converge in {iterations} iterations")]
    NoConvergence {
        /// Which solve.
        what: &'static str,
        /// Iterations spent.
        iterations: usize,
    },
    /// A tessellation could not be built or is not a valid set of floes.
    #[error("invalid tessellation: {reason}")]
    InvalidTessellation {
        /// What is wrong.
        reason: String,
    },
    /// A generator would create more floes than the engine's cap
    /// ([`crate::tessellation::MAX_FLOES`]); refused before allocating.
    #[error("tessellation would create about {requested} floes, above the cap of {limit}")]
    TooManyFloes {
        /// Number of floes (or candidate cells) the request implies.
        requested: u64,
        /// The cap.
        limit: u64,
    },
    /// A saved state is inconsistent (damaged or from another scenario).
    #[error("invalid checkpoint: {reason}")]
    InvalidCheckpoint {
        /// What is wrong.
        reason: String,
    },
    /// The forcing cannot be evaluated (a gridded field's time, grid or
    /// values; the message names the file).
    #[error("{0}")]
    Forcing(#[from] ForcingFailure),
}

/// Why a gridded forcing cannot go on: names the source (file and
/// variables), the time or the floe.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{0}")]
pub struct ForcingFailure(pub String);

/// `Err(DemError::InvalidParameter { name, value, reason })`, for a check
/// that refuses several parameters (in place of a closure in each).
pub(crate) fn invalid_parameter<T>(
    name: &'static str,
    value: f64,
    reason: &'static str,
) -> Result<T, DemError> {
    Err(DemError::InvalidParameter {
        name,
        value,
        reason,
    })
}
