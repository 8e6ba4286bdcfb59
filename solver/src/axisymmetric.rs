//! Axisymmetric (r, z) SPH for D = 2: x is the distance r from the axis of symmetry, y is z, and
//! each particle stands for a ring whose mass is the particle's mass.
//!
//! Formulation: the ring-density form of Brookshaw (2003, ANZIAM J. 44(E), C114) and
//! García-Senz, Relaño, Cabezón & Bravo (2009, MNRAS 392, 346), written here for a solid's full
//! stress σ = −pI + s. With the ring density η = 2πrρ the cylindrical equations
//!
//!   Dρ/Dt = −ρ(∂_r v_r + ∂_z v_z + v_r/r),
//!   ρ Dv_r/Dt = ∂_r σ_rr + ∂_z σ_rz + (σ_rr − σ_θθ)/r,   ρ Dv_z/Dt = ∂_r σ_rz + ∂_z σ_zz + σ_rz/r,
//!   ρ De/Dt = σ:ε̇, ε̇_θθ = v_r/r,
//!
//! become planar ones in the ring fields:
//!
//!   Dη/Dt = −η ∇·v,   η Dv/Dt = ∇·(2πr σ) − 2π σ_θθ ê_r,
//!
//! (∇ the planar (r, z) operator). So the planar pair loops serve unchanged when they see a
//! particle's density as η and its pressure and stress as the ring fluxes 2πr p, 2πr s
//! ([`PairGeometry`]): their volume form then gives Dη/Dt, the z force conserves z momentum
//! pair by pair, and what is left is the hoop force −σ_θθ/(ρr) on v_r with its work σ_θθ v_r/(ρr)
//! on e, which cancel in the total energy particle by particle ([`add_hoop_terms`]).
//!
//! The axis is a mirror wall at r = 0, and an image there carries the ring density and flux of
//! the ring it mirrors, 2π|r|ρ and 2π|r| σ: the images are even, exactly like a wall's, so
//! the pair terms with them conserve energy and axial momentum as a frictionless wall does
//! (an odd flux, −2π|r| σ on the image, would continue 2πr σ linearly across the axis but
//! breaks that symmetry: measured 0.5 % energy created in 2 µs of a jostled copper column,
//! not shrinking with Δt, and 2.9 %, 1.6 % of the impact energy lost in the Taylor bar at 8, 12
//! rings across). The even flux has a kink at the axis which the planar gradient smooths, so
//! there the pair sum returns less than 2πσ_rr; the hoop terms carry the same discrete
//! derivative G_i (below), so a uniform stress still stays at rest, and what remains is a
//! local error of the first ring off the axis, whose hoop terms carry G ≈ 0.5 (the second
//! ring's ≈ 1). The density must come from the continuity equation: a summation of ring
//! masses near the axis smears η = 2π|r|ρ over the same kink (García-Senz et al. need
//! explicit near-axis corrections for it).
//!
//! The hoop terms carry the discrete ∂r/∂r, G_i = Σ_j A_j (|r_j| − r_i) ∂W_ij/∂r_i with the
//! ring areas A_j = m_j/η_j ([`radius_gradients`]), where the continuum has 1: the planar pair
//! sum returns the gradient of the ring flux 2π|r| σ_rr as 2πσ_rr G_i, not 2πσ_rr (away from the
//! axis the cubic spline's gradient sum at η = 1.2 is short by about 1 %), and a hoop force
//! with 1 in place of G_i would leave the difference of σ_θθ/(ρr) uncancelled, at the first
//! rings off the axis more than the forces that deform a Taylor bar. With G_i a uniform stress
//! stays exactly at rest, and since the hoop strain rate v_r/r carries the same G_i, the hoop
//! work still cancels in the energy.

use crate::kernel::Kernel;
use crate::neighbours::NeighbourList;
use crate::particles::Particles;
use rayon::prelude::*;
use std::f64::consts::PI;

/// How the planar pair loops see a particle: planar as it is, or axisymmetric through its ring
/// fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairGeometry {
    Planar,
    Axisymmetric,
}

impl PairGeometry {
    /// The factors by which particle k's ρ and its p, s are seen in the pairs: 1 and 1, or
    /// 2π|r_src| and 2π|r|. The ring density takes the radius of the real particle an image
    /// stands for, so that every image keeps its source's ring area m/η (a mirror across an
    /// outer wall at R would otherwise hold the mass of a ring at r on one at 2R − r); the ring
    /// flux takes the image's own radius, its continuation across an outer wall (across the
    /// axis both are the source's).
    #[inline]
    pub fn scales<const D: usize>(self, particles: &Particles<D>, k: usize) -> (f64, f64) {
        match self {
            PairGeometry::Planar => (1.0, 1.0),
            PairGeometry::Axisymmetric => {
                let source = particles.position[particles.real_index(k)][0];
                (
                    2.0 * PI * source.abs(),
                    2.0 * PI * particles.position[k][0].abs(),
                )
            }
        }
    }
}

/// G_i = Σ_j A_j (r_j − r_i) ∂W_ij/∂r_i, A_j = m_j/(2π|r_j|ρ_j), of the real particles: the
/// planar pair sums' derivative of r (1 in the continuum; see the module note).
pub fn radius_gradients<const D: usize>(
    particles: &Particles<D>,
    neighbours: &NeighbourList,
    kernel: &Kernel<D>,
) -> Vec<f64> {
    let p = particles;
    let geometry = PairGeometry::Axisymmetric;
    (0..p.n_real())
        .into_par_iter()
        .map(|i| {
            neighbours.of(i).fold(0.0, |sum, j| {
                let dx = p.position[i] - p.position[j];
                let r = dx.norm();
                if r == 0.0 {
                    return sum;
                }
                let h = 0.5 * (p.smoothing_length[i] + p.smoothing_length[j]);
                let area = p.mass[j] / (p.density[j] * geometry.scales(p, j).0);
                sum - area
                    * kernel.derivative(r, h)
                    * (p.position[i][0] - p.position[j][0].abs())
                    * dx[0]
                    / r
            })
        })
        .collect()
}

/// The hoop strain rates ε̇_θθ = G_i v_r/r of the real particles.
pub fn hoop_strain_rates<const D: usize>(
    particles: &Particles<D>,
    radius_gradient: &[f64],
) -> Vec<f64> {
    let p = particles;
    (0..p.n_real())
        .map(|i| radius_gradient[i] * p.velocity[i][0] / p.position[i][0])
        .collect()
}

/// Completes the rates of the real particles after the planar pair loops have run in the ring
/// fields: turns their Dη/Dt into Dρ/Dt = Dη/Dt/(2πr) − ρ ε̇_θθ, adds the hoop force
/// −G σ_θθ/(ρr) to Dv_r/Dt and the hoop part of the pressure work, −p ε̇_θθ/ρ, to De/Dt (the
/// stress pass adds s_θθ ε̇_θθ/ρ with the rest of s:ε̇), where σ_θθ = −p + s_θθ,
/// s_θθ = −(s_rr + s_zz), ε̇_θθ = G v_r/r and G the discrete ∂r/∂r ([`radius_gradients`]).
pub fn add_hoop_terms<const D: usize>(
    particles: &mut Particles<D>,
    radius_gradient: &[f64],
    hoop_rate: &[f64],
) {
    let p = particles;
    for i in 0..p.n_real() {
        let r = p.position[i][0];
        let rho = p.density[i];
        if let Some(ring_rate) = p.density_rate.get_mut(i) {
            *ring_rate = *ring_rate / (2.0 * PI * r) - rho * hoop_rate[i];
        }
        let s_hoop = p.deviatoric_stress.get(i).map_or(0.0, |s| -s.trace());
        let sigma_hoop = -p.pressure[i] + s_hoop;
        p.acceleration[i][0] -= radius_gradient[i] * sigma_hoop / (rho * r);
        p.energy_rate[i] -= p.pressure[i] * hoop_rate[i] / rho;
    }
}
