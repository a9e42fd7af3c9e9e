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
    /// More polygons over one place than the overlap sums are built for
    /// ([`crate::grid_fields::MAX_OVERLAP_ORDER`]): not a pack of soft floes.
    #[error(
        "{count} floes overlap near ({:.1}, {:.1}) m: more than the {most} the gridded \
         concentration counts a place under (a pack of soft contacts puts 2 to 4 there)",
        near[0], near[1]
    )]
    TooManyOverlaps {
        /// How many were found over the place (at least `most + 1`).
        count: usize,
        /// The most counted.
        most: usize,
        /// A point of the place, m.
        near: [f64; 2],
    },
    /// Not enough data for the metric (e.g. an empty series).
    #[error("{0}")]
    NotEnoughData(&'static str),
}
