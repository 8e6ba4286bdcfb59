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
    /// A side through which matter leaves: no images, and a real particle found beyond it
    /// between two steps leaves the simulation, its momentum and energy booked as carried out
    /// (with the walls' impulse and the transmitted energy). For matter streaming away from
    /// what a scene studies, such as the products of a surface burst expanding into vacuum,
    /// which would otherwise be followed without end and stretch the neighbour grid with it.
    Outflow,
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

    /// Appends the images of the particles that a real particle can reach across a wall or
    /// periodic side, `reach[i]` being real particle i's kernel reach κ·h_i (an image reaches as
    /// far as its source). Axes are done in turn over real particles and the images made so
    /// far, which makes the corner images; every particle within the largest reach of a side is
    /// imaged across it. An image is then kept only where it can pair with a real particle
    /// ([`SideReach`]): a few particles with a large h (a blast's empty centre) need images
    /// far from the side only near themselves, not along the whole side. The kept images keep
    /// the order in which they were made.
    pub fn make_images(&self, particles: &mut Particles<D>, reach: &[f64]) {
        particles.clear_images();
        let n = particles.n_real();
        assert_eq!(reach.len(), n);
        let reach_max = reach.iter().cloned().fold(0.0, f64::max);
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
                    if x - lo < reach_max {
                        image(Vector::repeat(1.0), hi - lo, false);
                    }
                    if hi - x < reach_max {
                        image(Vector::repeat(1.0), -(hi - lo), false);
                    }
                    continue;
                }
                if self.lower[a] == Boundary::Wall && x - lo < reach_max {
                    image(mirror, 2.0 * lo, true);
                }
                if self.upper[a] == Boundary::Wall && hi - x < reach_max {
                    image(mirror, 2.0 * hi, true);
                }
            }
        }
        if particles.len() == n {
            return;
        }
        let sides: Vec<SideReach<D>> = self
            .imaging_sides()
            .map(|(axis, upper)| SideReach::new(self, axis, upper, &particles.position[..n], reach))
            .collect();
        let keep: Vec<bool> = (n..particles.len())
            .map(|k| {
                let x = &particles.position[k];
                let own = reach[particles.real_index(k)];
                sides.iter().all(|side| side.may_pair(x, own))
            })
            .collect();
        particles.retain_images(&keep);
    }

    /// The sides that make images, as (axis, upper side).
    fn imaging_sides(&self) -> impl Iterator<Item = (usize, bool)> + '_ {
        (0..D).flat_map(move |a| {
            [(false, self.lower[a]), (true, self.upper[a])]
                .into_iter()
                .filter(|(_, b)| matches!(b, Boundary::Wall | Boundary::Periodic))
                .map(move |(upper, _)| (a, upper))
        })
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

    /// Reflects the real particles that crossed a wall in the last drift (their `position`s)
    /// back across it, with the normal component of the `velocity` they drift with reversed:
    /// a specular bounce, which is what a frictionless wall or a symmetry plane does (the
    /// mirror images usually keep particles off the wall; a particle sliding along it in
    /// plastic flow can still cross by a hair). Returns the impulse the walls gave,
    /// Σ 2 m |v_n|, so that momentum stays accounted for.
    pub fn reflect_at_walls(
        &self,
        position: &mut [Vector<D>],
        velocity: &mut [Vector<D>],
        mass: &[f64],
    ) -> Vector<D> {
        let mut impulse = Vector::<D>::zeros();
        for ((x, v), m) in position.iter_mut().zip(velocity).zip(mass) {
            for a in 0..D {
                // the wall crossed, and the sign of its inward normal
                let crossed = if self.lower[a] == Boundary::Wall && x[a] < self.lo[a] {
                    Some((self.lo[a], 1.0))
                } else if self.upper[a] == Boundary::Wall && x[a] > self.hi[a] {
                    Some((self.hi[a], -1.0))
                } else {
                    None
                };
                if let Some((wall, inward)) = crossed {
                    x[a] = 2.0 * wall - x[a];
                    impulse[a] += inward * 2.0 * m * v[a].abs();
                    v[a] = -v[a];
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

    /// Whether `x` lies beyond an outflow side.
    pub fn beyond_outflow(&self, x: &Vector<D>) -> bool {
        (0..D).any(|a| {
            (self.lower[a] == Boundary::Outflow && x[a] < self.lo[a])
                || (self.upper[a] == Boundary::Outflow && x[a] > self.hi[a])
        })
    }

    /// Whether some side is an outflow side.
    pub fn has_outflow(&self) -> bool {
        self.lower
            .iter()
            .chain(&self.upper)
            .any(|&b| b == Boundary::Outflow)
    }

    /// The axis of a wall that `x` has passed through, if any.
    pub fn outside_wall(&self, x: &Vector<D>) -> Option<usize> {
        (0..D).find(|&a| {
            (self.lower[a] == Boundary::Wall && x[a] < self.lo[a])
                || (self.upper[a] == Boundary::Wall && x[a] > self.hi[a])
        })
    }
}

/// How far beyond one side of the domain the real particles reach, mapped over the side: a
/// grid of cells across the side's plane, each holding the largest depth κh_i − d_i beyond the
/// plane of the real particles i (d_i inside it) whose kernel sphere crosses the plane over that
/// cell. A point beyond the side inside the sphere of i lies at a depth below κh_i − d_i and
/// over the disc of radius √((κh_i)² − d_i²) in which the sphere cuts the plane, so a point
/// beyond the side that no real particle's sphere covers by this map, and that is farther from
/// the side than its own reach, pairs with no real particle (a pair's reach, κ·max(h_i, h_j) or
/// κ·(h_i + h_j)/2, is at most the larger of the two spheres').
struct SideReach<const D: usize> {
    axis: usize,
    upper: bool,
    plane: f64,
    /// The cells span the other axes (axis `axis` has one cell).
    origin: Vector<D>,
    cell_size: f64,
    dims: [usize; D],
    depth: Vec<f64>,
}

impl<const D: usize> SideReach<D> {
    fn new(
        domain: &Domain<D>,
        axis: usize,
        upper: bool,
        position: &[Vector<D>],
        reach: &[f64],
    ) -> Self {
        let plane = if upper {
            domain.hi[axis]
        } else {
            domain.lo[axis]
        };
        let inside = |x: &Vector<D>| {
            if upper {
                plane - x[axis]
            } else {
                x[axis] - plane
            }
        };
        // (centre, depth beyond the plane, radius of the disc on it) of each crossing sphere
        let crossing: Vec<(Vector<D>, f64, f64)> = position
            .iter()
            .zip(reach)
            .filter_map(|(x, &r)| {
                let d = inside(x).max(0.0);
                (r > d).then(|| (*x, r - d, (r * r - d * d).sqrt()))
            })
            .collect();
        let mut lo = Vector::<D>::repeat(f64::INFINITY);
        let mut hi = Vector::<D>::repeat(f64::NEG_INFINITY);
        for (x, _, radius) in &crossing {
            lo = lo.inf(&x.add_scalar(-radius));
            hi = hi.sup(&x.add_scalar(*radius));
        }
        let mut radii: Vec<f64> = crossing.iter().map(|c| c.2).collect();
        let mut cell_size = if radii.is_empty() {
            1.0
        } else {
            let middle = radii.len() / 2;
            *radii.select_nth_unstable_by(middle, f64::total_cmp).1
        };
        let max_cells = (4 * crossing.len() + 64) as f64;
        let dims = loop {
            let per_axis: [f64; D] = std::array::from_fn(|a| {
                if a == axis || crossing.is_empty() {
                    1.0
                } else {
                    ((hi[a] - lo[a]) / cell_size).floor() + 1.0
                }
            });
            if per_axis.iter().product::<f64>() <= max_cells {
                break per_axis.map(|c| c as usize);
            }
            cell_size *= 2.0;
        };
        let mut map = Self {
            axis,
            upper,
            plane,
            origin: lo,
            cell_size,
            dims,
            depth: vec![0.0; dims.iter().product()],
        };
        for (x, depth, radius) in &crossing {
            let first = map.cell_of(&x.add_scalar(-radius));
            let last = map.cell_of(&x.add_scalar(*radius));
            let mut cell = first;
            loop {
                let c = map.linear_index(&cell);
                map.depth[c] = map.depth[c].max(*depth);
                // odometer increment over the box first..=last
                let mut a = 0;
                while a < D && cell[a] == last[a] {
                    cell[a] = first[a];
                    a += 1;
                }
                if a == D {
                    break;
                }
                cell[a] += 1;
            }
        }
        map
    }

    /// The cell over which `x` lies, clamped to the grid (axis `axis` ignored).
    fn cell_of(&self, x: &Vector<D>) -> [usize; D] {
        std::array::from_fn(|a| {
            if a == self.axis {
                0
            } else {
                let c = ((x[a] - self.origin[a]) / self.cell_size).floor();
                (c.max(0.0) as usize).min(self.dims[a] - 1)
            }
        })
    }

    fn linear_index(&self, cell: &[usize; D]) -> usize {
        (0..D).rev().fold(0, |acc, a| acc * self.dims[a] + cell[a])
    }

    /// Whether a particle at `x` with kernel reach `own` can pair with a real particle across
    /// this side: always where `x` is not beyond it.
    fn may_pair(&self, x: &Vector<D>, own: f64) -> bool {
        let beyond = if self.upper {
            x[self.axis] - self.plane
        } else {
            self.plane - x[self.axis]
        };
        if beyond <= 0.0 || beyond < own {
            return true;
        }
        let inside_grid = (0..D).all(|a| {
            a == self.axis
                || (x[a] >= self.origin[a]
                    && x[a] < self.origin[a] + self.dims[a] as f64 * self.cell_size)
        });
        inside_grid && beyond < self.depth[self.linear_index(&self.cell_of(x))]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::neighbours::{find_neighbours, PairReach};
    use crate::particles::{OptionalFields, ParticleInit};
    use proptest::prelude::*;

    /// An image as (source, sign per axis, shift per axis in quarters of the box).
    type ImageKey = (u32, [i8; 2], [i64; 2]);

    fn key(source: u32, sign: &Vector<2>, shift: &Vector<2>) -> ImageKey {
        (
            source,
            [sign[0] as i8, sign[1] as i8],
            [
                (4.0 * shift[0]).round() as i64,
                (4.0 * shift[1]).round() as i64,
            ],
        )
    }

    /// A particle of density 1 and h = 0.1 (the tests below pass reaches explicitly).
    fn particle(position: (f64, f64), velocity: (f64, f64), mass: f64) -> ParticleInit<2> {
        ParticleInit {
            position: Vector::<2>::new(position.0, position.1),
            velocity: Vector::<2>::new(velocity.0, velocity.1),
            mass,
            smoothing_length: 0.1,
            density: 1.0,
            internal_energy: 1.0,
            material: 0,
        }
    }

    /// Every image a unit box [lo, lo + 1]² can make of each particle, without any reach test:
    /// mirrors across each wall, x ↦ 2 lo − x and 2 hi − x (and both walls' corners), and
    /// copies shifted by ±1 along a periodic axis, as (key, position).
    fn every_image(domain: &Domain<2>, x: &[Vector<2>]) -> Vec<(ImageKey, Vector<2>)> {
        let per_axis = |a: usize| -> Vec<(f64, f64)> {
            match domain.lower[a] {
                Boundary::Periodic => vec![(1.0, 0.0), (1.0, 1.0), (1.0, -1.0)],
                _ => vec![
                    (1.0, 0.0),
                    (-1.0, 2.0 * domain.lo[a]),
                    (-1.0, 2.0 * domain.hi[a]),
                ],
            }
        };
        let mut images = Vec::new();
        for (j, xj) in x.iter().enumerate() {
            for &(s0, t0) in &per_axis(0) {
                for &(s1, t1) in &per_axis(1) {
                    if (s0, t0, s1, t1) == (1.0, 0.0, 1.0, 0.0) {
                        continue;
                    }
                    let sign = Vector::<2>::new(s0, s1);
                    let shift = Vector::<2>::new(t0, t1);
                    images.push((
                        key(j as u32, &sign, &shift),
                        xj.component_mul(&sign) + shift,
                    ));
                }
            }
        }
        images
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The images kept give every real particle the same image partners as every image the
        /// box can make: mirror walls on both axes, or a wall and a periodic axis; h varies
        /// fourfold, and a few particles have an h ten times the rest (a blast's centre). The
        /// box's corner is moved off the origin (by quarters, so the keys stay exact).
        #[test]
        fn kept_images_are_every_image_a_real_particle_reaches(
            corner in (-8i32..8, -8i32..8),
            coords in proptest::collection::vec(0.0f64..1.0, 120),
            hs in proptest::collection::vec(0.02f64..0.08, 60),
            large in proptest::collection::vec(0usize..60, 0..3),
            periodic in any::<bool>(),
            larger_h in any::<bool>(),
        ) {
            let lo = Vector::<2>::new(0.25 * corner.0 as f64, 0.25 * corner.1 as f64);
            let x: Vec<Vector<2>> = coords
                .chunks_exact(2)
                .map(|c| lo + Vector::<2>::new(c[0], c[1]))
                .collect();
            let mut h = hs.clone();
            for &k in &large {
                h[k] = 0.3;
            }
            let domain = Domain::new(
                lo,
                lo + Vector::<2>::repeat(1.0),
                [Boundary::Wall, if periodic { Boundary::Periodic } else { Boundary::Wall }],
            );
            let pair_reach = if larger_h { PairReach::LargerH } else { PairReach::MeanH };
            let support = 2.0;
            let init: Vec<ParticleInit<2>> = x
                .iter()
                .zip(&h)
                .map(|(x, &h)| ParticleInit {
                    position: *x,
                    velocity: Vector::zeros(),
                    mass: 1.0,
                    smoothing_length: h,
                    density: 1.0,
                    internal_energy: 1.0,
                    material: 0,
                })
                .collect();
            let mut p = Particles::new(&init, OptionalFields::default());
            let n = x.len();
            let reach: Vec<f64> = h.iter().map(|h| support * h).collect();
            domain.make_images(&mut p, &reach);
            let searched: Vec<f64> = (0..p.len()).map(|k| h[p.real_index(k)]).collect();
            let lists = find_neighbours(&p.position, &searched, support, pair_reach, n);
            let candidates = every_image(&domain, &x);
            for i in 0..n {
                let mut found: Vec<ImageKey> = lists
                    .of(i)
                    .filter_map(|k| p.image(k))
                    .map(|im| key(im.source, &im.velocity_sign, &im.shift))
                    .collect();
                found.sort_unstable();
                let mut expected: Vec<ImageKey> = candidates
                    .iter()
                    .filter(|(k, xj)| {
                        let (hi, hj) = (h[i], h[k.0 as usize]);
                        let r = match pair_reach {
                            PairReach::LargerH => support * hi.max(hj),
                            PairReach::MeanH => 0.5 * support * (hi + hj),
                        };
                        (xj - x[i]).norm() < r
                    })
                    .map(|(k, _)| *k)
                    .collect();
                expected.sort_unstable();
                prop_assert_eq!(found, expected, "particle {}", i);
            }
        }
    }

    /// A particle that crossed a wall comes back mirrored with its normal velocity reversed,
    /// and the wall books the impulse 2 m |v_n| along its inward normal: the lower wall of x
    /// pushes +x, the upper wall of y pushes −y. A particle on a wall (lower or upper) has not
    /// crossed it and is left alone.
    #[test]
    fn a_particle_through_a_wall_bounces_back_and_the_wall_takes_the_impulse() {
        let init: Vec<ParticleInit<2>> = [
            ((-0.01, 0.5), (-2.0, 1.0), 3.0),
            ((0.5, 1.02), (1.0, 4.0), 0.5),
            ((0.0, 0.5), (-1.0, 0.0), 1.0),
            ((0.5, 1.0), (0.0, 1.0), 1.0),
        ]
        .iter()
        .map(|&(x, v, mass)| particle(x, v, mass))
        .collect();
        let mut p = Particles::new(&init, OptionalFields::default());
        let domain = Domain::new(
            Vector::<2>::zeros(),
            Vector::<2>::repeat(1.0),
            [Boundary::Wall; 2],
        );
        let n = p.n_real();
        let impulse =
            domain.reflect_at_walls(&mut p.position[..n], &mut p.velocity[..n], &p.mass[..n]);
        assert_eq!(p.position[0], Vector::<2>::new(0.01, 0.5));
        assert_eq!(p.velocity[0], Vector::<2>::new(2.0, 1.0));
        assert!((p.position[1] - Vector::<2>::new(0.5, 0.98)).norm() < 1e-15);
        assert_eq!(p.velocity[1], Vector::<2>::new(1.0, -4.0));
        assert_eq!(p.position[2], Vector::<2>::new(0.0, 0.5));
        assert_eq!(p.velocity[2], Vector::<2>::new(-1.0, 0.0));
        assert_eq!(p.velocity[3], Vector::<2>::new(0.0, 1.0));
        // 2·3·2 = 12 along +x; 2·0.5·4 = 4 along −y
        assert_eq!(impulse, Vector::<2>::new(12.0, -4.0));
    }

    /// The transmitting sides are listed with their plane and outward normal, lower before
    /// upper, axis by axis; walls, periodic and open sides are not.
    #[test]
    fn transmitting_sides_are_listed_with_their_outward_normal() {
        let (t, w) = (Boundary::Transmitting, Boundary::Wall);
        let lo = Vector::<3>::new(-1.0, -2.0, -3.0);
        let hi = Vector::<3>::new(1.0, 2.0, 3.0);
        let domain = Domain::with_sides(lo, hi, [t, w, Boundary::Open], [t, t, w]).unwrap();
        assert_eq!(
            domain.transmitting_sides(),
            vec![(0, -1.0, -1.0), (0, 1.0, 1.0), (1, 2.0, 1.0)]
        );
    }

    /// A point is beyond an outflow side only past it (on the plane it is not), and only past
    /// a side that is an outflow side: here the upper x and the lower y, beside a wall and an
    /// open side; a domain of walls and open sides has none.
    #[test]
    fn a_point_is_beyond_an_outflow_side_only_past_one() {
        let (o, w) = (Boundary::Outflow, Boundary::Wall);
        let (lo, hi) = (Vector::<2>::zeros(), Vector::<2>::repeat(1.0));
        let domain = Domain::with_sides(lo, hi, [w, o], [o, Boundary::Open]).unwrap();
        assert!(domain.has_outflow());
        let beyond = |x: f64, y: f64| domain.beyond_outflow(&Vector::<2>::new(x, y));
        assert!(beyond(1.01, 0.5) && beyond(0.5, -0.01) && beyond(1.01, -0.01));
        assert!(!beyond(1.0, 0.5) && !beyond(0.5, 0.0) && !beyond(0.5, 0.5));
        assert!(!beyond(-0.01, 0.5) && !beyond(0.5, 1.01));
        let closed = Domain::with_sides(lo, hi, [w, w], [Boundary::Open, w]).unwrap();
        assert!(!closed.has_outflow() && !closed.beyond_outflow(&Vector::<2>::new(2.0, -1.0)));
    }

    /// A side is periodic on both ends of its axis or on neither, and an axis needs lo < hi:
    /// anything else is refused, naming the axis.
    #[test]
    fn sides_and_extents_are_checked_per_axis() {
        let (lo, hi) = (Vector::<2>::zeros(), Vector::<2>::repeat(1.0));
        let (wall, periodic) = (Boundary::Wall, Boundary::Periodic);
        assert!(Domain::with_sides(lo, hi, [wall, periodic], [wall, periodic]).is_ok());
        let mixed = Domain::with_sides(lo, hi, [wall, periodic], [wall, wall]).unwrap_err();
        assert!(mixed.to_string().contains("boundary on axis 1"), "{mixed}");
        let flat = Vector::<2>::new(1.0, 0.0);
        let empty = Domain::with_sides(lo, flat, [wall; 2], [wall; 2]).unwrap_err();
        assert!(empty.to_string().contains("domain on axis 1"), "{empty}");
    }

    /// Images are made within the largest reach of a side and then kept only where a real
    /// particle's kernel can reach them: in the unit box with walls all round, a particle A at
    /// (0.9, 0.9) with reach 0.6 and a particle B at (0.5, 0.2) with reach 0.04. B lies within
    /// 0.6 of three walls, but its mirrors there stand 0.4 to 1 from every real particle: none
    /// is kept. A keeps its mirrors across x = 1 and y = 1 and their corner, 0.2 to 0.28 away.
    #[test]
    fn images_no_real_particle_reaches_are_dropped() {
        let init = [(0.9, 0.9), (0.5, 0.2)].map(|x| particle(x, (0.0, 0.0), 1.0));
        let mut p = Particles::new(&init, OptionalFields::default());
        let domain = Domain::new(
            Vector::<2>::zeros(),
            Vector::<2>::repeat(1.0),
            [Boundary::Wall; 2],
        );
        domain.make_images(&mut p, &[0.6, 0.04]);
        let mut kept: Vec<Vector<2>> = (2..p.len()).map(|k| p.position[k]).collect();
        assert!((2..p.len()).all(|k| p.real_index(k) == 0), "{kept:?}");
        kept.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
        let expected = [(0.9, 1.1), (1.1, 0.9), (1.1, 1.1)];
        assert_eq!(kept.len(), expected.len(), "{kept:?}");
        for (x, (ex, ey)) in kept.iter().zip(expected) {
            assert!((x - Vector::<2>::new(ex, ey)).norm() < 1e-12, "{kept:?}");
        }
    }

    /// A particle that left a periodic box [−1, 3) re-enters on the other side, as far in as it
    /// went out (x ↦ lo + (x − lo) mod L); one inside, or on a wall axis, is not moved.
    #[test]
    fn a_particle_leaving_a_periodic_side_comes_back_at_the_other() {
        let init = [(3.5, 3.5), (-1.25, 0.0), (2.0, -1.5)].map(|x| particle(x, (0.0, 0.0), 1.0));
        let mut p = Particles::new(&init, OptionalFields::default());
        let domain = Domain::new(
            Vector::<2>::repeat(-1.0),
            Vector::<2>::repeat(3.0),
            [Boundary::Periodic, Boundary::Wall],
        );
        domain.wrap_periodic(&mut p);
        assert_eq!(p.position[0], Vector::<2>::new(-0.5, 3.5));
        assert_eq!(p.position[1], Vector::<2>::new(2.75, 0.0));
        assert_eq!(p.position[2], Vector::<2>::new(2.0, -1.5));
    }

    /// The reach map is resolved along the side: in a box [0, 3] × [0, 1] with walls, two
    /// particles of reach 0.6 at (0.1, 0.3) and (2.9, 0.3) cross the plane y = 0 over
    /// x ∈ [−0.42, 0.62] and [2.38, 3.42], and a particle of reach 0.04 at (1.5, 0.2) between
    /// them has its mirror across y = 0 made (0.2 from the wall) but dropped: no sphere covers
    /// x = 1.5 beyond the wall. Each wide particle keeps its three mirrors.
    #[test]
    fn the_reach_map_drops_an_image_between_two_reaching_particles() {
        let init = [(0.1, 0.3), (2.9, 0.3), (1.5, 0.2)].map(|x| particle(x, (0.0, 0.0), 1.0));
        let mut p = Particles::new(&init, OptionalFields::default());
        let domain = Domain::new(
            Vector::<2>::zeros(),
            Vector::<2>::new(3.0, 1.0),
            [Boundary::Wall; 2],
        );
        domain.make_images(&mut p, &[0.6, 0.6, 0.04]);
        let sources: Vec<usize> = (3..p.len()).map(|k| p.real_index(k)).collect();
        assert_eq!(sources.len(), 6, "{sources:?}");
        assert!(sources.iter().all(|&s| s != 2), "{sources:?}");
    }

    /// `outside_wall` names the axis of a wall a point has passed, lower or upper; open and
    /// periodic sides, and the wall's own plane, do not count.
    #[test]
    fn outside_wall_names_the_axis_passed() {
        let domain = Domain::with_sides(
            Vector::<2>::zeros(),
            Vector::<2>::repeat(1.0),
            [Boundary::Open, Boundary::Wall],
            [Boundary::Wall, Boundary::Wall],
        )
        .unwrap();
        let at = |x: f64, y: f64| domain.outside_wall(&Vector::<2>::new(x, y));
        assert_eq!(at(0.5, 0.5), None);
        assert_eq!(at(-0.5, 0.5), None);
        assert_eq!(at(1.5, 0.5), Some(0));
        assert_eq!(at(0.5, -0.1), Some(1));
        assert_eq!(at(0.5, 1.1), Some(1));
        assert_eq!(at(1.0, 0.0), None);
    }

    /// Only walls and periodic sides make images: a particle beside an open or transmitting
    /// side has none there, while its mirror across the wall at the other end is made.
    #[test]
    fn open_and_transmitting_sides_make_no_images() {
        for upper in [Boundary::Open, Boundary::Transmitting] {
            let init = [particle((0.5, 0.95), (0.0, 0.0), 1.0)];
            let mut p = Particles::new(&init, OptionalFields::default());
            let domain = Domain::with_sides(
                Vector::<2>::zeros(),
                Vector::<2>::repeat(1.0),
                [Boundary::Open, Boundary::Wall],
                [Boundary::Open, upper],
            )
            .unwrap();
            // the particle reaches the upper side (0.05 away) and the lower wall (0.95)
            domain.make_images(&mut p, &[1.0]);
            assert_eq!(p.len(), 2, "{upper:?}");
            assert_eq!(p.position[1], Vector::<2>::new(0.5, -0.95), "{upper:?}");
        }
    }
}
