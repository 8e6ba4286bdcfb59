//! Equations of state: pressure and sound speed from density and specific internal energy.
//! Ideal gas here; Mie–Grüneisen, JWL, stiffened gas and the compaction law of porous soil in
//! their own files.

mod compaction;
mod jwl;
mod mie_gruneisen;
mod stiffened_gas;

pub use compaction::Compaction;
pub use jwl::Jwl;
pub use mie_gruneisen::MieGruneisen;
pub use stiffened_gas::StiffenedGas;

use crate::error::SolverError;
use crate::strength::Strength;
use std::fmt::Debug;

/// p(ρ, e) and c(ρ, e) of a material.
pub trait EquationOfState: Debug + Send + Sync {
    /// Pressure p(ρ, e) in Pa.
    fn pressure(&self, density: f64, internal_energy: f64) -> f64;
    /// Adiabatic sound speed c(ρ, e) in m/s: c² = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ.
    fn sound_speed(&self, density: f64, internal_energy: f64) -> f64;
    /// The lowest pressure the material can carry: laws with a tensile cutoff clamp their
    /// pressure there; for the others a pressure below it means the state has left the physical
    /// range, and the run stops with a diagnosis.
    fn min_pressure(&self) -> f64 {
        0.0
    }
    /// Whether p and c depend on the highest density the particle has reached (a porous
    /// material that compacts); the particles then carry that density as history.
    fn remembers_peak_density(&self) -> bool {
        false
    }
    /// p(ρ, e) of a particle whose density has been as high as `peak_density`.
    fn pressure_after(&self, density: f64, internal_energy: f64, _peak_density: f64) -> f64 {
        self.pressure(density, internal_energy)
    }
    /// c(ρ, e) of a particle whose density has been as high as `peak_density`.
    fn sound_speed_after(&self, density: f64, internal_energy: f64, _peak_density: f64) -> f64 {
        self.sound_speed(density, internal_energy)
    }
}

/// Ideal gas p = (γ − 1) ρ e.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IdealGas {
    gamma: f64,
}

impl IdealGas {
    /// γ must exceed 1 (γ = 1 is the isothermal limit, which this law cannot represent).
    pub fn new(gamma: f64) -> Result<Self, SolverError> {
        if !(gamma > 1.0 && gamma.is_finite()) {
            return Err(SolverError::invalid("gamma", gamma, "finite and > 1"));
        }
        Ok(Self { gamma })
    }

    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// Specific internal energy e = p / ((γ − 1) ρ) of a state given by (ρ, p).
    pub fn internal_energy(&self, density: f64, pressure: f64) -> f64 {
        pressure / ((self.gamma - 1.0) * density)
    }
}

impl EquationOfState for IdealGas {
    #[inline]
    fn pressure(&self, density: f64, internal_energy: f64) -> f64 {
        (self.gamma - 1.0) * density * internal_energy
    }

    #[inline]
    fn sound_speed(&self, _density: f64, internal_energy: f64) -> f64 {
        // c² = γ p / ρ = γ (γ − 1) e; a negative e is caught by the health check, not here.
        (self.gamma * (self.gamma - 1.0) * internal_energy.max(0.0)).sqrt()
    }
}

/// A named material: its equation of state and, for a solid, its strength.
#[derive(Debug)]
pub struct Material {
    pub name: String,
    pub eos: Box<dyn EquationOfState>,
    pub strength: Option<Strength>,
}

impl Material {
    /// A fluid (no strength).
    pub fn new(name: impl Into<String>, eos: impl EquationOfState + 'static) -> Self {
        Self {
            name: name.into(),
            eos: Box::new(eos),
            strength: None,
        }
    }

    /// The same material as a solid with `strength`.
    pub fn with_strength(self, strength: Strength) -> Self {
        Self {
            strength: Some(strength),
            ..self
        }
    }
}

/// Checks of any equation of state, shared by the tests of each law.
#[cfg(test)]
pub(crate) mod checks {
    use super::EquationOfState;

    /// c² against ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ by central differences of relative step 1e-6
    /// (truncation ~1e-12, round-off ~1e-10 relative): the relative mismatch. A derivative
    /// that is not positive (no real sound speed) is a mismatch of at least 1.
    pub fn sound_speed_mismatch(eos: &dyn EquationOfState, rho: f64, e: f64) -> f64 {
        let (dr, de) = (rho * 1e-6, e.abs().max(1.0) * 1e-6);
        let dp_drho = (eos.pressure(rho + dr, e) - eos.pressure(rho - dr, e)) / (2.0 * dr);
        let dp_de = (eos.pressure(rho, e + de) - eos.pressure(rho, e - de)) / (2.0 * de);
        let c2 = dp_drho + eos.pressure(rho, e) / (rho * rho) * dp_de;
        let c = eos.sound_speed(rho, e);
        (c * c - c2).abs() / c2.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The sound speed equals the isentropic derivative c² = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ,
        /// taken by central differences (relative truncation error ~1e-10).
        #[test]
        fn ideal_gas_sound_speed_is_the_isentropic_derivative(
            gamma in 1.01f64..3.0, rho in 1e-3f64..1e4, e in 1e-2f64..1e7
        ) {
            let eos = IdealGas::new(gamma).unwrap();
            prop_assert!(checks::sound_speed_mismatch(&eos, rho, e) <= 1e-6);
        }
    }

    proptest! {
        /// internal_energy inverts the pressure: p(ρ, e(ρ, p)) = p to round-off (a division
        /// and three products, a few units of 1.1e-16 each, well inside 1e-14).
        #[test]
        fn internal_energy_gives_back_the_pressure(
            gamma in 1.01f64..3.0, rho in 1e-3f64..1e4, p in 1e-2f64..1e10
        ) {
            let eos = IdealGas::new(gamma).unwrap();
            let e = eos.internal_energy(rho, p);
            prop_assert!((eos.pressure(rho, e) / p - 1.0).abs() <= 1e-14);
        }

        /// A law without history (every law but compaction) ignores the peak density it is
        /// given, and a gas carries no tension: its floor is p = 0.
        #[test]
        fn a_law_without_history_ignores_the_peak_density(
            rho in 1e-3f64..1e4, e in 1e-2f64..1e7, peak in 1e-3f64..1e5
        ) {
            let eos = IdealGas::new(1.4).unwrap();
            prop_assert!(!eos.remembers_peak_density());
            prop_assert_eq!(eos.pressure_after(rho, e, peak), eos.pressure(rho, e));
            prop_assert_eq!(eos.sound_speed_after(rho, e, peak), eos.sound_speed(rho, e));
            prop_assert_eq!(eos.min_pressure(), 0.0);
        }
    }

    /// Air's p = (γ − 1) ρ e at 1.225 kg/m³ and 101 325 Pa: e = 101 325/(0.4 · 1.225) =
    /// 206 785.714… J/kg for γ = 1.4 (worked by hand; 1e-12 leaves room for round-off only),
    /// and the gas keeps γ as given.
    #[test]
    fn air_at_sea_level() {
        let air = IdealGas::new(1.4).unwrap();
        assert_eq!(air.gamma(), 1.4);
        let e = air.internal_energy(1.225, 101_325.0);
        assert!((e / 206_785.714_285_714_3 - 1.0).abs() < 1e-12, "{e}");
    }

    #[test]
    fn gamma_must_exceed_one() {
        let err = IdealGas::new(1.0).unwrap_err().to_string();
        assert!(err.contains("gamma") && err.contains("> 1"), "{err}");
    }
}
