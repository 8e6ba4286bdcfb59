//! The domain and its boundaries: open (free surface), wall (mirror images, Libersky & Petschek
//! 1993) or periodic (shifted images), chosen per axis. Images are made afresh every step for the
//! particles within reach of a boundary, so the pair loops need no special cases.

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
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain<const D: usize> {
    pub lo: Vector<D>,
    pub hi: Vector<D>,
    pub boundary: [Boundary; D],
}

impl<const D: usize> Domain<D> {
    /// Unbounded: every axis open.
    pub fn open() -> Self {
        Self {
            lo: Vector::repeat(f64::NEG_INFINITY),
            hi: Vector::repeat(f64::INFINITY),
            boundary: [Boundary::Open; D],
        }
    }

    pub fn new(lo: Vector<D>, hi: Vector<D>, boundary: [Boundary; D]) -> Self {
        Self { lo, hi, boundary }
    }

    /// Appends images of every particle within `reach` of a wall or periodic side. Axes are done
    /// in turn over real particles and the images made so far, which makes the corner images.
    pub fn make_images(&self, particles: &mut Particles<D>, reach: f64) {
        particles.clear_images();
        for a in 0..D {
            if self.boundary[a] == Boundary::Open {
                continue;
            }
            let (lo, hi) = (self.lo[a], self.hi[a]);
            let mut flip = Vector::<D>::repeat(1.0);
            let periodic = self.boundary[a] == Boundary::Periodic;
            if !periodic {
                flip[a] = -1.0;
            }
            for i in 0..particles.len() {
                let x = particles.position[i];
                for (near, target) in [
                    (
                        x[a] - lo < reach,
                        if periodic {
                            x[a] + (hi - lo)
                        } else {
                            2.0 * lo - x[a]
                        },
                    ),
                    (
                        hi - x[a] < reach,
                        if periodic {
                            x[a] - (hi - lo)
                        } else {
                            2.0 * hi - x[a]
                        },
                    ),
                ] {
                    if near {
                        let mut y = x;
                        y[a] = target;
                        particles.push_image(i, y, flip, !periodic);
                    }
                }
            }
        }
    }

    /// Moves real particles that crossed a periodic side back into the box.
    pub fn wrap_periodic(&self, particles: &mut Particles<D>) {
        for a in (0..D).filter(|&a| self.boundary[a] == Boundary::Periodic) {
            let (lo, len) = (self.lo[a], self.hi[a] - self.lo[a]);
            let n = particles.n_real();
            for x in &mut particles.position[..n] {
                x[a] = lo + (x[a] - lo).rem_euclid(len);
            }
        }
    }

    /// The axis of a wall that `x` has passed through, if any.
    pub fn outside_wall(&self, x: &Vector<D>) -> Option<usize> {
        (0..D).find(|&a| {
            self.boundary[a] == Boundary::Wall && (x[a] < self.lo[a] || x[a] > self.hi[a])
        })
    }
}
