//! Stiffened gas p = (γ − 1) ρ e − γ p∞ (Harlow & Amsden 1971; used for water), with sound
//! speed c² = γ (p + p∞)/ρ. The liquid carries tension down to −p∞, where c vanishes; pressures
//! are clamped at the cutoff p_min ≥ −p∞.

use super::EquationOfState;
use crate::error::SolverError;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffenedGas {
    pub gamma: f64,
    pub p_inf: f64,
    pub p_min: f64,
}

impl StiffenedGas {
    pub fn new(gamma: f64, p_inf: f64, p_min: f64) -> Result<Self, SolverError> {
        if !(gamma > 1.0 && gamma.is_finite()) {
            return Err(SolverError::invalid("gamma", gamma, "finite and > 1"));
        }
        if !(p_inf >= 0.0 && p_inf.is_finite()) {
            return Err(SolverError::invalid("p_inf", p_inf, "finite and ≥ 0"));
        }
        if !(p_min >= -p_inf && p_min <= 0.0) {
            return Err(SolverError::invalid(
                "p_min",
                p_min,
                &format!("−p∞ = {} ≤ p_min ≤ 0", -p_inf),
            ));
        }
        Ok(Self {
            gamma,
            p_inf,
            p_min,
        })
    }

    /// Specific internal energy of the state (ρ, p).
    pub fn internal_energy(&self, density: f64, pressure: f64) -> f64 {
        (pressure + self.gamma * self.p_inf) / ((self.gamma - 1.0) * density)
    }
}

impl EquationOfState for StiffenedGas {
    fn pressure(&self, density: f64, internal_energy: f64) -> f64 {
        ((self.gamma - 1.0) * density * internal_energy - self.gamma * self.p_inf).max(self.p_min)
    }

    fn sound_speed(&self, density: f64, internal_energy: f64) -> f64 {
        // c² = γ (p + p∞)/ρ, with the pressure before the cutoff
        let p = (self.gamma - 1.0) * density * internal_energy - self.gamma * self.p_inf;
        (self.gamma * (p + self.p_inf) / density).max(0.0).sqrt()
    }

    fn min_pressure(&self) -> f64 {
        self.p_min
    }
}

#[cfg(test)]
mod tests {
    use super::super::checks::sound_speed_mismatch;
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// c² = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ within 1e-6 wherever the liquid is not at its
        /// cutoff.
        #[test]
        fn sound_speed_is_the_isentropic_derivative(rho in 900.0f64..1200.0, p in 1e4f64..1e9) {
            let eos = StiffenedGas::new(4.4, 6e8, -6e8).unwrap();
            let e = eos.internal_energy(rho, p);
            prop_assert!(sound_speed_mismatch(&eos, rho, e) <= 1e-6);
            prop_assert!((eos.pressure(rho, e) / p - 1.0).abs() < 1e-6);
        }
    }

    /// The liquid's floor is its cutoff: a state stretched past it reads p_min, and p_min is
    /// the floor the health check holds the liquid to (not a gas's p = 0).
    #[test]
    fn tension_stops_at_the_cutoff() {
        let eos = StiffenedGas::new(4.4, 6e8, -1e6).unwrap();
        assert_eq!(eos.min_pressure(), -1e6);
        let e = eos.internal_energy(1000.0, -5e8);
        assert_eq!(eos.pressure(1000.0, e), -1e6);
    }

    #[test]
    fn bad_parameters_are_named() {
        assert!(StiffenedGas::new(1.0, 6e8, 0.0)
            .unwrap_err()
            .to_string()
            .contains("gamma"));
        assert!(StiffenedGas::new(4.4, 6e8, -7e8)
            .unwrap_err()
            .to_string()
            .contains("p_min"));
    }
}
