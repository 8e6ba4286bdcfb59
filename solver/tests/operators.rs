//! Wiring tests of the corrected operators: Shepard's interpolant and CSPM's gradient reproduce
//! constant and linear fields by construction (Σ W u / Σ W with u = 1; a gradient multiplied
//! by the inverse of the kernel's first moment). These tests show the code is wired as the
//! formulas say, on an irregular 2D point set with a boundary; they verify nothing beyond that.

use blastsph_solver::operators::{cspm_gradient, shepard_interpolate, PointSet};
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
