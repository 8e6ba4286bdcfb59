//! The formulation of a scene: its coordinates, how density and smoothing lengths are found,
//! and how solids are discretised, as one type whose variants are exactly the combinations the
//! solver implements (grad-h exists only with summation density, an axisymmetric scene only
//! with continuity density, a radial one with summation or continuity density and a plain h
//! rule).
//! What a type cannot say, the dimension a formulation needs, is checked when the simulation
//! is built, naming the field.

use crate::error::SolverError;
use crate::neighbours::PairReach;
use crate::physics::PairKernel;
use crate::radial::Geometry;

/// How each particle's smoothing length follows the flow, where it is not solved with the
/// density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SmoothingLength {
    /// h stays as given.
    Fixed,
    /// h_i = η (m_i/ρ_i)^{1/D} from the latest density, before each neighbour search. Each
    /// pair uses W(r, h̄_ij); energy is conserved up to the change of h between steps.
    FollowDensity { eta: f64 },
    /// h_i = max(η (m_i/ρ_i)^{1/D}, h_i⁰): as `FollowDensity`, but never below the particle's
    /// initial h. Lagrangian shells that a blast sweeps up thin without bound (air next to a
    /// charge ends as a sheet thinner by (r₀/r)² times its compression), and their h would set
    /// a time step hundreds of times shorter than the flow needs; with the floor they keep the
    /// kernel width they started with and gain neighbours instead. Meant with continuity
    /// density, whose density does not depend on h.
    FollowDensityFloored { eta: f64 },
}

impl SmoothingLength {
    pub fn name(self) -> &'static str {
        match self {
            SmoothingLength::Fixed => "fixed",
            SmoothingLength::FollowDensity { .. } => "follow-density",
            SmoothingLength::FollowDensityFloored { .. } => "follow-density-floored",
        }
    }

    fn with_eta(self, eta: f64) -> Self {
        match self {
            SmoothingLength::Fixed => SmoothingLength::Fixed,
            SmoothingLength::FollowDensity { .. } => SmoothingLength::FollowDensity { eta },
            SmoothingLength::FollowDensityFloored { .. } => {
                SmoothingLength::FollowDensityFloored { eta }
            }
        }
    }
}

/// How density, and with it the smoothing length, is obtained in a Cartesian scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Density {
    /// ρ_i = Σ_j m_j W_ij (self term included): exact mass conservation, smooths contact jumps.
    Summation(SmoothingLength),
    /// Grad-h SPH: h_i = η (m_i/ρ_i)^{1/D} and ρ_i = Σ_j m_j W(r_ij, h_i) solved together by
    /// Newton–Raphson until a step changes h by less than `tolerance`·h, with the Ω terms in
    /// momentum and energy (Springel & Hernquist 2002; Price 2012), so that total energy is
    /// conserved to the integrator's accuracy.
    GradH { eta: f64, tolerance: f64 },
    /// Dρ_i/Dt = ρ_i Σ_j (m_j/ρ_j) v_ij · ∇_i W_ij: keeps density jumps sharp (the seed
    /// recommends it for strong discontinuities); the initial density is the prescribed one.
    /// The velocity divergence is weighted by the neighbours' volumes m_j/ρ_j rather than by
    /// m_j/ρ_i (the seed's Σ m_j v_ij·∇W form): across a material interface, where neighbours
    /// of equal size differ in mass by the density ratio, only the volume weights estimate
    /// ∇·v consistently (Monaghan 1992 §2; Colagrossi & Landrini 2003 for density ratios of
    /// 1000). In a single material with a smooth density both forms agree to O(h²).
    Continuity(SmoothingLength),
}

/// The default grad-h tolerance: the Ω terms assume h and ρ agree exactly, and a relative
/// mismatch δ shows up as an energy error of order δ per step; 1e-6 keeps that below the
/// integrator's error at a cost of one or two extra density passes.
pub const GRAD_H_TOLERANCE: f64 = 1e-6;

/// The allowed range of η = h/(m/ρ)^{1/D}: from under one neighbour spacing to four.
pub const ETA_RANGE: (f64, f64) = (0.5, 4.0);

impl Density {
    /// The names the command line and the reports use for the density method.
    pub const METHODS: [&'static str; 2] = ["summation", "continuity"];
    /// The names of the ways h is found.
    pub const SMOOTHING: [&'static str; 4] = [
        "fixed",
        "follow-density",
        "follow-density-floored",
        "grad-h",
    ];

    /// The density method and h rule named by `method` (one of [`Density::METHODS`]) and
    /// `smoothing` (one of [`Density::SMOOTHING`]), with η where h follows the density and
    /// the default grad-h tolerance.
    pub fn from_names(method: &str, smoothing: &str, eta: f64) -> Result<Self, SolverError> {
        let rule = match smoothing {
            "fixed" => SmoothingLength::Fixed,
            "follow-density" => SmoothingLength::FollowDensity { eta },
            "follow-density-floored" => SmoothingLength::FollowDensityFloored { eta },
            "grad-h" if method == "summation" => {
                return Ok(Density::GradH {
                    eta,
                    tolerance: GRAD_H_TOLERANCE,
                })
            }
            "grad-h" => {
                return Err(SolverError::invalid(
                    "density",
                    method,
                    "summation (grad-h solves h with the summation density)",
                ))
            }
            other => {
                return Err(SolverError::invalid(
                    "smoothing",
                    other,
                    &Self::SMOOTHING.join(", "),
                ))
            }
        };
        match method {
            "summation" => Ok(Density::Summation(rule)),
            "continuity" => Ok(Density::Continuity(rule)),
            other => Err(SolverError::invalid(
                "density",
                other,
                &Self::METHODS.join(", "),
            )),
        }
    }

    /// "summation", "continuity".
    pub fn method_name(self) -> &'static str {
        match self {
            Density::Summation(_) | Density::GradH { .. } => "summation",
            Density::Continuity(_) => "continuity",
        }
    }

    /// "fixed", "follow-density", "grad-h".
    pub fn smoothing_name(self) -> &'static str {
        match self {
            Density::Summation(rule) | Density::Continuity(rule) => rule.name(),
            Density::GradH { .. } => "grad-h",
        }
    }

    /// The same method with η replaced, where h follows the density.
    pub fn with_eta(self, eta: f64) -> Self {
        match self {
            Density::Summation(rule) => Density::Summation(rule.with_eta(eta)),
            Density::Continuity(rule) => Density::Continuity(rule.with_eta(eta)),
            Density::GradH { tolerance, .. } => Density::GradH { eta, tolerance },
        }
    }
}

/// How a radial scene (rings or shells, see [`crate::radial`]) finds its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShellDensity {
    /// ρ_i = m_i W̃(r_i, r_i; h_i) + Σ_j m_j W̃(r_i, r_j; h̄_ij), the ring- or shell-averaged
    /// kernel's sum: the Lagrangian the radial equations come from.
    Summation(SmoothingLength),
    /// Dρ_i/Dt = ρ_i [Σ_j V_j (v_i ∂W̃_ij/∂r_i + v_j ∂W̃_ij/∂r_j) + V_i v_i dW̃_ii/dr] with the
    /// volumes V = m/ρ: the rate of the summation with the masses replaced by ρ_i V_j, which
    /// keeps a contact of very different densities (a charge in air) sharp, as
    /// [`Density::Continuity`] does in Cartesian coordinates. The initial density is the
    /// prescribed one.
    Continuity(SmoothingLength),
}

impl ShellDensity {
    pub fn rule(self) -> SmoothingLength {
        match self {
            ShellDensity::Summation(rule) | ShellDensity::Continuity(rule) => rule,
        }
    }

    /// "summation", "continuity".
    pub fn method_name(self) -> &'static str {
        match self {
            ShellDensity::Summation(_) => "summation",
            ShellDensity::Continuity(_) => "continuity",
        }
    }

    /// The radial counterpart of a Cartesian density method; grad-h has none.
    pub fn from_density(density: Density) -> Result<Self, SolverError> {
        match density {
            Density::Summation(rule) => Ok(ShellDensity::Summation(rule)),
            Density::Continuity(rule) => Ok(ShellDensity::Continuity(rule)),
            Density::GradH { .. } => Err(SolverError::invalid(
                "smoothing",
                "grad-h",
                "fixed or follow-density in a radial geometry",
            )),
        }
    }
}

/// The formulation of a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Formulation {
    /// Cartesian coordinates in D dimensions, the kernel moving with the particles (solids
    /// then need the artificial stress where they stretch).
    Cartesian(Density),
    /// D = 2: x is the distance r from an axis of symmetry and y is z; each particle is a ring
    /// whose mass is the particle's (see [`crate::axisymmetric`]); continuity density (summed
    /// ring masses smear η near the axis). Needs a wall at r = 0 (the axis).
    Axisymmetric(SmoothingLength),
    /// D = 1 in the distance from an axis, masses per unit length, the ring-averaged kernel
    /// (see [`crate::radial`]); fluids only.
    Cylindrical(ShellDensity),
    /// D = 1 in the distance from a point, masses of whole shells; as `Cylindrical`.
    Spherical(ShellDensity),
    /// Solids only, the kernel in the reference configuration (see
    /// [`crate::total_lagrangian`]), with the hourglass control coefficient κ; density
    /// ρ0/det F and h from the deformation.
    TotalLagrangian { hourglass: f64 },
}

impl Formulation {
    /// The symmetry of the scene: planar, or 1D cylindrical or spherical.
    pub fn geometry(self) -> Geometry {
        match self {
            Formulation::Cylindrical(_) => Geometry::Cylindrical,
            Formulation::Spherical(_) => Geometry::Spherical,
            _ => Geometry::Planar,
        }
    }

    pub fn is_axisymmetric(self) -> bool {
        matches!(self, Formulation::Axisymmetric(_))
    }

    pub fn is_total_lagrangian(self) -> bool {
        matches!(self, Formulation::TotalLagrangian { .. })
    }

    /// The dimension the formulation needs, where it needs one.
    pub fn dimension(self) -> Option<usize> {
        match self {
            Formulation::Axisymmetric(_) => Some(2),
            Formulation::Cylindrical(_) | Formulation::Spherical(_) => Some(1),
            _ => None,
        }
    }

    /// Density integrated by the continuity equation (the particles carry Dρ/Dt).
    pub fn integrates_density(self) -> bool {
        matches!(
            self,
            Formulation::Cartesian(Density::Continuity(_))
                | Formulation::Axisymmetric(_)
                | Formulation::Cylindrical(ShellDensity::Continuity(_))
                | Formulation::Spherical(ShellDensity::Continuity(_))
        )
    }

    /// Density summed over the neighbours each step, with h found before the sum.
    pub fn sums_density(self) -> bool {
        matches!(
            self,
            Formulation::Cartesian(Density::Summation(_))
                | Formulation::Cylindrical(ShellDensity::Summation(_))
                | Formulation::Spherical(ShellDensity::Summation(_))
        )
    }

    /// η and the tolerance, where h is solved with the density (grad-h).
    pub fn grad_h(self) -> Option<(f64, f64)> {
        match self {
            Formulation::Cartesian(Density::GradH { eta, tolerance }) => Some((eta, tolerance)),
            _ => None,
        }
    }

    /// The h rule, where h is not solved with the density nor set by the deformation.
    pub fn smoothing(self) -> Option<SmoothingLength> {
        match self {
            Formulation::Cartesian(Density::Summation(rule) | Density::Continuity(rule))
            | Formulation::Axisymmetric(rule) => Some(rule),
            Formulation::Cylindrical(density) | Formulation::Spherical(density) => {
                Some(density.rule())
            }
            _ => None,
        }
    }

    /// η, where h follows or is solved with the density.
    pub fn eta(self) -> Option<f64> {
        match (self.grad_h(), self.smoothing()) {
            (Some((eta, _)), _)
            | (
                _,
                Some(
                    SmoothingLength::FollowDensity { eta }
                    | SmoothingLength::FollowDensityFloored { eta },
                ),
            ) => Some(eta),
            _ => None,
        }
    }

    /// "summation", "continuity" (total-Lagrangian: "reference").
    pub fn density_name(self) -> &'static str {
        match self {
            Formulation::Cartesian(density) => density.method_name(),
            Formulation::Axisymmetric(_) => "continuity",
            Formulation::Cylindrical(density) | Formulation::Spherical(density) => {
                density.method_name()
            }
            Formulation::TotalLagrangian { .. } => "reference",
        }
    }

    /// "fixed", "follow-density", "grad-h" ("deformation" for total-Lagrangian solids).
    pub fn smoothing_name(self) -> &'static str {
        match self {
            Formulation::Cartesian(density) => density.smoothing_name(),
            Formulation::TotalLagrangian { .. } => "deformation",
            _ => self.smoothing().map_or("fixed", SmoothingLength::name),
        }
    }

    /// How solids are discretised: "updated" (the kernel moves with the particles) or
    /// "total-lagrangian".
    pub fn solids_name(self) -> &'static str {
        if self.is_total_lagrangian() {
            "total-lagrangian"
        } else {
            "updated"
        }
    }

    /// Which kernel a pair uses: each side its own h with grad-h, the mean h otherwise.
    pub(crate) fn pair_kernel(self) -> PairKernel {
        match self.grad_h() {
            Some(_) => PairKernel::OwnH,
            None => PairKernel::MeanH,
        }
    }

    /// How far the neighbour search reaches for a pair.
    pub(crate) fn pair_reach(self) -> PairReach {
        match self.grad_h() {
            Some(_) => PairReach::LargerH,
            None => PairReach::MeanH,
        }
    }

    /// η within [`ETA_RANGE`], the grad-h tolerance within (0, 1e-2], κ within [0, 100].
    pub fn validate(self) -> Result<(), SolverError> {
        if let Some(eta) = self.eta() {
            let (lo, hi) = ETA_RANGE;
            if !(lo..=hi).contains(&eta) {
                return Err(SolverError::invalid(
                    "eta",
                    eta,
                    &format!("{lo} ≤ η ≤ {hi}"),
                ));
            }
        }
        if let Some((_, tolerance)) = self.grad_h() {
            if !(tolerance > 0.0 && tolerance <= 1e-2) {
                return Err(SolverError::invalid(
                    "grad-h tolerance",
                    tolerance,
                    "0 < tolerance ≤ 1e-2",
                ));
            }
        }
        if let Formulation::TotalLagrangian { hourglass } = self {
            if !(0.0..=100.0).contains(&hourglass) {
                return Err(SolverError::invalid(
                    "hourglass coefficient",
                    hourglass,
                    "0 ≤ κ ≤ 100",
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_compose_and_grad_h_needs_summation() {
        for method in Density::METHODS {
            for smoothing in Density::SMOOTHING {
                match Density::from_names(method, smoothing, 1.2) {
                    Ok(density) => {
                        assert_eq!(density.method_name(), method);
                        assert_eq!(density.smoothing_name(), smoothing);
                    }
                    Err(error) => {
                        assert_eq!((method, smoothing), ("continuity", "grad-h"));
                        assert!(error.to_string().contains("density"), "{error}");
                    }
                }
            }
        }
        let error = Density::from_names("summation", "adaptive", 1.2).unwrap_err();
        assert!(error.to_string().contains("smoothing"), "{error}");
    }

    const FOLLOW: SmoothingLength = SmoothingLength::FollowDensity { eta: 1.2 };

    /// What the records print for each formulation, the η each one carries and how each finds
    /// its density.
    #[test]
    fn names_and_eta_of_every_formulation() {
        let cases = [
            (
                Formulation::Cartesian(Density::Summation(FOLLOW)),
                "summation",
                "follow-density",
                "updated",
                Some(1.2),
            ),
            (
                Formulation::Cartesian(Density::GradH {
                    eta: 1.3,
                    tolerance: 1e-6,
                }),
                "summation",
                "grad-h",
                "updated",
                Some(1.3),
            ),
            (
                Formulation::Cartesian(Density::Continuity(SmoothingLength::Fixed)),
                "continuity",
                "fixed",
                "updated",
                None,
            ),
            (
                Formulation::Axisymmetric(FOLLOW),
                "continuity",
                "follow-density",
                "updated",
                Some(1.2),
            ),
            (
                Formulation::Spherical(ShellDensity::Summation(SmoothingLength::Fixed)),
                "summation",
                "fixed",
                "updated",
                None,
            ),
            (
                Formulation::Cylindrical(ShellDensity::Continuity(FOLLOW)),
                "continuity",
                "follow-density",
                "updated",
                Some(1.2),
            ),
            (
                Formulation::TotalLagrangian { hourglass: 0.1 },
                "reference",
                "deformation",
                "total-lagrangian",
                None,
            ),
        ];
        for (formulation, density, smoothing, solids, eta) in cases {
            assert_eq!(formulation.density_name(), density, "{formulation:?}");
            assert_eq!(formulation.smoothing_name(), smoothing, "{formulation:?}");
            assert_eq!(formulation.solids_name(), solids, "{formulation:?}");
            assert_eq!(formulation.eta(), eta, "{formulation:?}");
            // one way to the density: the continuity equation, a sum at a known h, grad-h's
            // sum solved with h, or the deformation gradient
            assert_eq!(
                formulation.integrates_density(),
                density == "continuity",
                "{formulation:?}"
            );
            assert_eq!(
                formulation.sums_density(),
                density == "summation" && smoothing != "grad-h",
                "{formulation:?}"
            );
        }
    }

    /// η outside its range, a grad-h tolerance outside (0, 1e-2] and κ outside [0, 100] are each
    /// refused by name; the range ends are accepted.
    #[test]
    fn out_of_range_numbers_are_refused_by_name() {
        let refused = |f: Formulation, field: &str| {
            let error = f.validate().unwrap_err().to_string();
            assert!(error.contains(field), "{f:?}: {error}");
        };
        let follow = |eta| {
            Formulation::Cartesian(Density::Summation(SmoothingLength::FollowDensity { eta }))
        };
        let grad_h = |eta, tolerance| Formulation::Cartesian(Density::GradH { eta, tolerance });
        refused(follow(0.4), "eta");
        refused(grad_h(4.5, 1e-6), "eta");
        assert!(follow(ETA_RANGE.0).validate().is_ok() && follow(ETA_RANGE.1).validate().is_ok());
        refused(grad_h(1.2, 0.0), "grad-h tolerance");
        refused(grad_h(1.2, 2e-2), "grad-h tolerance");
        refused(grad_h(1.2, f64::NAN), "grad-h tolerance");
        assert!(grad_h(1.2, 1e-2).validate().is_ok());
        refused(
            Formulation::TotalLagrangian { hourglass: -0.1 },
            "hourglass",
        );
        refused(
            Formulation::TotalLagrangian { hourglass: 101.0 },
            "hourglass",
        );
        assert!(Formulation::TotalLagrangian { hourglass: 100.0 }
            .validate()
            .is_ok());
    }

    /// Summing formulations find the density from the particles' masses and spacing, whatever
    /// density the scene gave them; integrating ones keep the given density until it is
    /// integrated. A lattice of spacing 0.5 (lines, or spherical shells) whose masses make
    /// ρ = 2, given ρ = 1: in its interior the sum gives 2 within the kernel's lattice error.
    #[test]
    fn summing_formulations_sum_and_integrating_ones_keep() {
        use crate::eos::{IdealGas, Material};
        use crate::particles::ParticleInit;
        use crate::step::{Simulation, SimulationConfig};
        use crate::{Domain, Vector};
        let interior_density = |formulation: Formulation| {
            let geometry = formulation.geometry();
            let init: Vec<ParticleInit<1>> = (0..40)
                .map(|k| {
                    let r0 = 0.5 * k as f64;
                    ParticleInit {
                        position: Vector::<1>::new(r0 + 0.25),
                        velocity: Vector::zeros(),
                        mass: 2.0 * geometry.volume_between(r0, r0 + 0.5),
                        smoothing_length: 1.0,
                        density: 1.0,
                        internal_energy: 1.0,
                        material: 0,
                    }
                })
                .collect();
            let config = SimulationConfig {
                formulation,
                ..SimulationConfig::default()
            };
            let gas = Material::new("gas", IdealGas::new(1.4).unwrap());
            let sim = Simulation::new(&init, vec![gas], Domain::open(), config).unwrap();
            sim.particles().density[20]
        };
        let fixed = SmoothingLength::Fixed;
        for summing in [
            Formulation::Cartesian(Density::Summation(fixed)),
            Formulation::Spherical(ShellDensity::Summation(fixed)),
        ] {
            let rho = interior_density(summing);
            // spherical shells far from the origin see a nearly planar lattice
            assert!((rho - 2.0).abs() < 0.05, "{summing:?}: {rho}");
        }
        assert_eq!(
            interior_density(Formulation::Cartesian(Density::Continuity(fixed))),
            1.0
        );
    }
}
