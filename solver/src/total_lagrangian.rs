//! Total-Lagrangian SPH for solids: the kernel lives in the reference (initial) configuration,
//! so each particle keeps the neighbours it started with, every kernel sum is worked out once,
//! and the motion enters through the deformation gradient F (Bonet & Lok 1999, Comput.
//! Methods Appl. Mech. Eng. 180, 97; Vignjevic, Reveles & Campbell 2006, CMES 14, 181;
//! Ganzenmüller 2015, CMAME 286, 87). This removes the two faults of the updated form in
//! large plastic flow: the tensile instability, which belongs to a kernel that moves with the
//! particles (Belytschko et al. 2000, IJNME 48, 1359), and the loss of neighbours where a free
//! surface stretches (the Taylor bar's rim stretches 2.2 times around its circumference).
//!
//! With X the reference positions, V_j = m_j/ρ0_j, ∇W_ij = ∇_i W(|X_i − X_j|, h̄_ij) and the
//! corrected gradient g_ij = L_i ∇W_ij, where L_i = B_i^{−T} and B_i = Σ_j V_j X_ij ⊗ ∇W_ij
//! (X_ij = X_j − X_i), so that the gradient of any linear field is exact:
//!
//!   F_i = Σ_j V_j x_ij ⊗ g_ij,   Ḟ_i = Σ_j V_j v_ij ⊗ g_ij,   ρ_i = ρ0_i / det F_i,
//!   l_i = Ḟ_i F_i⁻¹ (the velocity gradient that drives the Jaumann stress rate),
//!   P_i = det F_i σ_i F_i⁻ᵀ, σ_i = −(p_i + q_i) I + s_i (first Piola–Kirchhoff stress),
//!   m_i dv_i/dt = Σ_j V_i V_j (P_i L_i + P_j L_j) ∇W_ij,   m_i de_i/dt = V_i P_i : Ḟ_i.
//!
//! The force is minus the derivative of the discrete strain energy Σ_i V_i Ψ(F_i) with respect
//! to x_i, so momentum and energy are conserved to round-off. q_i is a bulk viscosity, the
//! artificial viscosity of finite-element codes (von Neumann & Richtmyer 1950; Wilkins 1980,
//! J. Comput. Phys. 36, 281): q = ρ ℓ (α c |θ| + β ℓ θ²) under compression θ = tr l < 0, with
//! ℓ the particle's current smallest spacing scaled by η (its h), so it heats only where the
//! material is squeezed, never in isochoric plastic flow.
//!
//! Hourglass control (Ganzenmüller 2015): F_i is a least-squares fit of the neighbours'
//! motion, blind to motions that leave it unchanged (zero-energy modes). Each pair's actual
//! separation x_ij is compared with what the two particles' F predict, d_ij = x_ij −
//! ½(F_i + F_j) X_ij, and its stretch along the pair, δ_ij = d_ij · x̂_ij, is resisted by the
//! pair force f_ij = κ Ē_ij V_i V_j W_ij δ_ij / |X_ij|² x̂_ij on i (and −f_ij on j), κ the
//! dimensionless coefficient and Ē_ij the pair's mean Young's modulus. Summed over a
//! neighbourhood the stiffness is about κ Ē V_i per unit squared strain (Σ_j V_j W_ij ≈ 1): at
//! κ = 1 a zero-energy mode meets the material's own stiffness. It has no potential, so its
//! power is returned as heat, half to each particle, and booked (like the artificial stress's
//! in the updated form), which keeps the energy conserved and its share visible.
//!
//! Symmetry planes and frictionless walls are mirror images of the reference configuration:
//! an image of particle k is x = S x_k + c (S the reflection, c fixed), with S v_k, S P_k S and
//! S L_k S. Its bonds are permanent, so a wall holds a particle in tension too.

use crate::boundary::Domain;
use crate::eos::Material;
use crate::kernel::Kernel;
use crate::neighbours::{find_neighbours, NeighbourList, PairReach};
use crate::pairs::{self, PairEquation, Partners};
use crate::particles::{mirrored, Particles};
use crate::physics::{ArtificialViscosity, RateTotals};
use crate::strength::{equivalent_strain_rate, jaumann_rate};
use crate::{SolverError, Tensor, Vector};

/// One neighbour j of a particle i in the reference configuration.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct Bond<const D: usize> {
    /// The real particle j is, or whose mirror image it is.
    other: u32,
    /// j's position is `reflection ⊙ x_other + offset` (1 and 0 for a real particle).
    reflection: Vector<D>,
    /// Some component of `reflection` is −1: j is a mirror image.
    reflected: bool,
    offset: Vector<D>,
    /// j is a wall's (or symmetry plane's) image: its force is the wall's reaction.
    is_wall: bool,
    /// X_ij = X_j − X_i.
    separation: Vector<D>,
    /// ∇_i W(|X_i − X_j|, h̄_ij).
    kernel_gradient: Vector<D>,
    /// V_j.
    volume: f64,
    /// V_i V_j W_ij / |X_ij|², the hourglass stiffness per unit modulus and coefficient.
    hourglass_stiffness: f64,
}

impl<const D: usize> Bond<D> {
    /// A position and a velocity of the real particle `other` as j sees them: reflected where
    /// j is a mirror image (x·1 = x exactly, so the unreflected skip the product).
    #[inline]
    fn seen(&self, x: Vector<D>, v: Vector<D>) -> (Vector<D>, Vector<D>) {
        if self.reflected {
            (
                self.reflection.component_mul(&x),
                self.reflection.component_mul(&v),
            )
        } else {
            (x, v)
        }
    }
}

/// The reference configuration: each particle's bonds, volume, density, correction matrix
/// and smoothing length, fixed for the run.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ReferenceConfiguration<const D: usize> {
    offsets: Vec<usize>,
    bonds: Vec<Bond<D>>,
    volume: Vec<f64>,
    density: Vec<f64>,
    correction: Vec<Tensor<D>>,
    smoothing_length: Vec<f64>,
}

/// The motion of one particle's neighbourhood.
#[derive(Clone, Copy, Debug)]
struct Kinematics<const D: usize> {
    deformation: Tensor<D>,
    deformation_rate: Tensor<D>,
}

/// What the force loop needs of a particle beyond the particle store: its stress, deformation
/// and Young's modulus at this evaluation.
#[derive(Clone, Copy, Debug)]
struct PiolaState<const D: usize> {
    /// P_i L_i.
    corrected_stress: Tensor<D>,
    deformation: Tensor<D>,
    young: f64,
}

/// What a particle's neighbours read of it in the force loop.
#[derive(Clone, Copy, Debug)]
struct StressSource<const D: usize> {
    index: usize,
    position: Vector<D>,
    velocity: Vector<D>,
    /// P_i L_i.
    corrected_stress: Tensor<D>,
    deformation: Tensor<D>,
    young: f64,
}

impl<const D: usize> ReferenceConfiguration<D> {
    /// The bonds of the particles as they stand (their positions and smoothing lengths), with
    /// the images `domain` makes of them. Every particle must have neighbours enough in at
    /// least D independent directions for its correction matrix.
    pub fn new(
        particles: &Particles<D>,
        domain: &Domain<D>,
        kernel: &Kernel<D>,
    ) -> Result<Self, SolverError> {
        let n = particles.n_real();
        let mut reference = particles.clone();
        let reach: Vec<f64> = reference.smoothing_length[..n]
            .iter()
            .map(|&h| kernel.support_radius(h))
            .collect();
        domain.make_images(&mut reference, &reach);
        let x = &reference.position;
        let h = &reference.smoothing_length;
        let neighbours = find_neighbours(x, h, kernel.shape().support(), PairReach::MeanH, n);
        let volume: Vec<f64> = (0..n)
            .map(|i| particles.mass[i] / particles.density[i])
            .collect();
        let mut offsets = vec![0];
        let mut bonds = Vec::new();
        let mut correction = Vec::with_capacity(n);
        for i in 0..n {
            let mut shape = Tensor::<D>::zeros();
            for j in neighbours.of(i) {
                let dx = x[i] - x[j];
                let r = dx.norm();
                if r == 0.0 {
                    continue;
                }
                let h_mean = 0.5 * (h[i] + h[j]);
                let kernel_gradient = kernel.gradient(&dx, r, h_mean);
                let (other, reflection, is_wall) = match reference.image(j) {
                    Some(image) => (image.source, image.velocity_sign, image.is_wall),
                    None => (j as u32, Vector::repeat(1.0), false),
                };
                let k = other as usize;
                let bond = Bond {
                    other,
                    reflection,
                    reflected: reflection.iter().any(|&s| s != 1.0),
                    offset: x[j] - reflection.component_mul(&x[k]),
                    is_wall,
                    separation: -dx,
                    kernel_gradient,
                    volume: volume[k],
                    hourglass_stiffness: volume[i] * volume[k] * kernel.value(r, h_mean) / (r * r),
                };
                shape += bond.separation * bond.kernel_gradient.transpose() * bond.volume;
                bonds.push(bond);
            }
            offsets.push(bonds.len());
            let det = determinant(&shape);
            let inverse = invert(&shape).filter(|_| det.abs() > 1e-3);
            let Some(inverse) = inverse else {
                return Err(SolverError::invalid(
                    &format!("particle {} neighbourhood", particles.id[i]),
                    format!(
                        "{} neighbours, det B = {det:.3e}",
                        offsets[i + 1] - offsets[i]
                    ),
                    "neighbours in every direction (det B > 1e-3, 1 for a full lattice)",
                ));
            };
            correction.push(inverse.transpose());
        }
        Ok(Self {
            offsets,
            bonds,
            volume,
            density: particles.density[..n].to_vec(),
            correction,
            smoothing_length: particles.smoothing_length[..n].to_vec(),
        })
    }

    fn bonds_of(&self, i: usize) -> &[Bond<D>] {
        &self.bonds[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Each particle's partners: the real particles its bonds join it to, themselves or
    /// through a mirror, other than itself. Bonds are symmetric, and so are these lists.
    pub(crate) fn partner_lists(&self) -> NeighbourList {
        NeighbourList::from_lists((0..self.volume.len()).map(|i| {
            let mut partners: Vec<u32> = self
                .bonds_of(i)
                .iter()
                .map(|bond| bond.other)
                .filter(|&j| j as usize != i)
                .collect();
            partners.sort_unstable();
            partners.dedup();
            partners
        }))
    }

    /// The particles whose state the rates of `which` (ascending) read: they and their bonds'
    /// partners, ascending.
    fn with_partners(&self, which: &[usize]) -> Vec<usize> {
        let mut read = vec![false; self.volume.len()];
        for &i in which {
            read[i] = true;
            for bond in self.bonds_of(i) {
                read[bond.other as usize] = true;
            }
        }
        (0..read.len()).filter(|&k| read[k]).collect()
    }

    /// Density, pressure, sound speed and h of the particles the rates of the real particles
    /// `which` (ascending) read (they and their bonds' partners), then the stress rates, forces
    /// and energy rates of `which` alone, and each one's share of the rate totals (in `which`'s
    /// order). All particles are real: this formulation makes no images. A neighbourhood turned
    /// inside out (det F ≤ 0) stops with the particle's index and det F.
    pub(crate) fn evaluate(
        &self,
        p: &mut Particles<D>,
        materials: &[Material],
        viscosity: &ArtificialViscosity,
        hourglass: f64,
        which: &[usize],
    ) -> Result<Vec<RateTotals<D>>, (usize, &'static str, f64)> {
        let n = self.volume.len();
        let read = if which.len() == n {
            which.to_vec()
        } else {
            self.with_partners(which)
        };
        let kinematics = pairs::gather_at(&Deformation { reference: self }, p, &Bonds(self), &read);
        let mut rated = vec![false; n];
        for &i in which {
            rated[i] = true;
        }
        // a particle outside `read` is no partner of `which`: no pair uses its entry (a pass
        // over many particles still packs it into its source)
        let unread = PiolaState {
            corrected_stress: Tensor::zeros(),
            deformation: Tensor::zeros(),
            young: 0.0,
        };
        let mut states = vec![unread; n];
        let mut viscous_heating = vec![0.0; n];
        for (&i, kin) in read.iter().zip(&kinematics) {
            let jacobian = determinant(&kin.deformation);
            let inverse = invert(&kin.deformation).filter(|_| jacobian > 0.0);
            let Some(inverse) = inverse else {
                return Err((i, "deformation gradient determinant", jacobian));
            };
            let material = &materials[p.material_of(i)];
            let strength = material
                .strength
                .as_ref()
                .expect("a total-Lagrangian scene holds solids only");
            let g = strength.shear_modulus;
            p.density[i] = self.density[i] / jacobian;
            // h shrinks with the material's most compressed direction: it sets the time step
            // and the viscosity's length
            p.smoothing_length[i] = self.smoothing_length[i] * least_singular_value(&inverse);
            let (rho, e) = (p.density[i], p.internal_energy[i]);
            let peak = p.peak_density_of(i);
            p.pressure[i] = material.eos.pressure_after(rho, e, peak);
            let bulk_speed = material.eos.sound_speed_after(rho, e, peak);
            // a solid carries shear waves too: the P-wave speed √(c² + 4G/(3ρ)) sets the step
            p.sound_speed[i] = (bulk_speed.powi(2) + 4.0 * g / (3.0 * rho)).sqrt();
            let bulk = rho * bulk_speed.powi(2);
            let young = 9.0 * bulk * g / (3.0 * bulk + g);
            let velocity_gradient = kin.deformation_rate * inverse;
            let strain_rate = 0.5 * (velocity_gradient + velocity_gradient.transpose());
            let compression = (-strain_rate.trace()).max(0.0);
            let spacing = p.smoothing_length[i];
            let q = rho
                * spacing
                * compression
                * (viscosity.alpha * p.sound_speed[i] + viscosity.beta * spacing * compression);
            let s = p.deviatoric_stress[i];
            let cauchy = s - Tensor::<D>::identity() * (p.pressure[i] + q);
            let piola = cauchy * inverse.transpose() * jacobian;
            if rated[i] {
                viscous_heating[i] = p.mass[i] * q * compression / rho;
                p.strain_rate[i] = equivalent_strain_rate(&strain_rate, 0.0);
                p.stress_rate[i] = jaumann_rate(g, &s, &velocity_gradient, 0.0);
                p.energy_rate[i] =
                    self.volume[i] * piola.component_mul(&kin.deformation_rate).sum() / p.mass[i];
            }
            states[i] = PiolaState {
                corrected_stress: piola * self.correction[i],
                deformation: kin.deformation,
                young,
            };
        }
        let forces = PiolaForces {
            volume: &self.volume,
            states: &states,
            hourglass,
        };
        let rates = pairs::gather_at(&forces, p, &Bonds(self), which);
        let mut books = Vec::with_capacity(which.len());
        for (&i, (force, wall, heating, approach)) in which.iter().zip(rates) {
            p.acceleration[i] = force / p.mass[i];
            p.energy_rate[i] += heating / p.mass[i];
            p.signal_speed[i] = p.sound_speed[i] + approach;
            books.push(RateTotals {
                wall_force: wall,
                viscous_heating: viscous_heating[i],
                hourglass_heating: heating,
                ..RateTotals::default()
            });
        }
        Ok(books)
    }
}

/// The bonds as the pair driver's partners: each carries its reference data.
struct Bonds<'a, const D: usize>(&'a ReferenceConfiguration<D>);

impl<const D: usize> Partners for Bonds<'_, D> {
    type Link = Bond<D>;

    #[inline]
    fn visit(&self, i: usize, mut visit: impl FnMut(usize, &Bond<D>)) {
        for bond in self.0.bonds_of(i) {
            visit(bond.other as usize, bond);
        }
    }
}

/// The deformation gradient F_i = (Σ_j V_j x_ij ⊗ ∇W_ij) L_i and its rate Ḟ_i from v_ij, with
/// x_ij and v_ij of a mirrored bond seen through its reflection.
struct Deformation<'a, const D: usize> {
    reference: &'a ReferenceConfiguration<D>,
}

impl<const D: usize> PairEquation<D, Bond<D>> for Deformation<'_, D> {
    /// Index, position and velocity.
    type Source = (usize, Vector<D>, Vector<D>);
    /// Σ V_j x_ij ⊗ ∇W_ij and Σ V_j v_ij ⊗ ∇W_ij.
    type Sum = (Tensor<D>, Tensor<D>);
    type Output = Kinematics<D>;

    fn source(&self, p: &Particles<D>, k: usize) -> Self::Source {
        (k, p.position[k], p.velocity[k])
    }

    fn start(&self, _: &Self::Source) -> Self::Sum {
        (Tensor::zeros(), Tensor::zeros())
    }

    #[inline]
    fn pair(
        &self,
        (separation_sum, velocity_sum): &mut Self::Sum,
        &(_, x_i, v_i): &Self::Source,
        &(_, x_k, v_k): &Self::Source,
        bond: &Bond<D>,
    ) {
        let (x_j, v_j) = bond.seen(x_k, v_k);
        let x_ij = x_j + bond.offset - x_i;
        let v_ij = v_j - v_i;
        let weighted = bond.kernel_gradient.transpose() * bond.volume;
        *separation_sum += x_ij * weighted;
        *velocity_sum += v_ij * weighted;
    }

    fn finish(
        &self,
        &(i, _, _): &Self::Source,
        (separation, velocity): Self::Sum,
    ) -> Kinematics<D> {
        let l_transposed = self.reference.correction[i].transpose();
        Kinematics {
            deformation: separation * l_transposed,
            deformation_rate: velocity * l_transposed,
        }
    }
}

/// The first Piola–Kirchhoff pair forces V_i V_j (P_i L_i + P_j L_j) ∇W_ij with
/// Ganzenmüller's hourglass control: per particle the force, the part of it the walls exert,
/// the hourglass heat and the fastest approach of a partner.
struct PiolaForces<'a, const D: usize> {
    volume: &'a [f64],
    states: &'a [PiolaState<D>],
    /// The hourglass coefficient (0: off).
    hourglass: f64,
}

impl<const D: usize> PairEquation<D, Bond<D>> for PiolaForces<'_, D> {
    type Source = StressSource<D>;
    type Sum = (Vector<D>, Vector<D>, f64, f64);
    type Output = Self::Sum;

    fn source(&self, p: &Particles<D>, k: usize) -> StressSource<D> {
        let state = &self.states[k];
        StressSource {
            index: k,
            position: p.position[k],
            velocity: p.velocity[k],
            corrected_stress: state.corrected_stress,
            deformation: state.deformation,
            young: state.young,
        }
    }

    fn start(&self, _: &StressSource<D>) -> Self::Sum {
        (Vector::zeros(), Vector::zeros(), 0.0, 0.0)
    }

    #[inline]
    fn pair(
        &self,
        (force, wall, heating, approach): &mut Self::Sum,
        me: &StressSource<D>,
        other: &StressSource<D>,
        bond: &Bond<D>,
    ) {
        let (x_j, v_j) = bond.seen(other.position, other.velocity);
        let x_ij = x_j + bond.offset - me.position;
        let v_ij = v_j - me.velocity;
        // an image's tensors are its source's seen in the mirror (S A S)
        let (stress_j, deformation_j) = if bond.reflected {
            (
                mirrored(&other.corrected_stress, &bond.reflection),
                mirrored(&other.deformation, &bond.reflection),
            )
        } else {
            (other.corrected_stress, other.deformation)
        };
        let mut pair = (me.corrected_stress + stress_j)
            * bond.kernel_gradient
            * (self.volume[me.index] * bond.volume);
        let r = x_ij.norm();
        if self.hourglass > 0.0 && r > 0.0 {
            let unit = x_ij / r;
            let predicted = 0.5 * (me.deformation + deformation_j) * bond.separation;
            let stretch = (x_ij - predicted).dot(&unit);
            let modulus = 0.5 * (me.young + other.young);
            let restoring = unit * (self.hourglass * modulus * bond.hourglass_stiffness * stretch);
            pair += restoring;
            // −f·(v_i − v_j), half of it to each of the pair
            *heating += 0.5 * restoring.dot(&v_ij);
        }
        if r > 0.0 {
            *approach = approach.max(-v_ij.dot(&x_ij) / r);
        }
        *force += pair;
        if bond.is_wall {
            *wall += pair;
        }
    }

    fn finish(&self, _: &StressSource<D>, sum: Self::Sum) -> Self::Sum {
        sum
    }
}

/// The least singular value of F from F⁻¹: 1/√λ_max(F⁻¹F⁻ᵀ), the largest eigenvalue found by
/// power iteration (to 1e-3; it only sets h for the time step and the viscosity).
fn least_singular_value<const D: usize>(inverse: &Tensor<D>) -> f64 {
    let c = inverse * inverse.transpose();
    // start from C's longest column, which has a share of the leading eigenvector
    let column = (0..D)
        .max_by(|&a, &b| c.column(a).norm().total_cmp(&c.column(b).norm()))
        .unwrap_or(0);
    let mut v: Vector<D> = c.column(column).normalize();
    let mut lambda = 0.0;
    for _ in 0..50 {
        let w = c * v;
        let next = w.norm();
        if next == 0.0 {
            break;
        }
        v = w / next;
        if (next - lambda).abs() <= 1e-3 * next {
            lambda = next;
            break;
        }
        lambda = next;
    }
    1.0 / lambda.sqrt()
}

/// det A for D = 1, 2, 3.
pub fn determinant<const D: usize>(a: &Tensor<D>) -> f64 {
    match D {
        1 => a[(0, 0)],
        2 => a[(0, 0)] * a[(1, 1)] - a[(0, 1)] * a[(1, 0)],
        3 => (0..3).map(|b| a[(0, b)] * cofactor(a, 0, b)).sum(),
        _ => unreachable!("D is 1, 2 or 3"),
    }
}

/// The cofactor C_ab of A (D = 2, 3).
fn cofactor<const D: usize>(a: &Tensor<D>, row: usize, column: usize) -> f64 {
    match D {
        2 => {
            let sign = if (row + column).is_multiple_of(2) {
                1.0
            } else {
                -1.0
            };
            sign * a[(1 - row, 1 - column)]
        }
        _ => {
            let (r1, r2) = ((row + 1) % 3, (row + 2) % 3);
            let (c1, c2) = ((column + 1) % 3, (column + 2) % 3);
            a[(r1, c1)] * a[(r2, c2)] - a[(r1, c2)] * a[(r2, c1)]
        }
    }
}

/// A⁻¹ = adj(A)/det A, or None where A is singular.
pub fn invert<const D: usize>(a: &Tensor<D>) -> Option<Tensor<D>> {
    let det = determinant(a);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some(match D {
        1 => Tensor::<D>::from_element(1.0 / det),
        _ => Tensor::<D>::from_fn(|r, c| cofactor(a, c, r) / det),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::Boundary;
    use crate::kernel::KernelShape;
    use crate::particles::{OptionalFields, ParticleInit};

    /// The rates of every particle, and their totals.
    fn evaluate_all(
        reference: &ReferenceConfiguration<3>,
        p: &mut Particles<3>,
        materials: &[Material],
        viscosity: &ArtificialViscosity,
        hourglass: f64,
    ) -> Result<RateTotals<3>, (usize, &'static str, f64)> {
        let all: Vec<usize> = (0..p.n_real()).collect();
        let mut totals = RateTotals::default();
        for share in &reference.evaluate(p, materials, viscosity, hourglass, &all)? {
            totals += share;
        }
        Ok(totals)
    }

    /// The symmetry plane of [`block`]: off the origin, so that the mirror's offset counts.
    const MIRROR_X: f64 = 0.4;

    /// A jittered 6×5×4 block of unit density, mirrored at x = [`MIRROR_X`] (a symmetry
    /// plane), open elsewhere; every length times `scale`.
    fn block(scale: f64) -> (Particles<3>, Domain<3>) {
        let dx = 0.1 * scale;
        let mut init = Vec::new();
        for k in 0..6 * 5 * 4 {
            let jitter =
                |salt: usize| 0.1 * (((k * 7919 + salt * 104729) % 1000) as f64 / 500.0 - 1.0);
            let position = Vector::<3>::new(
                MIRROR_X * scale + ((k % 6) as f64 + 0.5 + jitter(1)) * dx,
                ((k / 6 % 5) as f64 + 0.5 + jitter(2)) * dx,
                ((k / 30) as f64 + 0.5 + jitter(3)) * dx,
            );
            init.push(ParticleInit {
                position,
                velocity: Vector::zeros(),
                mass: dx.powi(3),
                smoothing_length: 1.2 * dx,
                density: 1.0,
                internal_energy: 0.0,
                material: 0,
            });
        }
        let domain = Domain::with_sides(
            Vector::<3>::new(MIRROR_X * scale, 0.0, 0.0),
            Vector::<3>::repeat((1.0 + MIRROR_X) * scale),
            [Boundary::Wall, Boundary::Open, Boundary::Open],
            [Boundary::Open; 3],
        )
        .unwrap();
        let optional = OptionalFields {
            stress: true,
            ..OptionalFields::default()
        };
        (Particles::new(&init, optional), domain)
    }

    /// An elastic solid of unit density with bulk modulus K (linear bulk response) and shear
    /// modulus G.
    fn solid(bulk: f64, shear: f64) -> Material {
        let eos = crate::eos::MieGruneisen::linear(1.0, bulk.sqrt(), 0.0, 0.0, f64::NEG_INFINITY)
            .unwrap();
        Material::new("solid", eos)
            .with_strength(crate::strength::Strength::elastic(shear).unwrap())
    }

    /// ±1 in a checkerboard over [`block`]'s 6×5×4 lattice: a displacement mode the
    /// corrected gradient cannot see.
    fn checkerboard_sign(k: usize) -> f64 {
        if (k % 6 + k / 6 % 5 + k / 30).is_multiple_of(2) {
            1.0
        } else {
            -1.0
        }
    }

    /// [`block`] of `material` with every particle displaced along y by ±`amplitude` in a
    /// checkerboard (a mode the corrected gradient cannot see), at `velocity(k)`, evaluated
    /// with hourglass coefficient `hourglass`; every length times `scale`.
    fn checkerboard(
        material: &Material,
        amplitude: f64,
        velocity: impl Fn(usize) -> Vector<3>,
        hourglass: f64,
        scale: f64,
    ) -> (Particles<3>, RateTotals<3>) {
        let (mut p, domain) = block(scale);
        let kernel = Kernel::<3>::new(KernelShape::CubicSpline);
        let reference = ReferenceConfiguration::new(&p, &domain, &kernel).unwrap();
        for k in 0..p.n_real() {
            p.position[k][1] += amplitude * scale * checkerboard_sign(k);
            p.velocity[k] = velocity(k);
        }
        let totals = evaluate_all(
            &reference,
            &mut p,
            std::slice::from_ref(material),
            &ArtificialViscosity::default(),
            hourglass,
        )
        .unwrap();
        (p, totals)
    }

    /// The corrected gradient reproduces linear fields: under x − m = A (X − m) + b,
    /// v = B (X − m) with m on the mirror plane (both keeping it: no shear across it, no shift
    /// along its normal) every
    /// particle, inside, on the free surface and beside the mirror, has F = A and Ḟ = B to
    /// round-off, and no bond deviates from the affine prediction, so the hourglass control
    /// is silent.
    #[test]
    fn affine_motion_is_reproduced_exactly() {
        let (mut p, domain) = block(1.0);
        let kernel = Kernel::<3>::new(KernelShape::CubicSpline);
        let reference = ReferenceConfiguration::new(&p, &domain, &kernel).unwrap();
        let a = Tensor::<3>::new(1.3, 0.0, 0.0, 0.0, 0.8, 0.25, 0.0, -0.1, 1.1);
        let b = Tensor::<3>::new(-2.0, 0.0, 0.0, 0.0, 0.5, 3.0, 0.0, -1.0, 0.7);
        let shift = Vector::<3>::new(0.0, 0.3, -0.2);
        let mirror = Vector::<3>::new(MIRROR_X, 0.0, 0.0);
        for i in 0..p.n_real() {
            let x = p.position[i] - mirror;
            p.velocity[i] = b * x;
            p.position[i] = a * x + shift + mirror;
        }
        let kinematics = pairs::gather(
            &Deformation {
                reference: &reference,
            },
            &p,
            &Bonds(&reference),
        );
        for (i, kin) in kinematics.iter().enumerate() {
            assert!(
                (kin.deformation - a).norm() < 1e-12,
                "F at {i}: {}",
                kin.deformation
            );
            assert!((kin.deformation_rate - b).norm() < 1e-12, "Ḟ at {i}");
            for bond in reference.bonds_of(i) {
                let k = bond.other as usize;
                let x_ij =
                    bond.reflection.component_mul(&p.position[k]) + bond.offset - p.position[i];
                assert!((x_ij - a * bond.separation).norm() < 1e-13);
            }
        }
        assert!(reference.bonds.iter().any(|bond| bond.is_wall));
    }

    /// Under the affine compression x = A X with v = B X (det A = 0.903, tr L = −6.2 /s for
    /// L = B A⁻¹), from rest and zero deviatoric stress, every particle takes the continuum
    /// state of F = A: ρ = ρ0/det F, p and c from the equation of state at that density, the
    /// P-wave speed √(c² + 4G/(3ρ)), h scaled by the least singular value of F⁻¹, the
    /// strain rate D = sym L, its equivalent √(2/3 D':D'), the elastic stress rate 2G D'
    /// (no spin term at s = 0), the viscous pressure q = ρ h |tr D| (α c_P + β h |tr D|), and the
    /// power of the stress per unit mass −(p + q) tr D/ρ (the hourglass control adds nothing
    /// to an affine motion); the viscous heating Σ m q |tr D|/ρ, and the forces sum to the
    /// mirror's reaction (momentum). Each to 1e-9 relative: F and Ḟ are reproduced to 1e-12.
    #[test]
    fn an_affine_compression_takes_the_continuum_state_and_rates() {
        let (mut p, domain) = block(1.0);
        let kernel = Kernel::<3>::new(KernelShape::CubicSpline);
        let reference = ReferenceConfiguration::new(&p, &domain, &kernel).unwrap();
        let h0 = p.smoothing_length.clone();
        let a = Tensor::<3>::new(0.95, 0.0, 0.0, 0.0, 0.97, 0.02, 0.0, -0.01, 0.98);
        let b = Tensor::<3>::new(-3.0, 0.0, 0.0, 0.0, -1.0, 2.0, 0.0, -0.5, -2.0);
        let mirror = Vector::<3>::new(MIRROR_X, 0.0, 0.0);
        let initial = p.position.clone();
        for i in 0..p.n_real() {
            let x = p.position[i] - mirror;
            p.velocity[i] = b * x;
            p.position[i] = a * x + mirror;
        }
        let shear_modulus = 1.5;
        let material = solid(4.0, shear_modulus);
        let viscosity = ArtificialViscosity::default();
        let totals = evaluate_all(
            &reference,
            &mut p,
            std::slice::from_ref(&material),
            &viscosity,
            1.0,
        )
        .unwrap();
        let close = |x: f64, expected: f64, what: &str| {
            assert!(
                (x - expected).abs() <= 1e-9 * expected.abs().max(1e-12),
                "{what}: {x} against {expected}"
            );
        };
        let inverse = invert(&a).unwrap();
        let rho = 1.0 / a.determinant();
        let pressure = material.eos.pressure(rho, 0.0);
        let bulk_speed = material.eos.sound_speed(rho, 0.0);
        let p_wave = (bulk_speed.powi(2) + 4.0 * shear_modulus / (3.0 * rho)).sqrt();
        let strain_rate = {
            let l = b * inverse;
            0.5 * (l + l.transpose())
        };
        let deviator = strain_rate - Tensor::<3>::identity() * (strain_rate.trace() / 3.0);
        let compression = -strain_rate.trace();
        assert!(compression > 0.0);
        let mut heating = 0.0;
        let mut momentum = Vector::<3>::zeros();
        for (i, &h_reference) in h0.iter().enumerate() {
            close(p.density[i], rho, "ρ");
            close(p.pressure[i], pressure, "p");
            close(p.sound_speed[i], p_wave, "c_P");
            let h = h_reference * least_singular_value(&inverse);
            close(p.smoothing_length[i], h, "h");
            let q = rho
                * h
                * compression
                * (viscosity.alpha * p_wave + viscosity.beta * h * compression);
            close(
                p.strain_rate[i],
                (2.0 / 3.0 * deviator.norm_squared()).sqrt(),
                "equivalent strain rate",
            );
            assert!(
                (p.stress_rate[i] - deviator * (2.0 * shear_modulus)).norm()
                    <= 1e-9 * shear_modulus * deviator.norm(),
                "stress rate at {i}"
            );
            close(
                p.energy_rate[i],
                (pressure + q) * compression / rho,
                "De/Dt",
            );
            // the signal: c_P and the fastest approach −v_ij·x̂_ij of a partner within the
            // kernel's reach 2h in the initial shape (mirror images included), where
            // x_ij = A X_ij and v_ij = B X_ij
            let reach = 2.0 * h_reference;
            let approach = initial
                .iter()
                .flat_map(|&x| [x, Vector::<3>::new(2.0 * MIRROR_X - x[0], x[1], x[2])])
                .map(|x| x - initial[i])
                .filter(|separation| separation.norm() > 0.0 && separation.norm() < reach)
                .map(|separation| -(b * separation).dot(&(a * separation).normalize()))
                .fold(0.0, f64::max);
            assert!(approach > 0.0, "the pairs approach one another");
            close(p.signal_speed[i], p_wave + approach, "signal speed");
            heating += p.mass[i] * q * compression / rho;
            momentum += p.acceleration[i] * p.mass[i];
        }
        close(totals.viscous_heating, heating, "viscous heating");
        assert!(totals.hourglass_heating.abs() < 1e-9 * heating);
        let scale: f64 = (0..p.n_real())
            .map(|i| (p.acceleration[i] * p.mass[i]).norm())
            .sum();
        assert!(totals.wall_force[0] > 0.0, "the mirror holds the block");
        assert!((momentum - totals.wall_force).norm() < 1e-12 * scale);
    }

    /// The hourglass control resists a mode the corrected gradient cannot see, with the stiffness
    /// of Young's modulus E = 9KG/(3K + G) (Ganzenmüller 2015): two solids of equal E from
    /// different bulk and shear moduli (K, G = 1, 1 and 1.5, 0.9: E = 2.25) feel the same
    /// hourglass force on a checkerboard displacement of 1e-4 spacings (the force with control
    /// less the force without), and one of twice the moduli (2, 2: E = 4.5) twice that force,
    /// to 1e-3 (K follows the slightly changed density, which moves E by about 1e-5).
    #[test]
    fn the_hourglass_control_is_as_stiff_as_youngs_modulus() {
        let hourglass_forces = |bulk: f64, shear: f64| {
            let material = solid(bulk, shear);
            let at_rest = |hourglass: f64| {
                let (p, _) = checkerboard(&material, 1e-5, |_| Vector::zeros(), hourglass, 1.0);
                // at rest, no pair approaches: the signal travels at the sound speed
                assert_eq!(p.signal_speed, p.sound_speed);
                p.acceleration
            };
            let (with, without) = (at_rest(1.0), at_rest(0.0));
            with.iter()
                .zip(&without)
                .map(|(a, b)| a - b)
                .collect::<Vec<_>>()
        };
        let (first, second) = (hourglass_forces(1.0, 1.0), hourglass_forces(1.5, 0.9));
        let stiffer = hourglass_forces(2.0, 2.0);
        let largest = first.iter().map(|f| f.norm()).fold(0.0, f64::max);
        assert!(largest > 0.0, "the control acts on the checkerboard");
        for ((a, b), c) in first.iter().zip(&second).zip(&stiffer) {
            assert!((a - b).norm() < 1e-3 * largest, "{a} against {b}");
            assert!(
                (2.0 * a - c).norm() < 2e-3 * largest,
                "{c} against twice {a}"
            );
        }
    }

    /// The hourglass control's force is a stress times an area: with every length of the
    /// block and of its checkerboard doubled, each particle's share (the forces with the
    /// control less those without) is four times as large. Its pair stiffness
    /// κ E V_i V_j W_ij/|X_ij|² grows as the length (V² as its sixth power, W as its inverse
    /// cube, |X|² as its square) and acts on a stretch that grows as the length; the force
    /// points along the bond. Doubling is exact in binary, so the factor four holds to
    /// round-off (1e-12 of the largest force; measured exactly).
    #[test]
    fn the_hourglass_force_scales_as_a_stress_times_an_area() {
        let material = solid(1.0, 1.0);
        let hourglass_forces = |scale: f64| {
            let forces = |hourglass: f64| {
                let (p, _) = checkerboard(&material, 1e-5, |_| Vector::zeros(), hourglass, scale);
                (0..p.n_real())
                    .map(|k| p.acceleration[k] * p.mass[k])
                    .collect::<Vec<_>>()
            };
            let (with, without) = (forces(1.0), forces(0.0));
            with.iter()
                .zip(&without)
                .map(|(a, b)| a - b)
                .collect::<Vec<_>>()
        };
        let (unit, doubled) = (hourglass_forces(1.0), hourglass_forces(2.0));
        let largest = unit.iter().map(|f| f.norm()).fold(0.0, f64::max);
        assert!(largest > 0.0, "the control acts on the checkerboard");
        for (a, b) in unit.iter().zip(&doubled) {
            assert!(
                (4.0 * a - b).norm() < 1e-12 * largest,
                "{b} against four times {a}"
            );
        }
    }

    /// The partner lists are symmetric, hold no particle's own index (a particle beside the
    /// mirror is bonded to its own image) and are never empty in a block; what the rates of a
    /// few particles read is they and their partners, ascending, and their rates evaluated
    /// alone are those of the whole block's evaluation, bitwise (the same sums in the same
    /// order), on a deformed, moving block.
    #[test]
    fn partner_lists_are_symmetric_and_the_rates_read_the_partners() {
        let (mut p, domain) = block(1.0);
        let kernel = Kernel::<3>::new(KernelShape::CubicSpline);
        let reference = ReferenceConfiguration::new(&p, &domain, &kernel).unwrap();
        let lists = reference.partner_lists();
        let n = p.n_real();
        let self_bonded = (0..n)
            .filter(|&i| reference.bonds_of(i).iter().any(|b| b.other as usize == i))
            .count();
        assert!(self_bonded > 0, "no particle is bonded to its own image");
        for i in 0..n {
            let partners: Vec<usize> = lists.of(i).collect();
            assert!(
                !partners.is_empty() && !partners.contains(&i),
                "{i}: {partners:?}"
            );
            for &j in &partners {
                assert!(
                    lists.of(j).any(|k| k == i),
                    "{i} lists {j}, not the reverse"
                );
            }
        }
        let which = [3, 40, 77];
        let mut expected: Vec<usize> = which.iter().flat_map(|&i| lists.of(i)).collect();
        expected.extend(which);
        expected.sort_unstable();
        expected.dedup();
        assert_eq!(reference.with_partners(&which), expected);
        for k in 0..n {
            p.position[k][1] += 0.01 * checkerboard_sign(k);
            p.velocity[k] = Vector::<3>::new(0.1 * k as f64, -0.2, 0.05 * (k % 7) as f64);
        }
        let materials = [solid(1.0, 1.0)];
        let viscosity = ArtificialViscosity::default();
        let mut whole = p.clone();
        evaluate_all(&reference, &mut whole, &materials, &viscosity, 1.0).unwrap();
        reference
            .evaluate(&mut p, &materials, &viscosity, 1.0, &which)
            .unwrap();
        for i in which {
            assert_eq!(p.acceleration[i], whole.acceleration[i], "particle {i}");
            assert_eq!(p.energy_rate[i], whole.energy_rate[i], "particle {i}");
            assert_eq!(p.stress_rate[i], whole.stress_rate[i], "particle {i}");
        }
    }

    /// Two bonded particles driven onto one point: their bond has no direction, and the
    /// hourglass control leaves it out rather than dividing by its zero length, so every
    /// rate stays finite.
    #[test]
    fn a_bond_of_zero_length_leaves_the_rates_finite() {
        let (mut p, domain) = block(1.0);
        let kernel = Kernel::<3>::new(KernelShape::CubicSpline);
        let reference = ReferenceConfiguration::new(&p, &domain, &kernel).unwrap();
        p.position[1] = p.position[0];
        evaluate_all(
            &reference,
            &mut p,
            &[solid(1.0, 1.0)],
            &ArtificialViscosity::default(),
            1.0,
        )
        .unwrap();
        for k in 0..p.n_real() {
            assert!(
                p.acceleration[k].iter().all(|a| a.is_finite()),
                "particle {k}"
            );
            assert!(p.energy_rate[k].is_finite(), "particle {k}");
        }
    }

    /// The work of the forces becomes internal energy: on a checkerboard displacement with the
    /// particles moving at arbitrary speeds, the stress forces' power Σ m a·v is the negative
    /// of Σ m ė = Σ V0 P:Ḟ (the force and Ḟ are built from the same corrected gradients, so
    /// the discrete sums cancel exactly); the hourglass control's share of the forces (with
    /// less without) has the power Σ m Δa·v, and its share of the energy rates Σ m Δė is the
    /// booked hourglass heating, the negative of that power. Mirror images included: the
    /// whole symmetric body conserves energy, and the real half carries half of each sum. To
    /// 1e-9 of the power.
    #[test]
    fn the_forces_turn_their_work_into_internal_energy() {
        let material = solid(1.0, 1.0);
        let moving = |k: usize| {
            let s = k as f64;
            Vector::<3>::new((7.0 * s).sin(), (3.0 * s).cos(), (5.0 * s).sin())
        };
        let evaluated = |hourglass: f64| checkerboard(&material, 1e-3, moving, hourglass, 1.0);
        let ((with, totals), (without, _)) = (evaluated(1.0), evaluated(0.0));
        let (mut stress_power, mut internal, mut stress_scale) = (0.0, 0.0, 0.0);
        for i in 0..without.n_real() {
            let m = without.mass[i];
            let force_power = m * without.acceleration[i].dot(&without.velocity[i]);
            stress_power += force_power;
            stress_scale += force_power.abs();
            internal += m * without.energy_rate[i];
        }
        assert!(
            (stress_power + internal).abs() < 1e-9 * stress_scale,
            "stress power {stress_power}, internal {internal}"
        );
        let (mut power, mut heating, mut scale) = (0.0, 0.0, 0.0);
        for i in 0..with.n_real() {
            let m = with.mass[i];
            let force_power =
                m * (with.acceleration[i] - without.acceleration[i]).dot(&with.velocity[i]);
            power += force_power;
            scale += force_power.abs();
            heating += m * (with.energy_rate[i] - without.energy_rate[i]);
        }
        assert!(scale > 0.0, "the control acts");
        assert!(
            (heating - totals.hourglass_heating).abs() < 1e-9 * scale,
            "booked"
        );
        assert!(
            (power + heating).abs() < 1e-9 * scale,
            "power {power} heating {heating}"
        );
    }

    /// A lone particle has no neighbourhood to correct: refused by name.
    #[test]
    fn a_particle_without_neighbours_is_refused() {
        let (mut p, domain) = block(1.0);
        p.position[0] = Vector::<3>::new(0.5, 5.0, 5.0);
        let kernel = Kernel::<3>::new(KernelShape::CubicSpline);
        let error = ReferenceConfiguration::new(&p, &domain, &kernel).unwrap_err();
        assert!(
            error.to_string().contains("particle 0 neighbourhood"),
            "{error}"
        );
    }

    /// A stretch whose least singular values lie close (0.6 and 0.7 of the largest's 1.2, all
    /// times `scale`), turned on both sides: the power iteration's first estimate is several
    /// per cent off, and its stop at a relative change of 1e-3 in λ leaves less than 1e-3 at
    /// any scale (squeezed twentyfold to stretched tenfold).
    #[test]
    fn least_singular_value_of_a_turned_stretch() {
        let left = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let right = nalgebra::Rotation3::from_euler_angles(0.5, 0.2, -0.9).into_inner();
        for scale in [0.05, 1.0, 10.0] {
            let stretch = Tensor::<3>::from_diagonal(&Vector::<3>::new(1.2, 0.6, 0.7)) * scale;
            let f = left * stretch * right.transpose();
            let sigma = least_singular_value(&invert(&f).unwrap());
            assert!(
                (sigma / (0.6 * scale) - 1.0).abs() < 2e-3,
                "{sigma} at {scale}"
            );
        }
    }

    #[test]
    fn least_singular_value_of_a_stretch() {
        // F = R·diag(2, 0.5, 1.5): singular values 2, 0.5, 1.5
        let rotation = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let f = rotation * Tensor::<3>::from_diagonal(&Vector::<3>::new(2.0, 0.5, 1.5));
        let sigma = least_singular_value(&invert(&f).unwrap());
        assert!((sigma / 0.5 - 1.0).abs() < 2e-3, "{sigma}");
    }

    #[test]
    fn determinant_and_inverse_of_small_matrices() {
        let a3 = Tensor::<3>::new(2.0, 1.0, 0.5, -1.0, 3.0, 0.2, 0.3, 0.1, 1.5);
        let a2 = nalgebra::Matrix2::new(2.0, 1.5, -0.5, 3.0);
        let a1 = nalgebra::Matrix1::new(4.0);
        assert!((determinant(&a3) - a3.determinant()).abs() < 1e-12);
        assert!((determinant(&a2) - 6.75).abs() < 1e-12);
        assert!((invert(&a3).unwrap() * a3 - Tensor::<3>::identity()).norm() < 1e-12);
        assert!((invert(&a2).unwrap() * a2 - nalgebra::Matrix2::identity()).norm() < 1e-12);
        assert_eq!(invert(&a1).unwrap()[(0, 0)], 0.25);
        assert!(invert(&Tensor::<3>::zeros()).is_none());
    }
}
