//! Drucker–Prager for soil, matched to the Mohr–Coulomb compression meridian (cohesion c,
//! friction angle φ): σ_eq ≤ (6 c cos φ + 6 p sin φ)/(3 − sin φ), with no shear strength at
//! all below the tension cutoff p < −σ_t (the soil has failed in tension there).

use super::{YieldState, YieldSurface};
use crate::error::SolverError;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DruckerPrager {
    /// c (Pa).
    pub cohesion: f64,
    /// sin φ and cos φ (the limit is evaluated at every return).
    pub sin_friction: f64,
    pub cos_friction: f64,
    /// σ_t (Pa).
    pub tensile_strength: f64,
}

impl DruckerPrager {
    /// Cohesion c ≥ 0 (Pa), friction angle φ in degrees in [0, 60), not both zero; tensile
    /// strength σ_t ≥ 0 (Pa) no larger than the cone's apex c/tan φ.
    pub fn new(
        cohesion: f64,
        friction_angle_degrees: f64,
        tensile_strength: f64,
    ) -> Result<Self, SolverError> {
        if !(cohesion >= 0.0 && cohesion.is_finite()) {
            return Err(SolverError::invalid("cohesion", cohesion, "finite and ≥ 0"));
        }
        if !(0.0..60.0).contains(&friction_angle_degrees) {
            return Err(SolverError::invalid(
                "friction angle",
                friction_angle_degrees,
                "0 ≤ φ < 60 degrees",
            ));
        }
        if cohesion == 0.0 && friction_angle_degrees == 0.0 {
            return Err(SolverError::invalid(
                "cohesion and friction angle",
                "0, 0",
                "not both zero (the material would have no strength)",
            ));
        }
        let phi = friction_angle_degrees.to_radians();
        let apex = if phi > 0.0 {
            cohesion / phi.tan()
        } else {
            f64::INFINITY
        };
        if !(tensile_strength >= 0.0 && tensile_strength <= apex) {
            return Err(SolverError::invalid(
                "tensile strength",
                tensile_strength,
                &format!("0 ≤ σ_t ≤ c/tan φ = {apex:.4e} Pa (the cone's apex)"),
            ));
        }
        Ok(Self {
            cohesion,
            sin_friction: phi.sin(),
            cos_friction: phi.cos(),
            tensile_strength,
        })
    }
}

impl YieldSurface for DruckerPrager {
    fn limit(&self, state: &YieldState) -> f64 {
        let (sin, cos) = (self.sin_friction, self.cos_friction);
        if state.pressure < -self.tensile_strength {
            return 0.0;
        }
        (6.0 * (self.cohesion * cos + state.pressure * sin) / (3.0 - sin)).max(0.0)
    }

    fn tension_cutoff(&self) -> Option<f64> {
        Some(self.tensile_strength)
    }
}
