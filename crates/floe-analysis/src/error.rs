//! The one error type of the analysis crate.

use thiserror::Error;

/// Why a metric could not be computed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AnalysisError {
    /// Input arrays that should have the same length do not.
    #[error("{what}: {left} and {right} entries do not match")]
    LengthMismatch {
        /// Which arrays.
        what: &'static str,
        /// Length of the first.
        left: usize,
        /// Length of the second.
        right: usize,
    },
    /// A parameter outside its valid range.
    #[error("{name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// Not enough data for the metric (e.g. an empty series).
    #[error("{0}")]
    NotEnoughData(&'static str),
}
