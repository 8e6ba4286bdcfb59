//! Von Mises plasticity with linear isotropic hardening: σ_eq ≤ Y0 + H ε_p (H = 0 is the
//! thesis' elastic–perfectly plastic model).

use super::{finite_non_negative, positive, YieldState, YieldSurface};
use crate::error::SolverError;

/// Yield stress Y0 (Pa) and hardening modulus H = dY/dε_p (Pa).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VonMises {
    pub yield_stress: f64,
    pub hardening_modulus: f64,
}

impl VonMises {
    /// Y0 > 0 and H ≥ 0, both finite.
    pub fn new(yield_stress: f64, hardening_modulus: f64) -> Result<Self, SolverError> {
        positive("yield stress", yield_stress)?;
        finite_non_negative("hardening modulus", hardening_modulus)?;
        Ok(Self {
            yield_stress,
            hardening_modulus,
        })
    }

    /// No yield at any stress: the return never acts (a purely elastic solid).
    pub fn never_yielding() -> Self {
        Self {
            yield_stress: f64::INFINITY,
            hardening_modulus: 0.0,
        }
    }
}

impl YieldSurface for VonMises {
    fn limit(&self, state: &YieldState) -> f64 {
        self.yield_stress + self.hardening_modulus * state.plastic_strain
    }

    fn hardening(&self) -> f64 {
        self.hardening_modulus
    }
}
