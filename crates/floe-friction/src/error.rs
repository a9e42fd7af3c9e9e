//! The one error type of this crate.

use thiserror::Error;

/// Everything that can go wrong in `floe-friction`.
///
/// Messages name the offending quantity and its value so a caller can pass them
/// straight to a user.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FrictionError {
    /// A parameter is outside its physical range (e.g. a negative stiffness).
    #[error("{name} = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Parameter name, with its unit suffix as in the API (e.g. `stiffness_n_per_m`).
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// A load-point protocol is unusable (e.g. empty, or a segment of negative duration).
    #[error("protocol segment {index}: {reason}")]
    InvalidProtocol {
        /// Zero-based segment index.
        index: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A law cannot be registered or built (a name taken twice, values
    /// that do not go together).
    #[error("{0}")]
    InvalidLaw(String),
    /// A least-squares fit could not be carried out.
    #[error("fit failed: {0}")]
    Fit(String),
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, FrictionError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(FrictionError::InvalidParameter {
            name,
            value,
            reason: "must be a finite number > 0",
        })
    }
}

/// Checks that `value` is finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, FrictionError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(FrictionError::InvalidParameter {
            name,
            value,
            reason: "must be a finite number",
        })
    }
}
