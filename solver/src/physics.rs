//! The Euler equations in SPH form (the seed's Table 3-3), as small pair terms and the loops that
//! sum them. Every pair uses the symmetrised kernel W(r_ij, h̄_ij), h̄_ij = (h_i + h_j)/2, so the
//! pair forces are antisymmetric and momentum and energy are conserved to round-off whatever
//! each particle's h is.
//!
//! Loops gather over each particle's own list (each pair is visited from both sides) so the
//! parallel result is bitwise independent of the thread count.

use crate::error::SolverError;
use crate::kernel::Kernel;
use crate::neighbours::NeighbourList;
use crate::particles::Particles;
use crate::Vector;
use rayon::prelude::*;

/// How density is obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DensityMethod {
    /// ρ_i = Σ_j m_j W_ij (self term included): exact mass conservation, smooths contact jumps.
    Summation,
    /// Dρ_i/Dt = Σ_j m_j v_ij · ∇_i W_ij: keeps density jumps sharp (the seed recommends it for
    /// strong discontinuities); the initial density is the prescribed one.
    Continuity,
}

impl DensityMethod {
    pub const ALL: [DensityMethod; 2] = [DensityMethod::Summation, DensityMethod::Continuity];

    pub fn name(self) -> &'static str {
        match self {
            DensityMethod::Summation => "summation",
            DensityMethod::Continuity => "continuity",
        }
    }
}

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
}

impl Default for ArtificialViscosity {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta: 2.0,
            eta2: 0.01,
            alpha_u: 0.0,
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
        Ok(())
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

/// What the density loop reads of a neighbour, packed so one cache line serves one pair.
#[derive(Clone, Copy)]
struct DensitySource<const D: usize> {
    position: Vector<D>,
    smoothing_length: f64,
    mass: f64,
}

/// Summation density ρ_i = m_i W(0, h_i) + Σ_j m_j W(r_ij, h̄_ij) for the real particles.
pub fn summation_density<const D: usize>(
    particles: &mut Particles<D>,
    neighbours: &NeighbourList,
    kernel: &Kernel<D>,
) {
    let n = particles.n_real();
    let p = &*particles;
    let sources: Vec<DensitySource<D>> = (0..p.len())
        .into_par_iter()
        .map(|k| DensitySource {
            position: p.position[k],
            smoothing_length: p.smoothing_length[k],
            mass: p.mass[k],
        })
        .collect();
    let density: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| density_at(i, &sources, neighbours, kernel))
        .collect();
    particles.density[..n].copy_from_slice(&density);
}

#[inline(never)]
fn density_at<const D: usize>(
    i: usize,
    sources: &[DensitySource<D>],
    neighbours: &NeighbourList,
    kernel: &Kernel<D>,
) -> f64 {
    let me = &sources[i];
    neighbours.of(i).fold(
        me.mass * kernel.value(0.0, me.smoothing_length),
        |rho, j| {
            let other = &sources[j];
            let r = (me.position - other.position).norm();
            let h = 0.5 * (me.smoothing_length + other.smoothing_length);
            rho + other.mass * kernel.value(r, h)
        },
    )
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
    /// p/ρ², computed once so that the pair term P_i + P_j is the same floating-point number
    /// seen from i and from j.
    pressure_over_rho2: f64,
    /// A wall image: its force on a real particle is the wall's reaction.
    is_wall: bool,
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
}

/// The parameters of the rate loop that are the same for every pair.
struct RateTerms<'a, const D: usize> {
    kernel: &'a Kernel<D>,
    viscosity: &'a ArtificialViscosity,
    energy: EnergyEquation,
}

/// Momentum, energy and (for continuity density) density rates of the real particles:
/// Dv_i/Dt = −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j² + Π_ij) ∇_i W_ij,
/// De_i/Dt in the chosen [`EnergyEquation`] form,
/// Dρ_i/Dt = Σ_j m_j v_ij·∇_i W_ij.
/// Returns the total force the walls exert on the particles.
pub fn compute_rates<const D: usize>(
    particles: &mut Particles<D>,
    neighbours: &NeighbourList,
    kernel: &Kernel<D>,
    viscosity: &ArtificialViscosity,
    energy: EnergyEquation,
) -> Vector<D> {
    let n = particles.n_real();
    let p = &*particles;
    let terms = RateTerms {
        kernel,
        viscosity,
        energy,
    };
    let sources: Vec<RateSource<D>> = (0..p.len())
        .into_par_iter()
        .map(|k| RateSource {
            position: p.position[k],
            velocity: p.velocity[k],
            smoothing_length: p.smoothing_length[k],
            mass: p.mass[k],
            density: p.density[k],
            sound_speed: p.sound_speed[k],
            pressure: p.pressure[k],
            internal_energy: p.internal_energy[k],
            pressure_over_rho2: pressure_term(p.pressure[k], p.density[k], 0.0, 1.0),
            is_wall: p.image(k).is_some_and(|im| im.is_wall),
        })
        .collect();
    let rates: Vec<Rates<D>> = (0..n)
        .into_par_iter()
        .map(|i| rates_at(i, &sources, neighbours, &terms))
        .collect();
    let continuity = !particles.density_rate.is_empty();
    let mut wall_force = Vector::zeros();
    for (i, rate) in rates.iter().enumerate() {
        particles.acceleration[i] = rate.acceleration;
        particles.energy_rate[i] = rate.energy_rate;
        particles.signal_speed[i] = rate.signal_speed;
        if continuity {
            particles.density_rate[i] = rate.density_rate;
        }
        wall_force += rate.wall_force;
    }
    wall_force
}

#[inline(never)]
fn rates_at<const D: usize>(
    i: usize,
    sources: &[RateSource<D>],
    neighbours: &NeighbourList,
    terms: &RateTerms<D>,
) -> Rates<D> {
    let me = &sources[i];
    let mut out = Rates {
        acceleration: Vector::zeros(),
        energy_rate: 0.0,
        density_rate: 0.0,
        signal_speed: me.sound_speed,
        wall_force: Vector::zeros(),
    };
    for part in neighbours.parts(i) {
        for &j in part {
            let other = &sources[j as usize];
            let dx = me.position - other.position;
            let r2 = dx.norm_squared();
            if r2 == 0.0 {
                continue; // coincident particles: ∇W = 0 by symmetry
            }
            let r = r2.sqrt();
            let inv_r = 1.0 / r;
            let h = 0.5 * (me.smoothing_length + other.smoothing_length);
            let dw_dr = terms.kernel.derivative(r, h);
            let grad = dx * (dw_dr * inv_r);
            let v_ij = me.velocity - other.velocity;
            let v_dot_x = v_ij.dot(&dx);
            let c_mean = 0.5 * (me.sound_speed + other.sound_speed);
            let rho_mean = 0.5 * (me.density + other.density);
            let pi_ij = terms.viscosity.pi(v_dot_x, r2, h, c_mean, rho_mean);
            let m_j = other.mass;
            let coefficient = m_j * (me.pressure_over_rho2 + other.pressure_over_rho2 + pi_ij);
            let v_dot_grad = v_ij.dot(&grad);
            let force = grad * (-coefficient);
            out.acceleration += force;
            out.energy_rate += match terms.energy {
                EnergyEquation::OwnPressure => {
                    m_j * (me.pressure_over_rho2 + 0.5 * pi_ij) * v_dot_grad
                }
                EnergyEquation::Symmetric => 0.5 * coefficient * v_dot_grad,
            };
            out.energy_rate += m_j
                * dw_dr
                * terms.viscosity.conduction(
                    me.internal_energy,
                    other.internal_energy,
                    me.pressure,
                    other.pressure,
                    rho_mean,
                );
            out.density_rate += m_j * v_dot_grad;
            let v_sig = signal_speed(me.sound_speed, other.sound_speed, v_dot_x * inv_r);
            out.signal_speed = out.signal_speed.max(v_sig);
            if other.is_wall {
                out.wall_force += force * me.mass;
            }
        }
    }
    out
}
