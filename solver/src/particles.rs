//! The particle store: structure of arrays, one code path for D = 1, 2, 3.
//!
//! Indices `0..n_real` are real particles; indices `n_real..len` are images (ghosts) made by the
//! boundary conditions for one step and thrown away before the next. Whoever reorders particles
//! calls [`Particles::permute`], which moves every field at once.

use crate::{Tensor, Vector};

/// How an image particle derives from its real source: where it stands and which velocity
/// components flip.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Image<const D: usize> {
    pub source: u32,
    /// +1 or −1 per axis (−1 where the image is a mirror across a wall normal to that axis):
    /// how the image's position and velocity components follow its source's.
    pub velocity_sign: Vector<D>,
    /// The image stands at `velocity_sign ⊙ x_source + shift`.
    pub shift: Vector<D>,
    /// True if the image stands for a wall (its forces are the wall's reaction), false for a
    /// periodic copy (its forces are internal).
    pub is_wall: bool,
}

/// Declares the particle store once: the fields that images carry (copied from their source,
/// seen through the mirror) and the fields of real particles alone. Every field is a `Vec`,
/// empty where the scene does not need it; `permute`, `clear_images`, `push_image` and
/// `refresh_image_state` visit the lists this macro makes, so a new field cannot be missed by
/// any of them.
macro_rules! particle_store {
    (
        imaged { $( $(#[$imaged_doc:meta])* $imaged:ident : $imaged_type:ty => $seen:expr, )* }
        real { $( $(#[$real_doc:meta])* $real:ident : $real_type:ty, )* }
    ) => {
        #[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
        pub struct Particles<const D: usize> {
            /// Positions of real particles and images (an image's is set by its boundary).
            pub position: Vec<Vector<D>>,
            $( $(#[$imaged_doc])* pub $imaged: Vec<$imaged_type>, )*
            $( $(#[$real_doc])* pub $real: Vec<$real_type>, )*
            n_real: usize,
            images: Vec<Image<D>>,
        }

        impl<const D: usize> Particles<D> {
            /// Visits every field that images carry, except the position.
            fn visit_imaged(&mut self, visitor: &mut impl ImagedFieldVisitor<D>) {
                $( visitor.visit(&mut self.$imaged, $seen); )*
            }

            /// Visits every field, the position included.
            fn visit_all(&mut self, visitor: &mut impl FieldVisitor) {
                visitor.visit(&mut self.position);
                $( visitor.visit(&mut self.$imaged); )*
                $( visitor.visit(&mut self.$real); )*
            }
        }
    };
}

particle_store! {
    imaged {
        velocity: Vector<D> => flipped,
        mass: f64 => same,
        smoothing_length: f64 => same,
        density: f64 => same,
        internal_energy: f64 => same,
        pressure: f64 => same,
        sound_speed: f64 => same,
        /// The grad-h correction Ω_i = 1 − (∂h_i/∂ρ_i) Σ_j m_j ∂W_ij(h_i)/∂h_i; empty unless h
        /// is solved with the density (grad-h).
        omega: f64 => same,
        /// Solids: the deviatoric stress (in-plane block); empty unless some material has
        /// strength.
        deviatoric_stress: Tensor<D> => mirrored,
    }
    real {
        /// Material index per particle; empty when the scene has a single material (index 0).
        material: u16,
        /// The particle's label at creation, kept through reordering (for outputs and
        /// diagnoses).
        id: u32,
        /// Dv/Dt of the last force evaluation.
        acceleration: Vector<D>,
        /// De/Dt of the last force evaluation.
        energy_rate: f64,
        /// Dρ/Dt; empty unless density is integrated by the continuity equation.
        density_rate: f64,
        /// Dh/Dt from the last force evaluation, which predicts the next step's h; empty unless
        /// grad-h.
        smoothing_rate: f64,
        /// The smallest h each particle may take, its initial h; empty unless h is floored
        /// ([`crate::formulation::SmoothingLength::FollowDensityFloored`]).
        smoothing_floor: f64,
        /// The highest density each particle has reached; empty unless a material's pressure
        /// depends on it (compaction).
        peak_density: f64,
        /// Solids: the rate of the deviatoric stress, the equivalent plastic strain and the
        /// plastic work per unit mass.
        stress_rate: Tensor<D>,
        plastic_strain: f64,
        plastic_work: f64,
        /// The equivalent strain rate √(2/3 ė':ė') of the last force evaluation (solids).
        strain_rate: f64,
        /// Programmed burn: each particle's lighting time (−∞ where it is not explosive) and burn
        /// fraction F (its pressure is F·p_EOS); empty without a burn.
        lighting_time: f64,
        burn_fraction: f64,
        /// Largest pair signal speed seen by each particle in the last force evaluation.
        signal_speed: f64,
        /// Each particle's own viscosity α (Morris & Monaghan's switch); empty without it.
        viscosity_alpha: f64,
        /// Balsara's factor of each particle's last force evaluation; empty without the switch.
        balsara_factor: f64,
        /// XSPH's correction to the drift velocity, ε Σ_j m_j/ρ̄_ij (v_j − v_i) W_ij, from the
        /// last force evaluation; empty without XSPH.
        xsph_velocity: Vector<D>,
        /// A constant acceleration from outside: the body force and support that hold the
        /// initial state in equilibrium (see `InitialState::held_in_equilibrium`); empty
        /// without one.
        external_acceleration: Vector<D>,
    }
}

/// Something done to every field alike (reordering, truncating).
trait FieldVisitor {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>);
}

/// Something done to every field an image carries; `seen` is how an image whose velocity
/// components flip with `sign` sees its source's value.
trait ImagedFieldVisitor<const D: usize> {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>, seen: fn(&T, &Vector<D>) -> T);
}

/// A scalar, the same from every side.
fn same<T: Copy, const D: usize>(value: &T, _: &Vector<D>) -> T {
    *value
}

/// A vector whose components flip with the mirror.
fn flipped<const D: usize>(value: &Vector<D>, sign: &Vector<D>) -> Vector<D> {
    value.component_mul(sign)
}

/// Keeps the first `n` entries of every field.
struct Truncate(usize);

impl FieldVisitor for Truncate {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>) {
        field.truncate(self.0);
    }
}

/// Keeps a field's real entries and the images marked in `keep` (fields that images do not
/// carry are left alone).
struct RetainImages<'a> {
    n_real: usize,
    keep: &'a [bool],
}

impl FieldVisitor for RetainImages<'_> {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>) {
        if field.len() > self.n_real {
            let mut index = 0;
            field.retain(|_| {
                let kept = index < self.n_real || self.keep[index - self.n_real];
                index += 1;
                kept
            });
        }
    }
}

/// Reorders every present field so that new index k holds old index `order[k]`.
struct Reorder<'a>(&'a [usize]);

impl FieldVisitor for Reorder<'_> {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>) {
        if !field.is_empty() {
            *field = self.0.iter().map(|&k| field[k]).collect();
        }
    }
}

/// Appends to every present field an image of entry `source` seen through `sign`.
struct AppendImage<const D: usize> {
    source: usize,
    sign: Vector<D>,
}

impl<const D: usize> ImagedFieldVisitor<D> for AppendImage<D> {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>, seen: fn(&T, &Vector<D>) -> T) {
        if !field.is_empty() {
            field.push(seen(&field[self.source], &self.sign));
        }
    }
}

/// Copies every present field of each real particle onto its images.
struct RefreshImages<'a, const D: usize> {
    n_real: usize,
    images: &'a [Image<D>],
}

impl<const D: usize> ImagedFieldVisitor<D> for RefreshImages<'_, D> {
    fn visit<T: Copy>(&mut self, field: &mut Vec<T>, seen: fn(&T, &Vector<D>) -> T) {
        if field.is_empty() {
            return;
        }
        for (k, image) in self.images.iter().enumerate() {
            field[self.n_real + k] = seen(&field[image.source as usize], &image.velocity_sign);
        }
    }
}

/// A tensor seen in a mirror: components s_ab change sign with the product of the axis signs
/// (a reflection across the plane normal to axis a flips s_ab for b ≠ a).
pub(crate) fn mirrored<const D: usize>(s: &Tensor<D>, sign: &Vector<D>) -> Tensor<D> {
    Tensor::from_fn(|a, b| s[(a, b)] * sign[a] * sign[b])
}

/// Initial state of one particle.
#[derive(Clone, Copy, Debug)]
pub struct ParticleInit<const D: usize> {
    pub position: Vector<D>,
    pub velocity: Vector<D>,
    pub mass: f64,
    pub smoothing_length: f64,
    pub density: f64,
    pub internal_energy: f64,
    pub material: u16,
}

/// The fields a scene needs beyond the ones every scene has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OptionalFields {
    /// Dρ/Dt (continuity density).
    pub density_rate: bool,
    /// Ω and Dh/Dt (grad-h).
    pub grad_h: bool,
    /// The highest density reached (compaction).
    pub peak_density: bool,
    /// Deviatoric stress and plastic state (solids).
    pub stress: bool,
    /// Each particle's initial h, the floor of its h.
    pub smoothing_floor: bool,
}

impl<const D: usize> Particles<D> {
    /// Builds the store with the `optional` fields; material ids are stored only when some
    /// particle is not material 0.
    pub fn new(init: &[ParticleInit<D>], optional: OptionalFields) -> Self {
        let n = init.len();
        let field = |present: bool, value: f64| if present { vec![value; n] } else { Vec::new() };
        let tensors = |present: bool| {
            if present {
                vec![Tensor::zeros(); n]
            } else {
                Vec::new()
            }
        };
        let of_each = |present: bool, value: fn(&ParticleInit<D>) -> f64| {
            if present {
                init.iter().map(value).collect()
            } else {
                Vec::new()
            }
        };
        let multi_material = init.iter().any(|p| p.material != 0);
        Self {
            position: init.iter().map(|p| p.position).collect(),
            velocity: init.iter().map(|p| p.velocity).collect(),
            mass: of_each(true, |p| p.mass),
            smoothing_length: of_each(true, |p| p.smoothing_length),
            density: of_each(true, |p| p.density),
            internal_energy: of_each(true, |p| p.internal_energy),
            pressure: field(true, 0.0),
            sound_speed: field(true, 0.0),
            material: if multi_material {
                init.iter().map(|p| p.material).collect()
            } else {
                Vec::new()
            },
            id: (0..n as u32).collect(),
            acceleration: vec![Vector::zeros(); n],
            energy_rate: field(true, 0.0),
            signal_speed: field(true, 0.0),
            density_rate: field(optional.density_rate, 0.0),
            omega: field(optional.grad_h, 1.0),
            smoothing_rate: field(optional.grad_h, 0.0),
            smoothing_floor: of_each(optional.smoothing_floor, |p| p.smoothing_length),
            peak_density: of_each(optional.peak_density, |p| p.density),
            deviatoric_stress: tensors(optional.stress),
            stress_rate: tensors(optional.stress),
            plastic_strain: field(optional.stress, 0.0),
            plastic_work: field(optional.stress, 0.0),
            strain_rate: field(optional.stress, 0.0),
            n_real: n,
            // set by the scene where it needs them: the burn, the viscosity switch
            ..Self::default()
        }
    }

    /// Number of real particles.
    pub fn n_real(&self) -> usize {
        self.n_real
    }

    /// Number of real particles plus images.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    #[inline]
    pub fn material_of(&self, i: usize) -> usize {
        let i = self.real_index(i);
        self.material.get(i).map_or(0, |&m| m as usize)
    }

    /// The highest density real particle i has reached (its density where that is not kept).
    #[inline]
    pub fn peak_density_of(&self, i: usize) -> f64 {
        self.peak_density.get(i).copied().unwrap_or(self.density[i])
    }

    /// What real solid particle i's yield limit depends on: plastic strain, the pressure and
    /// strain rate of the last force evaluation, and plastic work.
    pub fn yield_state(&self, i: usize) -> crate::strength::YieldState {
        crate::strength::YieldState {
            plastic_strain: self.plastic_strain[i],
            pressure: self.pressure[i],
            strain_rate: self.strain_rate[i],
            plastic_work: self.plastic_work[i],
        }
    }

    /// The real particle that index `i` is, or stands for.
    #[inline]
    pub fn real_index(&self, i: usize) -> usize {
        if i < self.n_real {
            i
        } else {
            self.images[i - self.n_real].source as usize
        }
    }

    #[inline]
    pub fn image(&self, i: usize) -> Option<&Image<D>> {
        i.checked_sub(self.n_real).map(|k| &self.images[k])
    }

    /// Removes all images.
    pub fn clear_images(&mut self) {
        let n = self.n_real;
        self.visit_all(&mut Truncate(n));
        self.images.clear();
    }

    /// Appends an image of particle `of` (real or image) at `flip ⊙ x_of + shift`: a mirror
    /// across a wall flips the axis normal to it and shifts by twice the wall's coordinate, a
    /// periodic copy shifts by the period.
    pub fn push_image(&mut self, of: usize, flip: Vector<D>, shift: Vector<D>, is_wall: bool) {
        let (source, sign, total_shift, wall) = match self.image(of) {
            Some(im) => (
                im.source,
                im.velocity_sign.component_mul(&flip),
                im.shift.component_mul(&flip) + shift,
                im.is_wall || is_wall,
            ),
            None => (of as u32, flip, shift, is_wall),
        };
        let position = self.position[of].component_mul(&flip) + shift;
        self.position.push(position);
        self.visit_imaged(&mut AppendImage {
            source: source as usize,
            sign,
        });
        self.images.push(Image {
            source,
            velocity_sign: sign,
            shift: total_shift,
            is_wall: wall,
        });
    }

    /// Keeps image k (the k-th made) where `keep[k]`, the kept ones in their order.
    pub fn retain_images(&mut self, keep: &[bool]) {
        assert_eq!(keep.len(), self.images.len());
        self.visit_all(&mut RetainImages {
            n_real: self.n_real,
            keep,
        });
        let mut kept = keep.iter();
        self.images.retain(|_| *kept.next().unwrap());
    }

    /// Copies the state of every real particle onto its images (seen through their mirrors).
    pub fn refresh_image_state(&mut self) {
        let images = std::mem::take(&mut self.images);
        self.visit_imaged(&mut RefreshImages {
            n_real: self.n_real,
            images: &images,
        });
        self.images = images;
    }

    /// Moves every image to where its source now puts it, and copies the source's state: the
    /// images as [`crate::boundary::Domain::make_images`] would make them afresh, kept in their
    /// places among the indices (which kept neighbour lists refer to).
    pub fn refresh_images(&mut self) {
        for (k, im) in self.images.iter().enumerate() {
            self.position[self.n_real + k] =
                self.position[im.source as usize].component_mul(&im.velocity_sign) + im.shift;
        }
        self.refresh_image_state();
    }

    /// Reorders the real particles so that new index k holds old index `order[k]`, moving every
    /// field at once. Images must have been cleared.
    pub fn permute(&mut self, order: &[usize]) {
        assert!(self.images.is_empty(), "clear images before reordering");
        assert_eq!(order.len(), self.n_real);
        self.visit_all(&mut Reorder(order));
    }

    /// Keeps the real particles `kept` (ascending indices), in that order, and drops the rest.
    pub fn keep_only(&mut self, kept: &[usize]) {
        assert!(
            self.images.is_empty(),
            "clear images before dropping particles"
        );
        debug_assert!(
            kept.windows(2).all(|w| w[0] < w[1]) && kept.iter().all(|&i| i < self.n_real)
        );
        self.visit_all(&mut Reorder(kept));
        self.n_real = kept.len();
    }

    /// Total mass of the real particles.
    pub fn total_mass(&self) -> f64 {
        self.mass[..self.n_real].iter().sum()
    }

    /// Total momentum Σ m v of the real particles.
    pub fn total_momentum(&self) -> Vector<D> {
        (0..self.n_real).fold(Vector::zeros(), |p, i| p + self.velocity[i] * self.mass[i])
    }

    /// Total energy Σ m (v²/2 + e) of the real particles.
    pub fn total_energy(&self) -> f64 {
        (0..self.n_real)
            .map(|i| {
                self.mass[i] * (0.5 * self.velocity[i].norm_squared() + self.internal_energy[i])
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four particles whose every field holds a value of its own particle.
    fn labelled() -> Particles<2> {
        let init: Vec<ParticleInit<2>> = (0..4)
            .map(|k| ParticleInit {
                position: Vector::<2>::new(k as f64, 0.0),
                velocity: Vector::<2>::new(0.0, k as f64),
                mass: 1.0 + k as f64,
                smoothing_length: 2.0 + k as f64,
                density: 3.0 + k as f64,
                internal_energy: 4.0 + k as f64,
                material: k as u16,
            })
            .collect();
        let all = OptionalFields {
            density_rate: true,
            grad_h: true,
            peak_density: true,
            stress: true,
            smoothing_floor: true,
        };
        let mut p = Particles::new(&init, all);
        for k in 0..4 {
            p.deviatoric_stress[k] = Tensor::<2>::from_element(k as f64);
            p.plastic_strain[k] = k as f64;
        }
        p
    }

    /// Reordering moves every field with its particle: afterwards each field of new index k
    /// holds old particle `order[k]`'s value, and its id says so.
    #[test]
    fn permute_moves_every_field_with_its_particle() {
        let mut p = labelled();
        let order = [2, 0, 3, 1];
        p.permute(&order);
        for (k, &old) in order.iter().enumerate() {
            let old_f = old as f64;
            assert_eq!(p.id[k], old as u32);
            assert_eq!(p.position[k][0], old_f);
            assert_eq!(p.velocity[k][1], old_f);
            assert_eq!(p.mass[k], 1.0 + old_f);
            assert_eq!(p.smoothing_length[k], 2.0 + old_f);
            assert_eq!(p.density[k], 3.0 + old_f);
            assert_eq!(p.peak_density[k], 3.0 + old_f);
            assert_eq!(p.internal_energy[k], 4.0 + old_f);
            assert_eq!(p.material_of(k), old);
            assert_eq!(p.deviatoric_stress[k][(0, 1)], old_f);
            assert_eq!(p.plastic_strain[k], old_f);
        }
    }

    /// Keeping particles 1 and 3 of four leaves two, each field of new index k holding kept
    /// particle k's value.
    #[test]
    fn keep_only_drops_the_others_and_moves_every_field() {
        let mut p = labelled();
        p.keep_only(&[1, 3]);
        assert_eq!((p.n_real(), p.len(), p.mass.len()), (2, 2, 2));
        for (k, old) in [1.0, 3.0].into_iter().enumerate() {
            assert_eq!(p.id[k], old as u32);
            assert_eq!(p.position[k][0], old);
            assert_eq!(p.mass[k], 1.0 + old);
            assert_eq!(p.plastic_strain[k], old);
            assert_eq!(p.deviatoric_stress[k][(0, 1)], old);
        }
    }

    /// An image across a wall normal to x carries its source's scalars, its velocity with the
    /// normal component flipped and its stress with the shear component flipped; refreshing
    /// copies the source's new state the same way; clearing removes every image's fields.
    #[test]
    fn images_see_their_source_through_the_mirror() {
        let mut p = labelled();
        p.velocity[1] = Vector::<2>::new(5.0, 7.0);
        p.deviatoric_stress[1] = Tensor::<2>::new(1.0, 2.0, 2.0, -1.0);
        let flip = Vector::<2>::new(-1.0, 1.0);
        // the mirror x = −0.5
        p.push_image(1, flip, Vector::<2>::new(-1.0, 0.0), true);
        let image = p.n_real();
        assert_eq!(p.len(), 5);
        assert_eq!(
            p.position[image],
            Vector::<2>::new(-1.0 - p.position[1][0], p.position[1][1])
        );
        assert_eq!(p.velocity[image], Vector::<2>::new(-5.0, 7.0));
        assert_eq!(
            p.deviatoric_stress[image],
            Tensor::<2>::new(1.0, -2.0, -2.0, -1.0)
        );
        assert_eq!((p.mass[image], p.density[image]), (2.0, 4.0));
        assert_eq!(p.real_index(image), 1);
        p.density[1] = 9.0;
        p.deviatoric_stress[1] = Tensor::<2>::new(0.0, 3.0, 3.0, 0.0);
        p.position[1] = Vector::<2>::new(0.25, 2.0);
        p.refresh_images();
        assert_eq!(p.density[image], 9.0);
        assert_eq!(p.deviatoric_stress[image][(0, 1)], -3.0);
        assert_eq!(p.position[image], Vector::<2>::new(-1.25, 2.0));
        p.clear_images();
        assert_eq!(p.len(), 4);
        assert_eq!(p.density.len(), 4);
        assert_eq!(p.deviatoric_stress.len(), 4);
        assert_eq!(p.omega.len(), 4);
    }

    /// Several images at once: an image of an image stands for a wall if either mirror is one
    /// and sees its source through both; refreshing and moving reach every image (not only
    /// the first); keeping some drops the others' entries from every field, the kept ones in
    /// their order.
    #[test]
    fn every_image_follows_its_own_source() {
        let mut p = labelled();
        let wall = Vector::<2>::new(-1.0, 1.0);
        let periodic = Vector::<2>::new(1.0, 1.0);
        p.push_image(1, wall, Vector::<2>::new(-1.0, 0.0), true);
        p.push_image(4, periodic, Vector::<2>::new(0.0, 10.0), false);
        p.push_image(2, periodic, Vector::<2>::new(0.0, -10.0), false);
        assert_eq!(p.len(), 7);
        let (corner, copy) = (&p.images[1], &p.images[2]);
        assert!(corner.is_wall && corner.source == 1 && corner.velocity_sign == wall);
        assert!(!copy.is_wall && copy.source == 2);
        assert_eq!(p.position[5], Vector::<2>::new(-2.0, 10.0));
        p.density[1] = 9.0;
        p.density[2] = 11.0;
        p.velocity[1] = Vector::<2>::new(5.0, 7.0);
        p.position[2] = Vector::<2>::new(2.5, 1.0);
        p.refresh_images();
        assert_eq!([p.density[4], p.density[5], p.density[6]], [9.0, 9.0, 11.0]);
        assert_eq!(p.velocity[5], Vector::<2>::new(-5.0, 7.0));
        assert_eq!(p.position[6], Vector::<2>::new(2.5, -9.0));
        p.retain_images(&[true, false, true]);
        assert_eq!((p.len(), p.images.len(), p.density.len()), (6, 2, 6));
        assert_eq!([p.density[4], p.density[5]], [9.0, 11.0]);
        assert_eq!(p.real_index(5), 2);
        // the scene's totals count real particles only
        assert_eq!(p.total_mass(), 1.0 + 2.0 + 3.0 + 4.0);
    }

    /// Σm, Σmv and Σm(v²/2 + e) worked by hand for the four labelled particles (masses 1–4,
    /// velocities (0, k), energies 4–7), with an image present that must not count.
    #[test]
    fn totals_of_the_real_particles() {
        let mut p = labelled();
        p.velocity[3] = Vector::<2>::new(2.0, 3.0);
        p.push_image(3, Vector::<2>::new(-1.0, 1.0), Vector::zeros(), true);
        assert!(!p.is_empty() && Particles::<2>::new(&[], OptionalFields::default()).is_empty());
        assert_eq!(p.total_mass(), 10.0);
        // Σ m v: 2·(0, 1) + 3·(0, 2) + 4·(2, 3)
        assert_eq!(p.total_momentum(), Vector::<2>::new(8.0, 20.0));
        // Σ m (v²/2 + e): 1·4 + 2·(1/2 + 5) + 3·(2 + 6) + 4·(13/2 + 7)
        assert_eq!(p.total_energy(), 4.0 + 11.0 + 24.0 + 54.0);
    }

    /// The peak density kept where the scene remembers one, the density where it does not;
    /// the yield state gathers its particle's own fields.
    #[test]
    fn peak_density_and_yield_state_read_their_particle() {
        let mut p = labelled();
        p.peak_density[2] = 8.5;
        assert_eq!(p.peak_density_of(2), 8.5);
        p.pressure[2] = 1e6;
        p.strain_rate[2] = 3.0;
        p.plastic_work[2] = 7.0;
        let state = p.yield_state(2);
        assert_eq!(
            (
                state.plastic_strain,
                state.pressure,
                state.strain_rate,
                state.plastic_work
            ),
            (2.0, 1e6, 3.0, 7.0)
        );
        let init = [ParticleInit {
            position: Vector::<1>::zeros(),
            velocity: Vector::<1>::zeros(),
            mass: 1.0,
            smoothing_length: 1.0,
            density: 2.5,
            internal_energy: 0.0,
            material: 0,
        }];
        let forgetful = Particles::new(&init, OptionalFields::default());
        assert_eq!(forgetful.peak_density_of(0), 2.5);
    }
}
