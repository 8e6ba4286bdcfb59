//! Mie–Grüneisen equation of state referenced to the shock Hugoniot of a solid at rest:
//! p(ρ, e) = p_H(ρ) + Γ0 ρ0 (e − e_H(ρ)), with Γρ = Γ0ρ0 constant (the usual hydrocode form).
//!
//! The Hugoniot is Steinberg's (1996) Us = C0 + S1 up + S2 up²/Us + S3 up³/Us², linear when
//! S2 = S3 = 0. With η = 1 − ρ0/ρ = up/Us (mass conservation across the shock) it gives
//! Us = C0/Δ, Δ = 1 − S1η − S2η² − S3η³, so p_H = ρ0 Us up = ρ0 C0² η/Δ² and
//! e_H = p_H η/(2ρ0) (Rankine–Hugoniot energy jump from rest). In tension (η < 0) the reference
//! is the linear elastic curve p = ρ0 C0² η, e = 0. Pressures below the tensile cutoff p_min
//! are clamped to it (spall).

use super::EquationOfState;
use crate::error::SolverError;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MieGruneisen {
    pub rho0: f64,
    pub c0: f64,
    pub s1: f64,
    pub s2: f64,
    pub s3: f64,
    pub gamma0: f64,
    /// Tensile cutoff (Pa, ≤ 0).
    pub p_min: f64,
}

impl MieGruneisen {
    /// A linear Us–up Hugoniot (S2 = S3 = 0).
    pub fn linear(
        rho0: f64,
        c0: f64,
        s1: f64,
        gamma0: f64,
        p_min: f64,
    ) -> Result<Self, SolverError> {
        Self::steinberg(rho0, c0, s1, 0.0, 0.0, gamma0, p_min)
    }

    pub fn steinberg(
        rho0: f64,
        c0: f64,
        s1: f64,
        s2: f64,
        s3: f64,
        gamma0: f64,
        p_min: f64,
    ) -> Result<Self, SolverError> {
        for (field, value) in [("rho0", rho0), ("c0", c0)] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(SolverError::invalid(field, value, "finite and > 0"));
            }
        }
        if !(s1 >= 0.0 && s1.is_finite()) {
            return Err(SolverError::invalid("s1", s1, "finite and ≥ 0"));
        }
        if !(s2.is_finite() && s3.is_finite()) {
            return Err(SolverError::invalid(
                "s2/s3",
                format!("{s2}/{s3}"),
                "finite",
            ));
        }
        if !(gamma0 >= 0.0 && gamma0.is_finite()) {
            return Err(SolverError::invalid("gamma0", gamma0, "finite and ≥ 0"));
        }
        if !(p_min <= 0.0) {
            return Err(SolverError::invalid(
                "p_min",
                p_min,
                "≤ 0 (a tensile cutoff)",
            ));
        }
        Ok(Self {
            rho0,
            c0,
            s1,
            s2,
            s3,
            gamma0,
            p_min,
        })
    }

    /// Shock velocity at particle velocity `up` (Steinberg's implicit form solved through η).
    pub fn shock_velocity(&self, up: f64) -> f64 {
        // Us = C0/Δ(η) with η = up/Us: a fixed point in Us, solved by Newton on g(Us) = Us·Δ − C0
        let mut us = self.c0 + self.s1 * up;
        for _ in 0..50 {
            let eta = up / us;
            let g = us * self.delta(eta) - self.c0;
            // d(us Δ)/dus = Δ − η Δ'(η)
            let dg = self.delta(eta) - eta * self.delta_slope(eta);
            let next = us - g / dg;
            if (next - us).abs() <= 1e-15 * us {
                return next;
            }
            us = next;
        }
        us
    }

    fn delta(&self, eta: f64) -> f64 {
        1.0 - self.s1 * eta - self.s2 * eta * eta - self.s3 * eta * eta * eta
    }

    fn delta_slope(&self, eta: f64) -> f64 {
        -self.s1 - 2.0 * self.s2 * eta - 3.0 * self.s3 * eta * eta
    }

    /// Reference pressure and energy p_H(η), e_H(η) and their derivatives in η.
    fn reference(&self, eta: f64) -> (f64, f64, f64, f64) {
        let k = self.rho0 * self.c0 * self.c0;
        if eta < 0.0 {
            return (k * eta, 0.0, k, 0.0);
        }
        let delta = self.delta(eta);
        let p = k * eta / (delta * delta);
        let dp = k * (delta - 2.0 * eta * self.delta_slope(eta)) / (delta * delta * delta);
        let e = 0.5 * p * eta / self.rho0;
        let de = 0.5 * (dp * eta + p) / self.rho0;
        (p, e, dp, de)
    }

    fn unclamped(&self, density: f64, internal_energy: f64) -> f64 {
        let (p_h, e_h, _, _) = self.reference(1.0 - self.rho0 / density);
        p_h + self.gamma0 * self.rho0 * (internal_energy - e_h)
    }
}

impl EquationOfState for MieGruneisen {
    fn pressure(&self, density: f64, internal_energy: f64) -> f64 {
        self.unclamped(density, internal_energy).max(self.p_min)
    }

    fn sound_speed(&self, density: f64, internal_energy: f64) -> f64 {
        let eta = 1.0 - self.rho0 / density;
        let (_, _, dp, de) = self.reference(eta);
        let deta_drho = self.rho0 / (density * density);
        let dp_drho = (dp - self.gamma0 * self.rho0 * de) * deta_drho;
        let dp_de = self.gamma0 * self.rho0;
        let p = self.unclamped(density, internal_energy);
        (dp_drho + p / (density * density) * dp_de).max(0.0).sqrt()
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

    /// Copper OFHC and PMMA of Steinberg's table (reference_data's hugoniot_linear.csv).
    fn copper() -> MieGruneisen {
        MieGruneisen::linear(8930.0, 3940.0, 1.489, 2.02, -1e12).unwrap()
    }
    fn pmma() -> MieGruneisen {
        MieGruneisen::steinberg(1182.0, 2180.0, 2.088, -1.124, 0.0, 0.85, -1e12).unwrap()
    }
    /// Lead of Steinberg's table (reference_data's hugoniot_linear.csv: C0 2006 m/s, S1 1.429,
    /// S2 0.8506, S3 −1.64), every term of Δ(η) non-zero.
    fn lead() -> MieGruneisen {
        MieGruneisen::steinberg(11340.0, 2006.0, 1.429, 0.8506, -1.64, 2.74, -1e12).unwrap()
    }

    /// Us of Steinberg's table with S3 = 0, solved in closed form from
    /// Us² − (C0 + S1 up) Us − S2 up² = 0 (independent of the EOS's own Newton solve).
    fn table_shock_velocity(eos: &MieGruneisen, up: f64) -> f64 {
        let b = eos.c0 + eos.s1 * up;
        0.5 * (b + (b * b + 4.0 * eos.s2 * up * up).sqrt())
    }

    proptest! {
        /// On the Hugoniot (ρ = ρ0 Us/(Us − up), e = up²/2) the pressure is ρ0 Us up, with Us
        /// from the table's quadratic (1e-12: a few roundings).
        #[test]
        fn pressure_on_the_hugoniot_is_rho0_us_up(up in 1.0f64..3000.0) {
            for eos in [copper(), pmma()] {
                let us = table_shock_velocity(&eos, up);
                prop_assert!((eos.shock_velocity(up) / us - 1.0).abs() < 1e-12);
                let rho = eos.rho0 * us / (us - up);
                let p = eos.pressure(rho, 0.5 * up * up);
                prop_assert!((p / (eos.rho0 * us * up) - 1.0).abs() < 1e-12, "up {up}: {p}");
            }
        }

        /// c² = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ within 1e-6, in compression and in tension; lead's
        /// S3 ≠ 0 puts the cubic term of Δ'(η) in play.
        #[test]
        fn sound_speed_is_the_isentropic_derivative(mu in -0.05f64..0.4, e in 0.0f64..2e6) {
            for eos in [copper(), pmma(), lead()] {
                let rho = eos.rho0 * (1.0 + mu);
                prop_assume!(mu.abs() > 1e-4); // the reference curve's joint at μ = 0
                prop_assert!(sound_speed_mismatch(&eos, rho, e) <= 1e-6);
            }
        }
    }

    /// Steinberg's lead ([`lead`]): the shock velocity the EOS solves through η satisfies the
    /// table's own implicit form Us = C0 + S1 up + S2 up²/Us + S3 up³/Us², every term in play.
    #[test]
    fn steinberg_shock_velocity_satisfies_the_implicit_hugoniot() {
        let lead = lead();
        for up in [100.0, 500.0, 1000.0, 2000.0] {
            let us = lead.shock_velocity(up);
            let implicit =
                2006.0 + 1.429 * up + 0.8506 * up * up / us - 1.64 * up.powi(3) / us.powi(2);
            assert!(
                (us - implicit).abs() < 1e-9 * us,
                "up {up}: {us} vs {implicit}"
            );
            // the S3 term alone moves Us by more than the tolerance: it is not dropped
            assert!(1.64 * up.powi(3) / us.powi(2) > 1e-6 * us);
        }
    }

    /// In tension the reference is the linear elastic curve p = ρ0 C0² η (η = 1 − ρ0/ρ < 0),
    /// not the Hugoniot's η/Δ² continued below ρ0 (which at 2 % tension in copper lies 6 %
    /// away); and at ρ0 the bulk sound speed is the Hugoniot's intercept C0, the speed of a
    /// shock of vanishing strength.
    #[test]
    fn tension_follows_the_linear_elastic_curve() {
        for eos in [copper(), pmma()] {
            let k = eos.rho0 * eos.c0 * eos.c0;
            let rho = eos.rho0 / 1.02;
            let eta = 1.0 - eos.rho0 / rho;
            assert!((eos.pressure(rho, 0.0) / (k * eta) - 1.0).abs() < 1e-12);
            let c = eos.sound_speed(eos.rho0 * (1.0 - 1e-9), 0.0);
            assert!((c / eos.c0 - 1.0).abs() < 1e-6, "{c}");
        }
    }

    #[test]
    fn linear_shock_velocity_is_c0_plus_s1_up() {
        let cu = copper();
        assert!((cu.shock_velocity(500.0) - (3940.0 + 1.489 * 500.0)).abs() < 1e-9);
    }

    #[test]
    fn non_physical_parameters_are_rejected_by_name() {
        for (rho0, c0, field) in [
            (0.0, 3940.0, "rho0"),
            (-1.0, 3940.0, "rho0"),
            (8930.0, 0.0, "c0"),
        ] {
            let err = MieGruneisen::linear(rho0, c0, 1.489, 2.02, -1e9)
                .unwrap_err()
                .to_string();
            assert!(err.contains(field) && err.contains("> 0"), "{err}");
        }
    }

    /// Non-finite S2, S3 and Γ0, and a negative S1 or Γ0, are refused by name.
    #[test]
    fn non_finite_hugoniot_terms_are_rejected_by_name() {
        let make = |s1: f64, s2: f64, s3: f64, gamma0: f64| {
            MieGruneisen::steinberg(8930.0, 3940.0, s1, s2, s3, gamma0, -1e9)
        };
        for (result, field) in [
            (make(1.489, f64::NAN, 0.0, 2.02), "s2"),
            (make(1.489, 0.0, f64::INFINITY, 2.02), "s3"),
            (make(1.489, 0.0, 0.0, f64::NAN), "gamma0"),
            (make(1.489, 0.0, 0.0, -0.1), "gamma0"),
            (make(-0.1, 0.0, 0.0, 2.02), "s1"),
        ] {
            let err = result.unwrap_err().to_string();
            assert!(err.contains(field), "{field}: {err}");
        }
    }

    #[test]
    fn tension_is_cut_off() {
        let eos = MieGruneisen::linear(8930.0, 3940.0, 1.489, 2.02, -1e9).unwrap();
        assert_eq!(eos.pressure(0.9 * 8930.0, 0.0), -1e9);
        assert!(MieGruneisen::linear(8930.0, 3940.0, 1.489, 2.02, 5.0).is_err());
    }
}
