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
//! there the pair sum returns less than 2πσ_rr; the hoop terms carry the kink's share of that
//! (G_i, below), so a uniform stress stays at rest near the axis as elsewhere, and what remains
//! is a local error of the first ring off the axis, whose hoop terms carry G ≈ 0.5 (the second
//! ring's ≈ 1). The density must come from the continuity equation: a summation of ring
//! masses near the axis smears η = 2π|r|ρ over the same kink (García-Senz et al. need
//! explicit near-axis corrections for it).
//!
//! The hoop terms carry a factor G_i for that kink ([`radius_gradients`]): the planar pair sum
//! returns the gradient of the ring flux 2π|r| σ_rr as 2πσ_rr G_i^even, where
//! G_i^even = Σ_j A_j (|r_j| − r_i) ∂W_ij/∂r_i (A_j = m_j/η_j) is the pair sums' derivative of
//! |r|, about 0.5 at the first ring off the axis; a hoop force with 1 there would leave most of
//! σ_θθ/(ρr) uncancelled, more than the forces that deform a Taylor bar. The factor is
//! G_i = G_i^even/G_i^odd, where G_i^odd is the same sum with the axis images at their signed
//! radius (the field r continued linearly across the axis): the ratio is the kink alone. Away
//! from the axis it is exactly 1, so the hoop force σ_θθ/(ρr) and the hoop strain rate v_r/r
//! of a ring are the exact local ones, also at a free surface. (G^even alone there is about
//! 0.5, the truncated kernel's, and halved a free rim's hoop restraint and hoop stretching:
//! the Taylor bar's outer column then ran out along the wall as a tongue one particle thick,
//! footprint +7 % at 16 rings across.) The price is that a uniform stress is at
//! rest only to the planar sums' own accuracy, about 1 % of the hoop term with the cubic spline
//! at η = 1.2, where G^even alone balanced it to round-off. The hoop strain rate v_r/r carries
//! the same G_i as the hoop force, so the hoop work still cancels in the energy.

use crate::pairs::{self, PairEquation};
use crate::particles::Particles;
use crate::physics::{KernelLink, KernelPairs};
use crate::Vector;
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

/// The hoop factor G_i of the real particles `which` (in that order): the kink that the even axis images put into the
/// planar pair sums' derivative of r, G_i = G_i^even/G_i^odd with
/// G_i^even = Σ_j A_j (|r_j| − r_i) ∂W_ij/∂r_i (the images at their mirrored radius, as the
/// ring flux sees them) and G_i^odd the same sum with the images' signed r_j < 0 (the linear
/// field r continued across the axis), A_j = m_j/(2π|r_j|ρ_j). See the module note.
pub fn radius_gradients<const D: usize>(
    particles: &Particles<D>,
    kernel_pairs: &KernelPairs,
    which: &[usize],
) -> Vec<f64> {
    pairs::gather_at(&RadiusGradient, particles, kernel_pairs, which)
}

/// The pass of [`radius_gradients`].
struct RadiusGradient;

/// What the radius-gradient pass reads of a neighbour.
struct RingSource<const D: usize> {
    position: Vector<D>,
    /// The ring's cross-section A = m/η.
    area: f64,
}

impl<const D: usize> PairEquation<D, KernelLink> for RadiusGradient {
    type Source = RingSource<D>;
    /// G^even and G^odd.
    type Sum = (f64, f64);
    type Output = f64;

    fn source(&self, p: &Particles<D>, k: usize) -> RingSource<D> {
        RingSource {
            position: p.position[k],
            area: p.mass[k] / (p.density[k] * PairGeometry::Axisymmetric.scales(p, k).0),
        }
    }

    fn start(&self, _: &RingSource<D>) -> (f64, f64) {
        (0.0, 0.0)
    }

    #[inline]
    fn pair(
        &self,
        (even, odd): &mut (f64, f64),
        me: &RingSource<D>,
        other: &RingSource<D>,
        link: &KernelLink,
    ) {
        // rings take the mean-h kernel, the same from both sides
        let &KernelLink { r, dw_i: dw, .. } = link;
        let dx = me.position - other.position;
        let weight = other.area * dw * dx[0] / r;
        let (r_i, r_j) = (me.position[0], other.position[0]);
        *even -= weight * (r_i - r_j.abs());
        *odd -= weight * (r_i - r_j);
    }

    /// A ring with no partner off its own radius has no pair sums to balance: its hoop terms
    /// are the exact ones (G = 1).
    fn finish(&self, _: &RingSource<D>, (even, odd): (f64, f64)) -> f64 {
        if odd == 0.0 {
            1.0
        } else {
            even / odd
        }
    }
}

/// The hoop strain rates ε̇_θθ = G_i v_r/r of the real particles `which` (in that order; G_i
/// from [`radius_gradients`] in the same order).
pub fn hoop_strain_rates<const D: usize>(
    particles: &Particles<D>,
    radius_gradient: &[f64],
    which: &[usize],
) -> Vec<f64> {
    let p = particles;
    which
        .iter()
        .zip(radius_gradient)
        .map(|(&i, g)| g * p.velocity[i][0] / p.position[i][0])
        .collect()
}

/// Completes the rates of the real particles `which` (`radius_gradient` and `hoop_rate` in
/// their order) after the planar pair loops have run in the ring
/// fields: turns their Dη/Dt into Dρ/Dt = Dη/Dt/(2πr) − ρ ε̇_θθ, adds the hoop force
/// −G σ_θθ/(ρr) to Dv_r/Dt and the hoop part of the pressure work, −p ε̇_θθ/ρ, to De/Dt (the
/// stress pass adds s_θθ ε̇_θθ/ρ with the rest of s:ε̇), where σ_θθ = −p + s_θθ,
/// s_θθ = −(s_rr + s_zz), ε̇_θθ = G v_r/r and G the discrete ∂r/∂r ([`radius_gradients`]).
pub fn add_hoop_terms<const D: usize>(
    particles: &mut Particles<D>,
    radius_gradient: &[f64],
    hoop_rate: &[f64],
    which: &[usize],
) {
    let p = particles;
    for (k, &i) in which.iter().enumerate() {
        let r = p.position[i][0];
        let rho = p.density[i];
        if let Some(ring_rate) = p.density_rate.get_mut(i) {
            *ring_rate = *ring_rate / (2.0 * PI * r) - rho * hoop_rate[k];
        }
        let s_hoop = p.deviatoric_stress.get(i).map_or(0.0, |s| -s.trace());
        let sigma_hoop = -p.pressure[i] + s_hoop;
        p.acceleration[i][0] -= radius_gradient[k] * sigma_hoop / (rho * r);
        p.energy_rate[i] -= p.pressure[i] * hoop_rate[k] / rho;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{Kernel, KernelShape};
    use crate::neighbours::{find_neighbours, PairReach};
    use crate::particles::{OptionalFields, ParticleInit};
    use crate::physics::PairKernel;
    use crate::random::SplitMix64;

    /// Away from the axis every partner has r_j > 0, so G^even and G^odd are the same sum and
    /// G is exactly 1, on any arrangement of rings: here a lattice jittered by a fifth of its
    /// spacing, whose pair sums' derivative of r (G^odd) is itself off 1 (by a few per cent
    /// inside, by half at the lattice's free edges).
    #[test]
    fn the_hoop_factor_is_exactly_one_away_from_the_axis() {
        let (dx, h) = (1.0, 1.2);
        let mut random = SplitMix64::new(7);
        let init: Vec<ParticleInit<2>> = (0..20 * 20)
            .map(|k| {
                let lattice = Vector::<2>::new((10 + k % 20) as f64, (k / 20) as f64);
                let jitter = Vector::<2>::new(random.uniform() - 0.5, random.uniform() - 0.5);
                let position = (lattice + 0.4 * jitter) * dx;
                ParticleInit {
                    position,
                    velocity: Vector::zeros(),
                    mass: 2.0 * std::f64::consts::PI * position[0] * dx * dx,
                    smoothing_length: h * dx,
                    density: 1.0,
                    internal_energy: 1.0,
                    material: 0,
                }
            })
            .collect();
        let p = Particles::new(&init, OptionalFields::default());
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let neighbours = find_neighbours(
            &p.position,
            &p.smoothing_length,
            KernelShape::CubicSpline.support(),
            PairReach::MeanH,
            p.n_real(),
        );
        let mut kernel_pairs = KernelPairs::default();
        let all: Vec<usize> = (0..p.n_real()).collect();
        kernel_pairs.rebuild(&p, &neighbours, &kernel, PairKernel::MeanH, &all);
        let g = radius_gradients(&p, &kernel_pairs, &all);
        assert!(g.iter().all(|&g| g == 1.0), "{g:?}");
    }
}
