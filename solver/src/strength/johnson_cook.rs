//! Johnson & Cook (1983): σ_eq ≤ (A + B ε_p^n)(1 + C ln ε̇*)(1 − T*^m), with
//! ε̇* = max(ε̇_eq/ε̇0, 1) and T* = (T − T0)/(T_melt − T0) clamped to [0, 1], the temperature
//! rising from T0 by the fraction χ (Taylor–Quinney) of the plastic work over c_v.

use super::{finite_non_negative, positive, YieldState, YieldSurface};
use crate::error::SolverError;

/// The Johnson–Cook parameters (SI; temperatures in K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JohnsonCook {
    pub a: f64,
    pub b: f64,
    pub n: f64,
    pub c: f64,
    pub m: f64,
    pub reference_rate: f64,
    pub room_temperature: f64,
    pub melt_temperature: f64,
    pub specific_heat: f64,
    pub taylor_quinney: f64,
}

impl JohnsonCook {
    /// The temperature after plastic work w_p per unit mass.
    pub fn temperature(&self, plastic_work: f64) -> f64 {
        self.room_temperature + self.taylor_quinney * plastic_work / self.specific_heat
    }

    /// The parameters checked by name: A, n, m, ε̇0, T0, c_v > 0; B, C ≥ 0; T_melt above T0;
    /// χ in [0, 1].
    pub fn validate(&self) -> Result<(), SolverError> {
        positive("Johnson-Cook A", self.a)?;
        positive("Johnson-Cook n", self.n)?;
        positive("Johnson-Cook m", self.m)?;
        positive("reference strain rate", self.reference_rate)?;
        positive("room temperature", self.room_temperature)?;
        positive("specific heat", self.specific_heat)?;
        finite_non_negative("Johnson-Cook B", self.b)?;
        finite_non_negative("Johnson-Cook C", self.c)?;
        if !(self.melt_temperature > self.room_temperature && self.melt_temperature.is_finite()) {
            return Err(SolverError::invalid(
                "melt temperature",
                self.melt_temperature,
                &format!(
                    "finite and above the room temperature {} K",
                    self.room_temperature
                ),
            ));
        }
        if !(0.0..=1.0).contains(&self.taylor_quinney) {
            return Err(SolverError::invalid(
                "Taylor-Quinney coefficient",
                self.taylor_quinney,
                "0 ≤ χ ≤ 1",
            ));
        }
        Ok(())
    }
}

impl YieldSurface for JohnsonCook {
    fn limit(&self, state: &YieldState) -> f64 {
        let hardening = self.a + self.b * state.plastic_strain.max(0.0).powf(self.n);
        let rate = (state.strain_rate / self.reference_rate).max(1.0);
        let homologous = ((self.temperature(state.plastic_work) - self.room_temperature)
            / (self.melt_temperature - self.room_temperature))
            .clamp(0.0, 1.0);
        hardening * (1.0 + self.c * rate.ln()) * (1.0 - homologous.powf(self.m))
    }

    fn temperature_rise(&self, plastic_work: f64) -> Option<f64> {
        Some(self.temperature(plastic_work) - self.room_temperature)
    }
}
