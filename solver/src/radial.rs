//! One-dimensional SPH in r for flows with cylindrical or spherical symmetry: each particle is a
//! ring (mass per unit length) or a shell (total mass) at radius r ≥ 0.
//!
//! The pair kernel is the ordinary 2D or 3D kernel averaged over the partner's ring or shell,
//! W̃(r_i, r_j; h) = ⟨W_D(|x_i − x_j|, h)⟩ over the directions of x_j, which is what 2D or 3D
//! SPH would sum if the partner's mass were spread evenly around the axis or the origin. With
//! s² = (r_i − r_j)² + 4 r_i r_j sin²θ (θ half the angle between x_i and x_j):
//! - cylindrical: W̃ = (2/π) ∫₀^{π/2} W₂(s, h) dθ,
//! - spherical:   W̃ = ∫₀^{π/2} sin 2θ · W₃(s, h) dθ.
//!
//! W̃ is symmetric in r_i, r_j and finite at r = 0, so the origin needs no images and no
//! special case: it reflects by symmetry. The equations follow from the Lagrangian
//! L = Σ m_i (v_i²/2 − e_i(ρ_i)) with ρ_i = m_i W̃(r_i, r_i; h_i) + Σ_j m_j W̃(r_i, r_j; h̄_ij)
//! (the self term depends on r_i: a pressurised shell pushes itself outwards), so total energy
//! is conserved by the pair terms. This replaces the origin corrections of Omang, Børve &
//! Trulsen (2006, J. Comput. Phys. 213, 391), who start from a 1D kernel, by the exact
//! average of the multi-dimensional one.
//!
//! In the spherical case the average has a closed form: with u = s, sin 2θ dθ = u du/(2 r_i r_j),
//! so W̃ = [F(r_i + r_j) − F(|r_i − r_j|)]/(2 r_i r_j) with the primitive
//! F(s) = ∫₀^s W₃(u) u du, which is exact Gauss–Legendre on each polynomial piece of the
//! kernel. Its derivatives follow from F′(s) = W₃(s) s. Close to the origin
//! (4 r_i r_j < 10⁻⁴ h²), where the difference of primitives cancels, and in the cylindrical
//! case, the θ integral is evaluated by Gauss–Legendre quadrature, split where s crosses the
//! kernel's knots so that each piece is smooth.

use crate::kernel::{Kernel, KernelShape};
use crate::neighbours::NeighbourList;
use crate::pairs::{self, PairEquation, Partners};
use crate::particles::Particles;
use crate::physics::{signal_speed, ArtificialViscosity, EnergyEquation};
use crate::step::SimulationConfig;
use crate::{Tensor, Vector};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// The symmetry of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// Cartesian coordinates in D dimensions.
    Planar,
    /// 1D in the distance from an axis; masses are per unit length.
    Cylindrical,
    /// 1D in the distance from a point; masses are those of whole shells.
    Spherical,
}

impl Geometry {
    pub const ALL: [Geometry; 3] = [Geometry::Planar, Geometry::Cylindrical, Geometry::Spherical];

    pub fn name(self) -> &'static str {
        match self {
            Geometry::Planar => "planar",
            Geometry::Cylindrical => "cylindrical",
            Geometry::Spherical => "spherical",
        }
    }

    /// The measure of a sphere of radius r in this geometry: 1 (planar, per unit area), 2πr
    /// (per unit length) or 4πr².
    pub fn area(self, r: f64) -> f64 {
        match self {
            Geometry::Planar => 1.0,
            Geometry::Cylindrical => 2.0 * PI * r,
            Geometry::Spherical => 4.0 * PI * r * r,
        }
    }

    /// The volume (per unit area, per unit length, or whole) between radii r0 < r1.
    pub fn volume_between(self, r0: f64, r1: f64) -> f64 {
        match self {
            Geometry::Planar => r1 - r0,
            Geometry::Cylindrical => PI * (r1 * r1 - r0 * r0),
            Geometry::Spherical => 4.0 / 3.0 * PI * (r1.powi(3) - r0.powi(3)),
        }
    }

    /// The width Δ of the ring or shell centred at r that holds `volume`: the root of
    /// volume_between(max(r − Δ/2, 0), r + Δ/2) = volume. While Δ ≤ 2r that volume is 2πrΔ
    /// (ring) or 4π(r²Δ + Δ³/12) (shell, solved by Newton's method from the thin-shell value
    /// V/(4πr²), which lies above the root of this convex cubic, so the iterates fall
    /// monotonically onto it); a ring or shell that reaches the origin holds π(r + Δ/2)² or
    /// 4π/3 (r + Δ/2)³. At the innermost shell of an even spacing (r = Δ/2, the whole ball)
    /// this is exactly Δ, where volume/area(r) is off by a third.
    pub fn shell_width(self, r: f64, volume: f64) -> f64 {
        match self {
            Geometry::Planar => volume,
            Geometry::Cylindrical => {
                let thin = volume / (2.0 * PI * r);
                if thin <= 2.0 * r {
                    thin
                } else {
                    2.0 * ((volume / PI).sqrt() - r)
                }
            }
            Geometry::Spherical => {
                let ball = (3.0 * volume / (4.0 * PI)).cbrt();
                if ball >= 2.0 * r {
                    return 2.0 * (ball - r);
                }
                let target = volume / (4.0 * PI);
                let mut width = target / (r * r);
                for _ in 0..50 {
                    let excess = width * width * width / 12.0 + r * r * width - target;
                    let step = excess / (0.25 * width * width + r * r);
                    width -= step;
                    if step <= 1e-15 * width {
                        break;
                    }
                }
                width
            }
        }
    }
}

/// An n-point Gauss–Legendre rule on [−1, 1] as (node, weight) pairs, exact for polynomials of
/// degree 2n − 1 (Abramowitz & Stegun, Table 25.4).
type GaussRule = &'static [(f64, f64)];

const GAUSS_3: GaussRule = &[
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];
const GAUSS_4: GaussRule = &[
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];
const GAUSS_5: GaussRule = &[
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.0, 128.0 / 225.0),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];
const GAUSS_8: GaussRule = &[
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// The fewest Gauss–Legendre points that integrate W₃(x) x exactly on a polynomial piece of
/// the 3D kernel: the piece's degree plus one is 4 (cubic spline), 5 (Lucy's quartic),
/// 6 (quintic spline, Wendland C2) or 9 (Wendland C4). The Gaussian is no polynomial: 8 points
/// on its unit pieces leave an error below 10⁻¹².
fn primitive_rule(shape: KernelShape) -> GaussRule {
    match shape {
        KernelShape::CubicSpline | KernelShape::LucyQuartic => GAUSS_3,
        KernelShape::QuinticSpline | KernelShape::WendlandC2 => GAUSS_4,
        KernelShape::WendlandC4 => GAUSS_5,
        KernelShape::Gaussian => GAUSS_8,
    }
}

/// The most quadrature pieces per pair: two kernel knots, the support and graded pieces.
const MAX_PIECES: usize = 16;
/// The graded pieces start at u = max(gap, GRADING_START·h): below that the odd powers of s
/// are resolved by the first piece already.
const GRADING_START: f64 = 1.0 / 64.0;

/// Where a kernel shape changes its polynomial piece (in units of h, inside the support).
fn knots(shape: KernelShape) -> &'static [f64] {
    match shape {
        KernelShape::CubicSpline => &[1.0],
        KernelShape::QuinticSpline => &[1.0, 2.0],
        _ => &[],
    }
}

/// The spherical average uses the primitive where 4 r_i r_j ≥ PRIMITIVE_FROM·h²: below, the
/// difference F(r_i + r_j) − F(|r_i − r_j|) loses digits as 1/(r_i r_j) (10⁻¹² relative here).
const PRIMITIVE_FROM: f64 = 1e-4;

/// Where the primitive's pieces end (in units of h): the kernel's knots and its support, and
/// unit pieces for the Gaussian, which is not a polynomial.
fn primitive_pieces(shape: KernelShape) -> &'static [f64] {
    match shape {
        KernelShape::CubicSpline => &[1.0, 2.0],
        KernelShape::QuinticSpline | KernelShape::Gaussian => &[1.0, 2.0, 3.0],
        _ => &[2.0],
    }
}

/// The ring- or shell-averaged kernel W̃ and its derivative in the first radius.
#[derive(Clone, Copy, Debug)]
pub struct RadialKernel {
    geometry: Geometry,
    plane: Kernel<2>,
    space: Kernel<3>,
    /// Φ at the end of each primitive piece (spherical).
    piece_sums: [f64; 3],
}

impl RadialKernel {
    /// The averaged kernel of `shape` for a cylindrical or spherical geometry.
    pub fn new(geometry: Geometry, shape: KernelShape) -> Self {
        assert!(
            geometry != Geometry::Planar,
            "planar scenes use the plain kernel"
        );
        let mut kernel = Self {
            geometry,
            plane: Kernel::new(shape),
            space: Kernel::new(shape),
            piece_sums: [0.0; 3],
        };
        let mut start = 0.0;
        let mut total = 0.0;
        for (k, &end) in primitive_pieces(shape).iter().enumerate() {
            total += kernel.piece_integral(start, end);
            kernel.piece_sums[k] = total;
            start = end;
        }
        kernel
    }

    /// (W, dW/ds) of the underlying 2D or 3D kernel.
    #[inline]
    fn base(&self, s: f64, h: f64) -> (f64, f64) {
        match self.geometry {
            Geometry::Cylindrical => (self.plane.value(s, h), self.plane.derivative(s, h)),
            _ => (self.space.value(s, h), self.space.derivative(s, h)),
        }
    }

    /// The angular weight of the average at half-angle θ.
    #[inline]
    fn weight(&self, theta: f64) -> f64 {
        match self.geometry {
            Geometry::Cylindrical => 2.0 / PI,
            _ => (2.0 * theta).sin(),
        }
    }

    /// Whether shells at r_i and r_j are within the kernel's reach κh of each other.
    #[inline]
    pub fn reaches(&self, r_i: f64, r_j: f64, h: f64) -> bool {
        let support = self.space.support_radius(h);
        (r_i - r_j) * (r_i - r_j) < support * support
    }

    /// (W̃(r_i, r_j; h), ∂W̃/∂r_i, ∂W̃/∂r_j). Zero for |r_i − r_j| ≥ κh.
    pub fn value_and_derivatives(&self, r_i: f64, r_j: f64, h: f64) -> (f64, f64, f64) {
        if !self.reaches(r_i, r_j, h) {
            return (0.0, 0.0, 0.0);
        }
        let gap2 = (r_i - r_j) * (r_i - r_j);
        let product = 4.0 * r_i * r_j;
        if self.geometry == Geometry::Spherical && product >= PRIMITIVE_FROM * h * h {
            return self.shell_average(r_i, r_j, h);
        }
        self.quadrature(r_i, r_j, h, gap2, product)
    }

    /// The spherical average from the primitive F (see the module notes):
    /// W̃ = [F(a) − F(b)]/(2 r_i r_j), a = r_i + r_j, b = |r_i − r_j|,
    /// ∂W̃/∂r_i = [F′(a) − sgn(r_i − r_j) F′(b)]/(2 r_i r_j) − W̃/r_i, and i ↔ j.
    fn shell_average(&self, r_i: f64, r_j: f64, h: f64) -> (f64, f64, f64) {
        let (sum, gap) = (r_i + r_j, (r_i - r_j).abs());
        let sign = (r_i - r_j).signum();
        let inverse = 0.5 / (r_i * r_j);
        let value = (self.primitive(sum, h) - self.primitive(gap, h)) * inverse;
        let (outer, inner) = (
            self.space.value(sum, h) * sum,
            self.space.value(gap, h) * gap,
        );
        (
            value,
            (outer - sign * inner) * inverse - value / r_i,
            (outer + sign * inner) * inverse - value / r_j,
        )
    }

    /// F(s) = ∫₀^s W₃(u; h) u du = Φ(s/h)/h with Φ(q) = ∫₀^q W₃(x; 1) x dx: the pieces
    /// below q from the table, the last one by Gauss–Legendre ([`primitive_rule`]).
    fn primitive(&self, s: f64, h: f64) -> f64 {
        let q = (s / h).min(self.space.support_radius(1.0));
        let ends = primitive_pieces(self.space.shape());
        let k = ends.partition_point(|&end| end <= q);
        let start = if k == 0 { 0.0 } else { ends[k - 1] };
        let below = if k == 0 { 0.0 } else { self.piece_sums[k - 1] };
        if q <= start {
            // at a knot, or beyond the support (where r_i + r_j mostly lies): the table alone
            return below / h;
        }
        (below + self.piece_integral(start, q)) / h
    }

    /// ∫_a^b W₃(x; 1) x dx on one piece of the primitive, by [`primitive_rule`].
    fn piece_integral(&self, a: f64, b: f64) -> f64 {
        let (half, mid) = (0.5 * (b - a), 0.5 * (b + a));
        let sum: f64 = primitive_rule(self.space.shape())
            .iter()
            .map(|&(x, w)| {
                let u = mid + half * x;
                w * self.space.value(u, 1.0) * u
            })
            .sum();
        sum * half
    }

    /// (W̃, ∂W̃/∂r_i, ∂W̃/∂r_j) from the θ integral by Gauss–Legendre quadrature.
    fn quadrature(&self, r_i: f64, r_j: f64, h: f64, gap2: f64, product: f64) -> (f64, f64, f64) {
        // the half-angle where s reaches a distance d (π/2 if it never does)
        let angle_at = |d: f64| {
            let sin2 = (d * d - gap2) / product;
            if product > 0.0 && sin2 < 1.0 {
                sin2.max(0.0).sqrt().asin()
            } else {
                FRAC_PI_2
            }
        };
        let (mut value, mut d_first, mut d_second) = (0.0, 0.0, 0.0);
        let mut start = 0.0;
        for d in self.piece_ends(gap2.sqrt(), h) {
            let end = angle_at(d);
            if end > start {
                let (half, mid) = (0.5 * (end - start), 0.5 * (end + start));
                for &(x, w) in GAUSS_8 {
                    let theta = mid + half * x;
                    let sin2 = theta.sin().powi(2);
                    let s = (gap2 + product * sin2).sqrt();
                    let (kernel, slope) = self.base(s, h);
                    let weight = w * half * self.weight(theta);
                    value += weight * kernel;
                    if s > 0.0 {
                        // ∂s/∂r_i = (r_i − r_j + 2 r_j sin²θ)/s, and i ↔ j for ∂s/∂r_j
                        let factor = weight * slope / s;
                        d_first += factor * (r_i - r_j + 2.0 * r_j * sin2);
                        d_second += factor * (r_j - r_i + 2.0 * r_i * sin2);
                    }
                }
            }
            start = end;
            if end >= FRAC_PI_2 {
                break;
            }
        }
        (value, d_first, d_second)
    }

    /// The distances s at which the quadrature pieces end, ascending, the last the support.
    /// Besides the kernel's knots: odd powers of s = √(gap² + u²) (u = √(4 r_i r_j) sin θ)
    /// change character over u ≈ gap, which a single Gauss rule over u ∈ [0, 2h] resolves
    /// poorly when the gap is much shorter than h; pieces ending at u = gap·2^k, k = 0, 1, …
    /// keep each piece's length comparable to its distance from that feature.
    fn piece_ends(&self, gap: f64, h: f64) -> impl Iterator<Item = f64> {
        let support = self.space.support_radius(h);
        let mut ends = [0.0; MAX_PIECES];
        let mut count = 0;
        for &q in knots(self.space.shape()) {
            if q * h > gap {
                ends[count] = q * h;
                count += 1;
            }
        }
        let mut u = gap.max(GRADING_START * h);
        while count < MAX_PIECES - 1 {
            let d = (gap * gap + u * u).sqrt();
            if d >= support {
                break;
            }
            ends[count] = d;
            count += 1;
            u *= 2.0;
        }
        ends[count] = support;
        count += 1;
        ends[..count].sort_by(f64::total_cmp);
        ends.into_iter().take(count)
    }

    /// d/dr W̃(r, r; h): how a ring's or shell's weight on itself changes as it moves, twice
    /// ∂W̃/∂r_i at r_i = r_j by symmetry.
    pub fn self_derivative(&self, r: f64, h: f64) -> f64 {
        2.0 * self.value_and_derivatives(r, r, h).1
    }
}

/// What the radial passes read of a neighbour.
pub(crate) struct ShellSource {
    radius: f64,
    velocity: f64,
    smoothing_length: f64,
    mass: f64,
    density: f64,
    sound_speed: f64,
    /// P = −σ_rr/ρ², or −σ_rr/ρ in the volume form (which divides by the partner's ρ in the
    /// pair): set by the rates' source; the density and divergence passes do not read it.
    pressure_term: f64,
    /// α_i/α_max of the viscosity switch (1 without it).
    alpha_factor: f64,
}

fn shell_source<const D: usize>(p: &Particles<D>, k: usize) -> ShellSource {
    ShellSource {
        radius: p.position[k][0],
        velocity: p.velocity[k][0],
        smoothing_length: p.smoothing_length[k],
        mass: p.mass[k],
        density: p.density[k],
        sound_speed: p.sound_speed[k],
        pressure_term: 0.0,
        alpha_factor: 1.0,
    }
}

/// The radial summation density ρ_i = m_i W̃(r_i, r_i; h_i) + Σ_j m_j W̃(r_i, r_j; h̄_ij).
pub(crate) struct RadialDensity<'a> {
    pub kernel: &'a RadialKernel,
}

impl<const D: usize> PairEquation<D> for RadialDensity<'_> {
    type Source = ShellSource;
    type Sum = f64;
    type Output = f64;

    fn source(&self, p: &Particles<D>, k: usize) -> ShellSource {
        shell_source(p, k)
    }

    fn start(&self, me: &ShellSource) -> f64 {
        let (r_i, h_i) = (me.radius, me.smoothing_length);
        me.mass * self.kernel.value_and_derivatives(r_i, r_i, h_i).0
    }

    #[inline]
    fn pair(&self, rho: &mut f64, me: &ShellSource, other: &ShellSource, _: &()) {
        let h = 0.5 * (me.smoothing_length + other.smoothing_length);
        *rho += other.mass
            * self
                .kernel
                .value_and_derivatives(me.radius, other.radius, h)
                .0;
    }

    fn finish(&self, _: &ShellSource, rho: f64) -> f64 {
        rho
    }
}

/// Each real shell's velocity divergence ∇·v = −(1/ρ) Dρ/Dt of the shell density:
/// −[Σ_j V_j (v_i d₁ + v_j d₂) + V_i v_i s_i] with V = m/ρ (the same sum as the continuity
/// density's), so it carries the hoop terms 2v/r (spherical) or v/r (cylindrical) that a
/// planar dv/dr lacks. The source of the viscosity switch. For the real particles `which`.
pub(crate) fn velocity_divergences<const D: usize>(
    particles: &Particles<D>,
    shell_pairs: &ShellPairs,
    kernel: &RadialKernel,
    which: &[usize],
) -> Vec<f64> {
    pairs::gather_at(&RadialDivergence { kernel }, particles, shell_pairs, which)
}

/// The averaged kernel of every pair of some real shells, (W̃, ∂W̃/∂r_i, ∂W̃/∂r_j) at
/// h̄ = (h_i + h_j)/2, worked out once for the passes that share it (the velocity divergence and
/// the rates); pairs beyond the kernel's reach are left out. Partners for the pair driver.
pub(crate) struct ShellPairs {
    /// Each real particle's place in `lists` (u32::MAX where it has none).
    slot: Vec<u32>,
    lists: Vec<Vec<(u32, [f64; 3])>>,
}

impl ShellPairs {
    /// The pairs of the real particles `which` among their neighbours.
    pub(crate) fn new<const D: usize>(
        particles: &Particles<D>,
        neighbours: &NeighbourList,
        kernel: &RadialKernel,
        which: &[usize],
    ) -> Self {
        let p = particles;
        let mut slot = vec![u32::MAX; p.n_real()];
        for (k, &i) in which.iter().enumerate() {
            slot[i] = k as u32;
        }
        let lists = which
            .par_iter()
            .with_min_len(pairs::PARTICLES_PER_TASK)
            .map(|&i| {
                let (r_i, h_i) = (p.position[i][0], p.smoothing_length[i]);
                let mut list = Vec::with_capacity(neighbours.partners(i).len());
                neighbours.visit(i, |j, _| {
                    let (r_j, h) = (p.position[j][0], 0.5 * (h_i + p.smoothing_length[j]));
                    if kernel.reaches(r_i, r_j, h) {
                        let (w, d1, d2) = kernel.value_and_derivatives(r_i, r_j, h);
                        list.push((j as u32, [w, d1, d2]));
                    }
                });
                list
            })
            .collect();
        Self { slot, lists }
    }
}

impl Partners for ShellPairs {
    type Link = [f64; 3];

    #[inline]
    fn visit(&self, i: usize, mut visit: impl FnMut(usize, &[f64; 3])) {
        for (j, kernel) in &self.lists[self.slot[i] as usize] {
            visit(*j as usize, kernel);
        }
    }
}

struct RadialDivergence<'a> {
    kernel: &'a RadialKernel,
}

impl<const D: usize> PairEquation<D, [f64; 3]> for RadialDivergence<'_> {
    type Source = ShellSource;
    type Sum = f64;
    type Output = f64;

    fn source(&self, p: &Particles<D>, k: usize) -> ShellSource {
        shell_source(p, k)
    }

    fn start(&self, me: &ShellSource) -> f64 {
        let self_slope = self.kernel.self_derivative(me.radius, me.smoothing_length);
        -me.mass / me.density * me.velocity * self_slope
    }

    #[inline]
    fn pair(&self, sum: &mut f64, me: &ShellSource, other: &ShellSource, kernel: &[f64; 3]) {
        let [_, d1, d2] = *kernel;
        *sum -= other.mass / other.density * (me.velocity * d1 + other.velocity * d2);
    }

    fn finish(&self, _: &ShellSource, divergence: f64) -> f64 {
        divergence
    }
}

/// Radial momentum and energy rates (P = p/ρ², d₁ = ∂W̃_ij/∂r_i, d₂ = ∂W̃_ij/∂r_j,
/// g = (d₁ − d₂)/2, s_i = dW̃(r_i, r_i; h_i)/dr):
/// Dv_i/Dt = −Σ_j m_j [(P_i + P_j) d₁ + Π_ij g] − m_i P_i s_i,
/// De_i/Dt = P_i [Σ_j m_j (v_i d₁ + v_j d₂) + m_i v_i s_i] + ½ Σ_j m_j Π_ij (v_i − v_j) g
/// (own-pressure form; the symmetric form shares (P_i + P_j)/2 instead of P_i). The viscous
/// gradient g is antisymmetric, so viscosity moves energy between kinetic and thermal and
/// creates none. Where the density is integrated (`volume_form`), P_i + P_j becomes
/// (p_i + p_j)/(ρ_i ρ_j) and the own-pressure heating p_i/(ρ_i ρ_j) per pair, as in Cartesian
/// coordinates (see [`crate::physics::compute_rates`]: across a density jump of 1000 the
/// standard form multiplies the light side's pressure by its heavy neighbour's mass), and
/// Dρ_i/Dt = ρ_i [Σ_j V_j (v_i d₁ + v_j d₂) + V_i v_i s_i] with V = m/ρ, so that
/// De_i/Dt = (p_i/ρ_i²) Dρ_i/Dt + viscous heating
/// (see [`crate::formulation::ShellDensity::Continuity`]).
///
/// Solids, in spheres: the deviator of a spherically symmetric stress is
/// s = s_rr (e_r e_r − ½ e_θ e_θ − ½ e_φ e_φ), so ∇·σ = ∂(−p + s_rr)/∂r + 3 s_rr/r. The pair
/// terms carry −σ_rr = p − s_rr in place of p (its radial gradient, and the matching heating
/// (p − s_rr)/ρ · (−∇·v)), and each shell adds the hoop force 3 s_rr/(ρ r) with its own work
/// −3 s_rr v/(ρ r) as heating; together the heating is s:ε̇/ρ = s_rr (ε̇_rr − ε̇_θθ)/ρ with
/// ε̇_rr = ∇·v − 2v/r and ε̇_θθ = ε̇_φφ = v/r, the same ∇·v the pair sums give, so the stress
/// conserves total energy as the pressure does. The Jaumann rate of s_rr is the 1D rate with
/// two out-of-plane normal rates v/r (no spin in radial flow). `shear_modulus[m]` is material
/// m's G (0 for a fluid); empty in a fluid scene. With XSPH (ε = `config.xsph` > 0) also
/// each shell's drift correction ε Σ_j m_j/ρ̄_ij (v_j − v_i) W̃_ij. For the real particles
/// `which`; the others keep their rates.
pub(crate) fn radial_rates<const D: usize>(
    particles: &mut Particles<D>,
    shell_pairs: &ShellPairs,
    kernel: &RadialKernel,
    config: &SimulationConfig,
    shear_modulus: &[f64],
    which: &[usize],
) {
    let equation = RadialRates {
        kernel,
        viscosity: &config.viscosity,
        energy: config.energy,
        volume_form: !particles.density_rate.is_empty(),
    };
    let rates = pairs::gather_at(&equation, particles, shell_pairs, which);
    let p = particles;
    for (&i, rate) in which.iter().zip(rates) {
        p.acceleration[i] = Vector::from_fn(|a, _| if a == 0 { rate.acceleration } else { 0.0 });
        p.energy_rate[i] = rate.heating;
        p.signal_speed[i] = rate.signal_speed;
        if let Some(drift) = p.xsph_velocity.get_mut(i) {
            drift[0] = config.xsph * rate.mean_motion;
        }
        if equation.volume_form {
            p.density_rate[i] = p.density[i] * rate.divergence;
        }
        if !p.deviatoric_stress.is_empty() {
            add_spherical_stress_terms(p, i, -rate.divergence, shear_modulus);
        }
    }
}

/// The hoop force and heating of shell i's deviatoric stress, its equivalent strain rate and
/// its stress rate, given ∇·v_i (see [`radial_rates`]).
fn add_spherical_stress_terms<const D: usize>(
    p: &mut Particles<D>,
    i: usize,
    divergence: f64,
    shear_modulus: &[f64],
) {
    let (r, v) = (p.position[i][0], p.velocity[i][0]);
    let hoop_rate = if r > 0.0 { v / r } else { 0.0 };
    let radial_rate = divergence - 2.0 * hoop_rate;
    let s_rr = p.deviatoric_stress[i][(0, 0)];
    if r > 0.0 {
        p.acceleration[i][0] += 3.0 * s_rr / (p.density[i] * r);
    }
    p.energy_rate[i] -= 3.0 * s_rr * hoop_rate / p.density[i];
    let gradient = Tensor::<D>::from_fn(|a, b| if a == 0 && b == 0 { radial_rate } else { 0.0 });
    p.strain_rate[i] = crate::strength::equivalent_strain_rate(&gradient, hoop_rate);
    let g = shear_modulus[p.material_of(i)];
    p.stress_rate[i] = if g > 0.0 {
        crate::strength::jaumann_rate(g, &p.deviatoric_stress[i], &gradient, hoop_rate)
    } else {
        Tensor::zeros()
    };
}

/// What [`RadialRates`] sums for one shell.
#[derive(Clone, Copy, Debug)]
struct ShellRates {
    acceleration: f64,
    heating: f64,
    signal_speed: f64,
    /// −∇·v: Σ_j V_j (v_i d₁ + v_j d₂) + V_i v_i s_i, which Dρ/Dt divides by ρ (with summation
    /// density m_j/ρ_i in place of V_j, the weights of its heating).
    divergence: f64,
    /// Σ_j m_j/ρ̄_ij (v_j − v_i) W̃_ij: the neighbours' motion relative to the shell's (XSPH).
    mean_motion: f64,
}

/// The pass of [`radial_rates`]: per real particle Dv/Dt, De/Dt, the signal speed and the
/// velocity divergence.
struct RadialRates<'a> {
    kernel: &'a RadialKernel,
    viscosity: &'a ArtificialViscosity,
    energy: EnergyEquation,
    /// Continuity density: the volume form of the pressure terms.
    volume_form: bool,
}

impl RadialRates<'_> {
    /// What a shell's pressure term is multiplied by in the pair with `other`: 1/ρ_j in the
    /// volume form.
    #[inline]
    fn partner_factor(&self, other: &ShellSource) -> f64 {
        if self.volume_form {
            1.0 / other.density
        } else {
            1.0
        }
    }
}

impl<const D: usize> PairEquation<D, [f64; 3]> for RadialRates<'_> {
    type Source = ShellSource;
    type Sum = ShellRates;
    type Output = ShellRates;

    fn source(&self, p: &Particles<D>, k: usize) -> ShellSource {
        let mut source = shell_source(p, k);
        // −σ_rr in the pressure's place (see `radial_rates`)
        let stress = p.pressure[k]
            - p.deviatoric_stress
                .get(p.real_index(k))
                .map_or(0.0, |s| s[(0, 0)]);
        source.pressure_term = if self.volume_form {
            stress / p.density[k]
        } else {
            stress / (p.density[k] * p.density[k])
        };
        if let Some(alpha) = p.viscosity_alpha.get(p.real_index(k)) {
            source.alpha_factor = alpha / self.viscosity.alpha;
        }
        source
    }

    /// The shell's force on itself: its self term m_i W̃(r_i, r_i; h_i) depends on r_i.
    fn start(&self, me: &ShellSource) -> ShellRates {
        let (own, m_i) = (me.pressure_term * self.partner_factor(me), me.mass);
        let self_slope = self.kernel.self_derivative(me.radius, me.smoothing_length);
        ShellRates {
            acceleration: -m_i * own * self_slope,
            heating: own * m_i * me.velocity * self_slope,
            signal_speed: me.sound_speed,
            divergence: m_i / me.density * me.velocity * self_slope,
            mean_motion: 0.0,
        }
    }

    #[inline]
    fn pair(&self, sum: &mut ShellRates, me: &ShellSource, other: &ShellSource, kernel: &[f64; 3]) {
        let (r_i, v_i) = (me.radius, me.velocity);
        let own = me.pressure_term * self.partner_factor(other);
        let (r_j, v_j, m_j) = (other.radius, other.velocity, other.mass);
        let h = 0.5 * (me.smoothing_length + other.smoothing_length);
        let [w, d1, d2] = *kernel;
        let g = 0.5 * (d1 - d2);
        let (x_ij, v_ij) = (r_i - r_j, v_i - v_j);
        let c_mean = 0.5 * (me.sound_speed + other.sound_speed);
        let rho_mean = 0.5 * (me.density + other.density);
        sum.mean_motion -= m_j / rho_mean * v_ij * w;
        let pi_ij = self
            .viscosity
            .pi(v_ij * x_ij, x_ij * x_ij, h, c_mean, rho_mean)
            * (0.5 * (me.alpha_factor + other.alpha_factor));
        let pressure_sum = own + other.pressure_term * self.partner_factor(me);
        sum.acceleration -= m_j * (pressure_sum * d1 + pi_ij * g);
        let flux = v_i * d1 + v_j * d2;
        let compression = m_j * flux;
        sum.heating += match self.energy {
            EnergyEquation::OwnPressure => own * compression,
            EnergyEquation::Symmetric => 0.5 * pressure_sum * compression,
        } + 0.5 * m_j * pi_ij * v_ij * g;
        // V_j in the volume form; m_j/ρ_i with summation density, as its heating weighs it
        sum.divergence += if self.volume_form {
            m_j / other.density
        } else {
            m_j / me.density
        } * flux;
        let approach = if x_ij == 0.0 {
            0.0
        } else {
            v_ij * x_ij.signum()
        };
        sum.signal_speed =
            sum.signal_speed
                .max(signal_speed(me.sound_speed, other.sound_speed, approach));
    }

    fn finish(&self, _: &ShellSource, sum: ShellRates) -> ShellRates {
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names the command line takes and the records show (`sedov --geometry`).
    #[test]
    fn geometries_go_by_their_names() {
        let names: Vec<&str> = Geometry::ALL.iter().map(|g| g.name()).collect();
        assert_eq!(names, ["planar", "cylindrical", "spherical"]);
    }

    /// The width holds the volume it was asked for, for thin rings and shells far out, thick
    /// ones that reach the origin and the innermost shell of an even lattice (to 10⁻¹¹: the
    /// test's own volume of a shell 10⁻⁴ r thin loses four digits to r₁² − r₀²).
    #[test]
    fn shell_width_holds_its_volume() {
        for geometry in [Geometry::Cylindrical, Geometry::Spherical] {
            for (r, width) in [
                (10.0f64, 1e-3f64),
                (1.0, 0.5),
                (0.25, 0.5),
                (0.1, 0.5),
                (2.0, 3.9),
            ] {
                let volume = geometry.volume_between((r - 0.5 * width).max(0.0), r + 0.5 * width);
                let got = geometry.shell_width(r, volume);
                assert!(
                    (got / width - 1.0).abs() < 1e-11,
                    "{geometry:?} r = {r}: {got} for {width}"
                );
            }
        }
    }

    /// The average by brute force: the midpoint rule over the full angle with many points.
    fn brute_average(geometry: Geometry, shape: KernelShape, r_i: f64, r_j: f64, h: f64) -> f64 {
        let n = 200_000;
        let dphi = PI / n as f64;
        (0..n)
            .map(|k| {
                let phi = (k as f64 + 0.5) * dphi;
                let s = (r_i * r_i + r_j * r_j - 2.0 * r_i * r_j * phi.cos())
                    .max(0.0)
                    .sqrt();
                match geometry {
                    Geometry::Cylindrical => Kernel::<2>::new(shape).value(s, h) / PI,
                    _ => 0.5 * phi.sin() * Kernel::<3>::new(shape).value(s, h),
                }
            })
            .sum::<f64>()
            * dphi
    }

    #[test]
    fn quadrature_matches_a_brute_force_average() {
        for geometry in [Geometry::Cylindrical, Geometry::Spherical] {
            for shape in KernelShape::ALL {
                let kernel = RadialKernel::new(geometry, shape);
                for (r_i, r_j) in [(0.0, 0.7), (0.3, 0.3), (0.5, 1.1), (2.0, 2.9), (10.0, 10.4)] {
                    let h = 0.5;
                    let got = kernel.value_and_derivatives(r_i, r_j, h).0;
                    let want = brute_average(geometry, shape, r_i, r_j, h);
                    let scale = Kernel::<3>::new(shape).value(0.0, h);
                    assert!(
                        (got - want).abs() < 1e-6 * scale,
                        "{geometry:?} {shape:?} ({r_i}, {r_j}): {got} vs {want}"
                    );
                }
            }
        }
    }

    /// Two rings or shells at the origin: every point of one lies on the other, so the
    /// average is the kernel's central value and, by symmetry, neither radius moves it.
    #[test]
    fn shells_at_the_origin_see_the_kernels_centre() {
        let h = 0.5;
        for (geometry, centre) in [
            (
                Geometry::Cylindrical,
                Kernel::<2>::new(KernelShape::CubicSpline).value(0.0, h),
            ),
            (
                Geometry::Spherical,
                Kernel::<3>::new(KernelShape::CubicSpline).value(0.0, h),
            ),
        ] {
            let kernel = RadialKernel::new(geometry, KernelShape::CubicSpline);
            let (value, d_first, d_second) = kernel.value_and_derivatives(0.0, 0.0, h);
            assert!(
                (value / centre - 1.0).abs() < 1e-14,
                "{geometry:?}: {value} against {centre}"
            );
            assert_eq!((d_first, d_second), (0.0, 0.0), "{geometry:?}");
        }
    }

    /// A solid shell at the centre (r = 0) carries no hoop terms: v/r and s_rr/(ρ r) are taken
    /// as 0 there (a shell of no radius has no hoop), so its rates stay finite; at rest with a
    /// radial deviatoric stress they are all 0.
    #[test]
    fn a_shell_at_the_centre_has_no_hoop_terms() {
        let init = [crate::particles::ParticleInit::<1> {
            position: Vector::<1>::new(0.0),
            velocity: Vector::<1>::new(0.0),
            mass: 1.0,
            smoothing_length: 0.1,
            density: 2.0,
            internal_energy: 0.0,
            material: 0,
        }];
        let optional = crate::particles::OptionalFields {
            stress: true,
            ..Default::default()
        };
        let mut p = Particles::new(&init, optional);
        p.deviatoric_stress[0][(0, 0)] = 5.0;
        add_spherical_stress_terms(&mut p, 0, 0.0, &[10.0]);
        assert_eq!(p.acceleration[0][0], 0.0);
        assert_eq!(p.energy_rate[0], 0.0);
        assert_eq!(p.strain_rate[0], 0.0);
        assert!(
            p.stress_rate[0].iter().all(|x| *x == 0.0),
            "{}",
            p.stress_rate[0]
        );
    }

    /// The quadrature's pieces end at the kernel's knots: for pairs whose distances cross h
    /// and 2h (gaps from h/10 to 2h) it agrees with the brute-force average to 2·10⁻⁹ of
    /// W(0) (the 2D kernel's for rings, the 3D kernel's for shells) for every shape, at
    /// h = 0.5 and with every length 1024 times shorter and longer. Measured: below
    /// 5·10⁻¹⁰ (the brute force's own error is about 10⁻¹⁰), while a Gauss piece
    /// across the quintic spline's knot at 2h is off by 4–8·10⁻⁹ (the most at the gap 1.7h),
    /// hence a limit within a factor ten of the measured value.
    #[test]
    fn the_quadrature_follows_the_kernels_knots() {
        for length in [1.0 / 1024.0, 1.0, 1024.0] {
            let h = 0.5 * length;
            for geometry in [Geometry::Cylindrical, Geometry::Spherical] {
                for shape in KernelShape::ALL {
                    let kernel = RadialKernel::new(geometry, shape);
                    // the average's own central value: W(0) of the plane's or the space's kernel
                    let scale = match geometry {
                        Geometry::Cylindrical => Kernel::<2>::new(shape).value(0.0, h),
                        _ => Kernel::<3>::new(shape).value(0.0, h),
                    };
                    for (r_i, r_j) in [
                        (0.3, 0.8),
                        (0.7, 1.6),
                        (0.2, 0.45),
                        (0.05, 0.9),
                        (0.2, 0.8),
                        (0.3, 1.15),
                    ] {
                        let (r_i, r_j) = (r_i * length, r_j * length);
                        let gap2 = (r_i - r_j) * (r_i - r_j);
                        let got = kernel.quadrature(r_i, r_j, h, gap2, 4.0 * r_i * r_j).0;
                        let want = brute_average(geometry, shape, r_i, r_j, h);
                        assert!(
                            (got - want).abs() < 2e-9 * scale,
                            "{geometry:?} {shape:?} ({r_i}, {r_j}) h = {h}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    /// The spherical closed form against the average computed independently to 30 digits
    /// (mpmath: ∫ W₃(u) u du over [|r_i − r_j|, r_i + r_j] split at the knots, divided by
    /// 2 r_i r_j, and its numerical derivatives), cubic spline, h = 0.3, (r_i, r_j) =
    /// (0.01, 0.2): W̃ = 6.543039824126543, ∂W̃/∂r_i = −1.308607309866695,
    /// ∂W̃/∂r_j = −39.23203732542431. Agreement to 10⁻¹¹ relative: r_i = h/30 here, and the
    /// derivatives lose digits as h/r_i to the difference of two terms.
    #[test]
    fn spherical_closed_form_matches_an_independent_evaluation() {
        let kernel = RadialKernel::new(Geometry::Spherical, KernelShape::CubicSpline);
        let got = kernel.value_and_derivatives(0.01, 0.2, 0.3);
        let want = (6.543039824126543, -1.308607309866695, -39.23203732542431);
        for (g, w) in [(got.0, want.0), (got.1, want.1), (got.2, want.2)] {
            assert!((g / w - 1.0).abs() < 1e-11, "{got:?} against {want:?}");
        }
    }

    /// The closed form and the θ quadrature are two evaluations of one integral: they agree to
    /// the quadrature's accuracy (10⁻⁷ of the kernel's central value in W̃, of W₃(0)/h in the
    /// derivatives), for every shape, from just above the switch between them
    /// (4 r_i r_j = 10⁻⁴ h²) to shells far from the origin. The truncated Gaussian's
    /// derivatives are left out: it jumps to zero at 3h, and the quadrature, which
    /// differentiates under the integral, misses the jump's moving edge that F′ accounts for.
    #[test]
    fn spherical_closed_form_matches_the_quadrature() {
        let h = 0.3;
        for shape in KernelShape::ALL {
            let kernel = RadialKernel::new(Geometry::Spherical, shape);
            let scale = Kernel::<3>::new(shape).value(0.0, h);
            for (r_i, r_j) in [
                (0.0016, 0.0015),
                (0.01, 0.2),
                (0.3, 0.3),
                (0.5, 1.1),
                (2.0, 2.05),
                (10.0, 10.4),
            ] {
                let gap2 = (r_i - r_j) * (r_i - r_j);
                let closed = kernel.shell_average(r_i, r_j, h);
                let summed = kernel.quadrature(r_i, r_j, h, gap2, 4.0 * r_i * r_j);
                let label = format!("{shape:?} ({r_i}, {r_j}): {closed:?} {summed:?}");
                assert!((closed.0 - summed.0).abs() < 1e-7 * scale, "{label}");
                if shape != KernelShape::Gaussian {
                    assert!((closed.1 - summed.1).abs() < 1e-7 * scale / h, "{label}");
                    assert!((closed.2 - summed.2).abs() < 1e-7 * scale / h, "{label}");
                }
            }
        }
    }

    /// The average has no length scale of its own: W̃(λr_i, λr_j; λh) = λ⁻³ W̃(r_i, r_j; h) and
    /// its derivatives scale as λ⁻⁴. With λ = 2¹⁰ or 2⁻¹⁰ every product, quotient and square
    /// root scales exactly, so both sides agree to round-off (10⁻¹³ here) wherever each pair is
    /// evaluated the same way at both scales: for shells near the axis (4 r_i r_j far below h²,
    /// where the primitive's difference would lose eight digits) as for shells far from it.
    #[test]
    fn the_spherical_average_scales_with_h() {
        let h = 0.3;
        for shape in KernelShape::ALL {
            let kernel = RadialKernel::new(Geometry::Spherical, shape);
            for (r_i, r_j) in [(1e-5, 2e-5), (0.0016, 0.0015), (0.01, 0.2), (2.0, 2.05)] {
                let base = kernel.value_and_derivatives(r_i, r_j, h);
                for scale in [1024.0f64, 1.0 / 1024.0] {
                    let scaled = kernel.value_and_derivatives(scale * r_i, scale * r_j, scale * h);
                    let label = format!("{shape:?} ({r_i}, {r_j}) × {scale}: {scaled:?} {base:?}");
                    let close = |got: f64, want: f64| (got - want).abs() <= 1e-13 * want.abs();
                    assert!(close(scaled.0 * scale.powi(3), base.0), "{label}");
                    assert!(close(scaled.1 * scale.powi(4), base.1), "{label}");
                    assert!(close(scaled.2 * scale.powi(4), base.2), "{label}");
                }
            }
        }
    }

    /// Each shape's rule integrates its kernel's pieces exactly: it agrees with the 8-point rule
    /// composed over 64 sub-intervals (exact to round-off for these polynomials, and for the
    /// Gaussian a quadrature error far below 10⁻¹⁴) to 10⁻¹³ of the whole primitive Φ(κ), from
    /// the start of each piece to points inside it (one point too few for Wendland C4 is off by
    /// 4·10⁻¹⁰).
    #[test]
    fn primitive_rules_are_exact_on_each_piece() {
        for shape in KernelShape::ALL {
            let kernel = RadialKernel::new(Geometry::Spherical, shape);
            let composite = |a: f64, b: f64| {
                let width = (b - a) / 64.0;
                (0..64)
                    .map(|k| {
                        let (lo, hi) = (a + k as f64 * width, a + (k + 1) as f64 * width);
                        let (half, mid) = (0.5 * (hi - lo), 0.5 * (hi + lo));
                        half * GAUSS_8
                            .iter()
                            .map(|&(x, w)| {
                                let u = mid + half * x;
                                w * kernel.space.value(u, 1.0) * u
                            })
                            .sum::<f64>()
                    })
                    .sum::<f64>()
            };
            let whole = composite(0.0, kernel.space.support_radius(1.0));
            let mut start = 0.0;
            for &end in primitive_pieces(shape) {
                for fraction in [0.13, 0.5, 0.77, 1.0] {
                    let b = start + fraction * (end - start);
                    let (got, want) = (kernel.piece_integral(start, b), composite(start, b));
                    assert!(
                        (got - want).abs() < 1e-13 * whole,
                        "{shape:?} on [{start}, {b}]: {got} against {want}"
                    );
                }
                start = end;
            }
        }
    }

    #[test]
    fn derivative_matches_a_central_difference() {
        for geometry in [Geometry::Cylindrical, Geometry::Spherical] {
            let kernel = RadialKernel::new(geometry, KernelShape::CubicSpline);
            for (r_i, r_j) in [(0.2, 0.5), (0.5, 0.2), (1.0, 1.3), (5.0, 4.4), (0.8, 0.8)] {
                let h = 0.4;
                let eps = 1e-6;
                let numeric = (kernel.value_and_derivatives(r_i + eps, r_j, h).0
                    - kernel.value_and_derivatives(r_i - eps, r_j, h).0)
                    / (2.0 * eps);
                let (_, analytic, second) = kernel.value_and_derivatives(r_i, r_j, h);
                assert!(
                    (analytic - numeric).abs() < 1e-6 * (1.0 + numeric.abs()),
                    "{geometry:?} ({r_i}, {r_j}): {analytic} vs {numeric}"
                );
                // W̃ is symmetric, so ∂W̃/∂r_j at (r_i, r_j) is ∂W̃/∂r_i at (r_j, r_i)
                let swapped = kernel.value_and_derivatives(r_j, r_i, h).1;
                assert!((second - swapped).abs() < 1e-12 * (1.0 + swapped.abs()));
            }
        }
    }

    /// Spreading unit mass over a ring or shell at r_i and summing its weight over all space
    /// gives one: ∫ W̃(r_i, r; h) A(r) dr = 1 with A the ring or shell measure.
    #[test]
    fn averaged_kernel_has_unit_integral() {
        for geometry in [Geometry::Cylindrical, Geometry::Spherical] {
            let kernel = RadialKernel::new(geometry, KernelShape::CubicSpline);
            for r_i in [0.0, 0.1, 0.6, 3.0] {
                let h = 0.3;
                let n = 20_000;
                let r_max = r_i + 2.0 * h;
                let dr = r_max / n as f64;
                let total: f64 = (0..n)
                    .map(|k| {
                        let r = (k as f64 + 0.5) * dr;
                        kernel.value_and_derivatives(r_i, r, h).0 * geometry.area(r) * dr
                    })
                    .sum();
                assert!(
                    (total - 1.0).abs() < 1e-6,
                    "{geometry:?} r = {r_i}: {total}"
                );
            }
        }
    }
}
