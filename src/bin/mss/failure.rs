//! Why `mss` stops: bad input (exit 2) or a failed run (exit 1), with its message.

use mass_spring_solvers::error::Error;

/// Why `mss` stops: the message and the exit status.
#[derive(Debug)]
pub(crate) struct Failure {
    pub(crate) status: u8,
    pub(crate) message: String,
}

impl Failure {
    /// Bad input: an option, a scene file or an output path.
    pub(crate) fn input(message: impl Into<String>) -> Self {
        Self {
            status: 2,
            message: message.into(),
        }
    }

    /// A run that failed, or output that could not be written.
    pub(crate) fn run(message: impl Into<String>) -> Self {
        Self {
            status: 1,
            message: message.into(),
        }
    }

    pub(crate) fn with_context(self, context: &str) -> Self {
        Self {
            message: format!("{context}: {}", self.message),
            ..self
        }
    }
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        match e {
            Error::InvalidParameter { .. } | Error::Input(_) => Failure::input(e.to_string()),
            Error::StepFailed { .. } | Error::Diverged { .. } | Error::NotConverged { .. } => {
                Failure::run(e.to_string())
            }
        }
    }
}
