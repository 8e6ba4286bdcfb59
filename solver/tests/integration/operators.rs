//! The interpolation and gradient operators.
//!
//! Standard SPH against an independent fact: in 1D the cubic spline with h equal to the spacing
//! is the cubic B-spline on the lattice's knots, and cubic B-splines sum to one and reproduce
//! linear functions exactly (Schoenberg's partition of unity), so on a uniform lattice the
//! interpolant of a linear field, and its derivative, are exact away from the ends.
//!
//! Wiring tests (named so) of the corrected operators: Shepard's interpolant and CSPM's gradient
//! reproduce constant and linear fields by construction (Σ W u / Σ W with u = 1; a gradient
//! multiplied by the inverse of the kernel's first moment). They show the code is wired as the
//! formulas say, on an irregular 2D point set with a boundary; they verify nothing beyond that.

use blastsph_solver::operators::{
    cspm_gradient, shepard_interpolate, sph_gradient, sph_interpolate, PointSet,
};
use blastsph_solver::random::SplitMix64;
use blastsph_solver::{Kernel, KernelShape, Vector};

/// A 10 × 10 lattice of unit spacing, each point moved by up to 0.3 in each direction.
fn jittered_points() -> (Vec<Vector<2>>, Vec<f64>) {
    let mut random = SplitMix64::new(11);
    let points: Vec<Vector<2>> = (0..100)
        .map(|k| {
            let mut jitter = || 0.6 * (random.uniform() - 0.5);
            Vector::<2>::new((k % 10) as f64 + jitter(), (k / 10) as f64 + jitter())
        })
        .collect();
    (points, vec![1.0; 100])
}

/// Round-off of sums of about thirty O(1) terms and a 2×2 solve.
const ROUND_OFF: f64 = 1e-12;

#[test]
fn wiring_shepard_reproduces_a_constant_everywhere() {
    let (position, volume) = jittered_points();
    let value = vec![3.5; position.len()];
    let set = PointSet {
        position: &position,
        volume: &volume,
        value: &value,
    };
    let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
    for x in [
        Vector::<2>::new(4.3, 4.7),
        Vector::<2>::new(0.0, 0.0),
        Vector::<2>::new(9.2, -0.4),
    ] {
        let u = shepard_interpolate(&kernel, 1.3, &set, &x).expect("neighbours in reach");
        assert!((u - 3.5).abs() < ROUND_OFF * 3.5, "{u} at {x:?}");
    }
    // nothing in reach: undefined, not zero
    assert!(shepard_interpolate(&kernel, 1.3, &set, &Vector::<2>::new(30.0, 30.0)).is_none());
}

#[test]
fn wiring_cspm_reproduces_a_linear_gradient_at_the_boundary_too() {
    let (position, volume) = jittered_points();
    let gradient = Vector::<2>::new(2.0, -0.7);
    let value: Vec<f64> = position.iter().map(|x| 1.0 + gradient.dot(x)).collect();
    let set = PointSet {
        position: &position,
        volume: &volume,
        value: &value,
    };
    let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
    for i in [0, 9, 45, 99] {
        let g = cspm_gradient(&kernel, 1.3, &set, i).expect("neighbours in reach");
        assert!((g - gradient).norm() < 1e-10, "{g:?} at point {i}");
    }
}

/// Points at 0, Δ, …, 20Δ with Δ = 0.5, each of volume Δ, carrying u = 2x + 1.
fn linear_lattice() -> (Vec<Vector<1>>, Vec<f64>, Vec<f64>) {
    let spacing = 0.5;
    let position: Vec<Vector<1>> = (0..=20)
        .map(|k| Vector::<1>::new(k as f64 * spacing))
        .collect();
    let value = position.iter().map(|x| 2.0 * x[0] + 1.0).collect();
    (position, vec![spacing; 21], value)
}

/// The interpolant of u = 2x + 1 and its derivative at interior points (more than 2h from
/// either end), to the round-off of sums of a few terms of size up to u ≈ 17 (hence 20 times
/// the O(1) round-off).
#[test]
fn the_cubic_spline_at_h_equal_to_the_spacing_reproduces_a_linear_field_exactly() {
    let (position, volume, value) = linear_lattice();
    let set = PointSet {
        position: &position,
        volume: &volume,
        value: &value,
    };
    let kernel = Kernel::<1>::new(KernelShape::CubicSpline);
    for x in [2.0, 3.3, 4.75, 6.1, 8.0] {
        let u = sph_interpolate(&kernel, 0.5, &set, &Vector::<1>::new(x));
        assert!((u - (2.0 * x + 1.0)).abs() < ROUND_OFF * 20.0, "{u} at {x}");
    }
    for i in 4..=16 {
        let g = sph_gradient(&kernel, 0.5, &set, i);
        assert!((g[0] - 2.0).abs() < ROUND_OFF * 20.0, "{g:?} at point {i}");
    }
}

/// Volume is a measure: a point of volume 2V and two coincident points of volume V each give
/// the same interpolants (standard and Shepard) and gradients (standard and CSPM).
#[test]
fn a_point_of_twice_the_volume_weighs_as_two_coincident_points() {
    let merged = [
        Vector::<2>::new(0.0, 0.0),
        Vector::<2>::new(0.8, 0.3),
        Vector::<2>::new(-0.5, 0.6),
        Vector::<2>::new(0.2, -0.7),
    ];
    let split = [merged[0], merged[0], merged[1], merged[2], merged[3]];
    let kernel = Kernel::<2>::new(KernelShape::CubicSpline);
    let x = Vector::<2>::new(0.3, 0.1);
    // (interpolants at x, gradients at the point at merged[1])
    let operators = |position: &[Vector<2>], volume: &[f64], value: &[f64], at: usize| {
        let set = PointSet {
            position,
            volume,
            value,
        };
        [
            sph_interpolate(&kernel, 1.0, &set, &x),
            shepard_interpolate(&kernel, 1.0, &set, &x).expect("in reach"),
            sph_gradient(&kernel, 1.0, &set, at)[0],
            sph_gradient(&kernel, 1.0, &set, at)[1],
            cspm_gradient(&kernel, 1.0, &set, at).expect("spans 2D")[0],
            cspm_gradient(&kernel, 1.0, &set, at).expect("spans 2D")[1],
        ]
    };
    let once = operators(&merged, &[2.0, 0.5, 0.7, 1.1], &[4.0, -1.0, 2.5, 0.3], 1);
    let twice = operators(
        &split,
        &[1.0, 1.0, 0.5, 0.7, 1.1],
        &[4.0, 4.0, -1.0, 2.5, 0.3],
        2,
    );
    for (a, b) in once.iter().zip(&twice) {
        assert!(
            (a - b).abs() < ROUND_OFF * a.abs().max(1.0),
            "{once:?} {twice:?}"
        );
    }
}
