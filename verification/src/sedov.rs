//! Exact Sedov–Taylor point-blast solution for a uniform ideal-gas background, in planar,
//! cylindrical and spherical geometry and for any γ, after Kamm & Timmes (2007), "On efficient
//! generation of numerically robust Sedov solutions", LA-UR-07-2849 (the standard case ω = 0).
//!
//! The self-similar profiles are parametrised by V ∈ (V0, V2] between the centre and the shock:
//! with x1 = aV, x2 = b(cV − 1), x3 = d(1 − eV), x4 = b(1 − cV/γ),
//! λ = r/R = x1^−α0 x2^−α2 x3^−α1, u/u2 = x1 λ, ρ/ρ2 = x2^α3 x3^α4 x4^α5,
//! p/p2 = x1^(α0 j) x3^(α4 − 2α1) x4^(1 + α5).
//! The energy integral α (E = α ρ0 R^(j+2)/t²) is their quadrature; the shock radius is
//! R = ξ0 (E t²/ρ0)^(1/(j+2)) with ξ0 = α^(−1/(j+2)).

use crate::VerifyError;
pub use blastsph_solver::Geometry;
use serde::Serialize;
use std::f64::consts::PI;

/// j = 1, 2, 3: the power of r in the volume element, dV ∝ r^(j−1) dr.
fn index(geometry: Geometry) -> f64 {
    match geometry {
        Geometry::Planar => 1.0,
        Geometry::Cylindrical => 2.0,
        Geometry::Spherical => 3.0,
    }
}

/// Measure of the unit "sphere": dV = A r^(j−1) dr. Planar: A = 1, the energy per unit area on
/// one side of the symmetry plane (Kamm & Timmes' convention; their planar α = 0.5385 for
/// γ = 1.4 is the one-sided integral).
fn area_factor(geometry: Geometry) -> f64 {
    match geometry {
        Geometry::Planar => 1.0,
        Geometry::Cylindrical => 2.0 * PI,
        Geometry::Spherical => 4.0 * PI,
    }
}

/// The geometry called `name` (planar, cylindrical, spherical).
pub fn geometry_named(name: &str) -> Option<Geometry> {
    Geometry::ALL.into_iter().find(|g| g.name() == name)
}

fn serialize_geometry<S: serde::Serializer>(g: &Geometry, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(g.name())
}

/// The similarity solution of one geometry and γ (independent of E, ρ0, t).
#[derive(Clone, Copy, Debug)]
pub struct Similarity {
    geometry: Geometry,
    gamma: f64,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    e: f64,
    alpha0: f64,
    alpha1: f64,
    alpha2: f64,
    alpha3: f64,
    alpha4: f64,
    alpha5: f64,
    /// V at the centre (λ → 0) and behind the shock (λ = 1).
    v0: f64,
    v2: f64,
    /// The energy integral α.
    pub energy_integral: f64,
}

/// Dimensionless profile at one point: λ = r/R and the ratios to the post-shock state.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ProfilePoint {
    lambda: f64,
    velocity: f64,
    density: f64,
    pressure: f64,
}

/// Quadrature points for α: the midpoint rule in s with V − V0 ∝ s^(1/|α2|), which makes λ
/// nearly linear in s; 20 000 points give α to ~1e-8.
const QUADRATURE_POINTS: usize = 20_000;

impl Similarity {
    pub fn new(geometry: Geometry, gamma: f64) -> Result<Self, VerifyError> {
        if !(gamma > 1.0 && gamma < 7.0) {
            return Err(VerifyError::bad_value(
                "gamma",
                gamma,
                "1 < γ < 7 (the standard Sedov case)",
            ));
        }
        let j = index(geometry);
        let g = gamma;
        let j2 = j + 2.0;
        let a = j2 * (g + 1.0) / 4.0;
        let b = (g + 1.0) / (g - 1.0);
        let c = j2 * g / 2.0;
        let d = j2 * (g + 1.0) / (j2 * (g + 1.0) - 2.0 * (2.0 + j * (g - 1.0)));
        let e = (2.0 + j * (g - 1.0)) / 2.0;
        let alpha0 = 2.0 / j2;
        let alpha2 = -(g - 1.0) / (2.0 * (g - 1.0) + j);
        let alpha1 =
            j2 * g / (2.0 + j * (g - 1.0)) * (2.0 * j * (2.0 - g) / (g * j2 * j2) - alpha2);
        let alpha3 = j / (2.0 * (g - 1.0) + j);
        let alpha4 = j2 * j * alpha1 / (j * (2.0 - g));
        let alpha5 = -2.0 * j / (j * (2.0 - g));
        let mut s = Self {
            geometry,
            gamma,
            a,
            b,
            c,
            d,
            e,
            alpha0,
            alpha1,
            alpha2,
            alpha3,
            alpha4,
            alpha5,
            v0: 2.0 / (j2 * g),
            v2: 4.0 / (j2 * (g + 1.0)),
            energy_integral: 0.0,
        };
        s.energy_integral = s.energy_quadrature();
        Ok(s)
    }

    fn at(&self, v: f64) -> ProfilePoint {
        let g = self.gamma;
        let j = index(self.geometry);
        let x1 = self.a * v;
        let x2 = self.b * (self.c * v - 1.0);
        let x3 = self.d * (1.0 - self.e * v);
        let x4 = self.b * (1.0 - self.c * v / g);
        let lambda = x1.powf(-self.alpha0) * x2.powf(-self.alpha2) * x3.powf(-self.alpha1);
        ProfilePoint {
            lambda,
            velocity: x1 * lambda,
            density: x2.powf(self.alpha3) * x3.powf(self.alpha4) * x4.powf(self.alpha5),
            pressure: x1.powf(self.alpha0 * j)
                * x3.powf(self.alpha4 - 2.0 * self.alpha1)
                * x4.powf(1.0 + self.alpha5),
        }
    }

    /// V at fraction s ∈ [0, 1] of the way from the centre to the shock.
    fn v_of(&self, s: f64) -> f64 {
        self.v0 + (self.v2 - self.v0) * s.powf(1.0 / self.alpha2.abs())
    }

    /// α = E t²/(ρ0 R^(j+2)) = A ∫0^1 [ρ̂ û²/2 + p̂/(γ−1)] λ^(j−1) dλ with ρ̂ = ρ/ρ0, û = u t/R,
    /// p̂ = p t²/(ρ0 R²), from the post-shock state ρ2 = bρ0, u2 = 4R/((j+2)(γ+1)t),
    /// p2 = 2ρ0 (2R/((j+2)t))²/(γ+1).
    fn energy_quadrature(&self) -> f64 {
        let (g, j) = (self.gamma, index(self.geometry));
        let shock_speed = 2.0 / (j + 2.0);
        let (rho2, u2, p2) = (
            self.b,
            2.0 / (g + 1.0) * shock_speed,
            2.0 / (g + 1.0) * shock_speed * shock_speed,
        );
        let integrand = |p: &ProfilePoint| {
            (0.5 * rho2 * p.density * (u2 * p.velocity).powi(2) + p2 * p.pressure / (g - 1.0))
                * p.lambda.powf(j - 1.0)
        };
        let n = QUADRATURE_POINTS;
        let mut previous = ProfilePoint {
            lambda: 0.0,
            ..self.at(self.v_of(1e-12))
        };
        let mut sum = 0.0;
        for k in 1..=n {
            let point = self.at(self.v_of(k as f64 / n as f64));
            sum +=
                0.5 * (integrand(&previous) + integrand(&point)) * (point.lambda - previous.lambda);
            previous = point;
        }
        area_factor(self.geometry) * sum
    }

    /// The profile at λ = r/R ∈ [0, 1] (bisection on V, monotone in λ).
    fn at_lambda(&self, lambda: f64) -> ProfilePoint {
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if self.at(self.v_of(mid)).lambda < lambda {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        self.at(self.v_of(0.5 * (lo + hi)))
    }
}

/// A dimensional Sedov blast: energy E into uniform density ρ0 at t = 0, seen at time t.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SedovBlast {
    #[serde(serialize_with = "serialize_geometry")]
    pub geometry: Geometry,
    pub gamma: f64,
    pub energy: f64,
    pub rho0: f64,
    pub time: f64,
    /// The similarity constant ξ0: R = ξ0 (E t²/ρ0)^(1/(j+2)).
    pub xi0: f64,
    pub energy_integral: f64,
    pub r_shock: f64,
    pub rho2: f64,
    pub u2: f64,
    pub p2: f64,
    pub e2: f64,
    #[serde(skip)]
    similarity: Similarity,
}

/// A state (ρ, u, p) of the blast at one radius.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BlastState {
    pub rho: f64,
    pub u: f64,
    pub p: f64,
}

impl SedovBlast {
    pub fn new(
        geometry: Geometry,
        gamma: f64,
        energy: f64,
        rho0: f64,
        time: f64,
    ) -> Result<Self, VerifyError> {
        for (field, value) in [("energy", energy), ("rho0", rho0), ("time", time)] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(VerifyError::bad_value(field, value, "finite and > 0"));
            }
        }
        let similarity = Similarity::new(geometry, gamma)?;
        let j = index(geometry);
        let alpha = similarity.energy_integral;
        let xi0 = alpha.powf(-1.0 / (j + 2.0));
        let r_shock = xi0 * (energy * time * time / rho0).powf(1.0 / (j + 2.0));
        let shock_speed = 2.0 * r_shock / ((j + 2.0) * time);
        let rho2 = rho0 * (gamma + 1.0) / (gamma - 1.0);
        let u2 = 2.0 / (gamma + 1.0) * shock_speed;
        let p2 = 2.0 / (gamma + 1.0) * rho0 * shock_speed * shock_speed;
        Ok(Self {
            geometry,
            gamma,
            energy,
            rho0,
            time,
            xi0,
            energy_integral: alpha,
            r_shock,
            rho2,
            u2,
            p2,
            e2: p2 / ((gamma - 1.0) * rho2),
            similarity,
        })
    }

    /// The exact state at radius r (the undisturbed gas, at zero pressure, beyond the shock).
    pub fn state_at(&self, r: f64) -> BlastState {
        let lambda = r.abs() / self.r_shock;
        if lambda > 1.0 {
            return BlastState {
                rho: self.rho0,
                u: 0.0,
                p: 0.0,
            };
        }
        let point = self.similarity.at_lambda(lambda);
        BlastState {
            rho: self.rho2 * point.density,
            u: self.u2 * point.velocity * r.signum(),
            p: self.p2 * point.pressure,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kamm & Timmes (2007) standard cases (γ = 1.4, ρ0 = 1, t = 1), as copied in
    /// `reference_data/sedov_standard_cases_gamma1.4.csv`: E0 gives r2 = 0.5, 0.75, 1.0.
    /// The post-shock values follow from r2 by the jump conditions and are checked to their
    /// printed digits (1e-5). The radius r2 ∝ α^(−1/(j+2)) carries the energy integral: ours
    /// gives r2 = 1.0000, 0.74999, 0.49994; the same formulas integrated by SciPy's adaptive
    /// quadrature give the same α (0.851072, 0.984074, 0.538743), so the table's planar E0 (and,
    /// by 3e-5, its cylindrical one) were computed with a less accurate α. The limit, 2e-4 on r2
    /// (6e-4 on α), covers that and still catches any error in an exponent or a constant.
    #[test]
    fn standard_cases_match_kamm_and_timmes() {
        let table = include_str!("../../reference_data/sedov_standard_cases_gamma1.4.csv");
        let mut rows = 0;
        for line in table
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("geometry"))
        {
            let f: Vec<&str> = line.split(',').collect();
            let geometry = geometry_named(f[0]).unwrap();
            let v: Vec<f64> = f[1..].iter().map(|x| x.parse().unwrap()).collect();
            let blast = SedovBlast::new(geometry, 1.4, v[0], 1.0, 1.0).unwrap();
            assert!(
                (blast.r_shock / v[1] - 1.0).abs() < 2e-4,
                "{line}: r2 = {}",
                blast.r_shock
            );
            // the jump conditions at the table's r2
            let at_table = SedovBlast::new(
                geometry,
                1.4,
                blast.energy_integral * v[1].powf(index(geometry) + 2.0),
                1.0,
                1.0,
            )
            .unwrap();
            assert!((at_table.rho2 - v[2]).abs() < 1e-9);
            for (value, printed) in [
                (at_table.u2, v[3]),
                (at_table.e2, v[4]),
                (at_table.p2, v[5]),
            ] {
                assert!(
                    (value / printed - 1.0).abs() < 1e-5,
                    "{line}: {value} vs {printed}"
                );
            }
            rows += 1;
        }
        assert_eq!(rows, 3);
    }

    /// The profile joins the post-shock state at the shock and conserves the energy it was
    /// built from: integrating the sampled profile at λ gives E back (1e-4: trapezoid on 4000
    /// points in r against the finer quadrature in V).
    #[test]
    fn profile_meets_the_shock_and_holds_the_energy() {
        for geometry in [Geometry::Planar, Geometry::Cylindrical, Geometry::Spherical] {
            let blast = SedovBlast::new(geometry, 5.0 / 3.0, 1.0, 1.0, 0.1).unwrap();
            let behind = blast.state_at(blast.r_shock * (1.0 - 1e-9));
            assert!((behind.rho / blast.rho2 - 1.0).abs() < 1e-6);
            assert!((behind.p / blast.p2 - 1.0).abs() < 1e-6);
            let n = 4000;
            let dr = blast.r_shock / n as f64;
            let j = index(geometry);
            let energy: f64 = (0..n)
                .map(|k| {
                    let r = (k as f64 + 0.5) * dr;
                    let s = blast.state_at(r);
                    (0.5 * s.rho * s.u * s.u + s.p / (blast.gamma - 1.0))
                        * area_factor(geometry)
                        * r.powf(j - 1.0)
                        * dr
                })
                .sum();
            assert!((energy - 1.0).abs() < 1e-3, "{geometry:?}: {energy}");
        }
    }

    #[test]
    fn bad_input_is_named() {
        let err = SedovBlast::new(Geometry::Spherical, 1.4, -1.0, 1.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("energy"));
        let err = SedovBlast::new(Geometry::Spherical, 1.0, 1.0, 1.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("gamma"));
    }
}
