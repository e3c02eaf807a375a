//! Typed errors of the closures: unknown model names and parameters or per-particle inputs out
//! of their physical range. Hot-path functions take numbers and never fail; callers that read
//! user input check it once with the `check` functions, which return these errors.

use thiserror::Error;

/// What went wrong, naming the model, the parameter or the input quantity.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ClosureError {
    /// A model name (as written in `couplingProperties`) that no closure answers to.
    #[error("unknown {family} model `{name}`; valid names: {valid}")]
    UnknownModel {
        /// The model family, e.g. "drag" or "model type".
        family: &'static str,
        /// The name as given.
        name: String,
        /// The accepted names, comma separated.
        valid: String,
    },
    /// A configuration parameter outside its allowed range.
    #[error("{model}: parameter `{key}` = {value} is invalid: {reason}")]
    BadParameter {
        /// The model the parameter belongs to.
        model: &'static str,
        /// The parameter's key.
        key: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range.
        reason: &'static str,
    },
    /// A per-particle (or per-material) input quantity that is not finite or out of range.
    #[error("input `{quantity}` = {value} is invalid: {reason}")]
    BadInput {
        /// The quantity's name, e.g. "diameter".
        quantity: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range.
        reason: &'static str,
    },
}

/// `Ok` if `value` is finite and `> 0`, else a [`ClosureError::BadInput`] naming `quantity`.
pub(crate) fn positive(quantity: &'static str, value: f64) -> Result<(), ClosureError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ClosureError::BadInput {
            quantity,
            value,
            reason: "must be finite and > 0",
        })
    }
}

/// `Ok` if `value` is finite and `>= 0`, else a [`ClosureError::BadInput`] naming `quantity`.
pub(crate) fn non_negative(quantity: &'static str, value: f64) -> Result<(), ClosureError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(ClosureError::BadInput {
            quantity,
            value,
            reason: "must be finite and >= 0",
        })
    }
}
