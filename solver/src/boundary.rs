//! The domain and its boundaries: open (free surface), wall (mirror images, Libersky & Petschek
//! 1993) or periodic (shifted images), chosen per axis. Images are made afresh every step for the
//! particles within reach of a boundary, so the pair loops need no special cases.

use crate::error::SolverError;
use crate::particles::Particles;
use crate::Vector;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// No images: a free surface.
    Open,
    /// Mirror images across the planes x_a = lo_a and x_a = hi_a, normal velocity reversed.
    Wall,
    /// Images shifted by ±(hi_a − lo_a); particles leaving one side re-enter at the other.
    Periodic,
    /// A side through which waves leave (Cartesian and axisymmetric scenes): no images, and the particles
    /// within a kernel support of the plane feel the traction of Lysmer & Kuhlemeyer's (1969)
    /// viscous boundary, −ρ c_P v_n normally and −ρ c_S v_t tangentially per unit area: the
    /// traction the material beyond would exert on a plane wave leaving through it. It is
    /// shared among them with the weights by which SPH's pressure terms share a free side's
    /// traction (see `Simulation`'s step), so that the two cancel for an outgoing wave. The
    /// work it takes out is booked as the energy transmitted, its impulse with the walls'.
    Transmitting,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain<const D: usize> {
    pub lo: Vector<D>,
    pub hi: Vector<D>,
    /// The boundary at x_a = lo_a, per axis.
    pub lower: [Boundary; D],
    /// The boundary at x_a = hi_a, per axis.
    pub upper: [Boundary; D],
}

impl<const D: usize> Domain<D> {
    /// Unbounded: every side open.
    pub fn open() -> Self {
        Self {
            lo: Vector::repeat(f64::NEG_INFINITY),
            hi: Vector::repeat(f64::INFINITY),
            lower: [Boundary::Open; D],
            upper: [Boundary::Open; D],
        }
    }

    /// The same boundary on both sides of each axis.
    pub fn new(lo: Vector<D>, hi: Vector<D>, boundary: [Boundary; D]) -> Self {
        Self {
            lo,
            hi,
            lower: boundary,
            upper: boundary,
        }
    }

    /// Each side its own boundary; a periodic axis must be periodic on both sides.
    pub fn with_sides(
        lo: Vector<D>,
        hi: Vector<D>,
        lower: [Boundary; D],
        upper: [Boundary; D],
    ) -> Result<Self, SolverError> {
        for a in 0..D {
            if (lower[a] == Boundary::Periodic) != (upper[a] == Boundary::Periodic) {
                return Err(SolverError::invalid(
                    &format!("boundary on axis {a}"),
                    format!("{:?}/{:?}", lower[a], upper[a]),
                    "periodic on both sides or on neither",
                ));
            }
            if !(lo[a] < hi[a]) {
                return Err(SolverError::invalid(
                    &format!("domain on axis {a}"),
                    format!("[{}, {}]", lo[a], hi[a]),
                    "lo < hi",
                ));
            }
        }
        Ok(Self {
            lo,
            hi,
            lower,
            upper,
        })
    }

    /// Appends images of every particle within `reach` of a wall or periodic side. Axes are done
    /// in turn over real particles and the images made so far, which makes the corner images.
    pub fn make_images(&self, particles: &mut Particles<D>, reach: f64) {
        particles.clear_images();
        for a in 0..D {
            let (lo, hi) = (self.lo[a], self.hi[a]);
            let periodic = self.lower[a] == Boundary::Periodic;
            let mut mirror = Vector::<D>::repeat(1.0);
            mirror[a] = -1.0;
            for i in 0..particles.len() {
                let x = particles.position[i][a];
                // the image along axis a at flip·x + shift
                let mut image = |flip: Vector<D>, shift: f64, is_wall: bool| {
                    let mut along = Vector::<D>::zeros();
                    along[a] = shift;
                    particles.push_image(i, flip, along, is_wall);
                };
                if periodic {
                    if x - lo < reach {
                        image(Vector::repeat(1.0), hi - lo, false);
                    }
                    if hi - x < reach {
                        image(Vector::repeat(1.0), -(hi - lo), false);
                    }
                    continue;
                }
                if self.lower[a] == Boundary::Wall && x - lo < reach {
                    image(mirror, 2.0 * lo, true);
                }
                if self.upper[a] == Boundary::Wall && hi - x < reach {
                    image(mirror, 2.0 * hi, true);
                }
            }
        }
    }

    /// Moves real particles that crossed a periodic side back into the box.
    pub fn wrap_periodic(&self, particles: &mut Particles<D>) {
        for a in (0..D).filter(|&a| self.lower[a] == Boundary::Periodic) {
            let (lo, len) = (self.lo[a], self.hi[a] - self.lo[a]);
            let n = particles.n_real();
            for x in &mut particles.position[..n] {
                x[a] = lo + (x[a] - lo).rem_euclid(len);
            }
        }
    }

    /// Reflects real particles that crossed a wall in the last drift back across it, with their
    /// normal velocity reversed: a specular bounce, which is what a frictionless wall or a
    /// symmetry plane does (the mirror images usually keep particles off the wall; a particle
    /// sliding along it in plastic flow can still cross by a hair). Returns the impulse the
    /// walls gave, Σ 2 m |v_n|, so that momentum stays accounted for.
    pub fn reflect_at_walls(&self, particles: &mut Particles<D>) -> Vector<D> {
        let mut impulse = Vector::<D>::zeros();
        for i in 0..particles.n_real() {
            for a in 0..D {
                let x = particles.position[i][a];
                // the wall crossed, and the sign of its inward normal
                let crossed = if self.lower[a] == Boundary::Wall && x < self.lo[a] {
                    Some((self.lo[a], 1.0))
                } else if self.upper[a] == Boundary::Wall && x > self.hi[a] {
                    Some((self.hi[a], -1.0))
                } else {
                    None
                };
                if let Some((wall, inward)) = crossed {
                    particles.position[i][a] = 2.0 * wall - x;
                    let v = particles.velocity[i][a];
                    particles.velocity[i][a] = -v;
                    impulse[a] += inward * 2.0 * particles.mass[i] * v.abs();
                }
            }
        }
        impulse
    }

    /// The transmitting sides: (axis, the plane's coordinate, the outward normal's sign).
    pub fn transmitting_sides(&self) -> Vec<(usize, f64, f64)> {
        let mut sides = Vec::new();
        for a in 0..D {
            if self.lower[a] == Boundary::Transmitting {
                sides.push((a, self.lo[a], -1.0));
            }
            if self.upper[a] == Boundary::Transmitting {
                sides.push((a, self.hi[a], 1.0));
            }
        }
        sides
    }

    /// The axis of a wall that `x` has passed through, if any.
    pub fn outside_wall(&self, x: &Vector<D>) -> Option<usize> {
        (0..D).find(|&a| {
            (self.lower[a] == Boundary::Wall && x[a] < self.lo[a])
                || (self.upper[a] == Boundary::Wall && x[a] > self.hi[a])
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::{OptionalFields, ParticleInit};

    /// A particle that crossed the lower wall comes back mirrored with its normal velocity
    /// reversed, and the wall books the impulse 2 m |v_n| along its inward normal.
    #[test]
    fn a_particle_through_a_wall_bounces_back_and_the_wall_takes_the_impulse() {
        let init = [ParticleInit {
            position: Vector::<2>::new(-0.01, 0.5),
            velocity: Vector::<2>::new(-2.0, 1.0),
            mass: 3.0,
            smoothing_length: 0.1,
            density: 1.0,
            internal_energy: 1.0,
            material: 0,
        }];
        let mut p = Particles::new(&init, OptionalFields::default());
        let domain = Domain::new(
            Vector::<2>::zeros(),
            Vector::<2>::repeat(1.0),
            [Boundary::Wall; 2],
        );
        let impulse = domain.reflect_at_walls(&mut p);
        assert_eq!(p.position[0], Vector::<2>::new(0.01, 0.5));
        assert_eq!(p.velocity[0], Vector::<2>::new(2.0, 1.0));
        assert_eq!(impulse, Vector::<2>::new(12.0, 0.0));
    }
}
