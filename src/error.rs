//! The crate's error type: every rejection names the field and the allowed range.

use thiserror::Error;

/// Everything that can go wrong when building a scene or running a solver.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A parameter outside its allowed range, with the field's path (`springs[3].stiffness`).
    #[error("invalid {field}: {value} (allowed: {allowed})")]
    InvalidParameter {
        field: String,
        value: String,
        allowed: String,
    },
    /// A time step that failed (for instance a factorisation made indefinite by compressed
    /// springs), with when it happened.
    #[error("{solver}: step {step} (t = {time} s) failed: {source}")]
    StepFailed {
        solver: String,
        step: u64,
        time: f64,
        source: Box<Error>,
    },
    /// A run whose state became non-finite or whose energy exploded.
    #[error("{solver} diverged at step {step} (t = {time} s): {reason}")]
    Diverged {
        solver: String,
        step: u64,
        time: f64,
        reason: String,
    },
    /// A Newton iteration that did not reach its tolerance.
    #[error("{what} did not converge: {detail}")]
    NotConverged { what: String, detail: String },
    /// Reading or parsing a file (scene file, published data).
    #[error("{0}")]
    Input(String),
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(field: impl Into<String>, value: impl std::fmt::Display, allowed: &str) -> Self {
        Error::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
}

/// The crate's result type.
pub type Result<T> = std::result::Result<T, Error>;

/// A number as a message shows it: as written from 1e-4 to 1e6, else in short scientific
/// form (`1e308`, not its 309 digits; `1e-320`, not its 320 decimals).
pub fn shown(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn require_positive(field: impl Into<String>, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(field, shown(value), "a finite number > 0"))
    }
}

/// Checks that `value` is finite and non-negative.
pub fn require_non_negative(field: impl Into<String>, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(field, shown(value), "a finite number >= 0"))
    }
}

/// Checks that `value` is within `min..=max` (and so finite).
pub fn require_within(
    field: impl Into<String>,
    value: f64,
    min: f64,
    max: f64,
    unit: &str,
) -> Result<f64> {
    let bound = |x: f64| {
        if x == 0.0 {
            "0".to_string()
        } else {
            format!("{x:e}")
        }
    };
    if (min..=max).contains(&value) {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            shown(value),
            &format!("a number from {} to {}, in {unit}", bound(min), bound(max)),
        ))
    }
}

/// Checks that `value` is finite.
pub fn require_finite(field: impl Into<String>, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(field, shown(value), "a finite number"))
    }
}

/// Why a command-line tool (`report`, `timing`) stops: bad input, found before anything runs
/// or is measured (exit 2), or a failure of the run or of writing its files (exit 1).
#[derive(Debug)]
pub enum Failure {
    Input(Error),
    Run(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Run(e)
    }
}

impl Failure {
    /// Prints the error after the tool's name on stderr and gives the exit code: 2 for bad
    /// input, 1 for a failed run.
    pub fn exit(self, tool: &str) -> std::process::ExitCode {
        match self {
            Failure::Input(e) => {
                eprintln!("{tool}: {e}");
                std::process::ExitCode::from(2)
            }
            Failure::Run(e) => {
                eprintln!("{tool}: {e}");
                std::process::ExitCode::FAILURE
            }
        }
    }
}
