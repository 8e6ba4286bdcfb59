//! Errors the solver reports: bad input, and a run that left the physical range.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum SolverError {
    /// A parameter outside its allowed range.
    #[error("invalid {field} = {value}: allowed {allowed}")]
    InvalidParameter {
        field: String,
        value: String,
        allowed: String,
    },
    /// A particle left the physical range (NaN, ρ ≤ 0, pressure below the material's floor).
    #[error(
        "blow-up at step {step} (t = {time:.6e} s): particle {particle} (material {material}) \
         at x = {position:?} has {quantity} = {value:.6e}"
    )]
    BlowUp {
        step: u64,
        time: f64,
        particle: u32,
        material: String,
        position: Vec<f64>,
        quantity: &'static str,
        value: f64,
    },
    /// The stable time step fell below the floor the run allows.
    #[error(
        "time step collapse at step {step} (t = {time:.6e} s): dt = {dt:.3e} s < floor {floor:.3e} s, \
         set by particle {particle} (material {material})"
    )]
    TimeStepCollapse {
        step: u64,
        time: f64,
        dt: f64,
        floor: f64,
        particle: u32,
        material: String,
    },
}

impl SolverError {
    pub fn invalid(field: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        SolverError::InvalidParameter {
            field: field.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
}
