//! Smoothing kernels W(r, h) = σ_D / h^D · w(q), q = r/h, with compact support κ·h.
//!
//! Shapes and normalisations (`reference_data/sph_kernels.csv` for the sources):
//! - cubic B-spline M4 (Monaghan & Lattanzio 1985), κ = 2;
//! - quintic spline M6 (Morris 1996), κ = 3;
//! - Wendland C2 and C4 (Wendland 1995; Dehnen & Aly 2012), κ = 2, with the 1D forms in 1D;
//! - Lucy quartic (Lucy 1977), written for support 2h: w = (1 + 3q/2)(1 − q/2)³;
//! - Gaussian (Gingold & Monaghan 1977), truncated at q = 3 and renormalised so that the
//!   truncated kernel still integrates to one.

use crate::Vector;
use std::f64::consts::PI;

/// The kernel shapes the solver offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelShape {
    CubicSpline,
    QuinticSpline,
    WendlandC2,
    WendlandC4,
    LucyQuartic,
    Gaussian,
}

impl KernelShape {
    pub const ALL: [KernelShape; 6] = [
        KernelShape::CubicSpline,
        KernelShape::QuinticSpline,
        KernelShape::WendlandC2,
        KernelShape::WendlandC4,
        KernelShape::LucyQuartic,
        KernelShape::Gaussian,
    ];

    /// Kebab-case name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            KernelShape::CubicSpline => "cubic-spline",
            KernelShape::QuinticSpline => "quintic-spline",
            KernelShape::WendlandC2 => "wendland-c2",
            KernelShape::WendlandC4 => "wendland-c4",
            KernelShape::LucyQuartic => "lucy-quartic",
            KernelShape::Gaussian => "gaussian",
        }
    }

    /// Support radius in units of h.
    pub fn support(self) -> f64 {
        match self {
            KernelShape::QuinticSpline | KernelShape::Gaussian => 3.0,
            _ => 2.0,
        }
    }
}

/// erf(3), Abramowitz & Stegun table 7.1, for the truncated Gaussian's normalisation.
const ERF_3: f64 = 0.999_977_909_503_001_4;

/// A kernel shape bound to a dimension, with its normalisation precomputed.
#[derive(Clone, Copy, Debug)]
pub struct Kernel<const D: usize> {
    shape: KernelShape,
    sigma: f64,
    support: f64,
}

impl<const D: usize> Kernel<D> {
    pub fn new(shape: KernelShape) -> Self {
        assert!((1..=3).contains(&D), "kernels are defined for D = 1, 2, 3");
        Self {
            shape,
            sigma: normalisation(shape, D),
            support: shape.support(),
        }
    }

    pub fn shape(&self) -> KernelShape {
        self.shape
    }

    /// Support radius κ·h: W vanishes for r ≥ κ·h.
    #[inline]
    pub fn support_radius(&self, h: f64) -> f64 {
        self.support * h
    }

    /// W(r, h).
    #[inline]
    pub fn value(&self, r: f64, h: f64) -> f64 {
        let inv_h = 1.0 / h;
        let q = r * inv_h;
        if q >= self.support {
            return 0.0;
        }
        self.sigma * inv_h.powi(D as i32) * shape_value(self.shape, D, q)
    }

    /// Whether a partner at distance r lies within the kernel's support κh (the same test as
    /// [`Self::value`] and [`Self::derivative`] make).
    #[inline]
    pub fn reaches(&self, r: f64, h: f64) -> bool {
        r * (1.0 / h) < self.support
    }

    /// Whether a partner at squared distance `r2` lies clearly beyond the support κh:
    /// r² > (κh)²(1 + 10⁻¹²). The margin is far above the few roundings of r = √r², 1/h and
    /// their product, so [`Self::reaches`] is then false and W and dW/dr are 0 exactly: pairs in
    /// a neighbour list's skin are dropped without a square root or a division.
    #[inline]
    pub fn clearly_beyond(&self, r2: f64, h: f64) -> bool {
        let reach = self.support * h;
        r2 > reach * reach * (1.0 + 1e-12)
    }

    /// dW/dr (h held fixed).
    #[inline]
    pub fn derivative(&self, r: f64, h: f64) -> f64 {
        let inv_h = 1.0 / h;
        let q = r * inv_h;
        if q >= self.support {
            return 0.0;
        }
        self.sigma * inv_h.powi(D as i32 + 1) * shape_derivative(self.shape, D, q)
    }

    /// ∂W/∂h (r held fixed) = −(D·W + r·∂W/∂r)/h, from W = σ h^{−D} w(r/h); the grad-h
    /// terms (Springel & Hernquist 2002) need it.
    #[inline]
    pub fn h_derivative(&self, r: f64, h: f64) -> f64 {
        -(D as f64 * self.value(r, h) + r * self.derivative(r, h)) / h
    }

    /// ∇_i W(|x_i − x_j|, h) for the separation `dx = x_i − x_j` of length `r`.
    #[inline]
    pub fn gradient(&self, dx: &Vector<D>, r: f64, h: f64) -> Vector<D> {
        if r <= 0.0 {
            return Vector::<D>::zeros();
        }
        dx * (self.derivative(r, h) / r)
    }
}

/// σ_D such that ∫ W dV = 1.
fn normalisation(shape: KernelShape, dim: usize) -> f64 {
    use KernelShape::*;
    match (shape, dim) {
        (CubicSpline, 1) => 2.0 / 3.0,
        (CubicSpline, 2) => 10.0 / (7.0 * PI),
        (CubicSpline, _) => 1.0 / PI,
        (QuinticSpline, 1) => 1.0 / 120.0,
        (QuinticSpline, 2) => 7.0 / (478.0 * PI),
        (QuinticSpline, _) => 1.0 / (120.0 * PI),
        (WendlandC2, 1) => 5.0 / 8.0,
        (WendlandC2, 2) => 7.0 / (4.0 * PI),
        (WendlandC2, _) => 21.0 / (16.0 * PI),
        (WendlandC4, 1) => 3.0 / 4.0,
        (WendlandC4, 2) => 9.0 / (4.0 * PI),
        (WendlandC4, _) => 495.0 / (256.0 * PI),
        // Lucy's constants 5/4, 5/π, 105/(16π) for support h, rescaled to support 2h.
        (LucyQuartic, 1) => 5.0 / 8.0,
        (LucyQuartic, 2) => 5.0 / (4.0 * PI),
        (LucyQuartic, _) => 105.0 / (128.0 * PI),
        (Gaussian, 1) => 1.0 / (PI.sqrt() * ERF_3),
        (Gaussian, 2) => 1.0 / (PI * (1.0 - (-9.0f64).exp())),
        (Gaussian, _) => 1.0 / (PI.powf(1.5) * ERF_3 - 6.0 * PI * (-9.0f64).exp()),
    }
}

/// The dimensionless shape w(q) for 0 ≤ q < κ.
#[inline]
fn shape_value(shape: KernelShape, dim: usize, q: f64) -> f64 {
    use KernelShape::*;
    let s = 1.0 - 0.5 * q;
    match shape {
        CubicSpline if q < 1.0 => 1.0 - 1.5 * q * q + 0.75 * q * q * q,
        CubicSpline => 0.25 * (2.0 - q).powi(3),
        QuinticSpline => {
            let t3 = (3.0 - q).powi(5);
            let t2 = if q < 2.0 { (2.0 - q).powi(5) } else { 0.0 };
            let t1 = if q < 1.0 { (1.0 - q).powi(5) } else { 0.0 };
            t3 - 6.0 * t2 + 15.0 * t1
        }
        WendlandC2 if dim == 1 => s.powi(3) * (1.0 + 1.5 * q),
        WendlandC2 => s.powi(4) * (1.0 + 2.0 * q),
        WendlandC4 if dim == 1 => s.powi(5) * (1.0 + 2.5 * q + 2.0 * q * q),
        WendlandC4 => s.powi(6) * (1.0 + 3.0 * q + 35.0 / 12.0 * q * q),
        LucyQuartic => s.powi(3) * (1.0 + 1.5 * q),
        Gaussian => (-q * q).exp(),
    }
}

/// dw/dq for 0 ≤ q < κ.
#[inline]
fn shape_derivative(shape: KernelShape, dim: usize, q: f64) -> f64 {
    use KernelShape::*;
    let s = 1.0 - 0.5 * q;
    match shape {
        CubicSpline if q < 1.0 => -3.0 * q + 2.25 * q * q,
        CubicSpline => -0.75 * (2.0 - q) * (2.0 - q),
        QuinticSpline => {
            let t3 = (3.0 - q).powi(4);
            let t2 = if q < 2.0 { (2.0 - q).powi(4) } else { 0.0 };
            let t1 = if q < 1.0 { (1.0 - q).powi(4) } else { 0.0 };
            -5.0 * t3 + 30.0 * t2 - 75.0 * t1
        }
        WendlandC2 if dim == 1 => -3.0 * q * s * s,
        WendlandC2 => -5.0 * q * s.powi(3),
        WendlandC4 if dim == 1 => -3.5 * q * s.powi(4) * (1.0 + 2.0 * q),
        WendlandC4 => -14.0 / 3.0 * q * s.powi(5) * (1.0 + 2.5 * q),
        LucyQuartic => -3.0 * q * s * s,
        Gaussian => -2.0 * q * (-q * q).exp(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    /// ∫ W dV by the midpoint rule in the radial coordinate: exact to ~1e-9 with 20 000 cells
    /// (the integrands are at least C¹ and the rule is second order).
    fn integral<const D: usize>(kernel: &Kernel<D>, h: f64) -> f64 {
        let cells = 20_000;
        let rmax = kernel.support_radius(h);
        let dr = rmax / cells as f64;
        (0..cells)
            .map(|k| {
                let r = (k as f64 + 0.5) * dr;
                let shell = match D {
                    1 => 2.0,
                    2 => 2.0 * PI * r,
                    _ => 4.0 * PI * r * r,
                };
                kernel.value(r, h) * shell * dr
            })
            .sum()
    }

    #[test]
    fn every_kernel_has_unit_integral_in_every_dimension() {
        for shape in KernelShape::ALL {
            for h in [0.3, 1.0, 2.7] {
                assert_relative_eq!(integral(&Kernel::<1>::new(shape), h), 1.0, epsilon = 1e-7);
                assert_relative_eq!(integral(&Kernel::<2>::new(shape), h), 1.0, epsilon = 1e-7);
                assert_relative_eq!(integral(&Kernel::<3>::new(shape), h), 1.0, epsilon = 1e-7);
            }
        }
    }

    fn check_derivative<const D: usize>(shape: KernelShape, q: f64) {
        let kernel = Kernel::<D>::new(shape);
        let h = 0.7;
        let r = q * h;
        let eps = 1e-6 * h;
        let numeric = (kernel.value(r + eps, h) - kernel.value(r - eps, h)) / (2.0 * eps);
        let scale = kernel.value(0.0, h) / h;
        assert!(
            (kernel.derivative(r, h) - numeric).abs() <= 1e-6 * scale,
            "{shape:?} D={D} q={q}: analytic {} numeric {numeric}",
            kernel.derivative(r, h)
        );
        let numeric_h = (kernel.value(r, h + eps) - kernel.value(r, h - eps)) / (2.0 * eps);
        assert!(
            (kernel.h_derivative(r, h) - numeric_h).abs() <= 1e-6 * scale,
            "{shape:?} D={D} q={q}: ∂W/∂h analytic {} numeric {numeric_h}",
            kernel.h_derivative(r, h)
        );
    }

    proptest! {
        /// The analytic derivatives in r and h match central differences (error O(eps²) ≪ 1e-6).
        #[test]
        fn derivative_matches_central_difference(q in 0.01f64..2.99, k in 0usize..6) {
            let shape = KernelShape::ALL[k];
            // skip the kinks of the piecewise shapes and the truncation edge
            let kinks = [1.0, 2.0, 3.0];
            prop_assume!(kinks.iter().all(|x| (q - x).abs() > 1e-3));
            prop_assume!(q < shape.support() - 1e-3);
            check_derivative::<1>(shape, q);
            check_derivative::<2>(shape, q);
            check_derivative::<3>(shape, q);
        }

        /// Positive, monotonically non-increasing, zero outside the support.
        #[test]
        fn kernel_is_positive_monotone_and_compact(q in 0.0f64..4.0, k in 0usize..6) {
            let kernel = Kernel::<3>::new(KernelShape::ALL[k]);
            let w = kernel.value(q, 1.0);
            prop_assert!(w >= 0.0);
            prop_assert!(kernel.derivative(q, 1.0) <= 1e-15);
            if q >= kernel.support_radius(1.0) {
                prop_assert_eq!(w, 0.0);
            }
        }
    }

    #[test]
    fn every_kernel_vanishes_at_the_edge_of_its_support() {
        // the truncated Gaussian is exp(−9) ≠ 0 just inside q = 3, so only the support test
        // makes W and dW/dr zero at and beyond κh; the splines reach zero there smoothly
        for shape in KernelShape::ALL {
            let kernel = Kernel::<2>::new(shape);
            let h = 0.4;
            let edge = kernel.support_radius(h);
            assert_eq!(edge, shape.support() * h);
            assert_eq!(kernel.value(edge, h), 0.0, "{shape:?}");
            assert_eq!(kernel.derivative(edge, h), 0.0, "{shape:?}");
            assert!(!kernel.reaches(edge, h), "{shape:?}");
            let inside = edge * (1.0 - 1e-9);
            assert!(kernel.reaches(inside, h), "{shape:?}");
            assert!(kernel.value(inside, h) > 0.0, "{shape:?}");
        }
        let gaussian = Kernel::<1>::new(KernelShape::Gaussian);
        assert!(gaussian.value(3.0 * (1.0 - 1e-9), 1.0) > 1e-5);
    }

    /// The square-root-free test may only drop pairs that the exact one drops: wherever
    /// `clearly_beyond` holds, `reaches` is false and W, dW/dr are 0. Checked over h of 24
    /// decades and separations packed about the edge (down to one ulp of r² either side), and
    /// it must drop every pair a relative 10⁻¹¹ beyond the edge.
    #[test]
    fn the_square_root_free_support_test_drops_only_what_the_exact_one_drops() {
        for shape in KernelShape::ALL {
            let kernel = Kernel::<3>::new(shape);
            for decade in -12..12 {
                let h = 1.37 * 10f64.powi(decade);
                let edge2 = kernel.support_radius(h).powi(2);
                let mut r2s: Vec<f64> = (-40..=40)
                    .map(|k| edge2 * (1.0 + k as f64 * 2.5e-14))
                    .collect();
                r2s.extend([edge2.next_down(), edge2, edge2.next_up(), 4.0 * edge2]);
                for r2 in r2s {
                    if kernel.clearly_beyond(r2, h) {
                        let r = r2.sqrt();
                        assert!(!kernel.reaches(r, h), "{shape:?} h {h} r² {r2}");
                        assert_eq!(kernel.value(r, h), 0.0);
                        assert_eq!(kernel.derivative(r, h), 0.0);
                    }
                }
                assert!(kernel.clearly_beyond(edge2 * (1.0 + 1e-11), h));
                assert!(!kernel.clearly_beyond(edge2, h));
            }
        }
    }

    #[test]
    fn the_gradient_at_zero_separation_is_zero() {
        // the self-contribution: dW/dr = 0 at r = 0, and dx/r would be 0/0
        for shape in KernelShape::ALL {
            let kernel = Kernel::<3>::new(shape);
            assert_eq!(
                kernel.gradient(&Vector::<3>::zeros(), 0.0, 1.0),
                Vector::<3>::zeros()
            );
        }
    }

    #[test]
    fn names_are_distinct_kebab_case() {
        let names: Vec<&str> = KernelShape::ALL.iter().map(|s| s.name()).collect();
        assert_eq!(
            names,
            [
                "cubic-spline",
                "quintic-spline",
                "wendland-c2",
                "wendland-c4",
                "lucy-quartic",
                "gaussian"
            ]
        );
    }

    #[test]
    #[should_panic(expected = "D = 1, 2, 3")]
    fn a_fourth_dimension_is_refused() {
        Kernel::<4>::new(KernelShape::CubicSpline);
    }

    #[test]
    fn gradient_is_antisymmetric_and_radial() {
        let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
        let dx = Vector::<2>::new(0.3, -0.4);
        let g = kernel.gradient(&dx, dx.norm(), 0.5);
        let g_back = kernel.gradient(&(-dx), dx.norm(), 0.5);
        assert_eq!(g, -g_back);
        assert_relative_eq!(g.x * dx.y, g.y * dx.x, epsilon = 1e-15);
    }
}
