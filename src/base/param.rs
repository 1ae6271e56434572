//! The typed error for an invalid parameter (simulation, LOD, view, command line).

/// A parameter outside its valid range (or NaN/infinite). Names the parameter, the value given
/// and the valid range, so the CLI can print it verbatim and exit non-zero.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The parameter's name as the user spells it (CLI flag / config key).
    pub parameter: &'static str,
    /// The rejected value.
    pub value: f64,
    /// Human-readable valid range, e.g. "a finite number > 0 (m/s)".
    pub valid: &'static str,
}

impl ParamError {
    /// Builds the error for `parameter` = `value`, which should be `valid`.
    pub fn new(parameter: &'static str, value: f64, valid: &'static str) -> Self {
        Self {
            parameter,
            value,
            valid,
        }
    }
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "invalid {}: {} (expected {})",
            self.parameter, self.value, self.valid
        )
    }
}

impl std::error::Error for ParamError {}
