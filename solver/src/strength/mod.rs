//! Strength of solids: hypoelastic deviatoric stress with a yield surface.
//!
//! The deviatoric stress s evolves by the Jaumann rate (objective under rotation),
//! ṡ = 2G (ε̇ − ⅓ tr ε̇ I) + Ω s − s Ω, with ε̇ and Ω the symmetric and antisymmetric parts of
//! the velocity gradient. After each update the stress is returned radially to the yield surface
//! (Wilkins 1964): if σ_eq = √(3/2 s:s) exceeds the limit Y of the particle's state, s is scaled
//! towards Y and the equivalent plastic strain grows by (σ_eq − Y)/(3G + H), H = dY/dε_p.
//!
//! A yield surface is one file here with a type that implements [`YieldSurface`] (the limit in
//! a particle's [`YieldState`], and optionally its hardening, tension cutoff and heating),
//! registered by its `mod` line below: von Mises with linear hardening, Drucker–Prager for
//! soil, Johnson–Cook for metals at high rates and temperatures.
//!
//! In 1D and 2D the stored tensor is the in-plane block; the out-of-plane normal components
//! follow from tr s = 0 (uniaxial strain in 1D: the two transverse components are equal;
//! plane strain in 2D: one), so s:s = |s_D|² + (tr s_D)²/(3 − D).

mod drucker_prager;
mod johnson_cook;
mod von_mises;

pub use drucker_prager::DruckerPrager;
pub use johnson_cook::JohnsonCook;
pub use von_mises::VonMises;

use crate::error::SolverError;
use nalgebra::{Matrix3, SMatrix};
use std::fmt::Debug;
use std::sync::Arc;

/// Where plastic flow begins, as a limit on the von Mises equivalent stress σ_eq.
pub trait YieldSurface: Debug + Send + Sync {
    /// The limit on σ_eq in the particle's state (Pa, ≥ 0).
    fn limit(&self, state: &YieldState) -> f64;

    /// The hardening modulus dY/dε_p of the return's consistency condition. 0 (the default)
    /// takes the limit at the start of the step: first order in the plastic-strain increment.
    fn hardening(&self) -> f64 {
        0.0
    }

    /// σ_t of a surface with a tension cutoff on the pressure: no shear strength where
    /// p < −σ_t (the material has failed in tension there).
    fn tension_cutoff(&self) -> Option<f64> {
        None
    }

    /// The temperature rise after plastic work w_p per unit mass (J/kg), for a surface that
    /// carries its own thermal data.
    fn temperature_rise(&self, _plastic_work: f64) -> Option<f64> {
        None
    }
}

/// What a yield limit can depend on, per particle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct YieldState {
    /// Equivalent plastic strain ε_p.
    pub plastic_strain: f64,
    /// Pressure p (Pa).
    pub pressure: f64,
    /// Equivalent strain rate √(2/3 ė':ė') (1/s).
    pub strain_rate: f64,
    /// Plastic work per unit mass (J/kg).
    pub plastic_work: f64,
}

/// Elastic–plastic strength: the shear modulus and the yield surface.
#[derive(Clone, Debug)]
pub struct Strength {
    pub shear_modulus: f64,
    pub surface: Arc<dyn YieldSurface>,
    /// A brittle material's tensile strength f_t (Pa; Rankine's criterion): the largest
    /// principal stress of σ = −pI + s is held at or below it, and where it reaches it the
    /// material cracks (see [`Strength::with_tensile_strength`]).
    pub tensile_strength: Option<f64>,
    /// How plastic work heats the material, for the temperature-rise output (a surface with
    /// its own thermal data, such as Johnson–Cook, takes precedence).
    pub heating: Option<PlasticHeating>,
}

/// The share of plastic work that becomes heat, χ (Taylor & Quinney 1934: about 0.9 for
/// metals), and the specific heat c (J/(kg K)): ΔT = χ w_p / c.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticHeating {
    pub specific_heat: f64,
    pub taylor_quinney: f64,
}

impl Strength {
    /// Shear modulus G > 0 (Pa) and a yield surface.
    pub fn plastic(
        shear_modulus: f64,
        surface: impl YieldSurface + 'static,
    ) -> Result<Self, SolverError> {
        positive("shear modulus", shear_modulus)?;
        Ok(Self {
            heating: None,
            tensile_strength: None,
            shear_modulus,
            surface: Arc::new(surface),
        })
    }

    /// Von Mises with linear hardening (see [`VonMises`]).
    pub fn new(
        shear_modulus: f64,
        yield_stress: f64,
        hardening_modulus: f64,
    ) -> Result<Self, SolverError> {
        let surface = VonMises::new(yield_stress, hardening_modulus)?;
        Self::plastic(shear_modulus, surface)
    }

    /// A purely elastic solid (rubber, a lining kept below yield): von Mises with an infinite
    /// yield stress, so the return never acts.
    pub fn elastic(shear_modulus: f64) -> Result<Self, SolverError> {
        Self::plastic(shear_modulus, VonMises::never_yielding())
    }

    /// Drucker–Prager / Mohr–Coulomb for soil (see [`DruckerPrager::new`]).
    pub fn drucker_prager(
        shear_modulus: f64,
        cohesion: f64,
        friction_angle_degrees: f64,
        tensile_strength: f64,
    ) -> Result<Self, SolverError> {
        let surface = DruckerPrager::new(cohesion, friction_angle_degrees, tensile_strength)?;
        Self::plastic(shear_modulus, surface)
    }

    /// Johnson–Cook (see [`JohnsonCook`]), parameters checked by name.
    pub fn johnson_cook(shear_modulus: f64, parameters: JohnsonCook) -> Result<Self, SolverError> {
        parameters.validate()?;
        Self::plastic(shear_modulus, parameters)
    }

    /// The same strength with plastic heating: specific heat c > 0 (J/(kg K)) and
    /// Taylor–Quinney share χ in [0, 1].
    pub fn with_heating(
        self,
        specific_heat: f64,
        taylor_quinney: f64,
    ) -> Result<Self, SolverError> {
        positive("specific heat", specific_heat)?;
        if !(0.0..=1.0).contains(&taylor_quinney) {
            return Err(SolverError::invalid(
                "Taylor-Quinney coefficient",
                taylor_quinney,
                "0 ≤ χ ≤ 1",
            ));
        }
        Ok(Self {
            heating: Some(PlasticHeating {
                specific_heat,
                taylor_quinney,
            }),
            ..self
        })
    }

    /// The same strength with a tensile strength f_t > 0 (Pa) on the largest principal stress
    /// (Rankine), the cracking of a brittle solid such as concrete. Where a trial stress
    /// exceeds it, the deviator is scaled towards the hydrostatic axis until the largest
    /// principal stress is f_t (all of it where the pressure alone is a tension beyond f_t):
    /// the radial return of [`Strength::return_map`] onto a tension cutoff. A surface with its
    /// own cutoff on the pressure (Drucker–Prager) refuses a second one.
    pub fn with_tensile_strength(self, tensile_strength: f64) -> Result<Self, SolverError> {
        positive("tensile strength", tensile_strength)?;
        if self.surface.tension_cutoff().is_some() {
            return Err(SolverError::invalid(
                "tensile strength",
                tensile_strength,
                "none with Drucker-Prager (its tension cutoff is on the pressure)",
            ));
        }
        Ok(Self {
            tensile_strength: Some(tensile_strength),
            ..self
        })
    }

    /// The temperature rise after plastic work w_p per unit mass: the surface's own (Johnson–Cook),
    /// else χ w_p / c where the material knows its heating.
    pub fn temperature_rise(&self, plastic_work: f64) -> Option<f64> {
        self.surface.temperature_rise(plastic_work).or_else(|| {
            self.heating
                .map(|h| h.taylor_quinney * plastic_work / h.specific_heat)
        })
    }

    /// The shear modulus G = E/(2(1 + ν)) and bulk modulus K = E/(3(1 − 2ν)) of Young's
    /// modulus E and Poisson's ratio ν ∈ (−1, 0.5).
    pub fn elastic_moduli(young: f64, poisson: f64) -> Result<(f64, f64), SolverError> {
        if !(young > 0.0 && young.is_finite()) {
            return Err(SolverError::invalid(
                "Young's modulus",
                young,
                "finite and > 0",
            ));
        }
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(SolverError::invalid(
                "Poisson's ratio",
                poisson,
                "−1 < ν < 0.5",
            ));
        }
        Ok((
            young / (2.0 * (1.0 + poisson)),
            young / (3.0 * (1.0 - 2.0 * poisson)),
        ))
    }

    /// The limit on σ_eq in the particle's state.
    pub fn current_yield(&self, state: &YieldState) -> f64 {
        self.surface.limit(state)
    }

    /// Whether a particle at pressure p with deviatoric stress s has failed in tension: below
    /// its surface's tension cutoff (no shear strength), or a brittle solid with its largest
    /// principal stress at its tensile strength (cracked; to 1e-9 of f_t, as the return
    /// leaves it).
    pub fn failed_in_tension<const D: usize>(&self, pressure: f64, s: &SMatrix<f64, D, D>) -> bool {
        if let Some(cutoff) = self.surface.tension_cutoff() {
            return pressure < -cutoff;
        }
        self.tensile_strength.is_some_and(|limit| {
            let threshold = limit * (1.0 - 1e-9);
            // the bound clears most particles without the eigenvalues
            principal_deviator_bound(s) - pressure >= threshold
                && largest_principal_deviator(s) - pressure >= threshold
        })
    }

    /// Radial return of `s` onto the yield surface in `state` (the deviator is scaled at fixed
    /// p, Wilkins' scheme; for Drucker–Prager a non-associated return), then onto the tension
    /// cutoff of a brittle solid. Returns the increment of equivalent plastic strain (0 where
    /// the state is elastic or only cracked).
    pub fn return_map<const D: usize>(
        &self,
        s: &mut SMatrix<f64, D, D>,
        state: &YieldState,
    ) -> f64 {
        let sigma_eq = von_mises(s);
        let yield_stress = self.current_yield(state);
        let increment = if sigma_eq > yield_stress {
            // consistency with hardening: σ_eq − 3G Δε = Y0 + H (ε_p + Δε)
            let increment =
                (sigma_eq - yield_stress) / (3.0 * self.shear_modulus + self.surface.hardening());
            *s *= ((sigma_eq - 3.0 * self.shear_modulus * increment) / sigma_eq).max(0.0);
            increment
        } else {
            0.0
        };
        if let Some(limit) = self.tensile_strength {
            // Rankine: −p + s₁ ≤ f_t, with s₁ the largest principal deviatoric stress; scaling
            // s keeps its principal directions. Cracking is not plastic flow: the strain it
            // releases is no plastic strain (the shear energy it frees stays in the internal
            // energy, as the stress power booked it)
            // the bound clears most particles without the eigenvalues
            if principal_deviator_bound(s) - state.pressure > limit {
                let s1 = largest_principal_deviator(s);
                if s1 - state.pressure > limit {
                    *s *= ((limit + state.pressure) / s1).clamp(0.0, 1.0);
                }
            }
        }
        increment
    }
}

fn positive(field: &str, value: f64) -> Result<(), SolverError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(SolverError::invalid(field, value, "finite and > 0"))
    }
}

fn finite_non_negative(field: &str, value: f64) -> Result<(), SolverError> {
    if value >= 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(SolverError::invalid(field, value, "finite and ≥ 0"))
    }
}

/// s:s of the full 3D deviator whose in-plane block is `s` (see the module note).
pub fn full_contraction<const D: usize>(s: &SMatrix<f64, D, D>) -> f64 {
    let out_of_plane = 3 - D;
    let in_plane = s.norm_squared();
    if out_of_plane == 0 {
        in_plane
    } else {
        in_plane + s.trace().powi(2) / out_of_plane as f64
    }
}

/// The full 3D deviator whose in-plane block is `s`: each of the 3 − D out-of-plane normals is
/// −tr s/(3 − D) (see the module note).
pub fn full_deviator<const D: usize>(s: &SMatrix<f64, D, D>) -> Matrix3<f64> {
    let mut full = Matrix3::zeros();
    full.fixed_view_mut::<D, D>(0, 0).copy_from(s);
    for a in D..3 {
        full[(a, a)] = -s.trace() / (3 - D) as f64;
    }
    full
}

/// The largest principal value of the full 3D deviator whose in-plane block is `s`.
pub fn largest_principal_deviator<const D: usize>(s: &SMatrix<f64, D, D>) -> f64 {
    full_deviator(s).symmetric_eigenvalues().max()
}

/// An upper bound on [`largest_principal_deviator`] without the eigenvalues: a symmetric
/// tensor with trace t and s:s = S has λ₁ ≤ t/3 + √(2/3 (S − t²/3)) (equality when the other
/// two are equal), here ≤ |t|/3 + √(2S/3), raised by 1e-12 of it, far beyond the rounding of
/// either side. Where the bound decides a comparison, the eigenvalue decides it alike.
pub fn principal_deviator_bound<const D: usize>(s: &SMatrix<f64, D, D>) -> f64 {
    let full = full_deviator(s);
    (full.trace().abs() / 3.0 + (2.0 / 3.0 * full.norm_squared()).sqrt()) * (1.0 + 1e-12)
}

/// Von Mises equivalent stress √(3/2 s:s).
pub fn von_mises<const D: usize>(s: &SMatrix<f64, D, D>) -> f64 {
    (1.5 * full_contraction(s)).sqrt()
}

/// The Jaumann stress rate 2G (ε̇ − ⅓ tr ε̇ I) + Ω s − s Ω of the in-plane block, from the
/// velocity gradient L_ab = ∂v_a/∂x_b, where each of the 3 − D out-of-plane normal strain rates
/// is `out_of_plane_rate` (0 in uniaxial and plane strain, v_r/r in axisymmetric (r, z)) and so
/// enters the trace. The out-of-plane stresses follow from tr s = 0.
pub fn jaumann_rate<const D: usize>(
    shear_modulus: f64,
    s: &SMatrix<f64, D, D>,
    velocity_gradient: &SMatrix<f64, D, D>,
    out_of_plane_rate: f64,
) -> SMatrix<f64, D, D> {
    let strain_rate = 0.5 * (velocity_gradient + velocity_gradient.transpose());
    let spin = 0.5 * (velocity_gradient - velocity_gradient.transpose());
    let mean = (strain_rate.trace() + (3 - D) as f64 * out_of_plane_rate) / 3.0;
    let deviatoric = strain_rate - SMatrix::<f64, D, D>::identity() * mean;
    deviatoric * (2.0 * shear_modulus) + spin * s - s * spin
}

/// The equivalent strain rate √(2/3 ė':ė') of the full 3D rate whose in-plane block is
/// `strain_rate` and whose 3 − D out-of-plane normals are each `out_of_plane_rate`.
pub fn equivalent_strain_rate<const D: usize>(
    strain_rate: &SMatrix<f64, D, D>,
    out_of_plane_rate: f64,
) -> f64 {
    let out_of_plane = (3 - D) as f64;
    let mean = (strain_rate.trace() + out_of_plane * out_of_plane_rate) / 3.0;
    let in_plane = strain_rate - SMatrix::<f64, D, D>::identity() * mean;
    let normal = out_of_plane * (out_of_plane_rate - mean).powi(2);
    (2.0 / 3.0 * (in_plane.norm_squared() + normal)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix1, Matrix2, Matrix3};
    use proptest::prelude::*;

    /// A yield surface defined outside this module (here a constant limit, Tresca-like in
    /// spirit): `Strength::plastic` takes it, and the radial return lands on its limit.
    #[test]
    fn a_surface_defined_elsewhere_plugs_in() {
        #[derive(Debug)]
        struct Constant(f64);
        impl YieldSurface for Constant {
            fn limit(&self, _: &YieldState) -> f64 {
                self.0
            }
        }
        let strength = Strength::plastic(10e9, Constant(5e6)).unwrap();
        // uniaxial strain: σ_eq = 3/2 |s_xx|, so s_xx = 8 MPa is σ_eq = 12 MPa
        let mut s = Matrix1::new(8e6);
        let increment = strength.return_map(&mut s, &YieldState::default());
        assert!((von_mises(&s) - 5e6).abs() < 1e-6);
        // Δε_p = (σ_eq − Y)/(3G) with no hardening
        assert!((increment - 7e6 / 30e9).abs() < 1e-18);
        assert!(!strength.failed_in_tension(-1e9, &s));
        assert!(Strength::plastic(0.0, Constant(5e6)).is_err());
    }

    fn copper() -> Strength {
        Strength::new(43.3e9, 400e6, 100e6).unwrap()
    }

    /// Uniaxial strain in 1D: s_xx = 4/3 G ε and the transverse components −2/3 G ε, so
    /// σ_eq = 3/2 |s_xx| = 2G|ε|.
    #[test]
    fn uniaxial_strain_has_the_right_equivalent_stress() {
        let s = Matrix1::new(4.0 / 3.0 * 10.0);
        assert!((von_mises(&s) - 20.0).abs() < 1e-12);
        let rate = jaumann_rate(10.0, &Matrix1::zeros(), &Matrix1::new(1.0), 0.0);
        assert!((rate[0] - 40.0 / 3.0).abs() < 1e-12);
    }

    /// Plane strain pure shear ε_xy: σ_eq = √3 |s_xy|; and 3D agrees with the 2D form when
    /// the 3D tensor has the 2D block and s_zz = −tr.
    #[test]
    fn plane_strain_contraction_matches_the_full_tensor() {
        let s2 = Matrix2::new(3.0, 1.5, 1.5, -1.0);
        let s3 = Matrix3::new(3.0, 1.5, 0.0, 1.5, -1.0, 0.0, 0.0, 0.0, -2.0);
        assert!((full_contraction(&s2) - full_contraction(&s3)).abs() < 1e-12);
    }

    /// ΔT = χ w_p / c: 1 MJ/kg of plastic work heats copper (c = 383, χ = 0.9) by 2350 K;
    /// without heating data no temperature; bad heating data named.
    #[test]
    fn plastic_work_heats_by_the_taylor_quinney_share() {
        let heated = copper().with_heating(383.0, 0.9).unwrap();
        let rise = heated.temperature_rise(1e6).unwrap();
        assert!((rise - 0.9e6 / 383.0).abs() < 1e-9);
        assert!(copper().temperature_rise(1e6).is_none());
        let err = copper().with_heating(383.0, 1.5).unwrap_err().to_string();
        assert!(err.contains("Taylor-Quinney"), "{err}");
        let err = copper().with_heating(0.0, 0.9).unwrap_err().to_string();
        assert!(err.contains("specific heat"), "{err}");
    }

    /// Axisymmetric (r, z): the 2D block with the hoop rate as the out-of-plane normal gives
    /// the same stress rate and equivalent strain rate as the full 3D tensor diag-extended by
    /// ε̇_θθ (the 3D rate with no out-of-plane terms).
    #[test]
    fn hoop_rate_matches_the_full_tensor() {
        let l2 = Matrix2::new(0.4, -0.25, 0.7, -1.1);
        let hoop = 0.35;
        let l3 = Matrix3::new(0.4, -0.25, 0.0, 0.7, -1.1, 0.0, 0.0, 0.0, hoop);
        let s2 = Matrix2::new(2.0, 0.7, 0.7, -0.5);
        let s3 = Matrix3::new(2.0, 0.7, 0.0, 0.7, -0.5, 0.0, 0.0, 0.0, -1.5);
        let rate2 = jaumann_rate(30.0, &s2, &l2, hoop);
        let rate3 = jaumann_rate(30.0, &s3, &l3, 0.0);
        assert!((rate2 - rate3.fixed_view::<2, 2>(0, 0)).norm() < 1e-12);
        assert!((rate3[(2, 2)] + rate2.trace()).abs() < 1e-12);
        let d2 = 0.5 * (l2 + l2.transpose());
        let d3 = 0.5 * (l3 + l3.transpose());
        let equivalent = equivalent_strain_rate(&d2, hoop);
        assert!((equivalent - equivalent_strain_rate(&d3, 0.0)).abs() < 1e-12);
    }

    fn concrete() -> Strength {
        // C35/45: von Mises at f_ck = 35 MPa, f_ctm = 3.2 MPa (EN 1992-1-1 Table 3.1)
        Strength::new(14e9, 35e6, 0.0)
            .unwrap()
            .with_tensile_strength(3.2e6)
            .unwrap()
    }

    /// The largest principal deviatoric stress of an in-plane block is the closed form of a
    /// 2 × 2 block, (a + d)/2 + √(((a − d)/2)² + b²), or the out-of-plane normal −(a + d)
    /// where that is larger; in 1D the axial value or the transverse −s_xx/2.
    #[test]
    fn the_largest_principal_deviator_takes_the_out_of_plane_normals() {
        let (a, b, d): (f64, f64, f64) = (3.0, 1.5, -1.0);
        let closed = 0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b * b).sqrt();
        let s = Matrix2::new(a, b, b, d);
        assert!((largest_principal_deviator(&s) - closed).abs() < 1e-12);
        // both in-plane normals negative: the out-of-plane one is the largest
        let s = Matrix2::new(-2.0, 0.5, 0.5, -1.0);
        assert!((largest_principal_deviator(&s) - 3.0).abs() < 1e-12);
        assert!((largest_principal_deviator(&Matrix1::new(4.0)) - 4.0).abs() < 1e-12);
        assert!((largest_principal_deviator(&Matrix1::new(-4.0)) - 2.0).abs() < 1e-12);
    }

    /// The bound holds above the eigenvalue for random blocks in 1, 2 and 3 dimensions (3D ones
    /// with a trace, as round-off leaves a deviator), within 2e-12 of it (its margin and the
    /// rounding) where the other two principal values are equal, and is 0 for a zero stress.
    #[test]
    fn the_principal_deviator_bound_is_above_the_eigenvalue_and_tight() {
        let mut rng = crate::random::SplitMix64::new(11);
        let mut draw = || (rng.uniform() - 0.5) * 10f64.powf(12.0 * rng.uniform() - 2.0);
        for _ in 0..2000 {
            let s1 = Matrix1::new(draw());
            let (a, b, d) = (draw(), draw(), draw());
            let s2 = Matrix2::new(a, b, b, d);
            let (e, f, g) = (draw(), draw(), draw());
            let s3 = Matrix3::new(a, b, e, b, d, f, e, f, g);
            assert!(principal_deviator_bound(&s1) >= largest_principal_deviator(&s1));
            assert!(principal_deviator_bound(&s2) >= largest_principal_deviator(&s2));
            assert!(principal_deviator_bound(&s3) >= largest_principal_deviator(&s3));
        }
        // λ = (2, −1, −1) turned about z: the bound is the eigenvalue
        let (c, s) = (0.6_f64, 0.8_f64);
        let turned = Matrix2::new(
            2.0 * c * c - s * s,
            3.0 * c * s,
            3.0 * c * s,
            2.0 * s * s - c * c,
        );
        let bound = principal_deviator_bound(&turned);
        assert!(
            (bound / largest_principal_deviator(&turned) - 1.0).abs() < 2e-12,
            "{bound}"
        );
        assert_eq!(principal_deviator_bound(&Matrix2::zeros()), 0.0);
    }

    /// Rankine's cutoff: a trial stress whose largest principal value −p + s₁ exceeds f_t is
    /// scaled along its own deviator until it equals f_t (principal directions kept, no
    /// plastic strain, the particle cracked); a pressure that is alone a tension beyond f_t
    /// leaves no deviator; compression and stresses under f_t are untouched.
    #[test]
    fn a_brittle_solid_cracks_at_its_tensile_strength() {
        let solid = concrete();
        let at = |pressure: f64| YieldState {
            pressure,
            ..Default::default()
        };
        // plane strain, p = −1 MPa, s with principal values ±5 MPa in plane, 0 out of plane
        let trial = Matrix2::new(3e6, 4e6, 4e6, -3e6);
        let mut s = trial;
        assert_eq!(solid.return_map(&mut s, &at(-1e6)), 0.0);
        assert!((largest_principal_deviator(&s) + 1e6 - 3.2e6).abs() < 1e-6);
        assert!((s - trial * (2.2 / 5.0)).norm() < 1e-6);
        assert!(solid.failed_in_tension(-1e6, &s));
        // hydrostatic tension 4 MPa beyond f_t: nothing of the deviator is left
        let mut s = trial;
        solid.return_map(&mut s, &at(-4e6));
        assert_eq!(s, Matrix2::zeros());
        assert!(solid.failed_in_tension(-4e6, &s));
        // under a compression of 10 MPa the same deviator is elastic: σ₁ = −5 MPa
        let mut s = trial;
        assert_eq!(solid.return_map(&mut s, &at(10e6)), 0.0);
        assert_eq!(s, trial);
        assert!(!solid.failed_in_tension(10e6, &s));
        // plane strain s = diag(3, −3) MPa at p = 0: σ₁ = 3 MPa stays under f_t although the
        // quick bound √(2 s:s/3) = 3.46 MPa passes it, so the eigenvalue decides
        let under = Matrix2::new(3e6, 0.0, 0.0, -3e6);
        assert!(principal_deviator_bound(&under) > 3.2e6);
        let mut s = under;
        solid.return_map(&mut s, &at(0.0));
        assert_eq!(s, under);
        assert!(!solid.failed_in_tension(0.0, &s));
        // without a tensile strength the same tension is elastic
        let ductile = Strength::new(14e9, 35e6, 0.0).unwrap();
        let mut s = trial;
        ductile.return_map(&mut s, &at(-1e6));
        assert_eq!(s, trial);
        assert!(!ductile.failed_in_tension(-1e6, &s));
    }

    /// A tensile strength must be finite and positive, and Drucker–Prager keeps its own.
    #[test]
    fn a_tensile_strength_is_checked_by_name() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let err = copper().with_tensile_strength(bad).unwrap_err().to_string();
            assert!(err.contains("tensile strength"), "{err}");
        }
        let soil = Strength::drucker_prager(1e7, 0.0, 30.0, 0.0).unwrap();
        let err = soil.with_tensile_strength(1e3).unwrap_err().to_string();
        assert!(err.contains("Drucker-Prager"), "{err}");
    }

    /// A rigid rotation (no strain) leaves σ_eq unchanged: the Jaumann rate of a spin is
    /// tangent to the sphere s:s = const.
    #[test]
    fn a_spin_does_not_change_the_equivalent_stress() {
        let s = Matrix2::new(2.0, 0.7, 0.7, -2.0);
        let spin = Matrix2::new(0.0, 0.3, -0.3, 0.0);
        let rate = jaumann_rate(50.0, &s, &spin, 0.0);
        // d(s:s)/dt = 2 s:ṡ = 0
        assert!(s.component_mul(&rate).sum().abs() < 1e-12);
    }

    proptest! {
        /// After the return no state lies outside the (hardened) yield surface by more than
        /// 1e-12 relative, and the return is radial (direction kept).
        #[test]
        fn return_map_lands_on_the_yield_surface(
            a in -2e9f64..2e9, b in -2e9f64..2e9, c in -2e9f64..2e9, eps in 0.0f64..1.0
        ) {
            let strength = copper();
            let mut s = Matrix2::new(a, c, c, b);
            let before = s;
            let state = |eps: f64| YieldState { plastic_strain: eps, ..YieldState::default() };
            let increment = strength.return_map(&mut s, &state(eps));
            let limit = strength.current_yield(&state(eps + increment));
            prop_assert!(von_mises(&s) <= limit * (1.0 + 1e-12));
            if increment > 0.0 {
                prop_assert!((von_mises(&s) / limit - 1.0).abs() < 1e-12);
                let k = s[(0, 0)] / before[(0, 0)];
                prop_assert!((s - before * k).norm() <= 1e-9 * before.norm());
            } else {
                prop_assert_eq!(s, before);
            }
        }
    }

    /// Drucker–Prager: the limit grows with pressure at 6 sin φ/(3 − sin φ), equals
    /// 6c cos φ/(3 − sin φ) at p = 0, and is zero below the tension cutoff (failed).
    #[test]
    fn drucker_prager_limit_follows_the_mohr_coulomb_meridian() {
        let soil = Strength::drucker_prager(50e6, 10e3, 30.0, 1e3).unwrap();
        let (sin, cos) = 30f64.to_radians().sin_cos();
        let at = |p: f64| {
            soil.current_yield(&YieldState {
                pressure: p,
                ..YieldState::default()
            })
        };
        assert!((at(0.0) - 6.0 * 10e3 * cos / (3.0 - sin)).abs() < 1e-6);
        assert!(((at(2e5) - at(1e5)) / 1e5 - 6.0 * sin / (3.0 - sin)).abs() < 1e-12);
        assert_eq!(at(-2e3), 0.0);
        let s = Matrix2::zeros();
        assert!(soil.failed_in_tension(-2e3, &s) && !soil.failed_in_tension(-0.5e3, &s));
        // at the cutoff itself the soil keeps the cone's strength and has not failed; the next
        // pressure below it has neither
        assert!(at(-1e3) > 0.0 && !soil.failed_in_tension(-1e3, &s));
        let beyond = (-1e3f64).next_down();
        assert!(at(beyond) == 0.0 && soil.failed_in_tension(beyond, &s));
        let mut s = Matrix2::new(1e6, 0.0, 0.0, -1e6);
        soil.return_map(
            &mut s,
            &YieldState {
                pressure: -2e3,
                ..YieldState::default()
            },
        );
        assert_eq!(s, Matrix2::zeros());
        let mut s = Matrix2::new(1e6, 0.0, 0.0, -1e6);
        soil.return_map(
            &mut s,
            &YieldState {
                pressure: 1e5,
                ..YieldState::default()
            },
        );
        assert!((von_mises(&s) / at(1e5) - 1.0).abs() < 1e-12);
    }

    /// Numbers of the size of Johnson & Cook's OFHC copper (quoted from memory, not a
    /// reference: they only exercise the formula, whose factors are checked one at a time).
    fn copper_jc() -> JohnsonCook {
        JohnsonCook {
            a: 90e6,
            b: 292e6,
            n: 0.31,
            c: 0.025,
            m: 1.09,
            reference_rate: 1.0,
            room_temperature: 294.0,
            melt_temperature: 1356.0,
            specific_heat: 383.0,
            taylor_quinney: 0.9,
        }
    }

    #[test]
    fn johnson_cook_factors_act_one_at_a_time() {
        let jc = copper_jc();
        let strength = Strength::johnson_cook(46e9, jc).unwrap();
        let y = |state: YieldState| strength.current_yield(&state);
        let base = YieldState::default();
        assert!((y(base) - 90e6).abs() < 1e-6);
        let strained = YieldState {
            plastic_strain: 0.5,
            ..base
        };
        assert!((y(strained) - (90e6 + 292e6 * 0.5f64.powf(0.31))).abs() < 1e-3);
        let fast = YieldState {
            strain_rate: 1e4,
            ..base
        };
        assert!((y(fast) / 90e6 - (1.0 + 0.025 * 1e4f64.ln())).abs() < 1e-12);
        // the rate enters as ε̇/ε̇0: with ε̇0 = 1e-3 s⁻¹ the same rate is 1e7 reference rates
        // (to round-off, as above: the factor is 1.40)
        let per_millisecond = Strength::johnson_cook(
            46e9,
            JohnsonCook {
                reference_rate: 1e-3,
                ..jc
            },
        )
        .unwrap();
        let factor = per_millisecond.current_yield(&fast) / 90e6;
        assert!(
            (factor - (1.0 + 0.025 * 1e7f64.ln())).abs() < 1e-12,
            "{factor}"
        );
        // below the reference rate the rate factor stays 1
        assert_eq!(
            y(YieldState {
                strain_rate: 1e-3,
                ..base
            }),
            y(base)
        );
        // heating by plastic work: T − T0 = χ w_p / c_v; at the melting point no strength
        let half_way = (1356.0 - 294.0) / 2.0 * 383.0 / 0.9;
        let warm = YieldState {
            plastic_work: half_way,
            ..base
        };
        assert!((y(warm) / 90e6 - (1.0 - 0.5f64.powf(1.09))).abs() < 1e-12);
        let molten = YieldState {
            plastic_work: 4.0 * half_way,
            ..base
        };
        assert_eq!(y(molten), 0.0);
        let mut bad = jc;
        bad.melt_temperature = 200.0;
        let err = Strength::johnson_cook(46e9, bad).unwrap_err().to_string();
        assert!(err.contains("melt temperature"), "{err}");
    }

    /// Johnson–Cook reports the temperature rise χ w_p / c_v of its own parameters.
    #[test]
    fn johnson_cook_temperature_rise_is_the_taylor_quinney_share() {
        let strength = Strength::johnson_cook(46e9, copper_jc()).unwrap();
        let rise = strength.temperature_rise(1e5).unwrap();
        assert!((rise - 0.9 * 1e5 / 383.0).abs() < 1e-9, "{rise}");
    }

    /// A body spinning rigidly at ω (v = ω × x, so L = [[0, −ω], [ω, 0]]) carries its stress
    /// round with it: s(t) = R(ωt) s0 R(ωt)ᵀ, whose rate at t = 0 is, for s0 = diag(1, −1),
    /// [[0, 2ω], [2ω, 0]] (differentiating cos 2ωt and sin 2ωt). The sign of Ω s − s Ω is
    /// what turns the stress the right way.
    #[test]
    fn jaumann_rate_turns_the_stress_with_the_material() {
        let omega = 0.7;
        let l = Matrix2::new(0.0, -omega, omega, 0.0);
        let s = Matrix2::new(1.0, 0.0, 0.0, -1.0);
        let rate = jaumann_rate(50.0, &s, &l, 0.0);
        let rotated = |t: f64| {
            let (sin, cos) = (omega * t).sin_cos();
            let r = Matrix2::new(cos, -sin, sin, cos);
            r * s * r.transpose()
        };
        let dt = 1e-6;
        let finite_difference = (rotated(dt) - rotated(-dt)) / (2.0 * dt);
        assert!(
            (rate - finite_difference).norm() < 1e-8,
            "{rate} vs {finite_difference}"
        );
        assert!((rate - Matrix2::new(0.0, 2.0 * omega, 2.0 * omega, 0.0)).norm() < 1e-12);
    }

    /// √(2/3 ė':ė') of three textbook flows: incompressible uniaxial extension
    /// (ε̇, −ε̇/2, −ε̇/2) gives ε̇; simple shear at rate γ̇ (ε̇_xy = γ̇/2) gives γ̇/√3; plane
    /// strain compression (ε̇, −ε̇, 0) gives 2ε̇/√3, and so does its 2D block with no
    /// out-of-plane rate; uniaxial strain in 1D (ε̇, 0, 0) gives 2ε̇/3.
    #[test]
    fn equivalent_strain_rate_of_known_flows() {
        let rate = 3.0;
        let uniaxial = Matrix3::new(rate, 0.0, 0.0, 0.0, -rate / 2.0, 0.0, 0.0, 0.0, -rate / 2.0);
        assert!((equivalent_strain_rate(&uniaxial, 0.0) - rate).abs() < 1e-12);
        let shear = Matrix3::new(0.0, rate / 2.0, 0.0, rate / 2.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        assert!((equivalent_strain_rate(&shear, 0.0) - rate / 3f64.sqrt()).abs() < 1e-12);
        let plane = Matrix2::new(rate, 0.0, 0.0, -rate);
        assert!((equivalent_strain_rate(&plane, 0.0) - 2.0 * rate / 3f64.sqrt()).abs() < 1e-12);
        let line = Matrix1::new(rate);
        assert!((equivalent_strain_rate(&line, 0.0) - 2.0 * rate / 3.0).abs() < 1e-12);
    }

    /// The edges of the parameter ranges: ν = −1 and T_melt = T_room are refused; a
    /// cohesionless sand (c = 0, φ > 0, no tensile strength) is a valid soil.
    #[test]
    fn parameter_ranges_at_their_edges() {
        let err = Strength::elastic_moduli(117e9, -1.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("Poisson"), "{err}");
        assert!(Strength::elastic_moduli(117e9, -0.99).is_ok());
        let mut jc = copper_jc();
        jc.melt_temperature = jc.room_temperature;
        let err = Strength::johnson_cook(46e9, jc).unwrap_err().to_string();
        assert!(err.contains("melt temperature"), "{err}");
        let sand = Strength::drucker_prager(50e6, 0.0, 35.0, 0.0).unwrap();
        let at = |p: f64| {
            sand.current_yield(&YieldState {
                pressure: p,
                ..YieldState::default()
            })
        };
        assert_eq!(at(0.0), 0.0);
        assert!(at(1e5) > 0.0);
    }

    #[test]
    fn bad_soil_parameters_are_rejected_by_name() {
        let err = |r: Result<Strength, SolverError>| r.unwrap_err().to_string();
        assert!(err(Strength::drucker_prager(1e6, -1.0, 30.0, 0.0)).contains("cohesion"));
        assert!(err(Strength::drucker_prager(1e6, 1e3, 75.0, 0.0)).contains("friction angle"));
        assert!(err(Strength::drucker_prager(1e6, 1e3, 30.0, 1e4)).contains("tensile strength"));
        assert!(err(Strength::drucker_prager(1e6, 0.0, 0.0, 0.0)).contains("not both zero"));
    }

    #[test]
    fn bad_moduli_are_rejected_by_name() {
        assert!(Strength::new(-1.0, 1.0, 0.0)
            .unwrap_err()
            .to_string()
            .contains("shear modulus"));
        assert!(Strength::new(1.0, 0.0, 0.0)
            .unwrap_err()
            .to_string()
            .contains("yield stress"));
        for hardening in [-1.0, f64::NAN, f64::INFINITY] {
            let err = Strength::new(1.0, 1.0, hardening).unwrap_err().to_string();
            assert!(err.contains("hardening modulus"), "H = {hardening}: {err}");
        }
        let mut jc = copper_jc();
        jc.b = -1.0;
        let err = Strength::johnson_cook(46e9, jc).unwrap_err().to_string();
        assert!(err.contains("Johnson-Cook B"), "{err}");
        let mut jc = copper_jc();
        jc.c = f64::NAN;
        let err = Strength::johnson_cook(46e9, jc).unwrap_err().to_string();
        assert!(err.contains("Johnson-Cook C"), "{err}");
        let err = Strength::elastic_moduli(117e9, 0.5)
            .unwrap_err()
            .to_string();
        assert!(err.contains("Poisson") && err.contains("0.5"), "{err}");
        for young in [0.0, -117e9, f64::INFINITY, f64::NAN] {
            let err = Strength::elastic_moduli(young, 0.35)
                .unwrap_err()
                .to_string();
            assert!(err.contains("Young's modulus"), "E = {young}: {err}");
        }
        let (g, k) = Strength::elastic_moduli(117e9, 0.35).unwrap();
        assert!((g - 43.333e9).abs() < 1e7 && (k - 130e9).abs() < 1e7);
    }
}
