//! The particle store: structure of arrays, one code path for D = 1, 2, 3.
//!
//! Indices `0..n_real` are real particles; indices `n_real..len` are images (ghosts) made by the
//! boundary conditions for one step and thrown away before the next. Whoever reorders particles
//! calls [`Particles::permute`], which moves every field at once.

use crate::{Tensor, Vector};

/// How an image particle derives from its real source: which velocity components flip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Image<const D: usize> {
    pub source: u32,
    /// +1 or −1 per axis (−1 where the image is a mirror across a wall normal to that axis).
    pub velocity_sign: Vector<D>,
    /// True if the image stands for a wall (its forces are the wall's reaction), false for a
    /// periodic copy (its forces are internal).
    pub is_wall: bool,
}

#[derive(Clone, Debug, Default)]
pub struct Particles<const D: usize> {
    pub position: Vec<Vector<D>>,
    pub velocity: Vec<Vector<D>>,
    pub mass: Vec<f64>,
    pub smoothing_length: Vec<f64>,
    pub density: Vec<f64>,
    pub internal_energy: Vec<f64>,
    pub pressure: Vec<f64>,
    pub sound_speed: Vec<f64>,
    /// Material index per particle; empty when the scene has a single material (index 0).
    pub material: Vec<u16>,
    /// The particle's label at creation, kept through reordering (for outputs and diagnoses).
    pub id: Vec<u32>,
    // Rates of the last force evaluation (real particles only).
    pub acceleration: Vec<Vector<D>>,
    pub energy_rate: Vec<f64>,
    /// Dρ/Dt; empty unless density is integrated by the continuity equation.
    pub density_rate: Vec<f64>,
    /// The grad-h correction Ω_i = 1 − (∂h_i/∂ρ_i) Σ_j m_j ∂W_ij(h_i)/∂h_i (real particles and
    /// images); empty unless h is solved with the density (grad-h).
    pub omega: Vec<f64>,
    /// Dh/Dt from the last force evaluation, which predicts the next step's h; empty unless
    /// grad-h.
    pub smoothing_rate: Vec<f64>,
    /// The highest density each particle has reached (real particles only); empty unless a
    /// material's pressure depends on it (compaction).
    pub peak_density: Vec<f64>,
    /// Solids: the deviatoric stress (in-plane block, real particles and images), its rate, the
    /// equivalent plastic strain and the plastic work per unit mass (real particles); empty
    /// unless some material has strength.
    pub deviatoric_stress: Vec<Tensor<D>>,
    pub stress_rate: Vec<Tensor<D>>,
    pub plastic_strain: Vec<f64>,
    pub plastic_work: Vec<f64>,
    /// The equivalent strain rate √(2/3 ė':ė') of the last force evaluation (solids).
    pub strain_rate: Vec<f64>,
    /// Programmed burn: each particle's lighting time (−∞ where it is not explosive) and burn
    /// fraction F (its pressure is F·p_EOS); empty without a burn.
    pub lighting_time: Vec<f64>,
    pub burn_fraction: Vec<f64>,
    /// Largest pair signal speed seen by each particle in the last force evaluation.
    pub signal_speed: Vec<f64>,
    /// Each real particle's own viscosity α (Morris & Monaghan's switch); empty without it.
    pub viscosity_alpha: Vec<f64>,
    n_real: usize,
    images: Vec<Image<D>>,
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
}

impl<const D: usize> Particles<D> {
    /// Builds the store with the `optional` fields; material ids are stored only when some
    /// particle is not material 0.
    pub fn new(init: &[ParticleInit<D>], optional: OptionalFields) -> Self {
        let n = init.len();
        let multi_material = init.iter().any(|p| p.material != 0);
        Self {
            position: init.iter().map(|p| p.position).collect(),
            velocity: init.iter().map(|p| p.velocity).collect(),
            mass: init.iter().map(|p| p.mass).collect(),
            smoothing_length: init.iter().map(|p| p.smoothing_length).collect(),
            density: init.iter().map(|p| p.density).collect(),
            internal_energy: init.iter().map(|p| p.internal_energy).collect(),
            pressure: vec![0.0; n],
            sound_speed: vec![0.0; n],
            material: if multi_material {
                init.iter().map(|p| p.material).collect()
            } else {
                Vec::new()
            },
            id: (0..n as u32).collect(),
            acceleration: vec![Vector::zeros(); n],
            energy_rate: vec![0.0; n],
            density_rate: if optional.density_rate {
                vec![0.0; n]
            } else {
                Vec::new()
            },
            omega: if optional.grad_h {
                vec![1.0; n]
            } else {
                Vec::new()
            },
            smoothing_rate: if optional.grad_h {
                vec![0.0; n]
            } else {
                Vec::new()
            },
            peak_density: if optional.peak_density {
                init.iter().map(|p| p.density).collect()
            } else {
                Vec::new()
            },
            deviatoric_stress: if optional.stress {
                vec![Tensor::zeros(); n]
            } else {
                Vec::new()
            },
            stress_rate: if optional.stress {
                vec![Tensor::zeros(); n]
            } else {
                Vec::new()
            },
            plastic_strain: if optional.stress {
                vec![0.0; n]
            } else {
                Vec::new()
            },
            plastic_work: if optional.stress {
                vec![0.0; n]
            } else {
                Vec::new()
            },
            strain_rate: if optional.stress {
                vec![0.0; n]
            } else {
                Vec::new()
            },
            lighting_time: Vec::new(),
            burn_fraction: Vec::new(),
            signal_speed: vec![0.0; n],
            viscosity_alpha: Vec::new(),
            n_real: n,
            images: Vec::new(),
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
        self.position.truncate(n);
        self.velocity.truncate(n);
        self.mass.truncate(n);
        self.smoothing_length.truncate(n);
        self.density.truncate(n);
        self.internal_energy.truncate(n);
        self.pressure.truncate(n);
        self.sound_speed.truncate(n);
        if !self.omega.is_empty() {
            self.omega.truncate(n);
        }
        if !self.deviatoric_stress.is_empty() {
            self.deviatoric_stress.truncate(n);
        }
        self.images.clear();
    }

    /// Appends an image of particle `of` (real or image) at `position`.
    pub fn push_image(&mut self, of: usize, position: Vector<D>, flip: Vector<D>, is_wall: bool) {
        let (source, sign, wall) = match self.image(of) {
            Some(im) => (
                im.source,
                im.velocity_sign.component_mul(&flip),
                im.is_wall || is_wall,
            ),
            None => (of as u32, flip, is_wall),
        };
        let s = source as usize;
        self.position.push(position);
        self.velocity.push(self.velocity[s].component_mul(&sign));
        self.mass.push(self.mass[s]);
        self.smoothing_length.push(self.smoothing_length[s]);
        self.density.push(self.density[s]);
        self.internal_energy.push(self.internal_energy[s]);
        self.pressure.push(self.pressure[s]);
        self.sound_speed.push(self.sound_speed[s]);
        if !self.omega.is_empty() {
            self.omega.push(self.omega[s]);
        }
        if !self.deviatoric_stress.is_empty() {
            self.deviatoric_stress
                .push(mirrored(&self.deviatoric_stress[s], &sign));
        }
        self.images.push(Image {
            source,
            velocity_sign: sign,
            is_wall: wall,
        });
    }

    /// Copies the thermodynamic state (ρ, e, p, c, h, Ω) of every real particle onto its images.
    pub fn refresh_image_state(&mut self) {
        for (k, image) in self.images.iter().enumerate() {
            let (i, s) = (self.n_real + k, image.source as usize);
            self.density[i] = self.density[s];
            self.internal_energy[i] = self.internal_energy[s];
            self.pressure[i] = self.pressure[s];
            self.sound_speed[i] = self.sound_speed[s];
            self.smoothing_length[i] = self.smoothing_length[s];
            if let Some(omega) = self.omega.get(s).copied() {
                self.omega[i] = omega;
            }
            if let Some(stress) = self.deviatoric_stress.get(s).copied() {
                self.deviatoric_stress[i] = mirrored(&stress, &image.velocity_sign);
            }
        }
    }

    /// Reorders the real particles so that new index k holds old index `order[k]`, moving every
    /// field at once. Images must have been cleared.
    pub fn permute(&mut self, order: &[usize]) {
        assert!(self.images.is_empty(), "clear images before reordering");
        assert_eq!(order.len(), self.n_real);
        fn apply<T: Copy>(field: &mut Vec<T>, order: &[usize]) {
            if !field.is_empty() {
                *field = order.iter().map(|&k| field[k]).collect();
            }
        }
        apply(&mut self.position, order);
        apply(&mut self.velocity, order);
        apply(&mut self.mass, order);
        apply(&mut self.smoothing_length, order);
        apply(&mut self.density, order);
        apply(&mut self.internal_energy, order);
        apply(&mut self.pressure, order);
        apply(&mut self.sound_speed, order);
        apply(&mut self.material, order);
        apply(&mut self.id, order);
        apply(&mut self.acceleration, order);
        apply(&mut self.energy_rate, order);
        apply(&mut self.density_rate, order);
        apply(&mut self.signal_speed, order);
        apply(&mut self.omega, order);
        apply(&mut self.smoothing_rate, order);
        apply(&mut self.peak_density, order);
        apply(&mut self.deviatoric_stress, order);
        apply(&mut self.stress_rate, order);
        apply(&mut self.plastic_strain, order);
        apply(&mut self.plastic_work, order);
        apply(&mut self.strain_rate, order);
        apply(&mut self.lighting_time, order);
        apply(&mut self.burn_fraction, order);
        apply(&mut self.viscosity_alpha, order);
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
