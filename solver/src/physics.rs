//! The Euler equations in SPH form (the seed's Table 3-3), as small pair terms and the loops that
//! sum them. Every pair uses the symmetrised kernel W(r_ij, h̄_ij), h̄_ij = (h_i + h_j)/2, so the
//! pair forces are antisymmetric and momentum and energy are conserved to round-off whatever
//! each particle's h is.
//!
//! Loops gather over each particle's own list (each pair is visited from both sides) so the
//! parallel result is bitwise independent of the thread count.

use crate::axisymmetric::PairGeometry;
use crate::error::SolverError;
use crate::kernel::Kernel;
use crate::neighbours::NeighbourList;
use crate::pairs::{self, PairEquation};
use crate::particles::Particles;
use crate::{Tensor, Vector};
use rayon::prelude::*;

/// Which form of the energy equation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyEquation {
    /// De_i/Dt = Σ_j m_j (p_i/ρ_i² + Π_ij/2) v_ij·∇_i W_ij (Monaghan 1992, eq. 2.23): the form
    /// that follows from the SPH Lagrangian. Only the particle's own pressure does work on it, so
    /// a cold particle next to a hot one cannot be driven to negative energy (Toro's Test 3,
    /// pressure ratio 10⁵, stays positive). The default.
    OwnPressure,
    /// De_i/Dt = ½ Σ_j m_j (p_i/ρ_i² + p_j/ρ_j² + Π_ij) v_ij·∇_i W_ij (the seed's Table 3-3).
    /// Equally conservative, but across a strong pressure jump it takes energy from the cold side
    /// (Toro's Test 3 reaches negative pressure in its first step).
    Symmetric,
}

impl EnergyEquation {
    pub const ALL: [EnergyEquation; 2] = [EnergyEquation::OwnPressure, EnergyEquation::Symmetric];

    pub fn name(self) -> &'static str {
        match self {
            EnergyEquation::OwnPressure => "own-pressure",
            EnergyEquation::Symmetric => "symmetric",
        }
    }
}

/// Monaghan–Gingold artificial viscosity (Monaghan & Gingold 1983; Monaghan 1992, eq. 4.1):
/// Π_ij = (−α c̄ μ + β μ²)/ρ̄ for approaching pairs, μ = h̄ v_ij·x_ij / (r² + η² h̄²).
///
/// Defaults α = 1, β = 2, η² = 0.01: α = 1 is the thesis' value and the standard one; β = 2α is
/// Monaghan's (1992) recommendation for strong shocks, where the quadratic term stops particle
/// interpenetration (the thesis used β = 1 for its blast runs; set `beta` to compare).
/// η² = 0.01 keeps μ finite for close pairs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArtificialViscosity {
    pub alpha: f64,
    pub beta: f64,
    pub eta2: f64,
    /// Artificial conductivity α_u (Price 2008, eq. 28): diffuses internal energy where the
    /// pressure jumps, which removes the pressure blip ("wall heating") a contact leaves behind
    /// a shock; 0 switches it off.
    pub alpha_u: f64,
    /// The seed's interface penalty force between particles of different materials (off when
    /// `None`).
    pub interface_penalty: Option<InterfacePenalty>,
    /// Balsara's switch: each pair's Π scaled by the mean of the two particles' factors
    /// [`balsara_factor`], which spares shear flow (plastic solids) while shocks keep their
    /// viscosity.
    pub balsara: bool,
    /// Monaghan's artificial stress against the tensile instability of solids (off when
    /// `None`).
    pub artificial_stress: Option<ArtificialStress>,
    /// Morris & Monaghan's time-dependent viscosity: each particle carries its own α between
    /// α_min and `alpha` (see [`ViscositySwitch`]); off (α everywhere) when `None`.
    pub switch: Option<ViscositySwitch>,
}

/// The time-dependent viscosity of Morris & Monaghan (1997, J. Comput. Phys. 136, 41), with the
/// bounded source of Rosswog et al. (2000, A&A 360, 171): each particle's α obeys
///
///   Dα_i/Dt = −(α_i − α_min)/τ_i + S_i (α_max − α_i),  τ_i = h_i/(ℓ c_i),  S_i = max(−∇·v_i, 0),
///
/// so α rises towards α_max (the viscosity's `alpha`) where the flow converges, at a shock, and
/// relaxes to α_min within a few τ, a few smoothing lengths of sound travel, behind it. A pair
/// uses α_ij = (α_i + α_j)/2 and β_ij = β α_ij/α_max, so Π_ij is the full Π scaled by
/// α_ij/α_max (β = 2α, as Morris & Monaghan pair them). Meant for flow that is not a shock,
/// such as the plastic flow of a solid, which is isochoric and so gives no source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViscositySwitch {
    /// α_min, the viscosity left where nothing converges (0.1 in Morris & Monaghan).
    pub alpha_min: f64,
    /// ℓ, the inverse decay time in units of c/h (0.1–0.2 in Morris & Monaghan).
    pub decay: f64,
}

impl ViscositySwitch {
    /// ℓ = 0.2: α relaxes over about five smoothing lengths of sound travel behind a shock, the
    /// faster end of Morris & Monaghan's range.
    pub const DECAY: f64 = 0.2;

    /// A particle's α after `dt` of the switch's equation, with the source and decay time of
    /// the step's end held over the step: the equation is linear in α, so its exact solution
    /// relaxes α to the balance α_eq = (α_min/τ + S α_max)/(1/τ + S) at the rate 1/τ + S, and
    /// α stays within [α_min, α_max] for any step. `sound_speed_over_h` is c_i/h_i.
    pub fn relax(
        &self,
        alpha: f64,
        alpha_max: f64,
        velocity_divergence: f64,
        sound_speed_over_h: f64,
        dt: f64,
    ) -> f64 {
        let decay_rate = self.decay * sound_speed_over_h;
        let source = (-velocity_divergence).max(0.0);
        let rate = decay_rate + source;
        let balance = (self.alpha_min * decay_rate + source * alpha_max) / rate;
        // the clamp only removes round-off: the exact solution never leaves the interval
        (balance + (alpha - balance) * (-rate * dt).exp()).clamp(self.alpha_min, alpha_max)
    }
}

/// Monaghan's (2000) artificial stress, in the form of Gray, Monaghan & Swift (2001): in the
/// principal frame of σ = −pI + s, each tensile principal stress σ' > 0 gives
/// R' = −ε σ'/ρ², rotated back to R; pairs feel m_j (R_i + R_j) f_ij^n ∇_i W_ij with
/// f_ij = W(r_ij)/W(Δp), Δp the mean particle spacing, which is large only for particles closer
/// than their spacing: exactly the pairs the instability clumps. The work of these forces is
/// returned as heat, half to each particle, so energy stays conserved. They are not
/// conservative: R grows as a pair opens under tension, so in a flow that keeps opening and
/// closing pairs they do net work on the motion, taken from the internal energy (booked in
/// [`crate::step::ArtificialHeating`]; half the impact energy in the 3D Taylor bar at 5
/// particles across).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArtificialStress {
    /// ε, 0.3 in Gray, Monaghan & Swift's elastic problems.
    pub epsilon: f64,
    /// n, 4 there.
    pub exponent: f64,
}

impl ArtificialStress {
    /// The pair's weight f^n, f = W(r)/W(Δp): by repeated squaring for a whole n (4 as a
    /// rule: two squarings, where the power function took 15 % of the colliding rings' time),
    /// which differs from the power function by a rounding or two; the power function for a
    /// fractional n or one beyond 64.
    #[inline]
    pub fn weight(&self, f: f64) -> f64 {
        if self.exponent.fract() == 0.0 && self.exponent.abs() <= 64.0 {
            f.powi(self.exponent as i32)
        } else {
            f.powf(self.exponent)
        }
    }
}

impl Default for ArtificialStress {
    fn default() -> Self {
        Self {
            epsilon: 0.3,
            exponent: 4.0,
        }
    }
}

/// The artificial stress R (in-plane block) of a particle with pressure p, deviatoric stress s
/// and density ρ: the tensile principal values of σ = −pI + s scaled by −ε/ρ².
pub fn artificial_stress_of<const D: usize>(
    pressure: f64,
    deviatoric: &Tensor<D>,
    density: f64,
    epsilon: f64,
) -> Tensor<D> {
    let sigma = deviatoric - Tensor::<D>::identity() * pressure;
    // the symmetric eigen-decomposition, through a dynamic matrix so that one code path
    // serves D = 1, 2, 3
    let eigen = nalgebra::DMatrix::from_iterator(D, D, sigma.iter().copied()).symmetric_eigen();
    let mut r = Tensor::<D>::zeros();
    for k in 0..D {
        let principal = eigen.eigenvalues[k];
        if principal > 0.0 {
            let axis = eigen.eigenvectors.column(k);
            let axis = crate::Vector::<D>::from_iterator(axis.iter().copied());
            r -= axis * axis.transpose() * (epsilon * principal / (density * density));
        }
    }
    r
}

/// Repulsion between particles of different materials that come closer than their mean
/// smoothing length (the seed's eqs. 3-29/3-30, a Lennard-Jones-like form after Monaghan 1994):
/// with pe = (h_i + h_j)/(2 r_ij), for pe ≥ 1 the pair feels
/// PB_ij = p̄ (pe^n1 − pe^n2) x_ij / r_ij² (an acceleration, m/s²). Applied here as the pair
/// force ±2 m_i m_j/(m_i + m_j) · PB_ij, which is the seed's acceleration for equal masses and
/// keeps momentum conserved for unequal ones. It is a conservative central force whose potential
/// energy is not tracked, so total energy is conserved only once pairs have separated again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfacePenalty {
    /// p̄ (m²/s²): problem dependent, about 1e5 in the seed's blast runs.
    pub p_bar: f64,
    /// The repulsive and attractive exponents, 12 and 6 in the seed.
    pub n1: f64,
    pub n2: f64,
}

impl InterfacePenalty {
    /// The seed's exponents with strength p̄.
    pub fn seed(p_bar: f64) -> Self {
        Self {
            p_bar,
            n1: 12.0,
            n2: 6.0,
        }
    }

    /// PB_ij · r_ij (m²/s²) at distance r for mean smoothing length h̄; zero for pe < 1.
    #[inline]
    pub fn acceleration_times_distance(&self, r: f64, h_mean: f64) -> f64 {
        let pe = h_mean / r;
        if pe < 1.0 {
            0.0
        } else {
            self.p_bar * (pe.powf(self.n1) - pe.powf(self.n2))
        }
    }

    pub fn validate(&self) -> Result<(), SolverError> {
        if !(self.p_bar >= 0.0 && self.p_bar.is_finite()) {
            return Err(SolverError::invalid(
                "penalty p_bar",
                self.p_bar,
                "finite and ≥ 0",
            ));
        }
        if !(self.n2 > 0.0 && self.n1 > self.n2 && self.n1.is_finite()) {
            return Err(SolverError::invalid(
                "penalty exponents n1/n2",
                format!("{}/{}", self.n1, self.n2),
                "n1 > n2 > 0",
            ));
        }
        Ok(())
    }
}

impl Default for ArtificialViscosity {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta: 2.0,
            eta2: 0.01,
            alpha_u: 0.0,
            interface_penalty: None,
            balsara: false,
            artificial_stress: None,
            switch: None,
        }
    }
}

impl ArtificialViscosity {
    pub fn validate(&self) -> Result<(), SolverError> {
        for (field, value) in [
            ("alpha", self.alpha),
            ("beta", self.beta),
            ("alpha_u", self.alpha_u),
        ] {
            if !(0.0..=10.0).contains(&value) {
                return Err(SolverError::invalid(field, value, "0 ≤ value ≤ 10"));
            }
        }
        if !(self.eta2 > 0.0 && self.eta2 <= 1.0) {
            return Err(SolverError::invalid("eta2", self.eta2, "0 < η² ≤ 1"));
        }
        if let Some(switch) = &self.switch {
            // each particle's α is carried as a share of α, which must then be positive
            if !(self.alpha > 0.0) {
                return Err(SolverError::invalid(
                    "alpha",
                    self.alpha,
                    "0 < α ≤ 10 with the viscosity switch on",
                ));
            }
            if !(0.0..=self.alpha).contains(&switch.alpha_min) {
                return Err(SolverError::invalid(
                    "switch alpha_min",
                    switch.alpha_min,
                    &format!("0 ≤ α_min ≤ α = {}", self.alpha),
                ));
            }
            if !(switch.decay > 0.0 && switch.decay <= 1.0) {
                return Err(SolverError::invalid(
                    "switch decay",
                    switch.decay,
                    "0 < ℓ ≤ 1",
                ));
            }
        }
        self.interface_penalty
            .as_ref()
            .map_or(Ok(()), InterfacePenalty::validate)
    }

    /// Π_ij for a pair with v_ij·x_ij = `v_dot_x`, r² = `r2`, mean h, c and ρ.
    #[inline]
    pub fn pi(&self, v_dot_x: f64, r2: f64, h: f64, c_mean: f64, rho_mean: f64) -> f64 {
        // μ = t/d with t = h v·x, d = r² + η²h²; Π = (−α c̄ μ + β μ²)/ρ̄ = t(β t − α c̄ d)/(d² ρ̄),
        // one division instead of two. Receding pairs (v·x ≥ 0) get t = 0 and so Π = 0, without
        // a branch that half the pairs of a random velocity field would mispredict.
        let t = h * v_dot_x.min(0.0);
        let d = r2 + self.eta2 * h * h;
        t * (self.beta * t - self.alpha * c_mean * d) / (d * d * rho_mean)
    }
}

impl ArtificialViscosity {
    /// The conductive heating of i by j divided by m_j dW/dr (Price 2008, eq. 28):
    /// α_u v_sig,u (u_i − u_j)/ρ̄ with v_sig,u = √(|p_i − p_j|/ρ̄). Antisymmetric in i, j, so
    /// it moves energy between particles without creating any.
    #[inline]
    pub fn conduction(&self, u_i: f64, u_j: f64, p_i: f64, p_j: f64, rho_mean: f64) -> f64 {
        self.alpha_u * ((p_i - p_j).abs() / rho_mean).sqrt() * (u_i - u_j) / rho_mean
    }
}

/// The pressure term p_i/ρ_i² + p_j/ρ_j² of the symmetric momentum and energy equations.
#[inline]
pub fn pressure_term(p_i: f64, rho_i: f64, p_j: f64, rho_j: f64) -> f64 {
    p_i / (rho_i * rho_i) + p_j / (rho_j * rho_j)
}

/// Monaghan's (1997) pair signal speed v_sig = c_i + c_j − 3 min(0, v_ij·r̂_ij), which bounds
/// the time step.
#[inline]
pub fn signal_speed(c_i: f64, c_j: f64, v_dot_rhat: f64) -> f64 {
    c_i + c_j - 3.0 * v_dot_rhat.min(0.0)
}

/// What the density pass reads of a neighbour, packed so one cache line serves one pair.
#[derive(Clone, Copy)]
pub(crate) struct DensitySource<const D: usize> {
    position: Vector<D>,
    smoothing_length: f64,
    mass: f64,
}

/// Summation density ρ_i = m_i W(0, h_i) + Σ_j m_j W(r_ij, h̄_ij).
pub(crate) struct SummationDensity<'a, const D: usize> {
    pub kernel: &'a Kernel<D>,
}

impl<const D: usize> PairEquation<D> for SummationDensity<'_, D> {
    type Source = DensitySource<D>;
    type Sum = f64;
    type Output = f64;

    fn source(&self, p: &Particles<D>, k: usize) -> DensitySource<D> {
        DensitySource {
            position: p.position[k],
            smoothing_length: p.smoothing_length[k],
            mass: p.mass[k],
        }
    }

    fn start(&self, me: &DensitySource<D>) -> f64 {
        me.mass * self.kernel.value(0.0, me.smoothing_length)
    }

    #[inline(always)]
    fn pair(&self, rho: &mut f64, me: &DensitySource<D>, other: &DensitySource<D>, _: &()) {
        let r2 = (me.position - other.position).norm_squared();
        let h = 0.5 * (me.smoothing_length + other.smoothing_length);
        if !self.kernel.clearly_beyond(r2, h) {
            *rho += other.mass * self.kernel.value(r2.sqrt(), h);
        }
    }

    fn finish(&self, _: &DensitySource<D>, rho: f64) -> f64 {
        rho
    }
}

/// g_i = Σ_j V_j ∇_i W_ij, the kernel's gradient summed over the partners (images included):
/// zero inside a material, and where the partners end at a free side the share of that side's
/// traction each particle takes in the pressure terms (−Σ_i V_i g_i·n = ½ per unit area).
pub(crate) struct KernelGradientSum<'a, const D: usize> {
    pub kernel: &'a Kernel<D>,
    /// Rings in (r, z): the pair loops' volume is the ring's m/η, η = 2π r ρ.
    pub axisymmetric: bool,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct VolumeSource<const D: usize> {
    position: Vector<D>,
    smoothing_length: f64,
    volume: f64,
}

impl<const D: usize> PairEquation<D> for KernelGradientSum<'_, D> {
    type Source = VolumeSource<D>;
    type Sum = Vector<D>;
    type Output = Vector<D>;

    fn source(&self, p: &Particles<D>, k: usize) -> VolumeSource<D> {
        let ring = if self.axisymmetric {
            2.0 * std::f64::consts::PI * p.position[k][0].abs()
        } else {
            1.0
        };
        VolumeSource {
            position: p.position[k],
            smoothing_length: p.smoothing_length[k],
            volume: p.mass[k] / (ring * p.density[k]),
        }
    }

    fn start(&self, _: &VolumeSource<D>) -> Vector<D> {
        Vector::zeros()
    }

    #[inline]
    fn pair(&self, g: &mut Vector<D>, me: &VolumeSource<D>, other: &VolumeSource<D>, _: &()) {
        let dx = me.position - other.position;
        let r = dx.norm();
        let h = 0.5 * (me.smoothing_length + other.smoothing_length);
        if !self.kernel.reaches(r, h) {
            return;
        }
        *g += self.kernel.gradient(&dx, r, h) * other.volume;
    }

    fn finish(&self, _: &VolumeSource<D>, g: Vector<D>) -> Vector<D> {
        g
    }
}

/// The outcome of solving one particle's h together with its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SmoothingSolution {
    /// h, ρ = Σ_j m_j W(r_ij, h) and Ω at the root.
    Converged { h: f64, density: f64, omega: f64 },
    /// The root lies beyond the reach the neighbour lists cover; solve again with lists that
    /// reach at least this h.
    BeyondReach { h: f64 },
    /// The iteration did not settle (a degenerate neighbourhood).
    Failed { h: f64 },
}

/// Iterations allowed per particle; bracketed Newton converges in a few where the guess is the
/// predicted h, and bisection fallbacks halve the bracket, so 60 means something is wrong.
const MAX_SMOOTHING_ITERATIONS: usize = 60;

/// Grad-h summation density (Springel & Hernquist 2002; Price 2012, §2.2): for each real
/// particle, the h that satisfies h = η (m/ρ)^{1/D} with ρ = Σ_j m_j W(r_ij, h) (self term
/// included, each particle with its own h), by Newton–Raphson on
/// f(h) = Σ_j m_j W(r_ij, h) − m (η/h)^D, kept inside a bracket [lo, hi] (f is negative below
/// the root and positive above it) with bisection where a Newton step would leave it. Stops when a step changes h
/// by less than `tolerance`·h, from `initial_guess`. Neighbours must include every particle
/// within κ·`reach[i]` of i; a root beyond that reach is reported, not guessed.
/// Ω_i = 1 + h_i/(D ρ_i) Σ_j m_j ∂W_ij/∂h_i. Solves the real particles `which` (the
/// solutions in its order); the guesses and reaches are indexed by particle.
pub fn solve_smoothing_lengths<const D: usize>(
    particles: &Particles<D>,
    neighbours: &NeighbourList,
    kernel: &Kernel<D>,
    (eta, tolerance): (f64, f64),
    (initial_guess, reach): (&[f64], &[f64]),
    which: &[usize],
) -> Vec<SmoothingSolution> {
    let p = particles;
    let sources = pairs::sources(&DensityAtH { kernel, h: 0.0 }, p);
    which
        .par_iter()
        .map_init(Vec::new, |within, &i| {
            let reach = reach[i];
            let guess = initial_guess[i].min(reach);
            // every trial h stays within the reach, where the kernel of a farther partner is 0
            within.clear();
            let x_i = p.position[i];
            for j in neighbours.of(i) {
                let r2 = (x_i - p.position[j]).norm_squared();
                if kernel.clearly_beyond(r2, reach) {
                    continue;
                }
                let r = r2.sqrt();
                if kernel.reaches(r, reach) {
                    within.push((j as u32, r));
                }
            }
            let partners = PartnersWithin { list: within };
            solve_one(
                i,
                &sources,
                &partners,
                kernel,
                (eta, tolerance),
                (guess, reach),
            )
        })
        .collect()
}

/// One particle's partners within a distance, each with its distance r: the pairs grad-h's
/// root finder sums at every trial h, found once.
struct PartnersWithin<'a> {
    list: &'a [(u32, f64)],
}

impl pairs::Partners for PartnersWithin<'_> {
    type Link = f64;

    #[inline]
    fn visit(&self, _: usize, mut visit: impl FnMut(usize, &f64)) {
        for &(j, r) in self.list {
            visit(j as usize, &r);
        }
    }
}

/// Σ_j m_j W(r_ij, h) and its h derivative Σ_j m_j ∂W(r_ij, h)/∂h at one trial h of the
/// particle, self term included: what grad-h's root finder evaluates.
struct DensityAtH<'a, const D: usize> {
    kernel: &'a Kernel<D>,
    h: f64,
}

impl<const D: usize> PairEquation<D, f64> for DensityAtH<'_, D> {
    /// The particle's mass.
    type Source = f64;
    type Sum = (f64, f64);
    type Output = (f64, f64);

    fn source(&self, p: &Particles<D>, k: usize) -> f64 {
        p.mass[k]
    }

    fn start(&self, &m_i: &f64) -> (f64, f64) {
        (
            m_i * self.kernel.value(0.0, self.h),
            m_i * self.kernel.h_derivative(0.0, self.h),
        )
    }

    #[inline]
    fn pair(&self, (rho, drho): &mut (f64, f64), _: &f64, &m_j: &f64, &r: &f64) {
        *rho += m_j * self.kernel.value(r, self.h);
        *drho += m_j * self.kernel.h_derivative(r, self.h);
    }

    fn finish(&self, _: &f64, sums: (f64, f64)) -> (f64, f64) {
        sums
    }
}

fn solve_one<const D: usize>(
    i: usize,
    sources: &[f64],
    partners: &PartnersWithin,
    kernel: &Kernel<D>,
    (eta, tolerance): (f64, f64),
    (guess, reach): (f64, f64),
) -> SmoothingSolution {
    let m_i = sources[i];
    let dim = D as f64;
    let sums = |h: f64| pairs::sum_at(&DensityAtH { kernel, h }, sources, partners, i);
    let (mut lo, mut hi) = (0.0, f64::INFINITY);
    let mut h = guess;
    for _ in 0..MAX_SMOOTHING_ITERATIONS {
        let (rho, drho_dh) = sums(h);
        let rho_eta = m_i * (eta / h).powi(D as i32);
        let f = rho - rho_eta;
        let f_prime = drho_dh + dim * rho_eta / h;
        if f < 0.0 {
            lo = h;
        } else {
            hi = h;
        }
        let newton = h - f / f_prime;
        // near the root Newton's step can be smaller than h's last digit: h − f/f′ is then h
        // itself, an end of the bracket, and the search has converged
        let settled = newton == h;
        let mut next = if f_prime > 0.0 && (newton > lo && newton < hi || settled) {
            newton
        } else if hi.is_finite() {
            0.5 * (lo + hi)
        } else {
            // no point above the root yet, where Newton always steps up: f′ = [D(ρ_η − ρ) −
            // Σ m_j r_j ∂W_j/∂r]/h is positive wherever f < 0 for a kernel that falls with r, so
            // this guards only against arithmetic that is not finite
            2.0 * h
        };
        if next > reach {
            if h >= reach {
                return SmoothingSolution::BeyondReach { h: next };
            }
            next = reach;
        }
        if (next - h).abs() <= tolerance * h {
            return SmoothingSolution::Converged {
                h,
                density: rho,
                omega: 1.0 + h * drho_dh / (dim * rho),
            };
        }
        h = next;
    }
    SmoothingSolution::Failed { h }
}

/// What the force loop reads of a neighbour, packed so that a pair touches one or two cache
/// lines instead of one per field.
#[derive(Clone, Copy)]
struct RateSource<const D: usize> {
    position: Vector<D>,
    velocity: Vector<D>,
    smoothing_length: f64,
    mass: f64,
    density: f64,
    sound_speed: f64,
    pressure: f64,
    internal_energy: f64,
    /// p/(Ω ρ²) (Ω = 1 without grad-h) in the standard form, p/ρ in the volume form (which
    /// divides by the partner's ρ in the pair), computed once so that the pair term P_i + P_j
    /// is the same floating-point number seen from i and from j.
    pressure_factor: f64,
    /// A wall image: its force on a real particle is the wall's reaction.
    is_wall: bool,
    material: u16,
    /// Balsara factor (1 without the switch).
    balsara: f64,
    /// α_k/α_max of the time-dependent viscosity (1 without it).
    alpha_factor: f64,
}

/// What the force loop returns for one particle.
#[derive(Clone, Copy, Debug)]
struct Rates<const D: usize> {
    acceleration: Vector<D>,
    energy_rate: f64,
    density_rate: f64,
    signal_speed: f64,
    /// The part of m_i a_i exerted by wall images.
    wall_force: Vector<D>,
    /// The viscosity's share of De_i/Dt.
    viscous_heating: f64,
}

/// The Euler pair terms: momentum, energy and density rates (see [`compute_rates`]).
struct EulerRates<'a> {
    viscosity: &'a ArtificialViscosity,
    energy: EnergyEquation,
    /// Continuity density: the volume form of density, momentum and energy rates.
    volume_form: bool,
    geometry: PairGeometry,
}

impl EulerRates<'_> {
    /// The factor that turns j's m_j v_ij·∇W into its share of Dρ_i/Dt.
    #[inline]
    fn density_weight<const D: usize>(&self, me: &RateSource<D>, other: &RateSource<D>) -> f64 {
        if self.volume_form {
            me.density / other.density
        } else {
            1.0
        }
    }

    /// What i's pressure factor is multiplied by in the pair with j: 1/ρ_j in the volume form.
    #[inline]
    fn partner_factor<const D: usize>(&self, other: &RateSource<D>) -> f64 {
        if self.volume_form {
            1.0 / other.density
        } else {
            1.0
        }
    }
}

impl<const D: usize> PairEquation<D, KernelLink> for EulerRates<'_> {
    type Source = RateSource<D>;
    type Sum = Rates<D>;
    type Output = Rates<D>;

    fn source(&self, p: &Particles<D>, k: usize) -> RateSource<D> {
        let (density_scale, stress_scale) = self.geometry.scales(p, k);
        let density = p.density[k] * density_scale;
        let pressure = p.pressure[k] * stress_scale;
        RateSource {
            position: p.position[k],
            velocity: p.velocity[k],
            smoothing_length: p.smoothing_length[k],
            mass: p.mass[k],
            density,
            sound_speed: p.sound_speed[k],
            pressure,
            internal_energy: p.internal_energy[k],
            pressure_factor: if self.volume_form {
                pressure / density
            } else {
                pressure_term(pressure, density, 0.0, 1.0) / p.omega.get(k).copied().unwrap_or(1.0)
            },
            is_wall: p.image(k).is_some_and(|im| im.is_wall),
            material: p.material_of(k) as u16,
            balsara: p
                .balsara_factor
                .get(p.real_index(k))
                .copied()
                .unwrap_or(1.0),
            alpha_factor: p
                .viscosity_alpha
                .get(p.real_index(k))
                .map_or(1.0, |alpha| alpha / self.viscosity.alpha),
        }
    }

    fn start(&self, me: &RateSource<D>) -> Rates<D> {
        Rates {
            acceleration: Vector::zeros(),
            energy_rate: 0.0,
            density_rate: 0.0,
            signal_speed: me.sound_speed,
            wall_force: Vector::zeros(),
            viscous_heating: 0.0,
        }
    }

    #[inline(always)]
    fn pair(
        &self,
        out: &mut Rates<D>,
        me: &RateSource<D>,
        other: &RateSource<D>,
        link: &KernelLink,
    ) {
        let dx = me.position - other.position;
        let r2 = dx.norm_squared();
        // dW/dr for i's pressure, for j's, and their mean for viscosity and conduction
        let &KernelLink { r, dw_i, dw_j } = link;
        let inv_r = 1.0 / r;
        let h = 0.5 * (me.smoothing_length + other.smoothing_length);
        let dw_mean = 0.5 * (dw_i + dw_j);
        let v_ij = me.velocity - other.velocity;
        let v_dot_x = v_ij.dot(&dx);
        let c_mean = 0.5 * (me.sound_speed + other.sound_speed);
        let rho_mean = 0.5 * (me.density + other.density);
        let pi_ij = self.viscosity.pi(v_dot_x, r2, h, c_mean, rho_mean)
            * (0.5 * (me.balsara + other.balsara))
            * (0.5 * (me.alpha_factor + other.alpha_factor));
        let m_j = other.mass;
        // every gradient here is dW/dr · x_ij/r, so the pair's terms combine as scalars
        let pressure_i = m_j * me.pressure_factor * self.partner_factor(other) * dw_i;
        let pressure_j = m_j * other.pressure_factor * self.partner_factor(me) * dw_j;
        // m_j Π_ij in both forms: in the volume form it is m_j q_ij/(ρ_i ρ_j) with the viscous
        // pressure q_ij = ρ̃ (−α c̄ μ + β μ²) at the harmonic mean density ρ̃, which the
        // lighter side sets across a density jump
        let viscous = m_j * pi_ij * dw_mean;
        let v_dot_rhat = v_dot_x * inv_r;
        out.acceleration -= dx * ((pressure_i + pressure_j + viscous) * inv_r);
        // half the pair's viscous dissipation heats each side, in both energy forms
        let viscous_heating = 0.5 * viscous * v_dot_rhat;
        out.viscous_heating += viscous_heating;
        out.energy_rate += viscous_heating
            + v_dot_rhat
                * match self.energy {
                    EnergyEquation::OwnPressure => pressure_i,
                    EnergyEquation::Symmetric => 0.5 * (pressure_i + pressure_j),
                };
        // without conduction (α_u = 0, the default) its term is 0 and its square root and two
        // divisions are spared
        if self.viscosity.alpha_u != 0.0 {
            out.energy_rate += m_j
                * dw_mean
                * self.viscosity.conduction(
                    me.internal_energy,
                    other.internal_energy,
                    me.pressure,
                    other.pressure,
                    rho_mean,
                );
        }
        out.density_rate += m_j * dw_i * v_dot_rhat * self.density_weight(me, other);
        let v_sig = signal_speed(me.sound_speed, other.sound_speed, v_dot_rhat);
        out.signal_speed = out.signal_speed.max(v_sig);
        if other.is_wall {
            out.wall_force -= dx * ((pressure_i + pressure_j + viscous) * inv_r * me.mass);
        }
        if let Some(penalty) = &self.viscosity.interface_penalty {
            if me.material != other.material {
                let force = dx
                    * (penalty.acceleration_times_distance(r, h)
                        * inv_r
                        * inv_r
                        * (2.0 * me.mass * m_j / (me.mass + m_j)));
                out.acceleration += force / me.mass;
                if other.is_wall {
                    out.wall_force += force;
                }
            }
        }
    }

    fn finish(&self, _: &RateSource<D>, rates: Rates<D>) -> Rates<D> {
        rates
    }
}

/// Which kernel a pair uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairKernel {
    /// W(r, h̄_ij), h̄_ij = (h_i + h_j)/2, on both sides of the pair.
    MeanH,
    /// Grad-h SPH (Price 2012, eqs. 34–35): i's pressure acts through ∇W(r, h_i), j's through
    /// ∇W(r, h_j), each divided by its Ω; viscosity and conduction through the mean of the two
    /// gradients, so the pair forces stay antisymmetric.
    OwnH,
}

impl PairKernel {
    /// dW/dr of the pair for i's and for j's side: the same W'(r, h̄_ij) twice (mean h), or
    /// W'(r, h_i) and W'(r, h_j) (grad-h).
    #[inline]
    pub fn derivatives<const D: usize>(
        self,
        kernel: &Kernel<D>,
        r: f64,
        h_i: f64,
        h_j: f64,
    ) -> (f64, f64) {
        match self {
            PairKernel::MeanH => {
                let dw = kernel.derivative(r, 0.5 * (h_i + h_j));
                (dw, dw)
            }
            PairKernel::OwnH => (kernel.derivative(r, h_i), kernel.derivative(r, h_j)),
        }
    }

    /// Whether both of [`Self::derivatives`] are certainly 0 at the squared distance `r2`
    /// ([`Kernel::clearly_beyond`] the h that reaches farther).
    #[inline]
    pub fn clearly_beyond<const D: usize>(
        self,
        kernel: &Kernel<D>,
        r2: f64,
        h_i: f64,
        h_j: f64,
    ) -> bool {
        match self {
            PairKernel::MeanH => kernel.clearly_beyond(r2, 0.5 * (h_i + h_j)),
            PairKernel::OwnH => kernel.clearly_beyond(r2, h_i.max(h_j)),
        }
    }
}

/// A pair within the kernel's reach, as the rate passes see it: the distance and dW/dr for
/// i's side and for j's ([`PairKernel::derivatives`]).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct KernelLink {
    pub r: f64,
    pub dw_i: f64,
    pub dw_j: f64,
}

/// Each real particle's partners within the kernel's reach, in the order of its neighbour
/// list, with their [`KernelLink`] worked out once for the passes of a rate evaluation that
/// share it (velocity gradients, radius gradients, the Euler rates, the stress forces). Pairs
/// with r = 0 or both derivatives zero, which every such pass skips, are left out; kept lists'
/// partners beyond the kernel's reach are among them. Partners for the pair driver. Rebuilt in
/// place at every rate evaluation, so that its buffers are allocated once.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct KernelPairs {
    /// The pairs of the particles in rows `PAIR_CHUNK·c..PAIR_CHUNK·(c + 1)`, end to end, in
    /// chunk c.
    chunks: Vec<Vec<(u32, KernelLink)>>,
    /// Where each row's pairs end in its chunk.
    ends: Vec<u32>,
    /// Each real particle's row (the particles rebuilt for, in their order; `u32::MAX` for
    /// the others).
    row: Vec<u32>,
}

/// Particles per chunk of [`KernelPairs`], each chunk filled by one parallel task.
const PAIR_CHUNK: usize = 256;

impl KernelPairs {
    /// The pairs of the real particles `which` (all of them, or those whose individual steps
    /// end), at their current positions and smoothing lengths.
    pub fn rebuild<const D: usize>(
        &mut self,
        particles: &Particles<D>,
        neighbours: &NeighbourList,
        kernel: &Kernel<D>,
        pair_kernel: PairKernel,
        which: &[usize],
    ) {
        let p = particles;
        self.row.clear();
        self.row.resize(p.n_real(), u32::MAX);
        for (row, &i) in which.iter().enumerate() {
            self.row[i] = row as u32;
        }
        // chunks beyond those in use keep their buffers for a later evaluation of more particles
        let in_use = which.len().div_ceil(PAIR_CHUNK);
        if self.chunks.len() < in_use {
            self.chunks.resize_with(in_use, Vec::new);
        }
        self.ends.resize(which.len(), 0);
        self.chunks[..in_use]
            .par_iter_mut()
            .zip(self.ends.par_chunks_mut(PAIR_CHUNK))
            .zip(which.par_chunks(PAIR_CHUNK))
            .for_each(|((pairs, ends), rows)| {
                pairs.clear();
                for (end, &i) in ends.iter_mut().zip(rows) {
                    let (x_i, h_i) = (p.position[i], p.smoothing_length[i]);
                    for j in neighbours.of(i) {
                        let (r2, h_j) =
                            ((x_i - p.position[j]).norm_squared(), p.smoothing_length[j]);
                        if r2 == 0.0 || pair_kernel.clearly_beyond(kernel, r2, h_i, h_j) {
                            continue;
                        }
                        let r = r2.sqrt();
                        let (dw_i, dw_j) = pair_kernel.derivatives(kernel, r, h_i, h_j);
                        if dw_i != 0.0 || dw_j != 0.0 {
                            pairs.push((j as u32, KernelLink { r, dw_i, dw_j }));
                        }
                    }
                    *end = pairs.len() as u32;
                }
            });
    }
}

impl pairs::Partners for KernelPairs {
    type Link = KernelLink;

    #[inline]
    fn visit(&self, i: usize, mut visit: impl FnMut(usize, &KernelLink)) {
        let row = self.row[i] as usize;
        let (chunk, k) = (row / PAIR_CHUNK, row % PAIR_CHUNK);
        let start = if k == 0 {
            0
        } else {
            self.ends[row - 1] as usize
        };
        for (j, link) in &self.chunks[chunk][start..self.ends[row] as usize] {
            visit(*j as usize, link);
        }
    }
}

/// Sums over the real particles that the rate loops return beside the per-particle rates.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RateTotals<const D: usize> {
    /// The force the walls exert on the particles (N).
    pub wall_force: Vector<D>,
    /// Σ_i m_i × the viscosity's share of De_i/Dt (W, never negative): the kinetic energy the
    /// artificial viscosity turns into heat.
    pub viscous_heating: f64,
    /// Σ_i m_i × the heat returned for the artificial stress's work (W): its negative is the
    /// power the artificial stress puts into the motion.
    pub artificial_stress_heating: f64,
    /// Σ_i m_i × the heat returned for the hourglass control's work (W; total-Lagrangian
    /// solids, see [`crate::total_lagrangian`]).
    pub hourglass_heating: f64,
    /// The power leaving through transmitting boundaries (never negative) and as work against
    /// external accelerations (W).
    pub transmitted_power: f64,
}

impl<const D: usize> std::ops::AddAssign<&RateTotals<D>> for RateTotals<D> {
    fn add_assign(&mut self, other: &RateTotals<D>) {
        self.wall_force += other.wall_force;
        self.viscous_heating += other.viscous_heating;
        self.artificial_stress_heating += other.artificial_stress_heating;
        self.hourglass_heating += other.hourglass_heating;
        self.transmitted_power += other.transmitted_power;
    }
}

impl<const D: usize> Default for RateTotals<D> {
    fn default() -> Self {
        Self {
            wall_force: Vector::zeros(),
            viscous_heating: 0.0,
            artificial_stress_heating: 0.0,
            hourglass_heating: 0.0,
            transmitted_power: 0.0,
        }
    }
}

/// Momentum, energy and (for continuity density or grad-h) density rates of the real particles:
/// Dv_i/Dt = −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j² + Π_ij) ∇_i W_ij, or with continuity density the
/// volume form −Σ_j m_j ((p_i + p_j)/(ρ_i ρ_j) + Π_ij) ∇_i W_ij (the seed's
/// (σ_i + σ_j)/(ρ_i ρ_j) form): across a density jump of 1000 the standard form multiplies the
/// light particle's own pressure by its heavy neighbour's mass and tears the interface apart in
/// one step, while the volume form weighs each neighbour by its volume. Both are antisymmetric
/// in i, j, and the energy equation's p_i/(ρ_i ρ_j) is p_i/ρ_i² times the volume-form Dρ_i/Dt,
/// so momentum and energy stay conserved,
/// De_i/Dt in the chosen [`EnergyEquation`] form,
/// Dρ_i/Dt = ρ_i Σ_j (m_j/ρ_j) v_ij·∇_i W_ij (continuity, see [`crate::formulation::Density::Continuity`]) or
/// Σ_j m_j v_ij·∇_i W_ij(h_i) (the rate of the grad-h summation density),
/// with the grad-h forms where `pair_kernel` is [`PairKernel::OwnH`] (the particles then carry
/// Ω, and get Dh/Dt = −h/(Dρ)·Dρ/Dt for the next step's guess). Particles that carry Balsara's
/// factor scale Π_ij by (f_i + f_j)/2; particles that carry their own α
/// ([`ViscositySwitch`]) scale Π_ij by (α_i + α_j)/(2α). In an axisymmetric `geometry` the pairs see
/// ring densities and fluxes (see [`crate::axisymmetric`]) and the density rate is Dη/Dt.
/// For the real particles `which`; each one's wall force and viscous heating join its entry
/// in `books`.
#[allow(clippy::too_many_arguments)]
pub fn compute_rates<const D: usize>(
    particles: &mut Particles<D>,
    kernel_pairs: &KernelPairs,
    viscosity: &ArtificialViscosity,
    energy: EnergyEquation,
    geometry: PairGeometry,
    which: &[usize],
    books: &mut [RateTotals<D>],
) {
    let equation = EulerRates {
        viscosity,
        energy,
        volume_form: !particles.density_rate.is_empty(),
        geometry,
    };
    let rates = pairs::gather_at(&equation, particles, kernel_pairs, which);
    let p = particles;
    let (continuity, grad_h) = (!p.density_rate.is_empty(), !p.smoothing_rate.is_empty());
    for ((&i, rate), book) in which.iter().zip(&rates).zip(books.iter_mut()) {
        p.acceleration[i] = rate.acceleration;
        p.energy_rate[i] = rate.energy_rate;
        p.signal_speed[i] = rate.signal_speed;
        if continuity {
            p.density_rate[i] = rate.density_rate;
        }
        if grad_h {
            let density_rate = rate.density_rate / p.omega[i];
            p.smoothing_rate[i] = -p.smoothing_length[i] * density_rate / (D as f64 * p.density[i]);
        }
        book.wall_force += rate.wall_force;
        book.viscous_heating += p.mass[i] * rate.viscous_heating;
    }
}

/// The velocity gradient L_i = Σ_j m_j w_ij (v_j − v_i) ⊗ ∇_i W_ij of the real particles `which`
/// (in that order), with
/// w_ij = 1/(Ω_i ρ_i) in the standard form and 1/ρ_j in the volume form (continuity density):
/// the weights under which the work of the stress forces equals the deviatoric heating
/// s_i:ε̇_i/ρ_i exactly (see [`add_stress_rates`]). Also the source of the Balsara switch.
/// Axisymmetric: the planar (r, z) block, with the ring densities as ρ.
pub fn velocity_gradients<const D: usize>(
    particles: &Particles<D>,
    kernel_pairs: &KernelPairs,
    geometry: PairGeometry,
    which: &[usize],
) -> Vec<Tensor<D>> {
    let equation = VelocityGradient {
        geometry,
        volume_form: !particles.density_rate.is_empty(),
    };
    pairs::gather_at(&equation, particles, kernel_pairs, which)
}

/// The velocity-gradient pass (see [`velocity_gradients`]).
struct VelocityGradient {
    geometry: PairGeometry,
    volume_form: bool,
}

/// What the velocity-gradient pass reads of a neighbour.
struct GradientSource<const D: usize> {
    position: Vector<D>,
    velocity: Vector<D>,
    mass: f64,
    /// ρ, or η = 2π|r|ρ in an axisymmetric scene.
    ring_density: f64,
    /// Ω (1 without grad-h).
    omega: f64,
}

impl<const D: usize> PairEquation<D, KernelLink> for VelocityGradient {
    type Source = GradientSource<D>;
    type Sum = Tensor<D>;
    type Output = Tensor<D>;

    fn source(&self, p: &Particles<D>, k: usize) -> GradientSource<D> {
        GradientSource {
            position: p.position[k],
            velocity: p.velocity[k],
            mass: p.mass[k],
            ring_density: p.density[k] * self.geometry.scales(p, k).0,
            omega: p.omega.get(k).copied().unwrap_or(1.0),
        }
    }

    fn start(&self, _: &GradientSource<D>) -> Tensor<D> {
        Tensor::zeros()
    }

    #[inline]
    fn pair(
        &self,
        gradient: &mut Tensor<D>,
        me: &GradientSource<D>,
        other: &GradientSource<D>,
        link: &KernelLink,
    ) {
        // ∇_i W(r, h̄) (mean h) or ∇_i W(r, h_i) (grad-h)
        let &KernelLink { r, dw_i: dw, .. } = link;
        if dw == 0.0 {
            return; // only j's kernel reaches i
        }
        let dx = me.position - other.position;
        let weight = if self.volume_form {
            1.0 / other.ring_density
        } else {
            1.0 / me.ring_density
        };
        let scale = other.mass * weight * dw / r;
        *gradient += (other.velocity - me.velocity) * (dx * scale).transpose();
    }

    fn finish(&self, me: &GradientSource<D>, gradient: Tensor<D>) -> Tensor<D> {
        if self.volume_form {
            gradient
        } else {
            gradient / me.omega
        }
    }
}

/// Balsara's (1995) switch f_i = |∇·v| / (|∇·v| + |∇×v| + 1e-4 c_i/h_i): near 1 in compression,
/// near 0 in shear, so the viscosity meant for shocks spares shearing (plastic) flow. The
/// divergence includes the hoop rate v_r/r of an axisymmetric scene (`hoop_rate`, 0 otherwise):
/// without it the radial plastic flow of a Taylor bar's foot, whose planar divergence is −v_r/r,
/// would count as compression. The curl's magnitude in 2D is |L_yx − L_xy|; in 3D the norm of
/// the axial vector; in 1D zero.
pub fn balsara_factor<const D: usize>(
    gradient: &Tensor<D>,
    hoop_rate: f64,
    sound_speed: f64,
    h: f64,
) -> f64 {
    let divergence = (gradient.trace() + hoop_rate).abs();
    let mut curl2 = 0.0;
    for a in 0..D {
        for b in (a + 1)..D {
            curl2 += (gradient[(b, a)] - gradient[(a, b)]).powi(2);
        }
    }
    divergence / (divergence + curl2.sqrt() + 1e-4 * sound_speed / h)
}

/// What the stress loop reads of a neighbour.
#[derive(Clone, Copy)]
struct StressSource<const D: usize> {
    position: Vector<D>,
    smoothing_length: f64,
    mass: f64,
    density: f64,
    /// s/(Ω ρ²) in the standard form, s/ρ in the volume form (see `pressure_factor`).
    stress_factor: Tensor<D>,
    is_wall: bool,
    velocity: Vector<D>,
    /// Monaghan's artificial stress R (zero for fluids and without the option).
    artificial: Tensor<D>,
    /// (m/ρ)^(1/D), the particle's spacing.
    spacing: f64,
}

/// The stress pair terms of [`add_stress_rates`]: per real particle its acceleration, the
/// part of m_i a_i exerted by wall images, and the heat returned for the artificial stress's
/// work.
struct StressForces<'a, const D: usize> {
    /// W itself, for the artificial stress's f = W(r)/W(Δp).
    kernel: &'a Kernel<D>,
    volume_form: bool,
    shear_modulus: &'a [f64],
    artificial_stress: Option<ArtificialStress>,
    geometry: PairGeometry,
}

impl<const D: usize> PairEquation<D, KernelLink> for StressForces<'_, D> {
    type Source = StressSource<D>;
    type Sum = (Vector<D>, Vector<D>, f64);
    type Output = (Vector<D>, Vector<D>, f64);

    fn source(&self, p: &Particles<D>, k: usize) -> StressSource<D> {
        let (density_scale, stress_scale) = self.geometry.scales(p, k);
        let density = p.density[k] * density_scale;
        let stress = p.deviatoric_stress[k] * stress_scale;
        StressSource {
            position: p.position[k],
            smoothing_length: p.smoothing_length[k],
            mass: p.mass[k],
            density,
            stress_factor: if self.volume_form {
                stress / density
            } else {
                stress / (p.omega.get(k).copied().unwrap_or(1.0) * density * density)
            },
            is_wall: p.image(k).is_some_and(|im| im.is_wall),
            velocity: p.velocity[k],
            // R = −εσ'/ρ² of the particle's own tensile stress, seen as a ring flux over η²
            artificial: match self.artificial_stress {
                Some(a) if self.shear_modulus[p.material_of(k)] > 0.0 => {
                    artificial_stress_of(
                        p.pressure[k],
                        &p.deviatoric_stress[k],
                        p.density[k],
                        a.epsilon,
                    ) * (stress_scale / (density_scale * density_scale))
                }
                _ => Tensor::zeros(),
            },
            spacing: (p.mass[k] / density).powf(1.0 / D as f64),
        }
    }

    fn start(&self, _: &StressSource<D>) -> Self::Sum {
        (Vector::zeros(), Vector::zeros(), 0.0)
    }

    #[inline(always)]
    fn pair(
        &self,
        (acceleration, wall, heating): &mut Self::Sum,
        me: &StressSource<D>,
        other: &StressSource<D>,
        link: &KernelLink,
    ) {
        let dx = me.position - other.position;
        let &KernelLink { r, dw_i, dw_j } = link;
        let partner = |other: &StressSource<D>| {
            if self.volume_form {
                1.0 / other.density
            } else {
                1.0
            }
        };
        let mut force = (me.stress_factor * (partner(other) * dw_i)
            + other.stress_factor * (partner(me) * dw_j))
            * (dx / r)
            * other.mass;
        if let Some(artificial_stress) = self.artificial_stress {
            let h = 0.5 * (me.smoothing_length + other.smoothing_length);
            let f =
                self.kernel.value(r, h) / self.kernel.value(0.5 * (me.spacing + other.spacing), h);
            let repulsion = (me.artificial + other.artificial)
                * (dx * (artificial_stress.weight(f) * 0.5 * (dw_i + dw_j) / r))
                * other.mass;
            force += repulsion;
            *heating -= 0.5 * repulsion.dot(&(me.velocity - other.velocity));
        }
        *acceleration += force;
        if other.is_wall {
            *wall += force * me.mass;
        }
    }

    fn finish(&self, _: &StressSource<D>, sum: Self::Sum) -> Self::Sum {
        sum
    }
}

/// The deviatoric-stress part of the solid equations, added to the rates `compute_rates` left
/// (the seed's σ = −p I + s forms): Dv_i/Dt += Σ_j m_j (s_i/ρ_i² + s_j/ρ_j²)·∇_i W_ij (or the
/// volume form (s_i + s_j)/(ρ_i ρ_j)), De_i/Dt += s_i:ε̇_i/ρ_i, and the Jaumann stress rate from
/// the velocity gradient L_i = Σ_j m_j w_ij (v_j − v_i) ⊗ ∇_i W_ij, w_ij = 1/(Ω_i ρ_i) (or
/// 1/ρ_j in the volume form): the weights that make the work of the stress forces equal the
/// deviatoric heating, so total energy is conserved. A separate pass, so that fluid scenes carry
/// no tensors. `velocity_gradient` comes from [`velocity_gradients`]; `shear_modulus[m]` is
/// material m's G (0 for a fluid). With `artificial_stress`, Monaghan's term joins (see
/// [`ArtificialStress`]). In an axisymmetric `geometry` the pairs see ring densities and
/// fluxes, and `hoop_rate` (ε̇_θθ per real particle, [`crate::axisymmetric::hoop_strain_rates`])
/// joins the heating, the equivalent strain rate and the stress rate. For the real particles
/// `which` (`velocity_gradient` and `hoop_rate` in that order); each one's wall force and
/// artificial stress heating join its entry in `books`.
#[allow(clippy::too_many_arguments)]
pub fn add_stress_rates<const D: usize>(
    particles: &mut Particles<D>,
    kernel_pairs: &KernelPairs,
    kernel: &Kernel<D>,
    velocity_gradient: &[Tensor<D>],
    shear_modulus: &[f64],
    artificial_stress: Option<ArtificialStress>,
    geometry: PairGeometry,
    hoop_rate: Option<&[f64]>,
    which: &[usize],
    books: &mut [RateTotals<D>],
) {
    let equation = StressForces {
        kernel,
        volume_form: !particles.density_rate.is_empty(),
        shear_modulus,
        artificial_stress,
        geometry,
    };
    let rates = pairs::gather_at(&equation, particles, kernel_pairs, which);
    let p = particles;
    for (k, (acceleration, wall, heating)) in rates.into_iter().enumerate() {
        let i = which[k];
        p.acceleration[i] += acceleration;
        p.energy_rate[i] += heating;
        books[k].artificial_stress_heating += p.mass[i] * heating;
        let s = p.deviatoric_stress[i];
        let gradient = &velocity_gradient[k];
        let strain_rate = 0.5 * (gradient + gradient.transpose());
        // out of the plane: ε̇_θθ = v_r/r (axisymmetric) or 0 (uniaxial, plane strain), where
        // s_θθ = −tr s
        let hoop = hoop_rate.map_or(0.0, |rates| rates[k]);
        p.energy_rate[i] += (s.component_mul(&strain_rate).sum() - s.trace() * hoop) / p.density[i];
        p.strain_rate[i] = crate::strength::equivalent_strain_rate(&strain_rate, hoop);
        let g = shear_modulus[p.material_of(i)];
        p.stress_rate[i] = if g > 0.0 {
            crate::strength::jaumann_rate(g, &s, gradient, hoop)
        } else {
            Tensor::zeros()
        };
        books[k].wall_force += wall;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::KernelShape;
    use crate::neighbours::{find_neighbours, PairReach};
    use crate::particles::{OptionalFields, ParticleInit};
    use approx::assert_relative_eq;

    /// A viscosity whose every coefficient differs from the others and from the defaults, so
    /// that a term taking the wrong one is seen.
    fn distinct_viscosity() -> ArtificialViscosity {
        ArtificialViscosity {
            alpha: 0.8,
            beta: 1.7,
            eta2: 0.03,
            alpha_u: 0.4,
            ..ArtificialViscosity::default()
        }
    }

    /// The energy equations' names are the values the problems' `energy` parameter takes.
    #[test]
    fn energy_equations_are_named_as_the_problems_take_them() {
        let names: Vec<&str> = EnergyEquation::ALL.iter().map(|e| e.name()).collect();
        assert_eq!(names, ["own-pressure", "symmetric"]);
    }

    /// Monaghan's Π = (−α c̄ μ + β μ²)/ρ̄, μ = h v·x/(r² + η²h²), written out term by term.
    #[test]
    fn monaghan_viscosity_is_its_formula_for_approaching_pairs_and_zero_otherwise() {
        let viscosity = distinct_viscosity();
        let (v_dot_x, r2, h, c, rho) = (-3.0, 0.49, 0.6, 5.0, 1.3);
        let mu = h * v_dot_x / (r2 + 0.03 * h * h);
        let expected = (-0.8 * c * mu + 1.7 * mu * mu) / rho;
        assert_relative_eq!(
            viscosity.pi(v_dot_x, r2, h, c, rho),
            expected,
            max_relative = 1e-14
        );
        assert!(expected > 0.0);
        assert_eq!(viscosity.pi(3.0, r2, h, c, rho), 0.0);
        assert_eq!(viscosity.pi(0.0, r2, h, c, rho), 0.0);
    }

    /// Price's conduction α_u √(|p_i − p_j|/ρ̄)(u_i − u_j)/ρ̄: antisymmetric, zero without a
    /// pressure jump; the pair helpers as their formulas.
    #[test]
    fn conduction_and_the_pair_helpers_are_their_formulas() {
        let viscosity = distinct_viscosity();
        let heat = viscosity.conduction(7.0, 2.0, 9.0, 1.0, 2.0);
        assert_relative_eq!(heat, 0.4 * 2.0 * 5.0 / 2.0, max_relative = 1e-14);
        assert_eq!(viscosity.conduction(2.0, 7.0, 1.0, 9.0, 2.0), -heat);
        assert_eq!(viscosity.conduction(7.0, 2.0, 3.0, 3.0, 2.0), 0.0);
        assert_relative_eq!(
            pressure_term(8.0, 2.0, 9.0, 3.0),
            8.0 / 4.0 + 9.0 / 9.0,
            max_relative = 1e-15
        );
        assert_eq!(signal_speed(2.0, 3.0, -1.5), 2.0 + 3.0 + 4.5);
        assert_eq!(signal_speed(2.0, 3.0, 1.5), 5.0);
    }

    /// The seed's penalty p̄ (pe^n1 − pe^n2), pe = h̄/r, from pe = 1 inwards only.
    #[test]
    fn interface_penalty_acts_inside_the_mean_smoothing_length_only() {
        let penalty = InterfacePenalty::seed(1e5);
        assert_eq!(
            penalty.acceleration_times_distance(0.5, 1.0),
            1e5 * (4096.0 - 64.0)
        );
        assert_eq!(penalty.acceleration_times_distance(1.0, 1.0), 0.0);
        assert_eq!(penalty.acceleration_times_distance(1.01, 1.0), 0.0);
        let unequal = InterfacePenalty {
            p_bar: 2.0,
            n1: 4.0,
            n2: 2.0,
        };
        assert_relative_eq!(
            unequal.acceleration_times_distance(0.8, 1.2),
            2.0 * (1.5f64.powi(4) - 1.5f64.powi(2)),
            max_relative = 1e-14
        );
    }

    /// Every coefficient at the edges of its range: the edges themselves accepted, one step
    /// beyond refused, naming the field.
    #[test]
    fn viscosity_coefficients_are_refused_outside_their_ranges_by_name() {
        let refused = |viscosity: ArtificialViscosity, field: &str| match viscosity.validate() {
            Err(SolverError::InvalidParameter { field: named, .. }) => {
                assert_eq!(named, field)
            }
            other => panic!("{field}: {other:?}"),
        };
        let base = ArtificialViscosity::default();
        for (alpha, beta, alpha_u) in [(0.0, 0.0, 0.0), (10.0, 10.0, 10.0)] {
            let edge = ArtificialViscosity {
                alpha,
                beta,
                alpha_u,
                eta2: 1.0,
                ..base
            };
            assert_eq!(edge.validate(), Ok(()));
        }
        refused(
            ArtificialViscosity {
                alpha: -0.1,
                ..base
            },
            "alpha",
        );
        refused(
            ArtificialViscosity {
                alpha: 10.1,
                ..base
            },
            "alpha",
        );
        refused(ArtificialViscosity { beta: 10.1, ..base }, "beta");
        refused(ArtificialViscosity { beta: -0.1, ..base }, "beta");
        refused(
            ArtificialViscosity {
                alpha_u: 10.1,
                ..base
            },
            "alpha_u",
        );
        refused(ArtificialViscosity { eta2: 0.0, ..base }, "eta2");
        refused(ArtificialViscosity { eta2: 1.01, ..base }, "eta2");
        let switch = ViscositySwitch {
            alpha_min: 0.1,
            decay: 0.2,
        };
        let switched = ArtificialViscosity {
            switch: Some(switch),
            ..base
        };
        assert_eq!(switched.validate(), Ok(()));
        let edges = [(0.0, 1.0), (1.0, 1e-9)];
        for (alpha_min, decay) in edges {
            let edge = ArtificialViscosity {
                switch: Some(ViscositySwitch { alpha_min, decay }),
                ..base
            };
            assert_eq!(edge.validate(), Ok(()), "α_min {alpha_min}, ℓ {decay}");
        }
        refused(
            ArtificialViscosity {
                alpha: 0.0,
                ..switched
            },
            "alpha",
        );
        for (alpha_min, decay, field) in [
            (-0.01, 0.2, "switch alpha_min"),
            (1.01, 0.2, "switch alpha_min"),
            (0.1, 0.0, "switch decay"),
            (0.1, 1.01, "switch decay"),
        ] {
            refused(
                ArtificialViscosity {
                    switch: Some(ViscositySwitch { alpha_min, decay }),
                    ..base
                },
                field,
            );
        }
        let with_penalty = |n1: f64, n2: f64, p_bar: f64| ArtificialViscosity {
            interface_penalty: Some(InterfacePenalty { p_bar, n1, n2 }),
            ..base
        };
        assert_eq!(with_penalty(12.0, 6.0, 0.0).validate(), Ok(()));
        refused(with_penalty(12.0, 6.0, -1.0), "penalty p_bar");
        refused(with_penalty(12.0, 6.0, f64::INFINITY), "penalty p_bar");
        refused(with_penalty(6.0, 6.0, 1.0), "penalty exponents n1/n2");
        refused(with_penalty(12.0, 0.0, 1.0), "penalty exponents n1/n2");
        refused(
            with_penalty(f64::INFINITY, 6.0, 1.0),
            "penalty exponents n1/n2",
        );
    }

    /// f^n by squaring for a whole n agrees with the power function to a few roundings (4 ulp:
    /// each squaring or product rounds once, the power function at most once); a fractional n
    /// takes the power function itself.
    #[test]
    fn the_artificial_stress_weight_is_f_to_the_n() {
        for exponent in [4.0, 3.0, 1.0, 0.0, -2.0, 2.5] {
            let stress = ArtificialStress {
                epsilon: 0.3,
                exponent,
            };
            for f in [0.37, 1.0, 1.9] {
                let (got, want) = (stress.weight(f), f64::powf(f, exponent));
                assert!(
                    (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                    "{f}^{exponent}: {got} against {want}"
                );
            }
        }
        let fractional = ArtificialStress {
            epsilon: 0.3,
            exponent: 2.5,
        };
        assert_eq!(fractional.weight(0.37), 0.37f64.powf(2.5));
        assert_eq!(ArtificialStress::default().weight(0.0), 0.0);
        // a whole n beyond 64 takes the power function too: (1 − 1e-10)^1e10 = 1/e, where
        // squarings would stop at the integer's limit 2³¹ − 1 (0.81)
        let huge = ArtificialStress {
            epsilon: 0.3,
            exponent: 1e10,
        };
        let f = 1.0 - 1e-10;
        assert_eq!(huge.weight(f), f.powf(1e10));
        assert!((huge.weight(f) - (-1.0f64).exp()).abs() < 1e-6);
    }

    /// R = −ε Σ_{σ' > 0} σ'/ρ² n n^T: a state with one tensile principal stress along a
    /// turned axis gives R along that axis only; a compressed state none.
    #[test]
    fn artificial_stress_takes_the_tensile_principal_stresses_only() {
        let (angle, tension, compression, rho, epsilon) = (0.3f64, 4.0, -7.0, 1.7, 0.3);
        let n = Vector::<2>::new(angle.cos(), angle.sin());
        let t = Vector::<2>::new(-angle.sin(), angle.cos());
        let sigma = n * n.transpose() * tension + t * t.transpose() * compression;
        // σ = −pI + s: any split of σ into its mean and its deviator
        let pressure = -0.5 * sigma.trace();
        let deviatoric = sigma + Tensor::<2>::identity() * pressure;
        let r = artificial_stress_of(pressure, &deviatoric, rho, epsilon);
        let expected = n * n.transpose() * (-epsilon * tension / (rho * rho));
        assert!((r - expected).norm() < 1e-14, "{r} against {expected}");
        let compressed = artificial_stress_of(3.0, &Tensor::<3>::zeros(), rho, epsilon);
        assert_eq!(compressed, Tensor::<3>::zeros());
        // hydrostatic tension: every axis is tensile
        let pulled = artificial_stress_of(-3.0, &Tensor::<3>::zeros(), rho, epsilon);
        assert!((pulled + Tensor::<3>::identity() * (epsilon * 3.0 / (rho * rho))).norm() < 1e-14);
    }

    /// f = |∇·v|/(|∇·v| + |∇×v| + 10⁻⁴ c/h): compression without rotation, rotation without
    /// compression, the hoop rate in the divergence, and the 3D curl's norm.
    #[test]
    fn balsara_factor_separates_compression_from_rotation() {
        let (c, h) = (300.0, 0.01);
        let noise = 1e-4 * c / h;
        let compression = Tensor::<2>::identity() * -2.0;
        assert_relative_eq!(
            balsara_factor(&compression, 0.0, c, h),
            4.0 / (4.0 + noise),
            max_relative = 1e-14
        );
        let rotation = Tensor::<2>::new(0.0, -5.0, 5.0, 0.0);
        assert_eq!(balsara_factor(&rotation, 0.0, c, h), 0.0);
        // a planar divergence that the hoop rate cancels: no compression
        let radial = Tensor::<2>::new(-1.5, 0.0, 0.0, 0.0);
        assert_eq!(balsara_factor(&radial, 1.5, c, h), 0.0);
        assert_relative_eq!(
            balsara_factor(&radial, 0.5, c, h),
            1.0 / (1.0 + noise),
            max_relative = 1e-14
        );
        // 3D: ∇×v = (L_zy − L_yz, L_xz − L_zx, L_yx − L_xy) = (2, 4, 6)
        let mixed = Tensor::<3>::new(1.0, -3.0, 2.0, 3.0, 2.0, -1.0, -2.0, 1.0, -6.0);
        let curl = (2f64.powi(2) + 4f64.powi(2) + 6f64.powi(2)).sqrt();
        assert_relative_eq!(
            balsara_factor(&mixed, 0.0, c, h),
            3.0 / (3.0 + curl + noise),
            max_relative = 1e-14
        );
    }

    /// [`approaching_pair`] with deviatoric stress fields (zero), for the stress passes.
    fn approaching_solids() -> Particles<2> {
        approaching_pair(OptionalFields {
            stress: true,
            ..OptionalFields::default()
        })
    }

    /// Two interacting 2D particles of different materials with every property distinct
    /// (mass, h, ρ, p, c, u, velocity; approaching), and four far away that interact with
    /// nothing: passes over one particle among six read their partners directly, over two
    /// they pack every source first (see `pairs::gather_at`).
    fn approaching_pair(optional: OptionalFields) -> Particles<2> {
        let particle =
            |x: f64, y: f64, vx: f64, vy: f64, mass: f64, h: f64, rho: f64| ParticleInit {
                position: Vector::<2>::new(x, y),
                velocity: Vector::<2>::new(vx, vy),
                mass,
                smoothing_length: h,
                density: rho,
                internal_energy: 0.0,
                material: 0,
            };
        let mut init = vec![
            particle(0.0, 0.0, 1.0, 0.5, 0.3, 0.6, 1.2),
            particle(0.4, 0.2, -0.8, -0.2, 0.5, 0.5, 2.1),
        ];
        init[1].material = 1;
        for k in 0..4 {
            init.push(particle(
                100.0 + 10.0 * k as f64,
                0.0,
                0.0,
                0.0,
                1.0,
                0.5,
                1.0,
            ));
        }
        let mut p = Particles::new(&init, optional);
        p.pressure[..2].copy_from_slice(&[3.0, 7.0]);
        p.sound_speed[..2].copy_from_slice(&[2.0, 3.5]);
        p.internal_energy[..2].copy_from_slice(&[5.0, 1.5]);
        if optional.grad_h {
            p.omega[..2].copy_from_slice(&[0.9, 1.15]);
        }
        p
    }

    fn kernel_pairs(p: &Particles<2>, kernel: &Kernel<2>, pair_kernel: PairKernel) -> KernelPairs {
        let reach = match pair_kernel {
            PairKernel::MeanH => PairReach::MeanH,
            PairKernel::OwnH => PairReach::LargerH,
        };
        let support = kernel.support_radius(1.0);
        let neighbours =
            find_neighbours(&p.position, &p.smoothing_length, support, reach, p.n_real());
        let mut pairs = KernelPairs::default();
        let all: Vec<usize> = (0..p.n_real()).collect();
        pairs.rebuild(p, &neighbours, kernel, pair_kernel, &all);
        pairs
    }

    /// The velocity gradients of particles 0 and 1 (planar), and the stress pass over them
    /// with `shear_modulus` per material: the gradients and the pass's totals.
    fn stress_pass(
        p: &mut Particles<2>,
        pairs: &KernelPairs,
        kernel: &Kernel<2>,
        shear_modulus: &[f64],
        artificial: Option<ArtificialStress>,
    ) -> (Vec<Tensor<2>>, Vec<RateTotals<2>>) {
        let geometry = PairGeometry::Planar;
        let gradients = velocity_gradients(p, pairs, geometry, &[0, 1]);
        let mut books = vec![RateTotals::default(); 2];
        add_stress_rates(
            p,
            pairs,
            kernel,
            &gradients,
            shear_modulus,
            artificial,
            geometry,
            None,
            &[0, 1],
            &mut books,
        );
        (gradients, books)
    }

    /// The Euler pair terms of [`compute_rates`] written out for particle 0 of
    /// [`approaching_pair`] in each form: standard (mean h and grad-h, each energy equation)
    /// and volume (continuity density), with conduction and the interface penalty; particle 1
    /// takes the opposite force (momentum), and a pass over particle 1 alone gives what a pass
    /// over both gives it.
    #[test]
    fn euler_pair_terms_are_the_equations_written_out() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let penalty = InterfacePenalty {
            p_bar: 0.7,
            n1: 4.0,
            n2: 2.0,
        };
        let forms = [
            (
                OptionalFields::default(),
                PairKernel::MeanH,
                EnergyEquation::OwnPressure,
                None,
            ),
            (
                OptionalFields::default(),
                PairKernel::MeanH,
                EnergyEquation::Symmetric,
                Some(penalty),
            ),
            (
                OptionalFields {
                    grad_h: true,
                    ..OptionalFields::default()
                },
                PairKernel::OwnH,
                EnergyEquation::OwnPressure,
                None,
            ),
            (
                OptionalFields {
                    density_rate: true,
                    ..OptionalFields::default()
                },
                PairKernel::MeanH,
                EnergyEquation::OwnPressure,
                Some(penalty),
            ),
        ];
        for (optional, pair_kernel, energy, interface_penalty) in forms {
            let form = format!("{optional:?} {pair_kernel:?} {energy:?} {interface_penalty:?}");
            let viscosity = ArtificialViscosity {
                interface_penalty,
                ..distinct_viscosity()
            };
            let mut p = approaching_pair(optional);
            // in the grad-h form each particle carries its own α and Balsara factor, which
            // scale Π by (α_0 + α_1)/(2α) and (f_0 + f_1)/2
            let mut pi_scale = 1.0;
            if optional.grad_h {
                p.viscosity_alpha = vec![0.5, 0.3, 0.8, 0.8, 0.8, 0.8];
                p.balsara_factor = vec![0.9, 0.4, 1.0, 1.0, 1.0, 1.0];
                pi_scale = (0.5 + 0.3) / (2.0 * 0.8) * (0.9 + 0.4) / 2.0;
            }
            let pairs = kernel_pairs(&p, &kernel, pair_kernel);
            let mut books = vec![RateTotals::default(); 2];
            let geometry = PairGeometry::Planar;
            compute_rates(
                &mut p,
                &pairs,
                &viscosity,
                energy,
                geometry,
                &[0, 1],
                &mut books,
            );

            let (m, h, rho) = (&p.mass, &p.smoothing_length, &p.density);
            let (pr, c, u) = (&p.pressure, &p.sound_speed, &p.internal_energy);
            let dx = p.position[0] - p.position[1];
            let r = dx.norm();
            let (h_mean, rho_mean) = (0.5 * (h[0] + h[1]), 0.5 * (rho[0] + rho[1]));
            let (dw_i, dw_j) = match pair_kernel {
                PairKernel::MeanH => (kernel.derivative(r, h_mean), kernel.derivative(r, h_mean)),
                PairKernel::OwnH => (kernel.derivative(r, h[0]), kernel.derivative(r, h[1])),
            };
            let v_r = (p.velocity[0] - p.velocity[1]).dot(&dx) / r;
            assert!(
                v_r < 0.0 && dw_i < 0.0 && dw_j < 0.0,
                "{form}: the pair approaches"
            );
            let mu = h_mean * v_r * r / (r * r + 0.03 * h_mean * h_mean);
            let pi = (-0.8 * 0.5 * (c[0] + c[1]) * mu + 1.7 * mu * mu) / rho_mean * pi_scale;
            let omega = |k: usize| p.omega.get(k).copied().unwrap_or(1.0);
            // the pressure terms m_j P_i dW_i and m_j P_j dW_j of each form
            let (own, partner) = if optional.density_rate {
                (pr[0] / (rho[0] * rho[1]), pr[1] / (rho[1] * rho[0]))
            } else {
                (
                    pr[0] / (omega(0) * rho[0] * rho[0]),
                    pr[1] / (omega(1) * rho[1] * rho[1]),
                )
            };
            let (own, partner) = (m[1] * own * dw_i, m[1] * partner * dw_j);
            let viscous = m[1] * pi * 0.5 * (dw_i + dw_j);
            let mut force = -(own + partner + viscous) * dx / r;
            if interface_penalty.is_some() {
                let pe: f64 = h_mean / r;
                assert!(pe > 1.0, "{form}: the penalty acts");
                let push = 0.7 * (pe.powi(4) - pe.powi(2)) / (r * r);
                force += dx * push * 2.0 * m[0] * m[1] / (m[0] + m[1]) / m[0];
            }
            let work = match energy {
                EnergyEquation::OwnPressure => own,
                EnergyEquation::Symmetric => 0.5 * (own + partner),
            };
            let conduction =
                0.4 * ((pr[0] - pr[1]).abs() / rho_mean).sqrt() * (u[0] - u[1]) / rho_mean;
            let heating = 0.5 * viscous * v_r;
            let energy_rate = heating + work * v_r + m[1] * 0.5 * (dw_i + dw_j) * conduction;
            let tolerance = 1e-13;
            assert!(
                (p.acceleration[0] - force).norm() <= tolerance * force.norm(),
                "{form}: {} against {force}",
                p.acceleration[0]
            );
            assert_relative_eq!(p.energy_rate[0], energy_rate, max_relative = tolerance);
            assert_relative_eq!(
                p.signal_speed[0],
                c[0] + c[1] - 3.0 * v_r,
                max_relative = tolerance
            );
            assert_relative_eq!(
                books[0].viscous_heating,
                m[0] * heating,
                max_relative = tolerance
            );
            assert_eq!(books[0].wall_force, Vector::<2>::zeros());
            if optional.density_rate {
                let continuity = rho[0] * m[1] / rho[1] * dw_i * v_r;
                assert_relative_eq!(p.density_rate[0], continuity, max_relative = tolerance);
            }
            if optional.grad_h {
                let density_rate = m[1] * dw_i * v_r / omega(0);
                let smoothing_rate = -h[0] * density_rate / (2.0 * rho[0]);
                assert_relative_eq!(
                    p.smoothing_rate[0],
                    smoothing_rate,
                    max_relative = tolerance
                );
            }
            let momentum = p.acceleration[0] * m[0] + p.acceleration[1] * m[1];
            assert!(
                momentum.norm() <= tolerance * force.norm() * m[0],
                "{form}: {momentum}"
            );
            for k in 2..p.n_real() {
                assert_eq!(p.acceleration[k], Vector::<2>::zeros());
            }

            let (alone, both) = (p.clone(), p.clone());
            let mut alone = alone;
            alone.acceleration[1] = Vector::<2>::zeros();
            let mut book = vec![RateTotals::default()];
            compute_rates(
                &mut alone,
                &pairs,
                &viscosity,
                energy,
                geometry,
                &[1],
                &mut book,
            );
            assert_eq!(alone.acceleration[1], both.acceleration[1], "{form}");
            assert_eq!(alone.energy_rate[1], both.energy_rate[1], "{form}");
            assert_eq!(book[0], books[1], "{form}");
        }
    }

    /// The velocity gradient L_0 = m_1 w (v_1 − v_0) ⊗ ∇_0 W and the stress pair terms of
    /// [`add_stress_rates`] written out for particle 0 of [`approaching_pair`], standard (w =
    /// 1/(Ω_0 ρ_0), grad-h) and volume form (w = 1/ρ_1), with Monaghan's artificial stress
    /// (both particles in tension, so that R ≠ 0) and without; the heating s:ε̇/ρ and the
    /// stress rate from L; momentum.
    #[test]
    fn stress_pair_terms_are_the_equations_written_out() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let stress = OptionalFields {
            stress: true,
            ..OptionalFields::default()
        };
        let forms = [
            (
                OptionalFields {
                    grad_h: true,
                    ..stress
                },
                PairKernel::OwnH,
                None,
            ),
            (
                OptionalFields {
                    density_rate: true,
                    ..stress
                },
                PairKernel::MeanH,
                Some(ArtificialStress {
                    epsilon: 0.3,
                    exponent: 3.0,
                }),
            ),
        ];
        let shear_modulus = [40.0, 25.0];
        for (optional, pair_kernel, artificial) in forms {
            let form = format!("{optional:?} {pair_kernel:?} {artificial:?}");
            let mut p = approaching_pair(optional);
            // tension: p < 0 along with a shear
            p.pressure[..2].copy_from_slice(&[-3.0, -2.0]);
            p.deviatoric_stress[0] = Tensor::<2>::new(1.5, 0.7, 0.7, -0.4);
            p.deviatoric_stress[1] = Tensor::<2>::new(-0.6, 1.1, 1.1, 0.9);
            let pairs = kernel_pairs(&p, &kernel, pair_kernel);
            let (gradients, books) =
                stress_pass(&mut p, &pairs, &kernel, &shear_modulus, artificial);

            let (m, h, rho) = (&p.mass, &p.smoothing_length, &p.density);
            let omega = |k: usize| p.omega.get(k).copied().unwrap_or(1.0);
            let dx = p.position[0] - p.position[1];
            let r = dx.norm();
            let h_mean = 0.5 * (h[0] + h[1]);
            let (dw_i, dw_j) = match pair_kernel {
                PairKernel::MeanH => (kernel.derivative(r, h_mean), kernel.derivative(r, h_mean)),
                PairKernel::OwnH => (kernel.derivative(r, h[0]), kernel.derivative(r, h[1])),
            };
            let weight = if optional.density_rate {
                1.0 / rho[1]
            } else {
                1.0 / (omega(0) * rho[0])
            };
            let gradient =
                (p.velocity[1] - p.velocity[0]) * (dx / r).transpose() * (m[1] * weight * dw_i);
            assert!(
                (gradients[0] - gradient).norm() <= 1e-13 * gradient.norm(),
                "{form}: L {} against {gradient}",
                gradients[0]
            );
            let s = &p.deviatoric_stress;
            let (own, partner) = if optional.density_rate {
                (s[0] / (rho[0] * rho[1]), s[1] / (rho[1] * rho[0]))
            } else {
                (
                    s[0] / (omega(0) * rho[0] * rho[0]),
                    s[1] / (omega(1) * rho[1] * rho[1]),
                )
            };
            let mut force = (own * dw_i + partner * dw_j) * (dx / r) * m[1];
            let mut heating = 0.0;
            if let Some(a) = artificial {
                let spacing = |k: usize| (m[k] / rho[k]).sqrt();
                let f =
                    kernel.value(r, h_mean) / kernel.value(0.5 * (spacing(0) + spacing(1)), h_mean);
                let tensile = |k: usize| artificial_stress_of(p.pressure[k], &s[k], rho[k], 0.3);
                assert!(tensile(0).norm() > 0.0 && tensile(1).norm() > 0.0, "{form}");
                let repulsion = (tensile(0) + tensile(1))
                    * (dx / r)
                    * (m[1] * f.powf(a.exponent) * 0.5 * (dw_i + dw_j));
                force += repulsion;
                heating = -0.5 * repulsion.dot(&(p.velocity[0] - p.velocity[1]));
            }
            // compute_rates did not run: the accelerations and energy rates are this pass's
            assert!(
                (p.acceleration[0] - force).norm() <= 1e-13 * force.norm(),
                "{form}: {} against {force}",
                p.acceleration[0]
            );
            let strain_rate = 0.5 * (gradient + gradient.transpose());
            let deviatoric_heating = s[0].component_mul(&strain_rate).sum() / rho[0];
            assert_relative_eq!(
                p.energy_rate[0],
                deviatoric_heating + heating,
                max_relative = 1e-12
            );
            assert_relative_eq!(
                books[0].artificial_stress_heating,
                m[0] * heating,
                max_relative = 1e-12
            );
            let expected_rate = crate::strength::jaumann_rate(40.0, &s[0], &gradients[0], 0.0);
            assert_eq!(p.stress_rate[0], expected_rate, "{form}");
            assert_eq!(
                p.strain_rate[0],
                crate::strength::equivalent_strain_rate(
                    &(0.5 * (gradients[0] + gradients[0].transpose())),
                    0.0
                )
            );
            let momentum = p.acceleration[0] * m[0] + p.acceleration[1] * m[1];
            assert!(
                momentum.norm() <= 1e-13 * force.norm() * m[0],
                "{form}: {momentum}"
            );
        }
    }

    /// A particle whose only partner is its own mirror image across a wall: all its force is
    /// the wall's, booked as m a in both passes; the totals add field by field.
    #[test]
    fn a_wall_image_force_is_booked_as_the_walls() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let mut p = approaching_solids();
        // particle 1 far away, particle 0 mirrored across the wall x = 0.15
        p.position[1] = Vector::<2>::new(50.0, 0.0);
        p.deviatoric_stress[0] = Tensor::<2>::new(1.5, 0.7, 0.7, -0.4);
        p.push_image(
            0,
            Vector::<2>::new(-1.0, 1.0),
            Vector::<2>::new(0.3, 0.0),
            true,
        );
        let pairs = kernel_pairs(&p, &kernel, PairKernel::MeanH);
        let geometry = PairGeometry::Planar;
        let mut books = vec![RateTotals::default(); 2];
        let viscosity = distinct_viscosity();
        let energy = EnergyEquation::OwnPressure;
        compute_rates(
            &mut p,
            &pairs,
            &viscosity,
            energy,
            geometry,
            &[0, 1],
            &mut books,
        );
        let pushed = p.acceleration[0] * p.mass[0];
        assert!(pushed[0] < 0.0, "the wall pushes back: {pushed}");
        assert!((books[0].wall_force - pushed).norm() <= 1e-14 * pushed.norm());
        let before = p.acceleration[0];
        let (_, stress_books) = stress_pass(&mut p, &pairs, &kernel, &[40.0, 25.0], None);
        let stress_push = (p.acceleration[0] - before) * p.mass[0];
        assert!(stress_push.norm() > 0.0);
        let booked = stress_books[0].wall_force;
        assert!((booked - stress_push).norm() <= 1e-12 * stress_push.norm());

        let mut total = books[0];
        let other = RateTotals {
            wall_force: Vector::<2>::new(0.5, -2.0),
            viscous_heating: 3.0,
            artificial_stress_heating: 5.0,
            hourglass_heating: 7.0,
            transmitted_power: 11.0,
        };
        total += &other;
        assert_eq!(total.wall_force, books[0].wall_force + other.wall_force);
        assert_eq!(total.viscous_heating, books[0].viscous_heating + 3.0);
        assert_eq!(
            total.artificial_stress_heating,
            books[0].artificial_stress_heating + 5.0
        );
        assert_eq!(total.hourglass_heating, books[0].hourglass_heating + 7.0);
        assert_eq!(total.transmitted_power, books[0].transmitted_power + 11.0);
    }

    /// Far from the axis a ring is a strip of the plane: rings about 10⁶ h out, each of mass
    /// 2πr times its planar particle's, feel the planar pair's stress forces, the artificial
    /// stress's among them, to the relative change of r across the pair (4e-7; measured 2e-7,
    /// limit 2e-6).
    #[test]
    fn far_from_the_axis_rings_feel_the_planar_stress_forces() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let mut planar = approaching_solids();
        // both in tension, so that the artificial stress acts on both
        planar.pressure[..2].copy_from_slice(&[-3.0, -7.0]);
        planar.deviatoric_stress[0] = Tensor::<2>::new(1.5, 0.7, 0.7, -0.4);
        planar.deviatoric_stress[1] = Tensor::<2>::new(-0.5, 0.2, 0.2, 0.9);
        let mut rings = planar.clone();
        for k in 0..rings.n_real() {
            rings.position[k][0] += 1e6;
            rings.mass[k] *= 2.0 * std::f64::consts::PI * rings.position[k][0];
        }
        let stress_forces = |p: &mut Particles<2>, geometry: PairGeometry| {
            let pairs = kernel_pairs(p, &kernel, PairKernel::MeanH);
            let gradients = velocity_gradients(p, &pairs, geometry, &[0, 1]);
            let mut books = vec![RateTotals::default(); 2];
            let before = [p.acceleration[0], p.acceleration[1]];
            add_stress_rates(
                p,
                &pairs,
                &kernel,
                &gradients,
                &[40.0, 25.0],
                Some(ArtificialStress::default()),
                geometry,
                None,
                &[0, 1],
                &mut books,
            );
            [p.acceleration[0] - before[0], p.acceleration[1] - before[1]]
        };
        let flat = stress_forces(&mut planar, PairGeometry::Planar);
        let ring = stress_forces(&mut rings, PairGeometry::Axisymmetric);
        for k in 0..2 {
            assert!(flat[k].norm() > 0.0);
            assert!(
                (ring[k] - flat[k]).norm() <= 2e-6 * flat[k].norm(),
                "particle {k}: ring {} against planar {}",
                ring[k],
                flat[k]
            );
        }
    }

    /// Grad-h lists a pair that only the larger smoothing length reaches, from both sides,
    /// with the smaller one's derivative 0: its force acts through the larger kernel alone.
    #[test]
    fn grad_h_keeps_a_pair_that_only_the_larger_h_reaches() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let mut p = approaching_pair(OptionalFields {
            grad_h: true,
            ..OptionalFields::default()
        });
        // r = 0.447: beyond the support 2h of h_1 = 0.2, within that of h_0 = 0.6
        p.smoothing_length[1] = 0.2;
        let pairs = kernel_pairs(&p, &kernel, PairKernel::OwnH);
        let links = |i: usize| {
            let mut found = Vec::new();
            pairs::Partners::visit(&pairs, i, |j, link: &KernelLink| {
                found.push((j, link.dw_i, link.dw_j))
            });
            found
        };
        let r = (p.position[1] - p.position[0]).norm();
        let larger = kernel.derivative(r, 0.6);
        assert!(larger < 0.0);
        assert_eq!(links(0), [(1, larger, 0.0)]);
        assert_eq!(links(1), [(0, 0.0, larger)]);
    }

    /// The interface penalty from a wall image of another material is the wall's force too:
    /// booked with the pressure and the viscosity as m a of the particle it pushes.
    #[test]
    fn an_interface_penalty_across_a_wall_is_booked_as_the_walls() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let mut p = approaching_pair(OptionalFields::default());
        // particle 1 (material 1) far away; its mirror image across a wall lies beside particle
        // 0 (material 0), at r = 0.22 with h̄ = 0.55: h̄/r = 2.5, inside the penalty's reach
        p.position[1] = Vector::<2>::new(50.0, 0.0);
        p.push_image(
            1,
            Vector::<2>::new(-1.0, 1.0),
            Vector::<2>::new(50.2, 0.1),
            true,
        );
        let pairs = kernel_pairs(&p, &kernel, PairKernel::MeanH);
        let run = |interface_penalty| {
            let mut q = p.clone();
            let mut books = vec![RateTotals::default(); 2];
            let viscosity = ArtificialViscosity {
                interface_penalty,
                ..distinct_viscosity()
            };
            let energy = EnergyEquation::OwnPressure;
            let geometry = PairGeometry::Planar;
            compute_rates(
                &mut q,
                &pairs,
                &viscosity,
                energy,
                geometry,
                &[0, 1],
                &mut books,
            );
            (q.acceleration[0] * q.mass[0], books[0].wall_force)
        };
        let (plain, plain_booked) = run(None);
        let (pushed, booked) = run(Some(InterfacePenalty::seed(10.0)));
        assert!(
            (pushed - plain).norm() > plain.norm(),
            "the penalty acts: {plain} without, {pushed} with"
        );
        // the sums differ in their order of additions: a few roundings of the largest term
        assert!((plain_booked - plain).norm() <= 1e-13 * plain.norm());
        assert!(
            (booked - pushed).norm() <= 1e-13 * pushed.norm(),
            "{booked} booked against {pushed}"
        );
    }

    /// A fluid particle (G = 0) carries no artificial stress, even in tension, and gets no
    /// stress rate.
    #[test]
    fn a_fluid_particle_gets_no_artificial_stress_and_no_stress_rate() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let mut p = approaching_solids();
        p.pressure[0] = -3.0;
        p.deviatoric_stress[0] = Tensor::<2>::new(1.5, 0.7, 0.7, -0.4);
        let pairs = kernel_pairs(&p, &kernel, PairKernel::MeanH);
        let shear_modulus = [0.0, 25.0];
        let runs = [None, Some(ArtificialStress::default())].map(|artificial| {
            let mut q = p.clone();
            stress_pass(&mut q, &pairs, &kernel, &shear_modulus, artificial);
            q
        });
        // particle 1 is compressed (p = 7, s = 0): its R is zero too
        assert_eq!(runs[0].acceleration[0], runs[1].acceleration[0]);
        assert_eq!(runs[0].stress_rate[0], Tensor::<2>::zeros());
        assert!(runs[0].stress_rate[1].norm() > 0.0);
    }

    /// A 9 × 9 lattice of spacing 0.1 shaken by up to 0.03 in each direction, masses of about
    /// ρ = 1.5 varied by up to ±10 %, every h = 0.13.
    fn shaken_lattice() -> Particles<2> {
        let mut random = crate::random::SplitMix64::new(7);
        let mut init = Vec::new();
        for a in 0..9 {
            for b in 0..9 {
                let mut shake = || 0.03 * (2.0 * random.uniform() - 1.0);
                let position = Vector::<2>::new(0.1 * a as f64 + shake(), 0.1 * b as f64 + shake());
                init.push(ParticleInit {
                    position,
                    velocity: Vector::<2>::zeros(),
                    mass: 1.5e-2 * (1.0 + 0.2 * (random.uniform() - 0.5)),
                    smoothing_length: 0.13,
                    density: 1.5,
                    internal_energy: 0.0,
                    material: 0,
                });
            }
        }
        Particles::new(&init, OptionalFields::default())
    }

    /// Lists of every pair within the kernel's reach at the larger of the two `reach`es, as
    /// grad-h's solve needs them.
    fn grad_h_lists(p: &Particles<2>, kernel: &Kernel<2>, reach: &[f64]) -> NeighbourList {
        find_neighbours(
            &p.position,
            reach,
            kernel.support_radius(1.0),
            PairReach::LargerH,
            p.n_real(),
        )
    }

    /// Σ_j m_j W(r, h) over every particle by brute force (the particle itself included).
    fn brute_density(p: &Particles<2>, kernel: &Kernel<2>, i: usize, h: f64) -> f64 {
        (0..p.n_real())
            .map(|j| p.mass[j] * kernel.value((p.position[i] - p.position[j]).norm(), h))
            .sum()
    }

    /// Grad-h's root against brute-force sums: ρ = Σ_j m_j W(r_ij, h) at the returned h,
    /// h = η (m/ρ)^(1/2) within the tolerance, Ω = 1 + h/(2ρ) ∂ρ/∂h by central differences;
    /// the same root from a guess far below and far above; a root beyond the reach reported
    /// as such.
    #[test]
    fn grad_h_solves_for_the_smoothing_length_of_its_own_density() {
        let p = shaken_lattice();
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let (eta, tolerance) = (1.3, 1e-10);
        let reach = vec![0.4; p.n_real()];
        let neighbours = grad_h_lists(&p, &kernel, &reach);
        let which = [40, 0, 13];
        let solve = |guess: f64, reach: &[f64]| {
            let guesses = vec![guess; p.n_real()];
            solve_smoothing_lengths(
                &p,
                &neighbours,
                &kernel,
                (eta, tolerance),
                (&guesses, reach),
                &which,
            )
        };
        let solutions = solve(0.13, &reach);
        for (&i, solution) in which.iter().zip(&solutions) {
            let SmoothingSolution::Converged { h, density, omega } = *solution else {
                panic!("particle {i}: {solution:?}");
            };
            assert_relative_eq!(
                density,
                brute_density(&p, &kernel, i, h),
                max_relative = 1e-12
            );
            assert_relative_eq!(h, eta * (p.mass[i] / density).sqrt(), max_relative = 1e-9);
            let step = 1e-6 * h;
            let slope = (brute_density(&p, &kernel, i, h + step)
                - brute_density(&p, &kernel, i, h - step))
                / (2.0 * step);
            assert_relative_eq!(
                omega,
                1.0 + h * slope / (2.0 * density),
                max_relative = 1e-7
            );
            for guess in [0.01, 0.39] {
                let SmoothingSolution::Converged { h: again, .. } =
                    solve(guess, &reach)[which.iter().position(|&k| k == i).unwrap()]
                else {
                    panic!("particle {i} from {guess}");
                };
                assert_relative_eq!(again, h, max_relative = 1e-9);
            }
        }
        let SmoothingSolution::Converged { h: root, .. } = solutions[0] else {
            unreachable!()
        };
        let short = vec![0.5 * root; p.n_real()];
        match solve(0.13, &short)[0] {
            SmoothingSolution::BeyondReach { h } => assert!(h > 0.5 * root, "{h}"),
            other => panic!("{other:?}"),
        }
    }

    /// Grad-h's root from guesses a millionth of the reach up to the reach, on lattices a
    /// millimetre, a metre and a kilometre across, and from a billion times the root: every solve converges, to h = η (m/ρ)^(1/2)
    /// with ρ the brute-force sum at h (to 1e-9: the solve stops on a step below 1e-10 h), and
    /// the root scales with the lattice. Newton's last step near the root is often below h's
    /// last digit, so h − f/f′ rounds onto h, an end of the bracket; refused there, it sent the
    /// search into doubling and bisection, which ran out of iterations from the far guesses.
    #[test]
    fn grad_h_finds_the_same_root_from_any_guess_in_any_unit() {
        let lattice = shaken_lattice();
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let (eta, tolerance) = (1.3, 1e-10);
        let which: Vec<usize> = (0..lattice.n_real()).collect();
        // every particle's root from `guess`, lists at `reach`, each checked against the
        // brute-force density at it
        let roots = |p: &Particles<2>, reach: f64, guess: f64| -> Vec<f64> {
            let reach = vec![reach; p.n_real()];
            let neighbours = grad_h_lists(p, &kernel, &reach);
            let guesses = vec![guess; p.n_real()];
            let solutions = solve_smoothing_lengths(
                p,
                &neighbours,
                &kernel,
                (eta, tolerance),
                (&guesses, &reach),
                &which,
            );
            let mut roots = Vec::new();
            for (i, solution) in solutions.into_iter().enumerate() {
                let SmoothingSolution::Converged { h, .. } = solution else {
                    panic!(
                        "reach {}, guess {guess}, particle {i}: {solution:?}",
                        reach[i]
                    );
                };
                let density = brute_density(p, &kernel, i, h);
                assert_relative_eq!(h, eta * (p.mass[i] / density).sqrt(), max_relative = 1e-9);
                roots.push(h);
            }
            roots
        };
        let at_one_metre = roots(&lattice, 0.4, 0.4);
        for scale in [1.0, 1e-3, 1e3] {
            let mut p = lattice.clone();
            p.position.iter_mut().for_each(|x| *x *= scale);
            for k in 0..=24 {
                let guess = 0.4 * scale * 10f64.powf(-0.25 * k as f64);
                for (h, root) in roots(&p, 0.4 * scale, guess).iter().zip(&at_one_metre) {
                    assert_relative_eq!(*h, scale * root, max_relative = 1e-9);
                }
            }
        }
        // from a billion times the root, every particle within reach: halvings down to it
        // (about 31), then Newton's few steps within the 60 iterations allowed (bisection alone
        // would need 33 more)
        for (h, root) in roots(&lattice, 4e8, 4e8).iter().zip(&at_one_metre) {
            assert_relative_eq!(h, root, max_relative = 1e-9);
        }
    }

    /// Summation density against brute force (self term at h_i, partners at h̄_ij); the
    /// kernel-gradient sum g_i = Σ_j V_j ∇_i W_ij antisymmetric in the pair, so Σ_i V_i g_i = 0
    /// for any arrangement, while a particle at the lattice's edge gets a g pointing into it.
    #[test]
    fn density_and_kernel_gradient_sums_against_brute_force() {
        let mut p = shaken_lattice();
        for (k, h) in p.smoothing_length.iter_mut().enumerate() {
            *h *= 1.0 + 0.1 * ((k % 5) as f64 - 2.0) / 2.0;
        }
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let neighbours = find_neighbours(
            &p.position,
            &p.smoothing_length,
            kernel.support_radius(1.0),
            PairReach::MeanH,
            p.n_real(),
        );
        let density = pairs::gather(&SummationDensity { kernel: &kernel }, &p, &neighbours);
        for (i, &summed) in density.iter().enumerate() {
            let h_i = p.smoothing_length[i];
            let brute: f64 = (0..p.n_real())
                .map(|j| {
                    let h = if i == j {
                        h_i
                    } else {
                        0.5 * (h_i + p.smoothing_length[j])
                    };
                    p.mass[j] * kernel.value((p.position[i] - p.position[j]).norm(), h)
                })
                .sum();
            assert_relative_eq!(summed, brute, max_relative = 1e-13);
        }
        p.density.copy_from_slice(&density);
        let sums = KernelGradientSum {
            kernel: &kernel,
            axisymmetric: false,
        };
        let g = pairs::gather(&sums, &p, &neighbours);
        let volume = |k: usize| p.mass[k] / p.density[k];
        let total: Vector<2> = (0..p.n_real()).map(|i| g[i] * volume(i)).sum();
        let scale: f64 = (0..p.n_real()).map(|i| g[i].norm() * volume(i)).sum();
        assert!(
            scale > 0.0 && total.norm() <= 1e-13 * scale,
            "{total} of {scale}"
        );
        // particle 4 sits on the side x ≈ 0, its partners at x > 0: ∇_i W points towards
        // each, and the sum into the lattice, about 1/(2h) there (−Σ V g·n = ½ per unit area)
        assert!(g[4][0] > 1.0, "{}", g[4]);
        // rings: the same sums with each partner's volume divided by 2π r
        let rings = pairs::gather(
            &KernelGradientSum {
                kernel: &kernel,
                axisymmetric: true,
            },
            &p,
            &neighbours,
        );
        let i = 40;
        let expected: Vector<2> = neighbours
            .of(i)
            .map(|j| {
                let dx = p.position[i] - p.position[j];
                let h = 0.5 * (p.smoothing_length[i] + p.smoothing_length[j]);
                kernel.gradient(&dx, dx.norm(), h) * volume(j)
                    / (2.0 * std::f64::consts::PI * p.position[j][0])
            })
            .sum();
        assert!((rings[i] - expected).norm() <= 1e-13 * expected.norm());
    }

    /// The kernel links of some particles equal those of all, row by row; coincident
    /// particles and partners beyond the kernel's reach get none.
    #[test]
    fn kernel_pairs_of_some_particles_are_those_of_all() {
        let mut p = shaken_lattice();
        // particle 1 onto particle 0
        p.position[1] = p.position[0];
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        // lists that reach twice as far as the kernel
        let wide = vec![0.26; p.n_real()];
        let neighbours = find_neighbours(
            &p.position,
            &wide,
            kernel.support_radius(1.0),
            PairReach::MeanH,
            p.n_real(),
        );
        let links = |pairs: &KernelPairs, i: usize| {
            let mut links = Vec::new();
            pairs::Partners::visit(pairs, i, |j, link: &KernelLink| {
                links.push((j, link.r, link.dw_i, link.dw_j))
            });
            links
        };
        let all: Vec<usize> = (0..p.n_real()).collect();
        let mut every = KernelPairs::default();
        every.rebuild(&p, &neighbours, &kernel, PairKernel::MeanH, &all);
        let some = [57, 3, 40, 0];
        let mut part = KernelPairs::default();
        part.rebuild(&p, &neighbours, &kernel, PairKernel::MeanH, &some);
        for i in some {
            assert_eq!(links(&part, i), links(&every, i), "particle {i}");
        }
        for i in all {
            let expected: Vec<usize> = neighbours
                .of(i)
                .filter(|&j| {
                    let r = (p.position[i] - p.position[j]).norm();
                    r > 0.0 && kernel.reaches(r, 0.13)
                })
                .collect();
            let found: Vec<usize> = links(&every, i).into_iter().map(|l| l.0).collect();
            assert_eq!(found, expected, "particle {i}");
            assert!(neighbours.of(i).count() > found.len() + 1, "particle {i}");
        }
    }

    /// The kernel links in kilometres are those in metres: the same partners, r a thousand
    /// times and dW/dr a billionth (W ∝ h⁻² in 2D) to 1e-13, with h̄ = 130 m, where a prefilter
    /// that missed the mean of the two h would lose pairs.
    #[test]
    fn kernel_pairs_are_the_same_in_any_unit_of_length() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let metres = shaken_lattice();
        let mut kilometres = metres.clone();
        kilometres.position.iter_mut().for_each(|x| *x *= 1e3);
        kilometres
            .smoothing_length
            .iter_mut()
            .for_each(|h| *h *= 1e3);
        let links = |p: &Particles<2>, i: usize| {
            let mut links = Vec::new();
            let pairs = kernel_pairs(p, &kernel, PairKernel::MeanH);
            pairs::Partners::visit(&pairs, i, |j, link: &KernelLink| links.push((j, *link)));
            links
        };
        for i in [0, 13, 40] {
            let (small, large) = (links(&metres, i), links(&kilometres, i));
            assert!(small.len() > 4, "particle {i}: {} links", small.len());
            assert_eq!(small.len(), large.len(), "particle {i}");
            for ((j, a), (k, b)) in small.iter().zip(&large) {
                assert_eq!(j, k);
                assert_relative_eq!(b.r, 1e3 * a.r, max_relative = 1e-13);
                assert_relative_eq!(b.dw_i, 1e-9 * a.dw_i, max_relative = 1e-13);
                assert_relative_eq!(b.dw_j, 1e-9 * a.dw_j, max_relative = 1e-13);
            }
        }
    }

    /// The switch's step against its equation: without a source α relaxes to α_min as
    /// exp(−ℓ c t/h); under steady compression S it settles at the balance
    /// (α_min ℓc/h + S α_max)/(ℓc/h + S); two half steps make one whole step (the solution is
    /// exact for frozen coefficients); and no step, however long, leaves [α_min, α_max].
    #[test]
    fn viscosity_switch_follows_its_equation() {
        let switch = ViscositySwitch {
            alpha_min: 0.1,
            decay: 0.2,
        };
        let c_over_h = 5e6;
        let decayed = switch.relax(1.0, 1.0, 0.0, c_over_h, 1e-6);
        assert!((decayed - (0.1 + 0.9 * (-0.2 * c_over_h * 1e-6_f64).exp())).abs() < 1e-14);
        let compression = 3e6;
        let settled = switch.relax(0.1, 1.0, -compression, c_over_h, 1.0);
        let balance = (0.1 * 0.2 * c_over_h + compression) / (0.2 * c_over_h + compression);
        assert!((settled - balance).abs() < 1e-14);
        // the same with α_max = 2: the source drives α towards α_max, not towards 1
        let settled = switch.relax(0.1, 2.0, -compression, c_over_h, 1.0);
        let balance = (0.1 * 0.2 * c_over_h + 2.0 * compression) / (0.2 * c_over_h + compression);
        assert!((settled - balance).abs() < 1e-14);
        // expansion is no source
        assert_eq!(
            switch.relax(0.5, 1.0, compression, c_over_h, 1e-7),
            switch.relax(0.5, 1.0, 0.0, c_over_h, 1e-7)
        );
        let half = switch.relax(0.3, 1.0, -compression, c_over_h, 2e-7);
        let whole = switch.relax(half, 1.0, -compression, c_over_h, 2e-7);
        let once = switch.relax(0.3, 1.0, -compression, c_over_h, 4e-7);
        assert!((whole - once).abs() < 1e-14);
        for (k, dt) in [0.0, 1e-9, 1e-6, 1.0, 1e9].into_iter().enumerate() {
            for divergence in [-1e12, -1.0, 0.0, 1e9] {
                let alpha = switch.relax(0.1 + 0.2 * k as f64, 1.0, divergence, c_over_h, dt);
                assert!((0.1..=1.0).contains(&alpha), "α = {alpha}");
            }
        }
    }
}
