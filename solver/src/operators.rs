//! Interpolation and derivative operators on a scattered point set with volumes V_j
//! (the seed's §3 corrective methods). They scan the whole set, which suits evaluation on small
//! sets and post-processing; the time-stepping loops use neighbour lists instead.
//!
//! - standard SPH:  u(x) ≈ Σ_j u_j W(x − x_j) V_j,  ∇u(x_i) ≈ Σ_j u_j ∇_i W_ij V_j;
//! - Shepard (zeroth-order, Randles & Libersky 1996; the seed's eq. 3-20):
//!   u(x) ≈ Σ_j u_j W V_j / Σ_j W V_j, exact for constants;
//! - CSPM first derivative (Chen, Beraun & Carney 1999; the seed's eq. 3-21, written for D
//!   dimensions): B ∇u_i = Σ_j (u_j − u_i) ∇_i W_ij V_j with B = Σ_j ∇_i W_ij ⊗ (x_j − x_i) V_j,
//!   exact for linear fields, also at a boundary.

use crate::kernel::Kernel;
use crate::Vector;
use nalgebra::SMatrix;

/// A set of data points with their volumes and one scalar field.
#[derive(Clone, Copy, Debug)]
pub struct PointSet<'a, const D: usize> {
    pub position: &'a [Vector<D>],
    pub volume: &'a [f64],
    pub value: &'a [f64],
}

/// Standard SPH interpolant Σ_j u_j W(x − x_j, h) V_j.
pub fn sph_interpolate<const D: usize>(
    kernel: &Kernel<D>,
    h: f64,
    set: &PointSet<D>,
    x: &Vector<D>,
) -> f64 {
    (0..set.position.len())
        .map(|j| set.value[j] * kernel.value((x - set.position[j]).norm(), h) * set.volume[j])
        .sum()
}

/// Shepard-corrected interpolant Σ_j u_j W V_j / Σ_j W V_j; `None` where no point is in reach.
pub fn shepard_interpolate<const D: usize>(
    kernel: &Kernel<D>,
    h: f64,
    set: &PointSet<D>,
    x: &Vector<D>,
) -> Option<f64> {
    let (mut weighted, mut weight) = (0.0, 0.0);
    for j in 0..set.position.len() {
        let w = kernel.value((x - set.position[j]).norm(), h) * set.volume[j];
        weighted += set.value[j] * w;
        weight += w;
    }
    (weight > 0.0).then(|| weighted / weight)
}

/// Standard SPH gradient at data point i: Σ_j u_j ∇_i W_ij V_j.
pub fn sph_gradient<const D: usize>(
    kernel: &Kernel<D>,
    h: f64,
    set: &PointSet<D>,
    i: usize,
) -> Vector<D> {
    let xi = set.position[i];
    (0..set.position.len()).fold(Vector::zeros(), |g, j| {
        let dx = xi - set.position[j];
        g + kernel.gradient(&dx, dx.norm(), h) * (set.value[j] * set.volume[j])
    })
}

/// CSPM gradient at data point i; `None` where the correction matrix is singular (too few
/// neighbours to span D dimensions).
pub fn cspm_gradient<const D: usize>(
    kernel: &Kernel<D>,
    h: f64,
    set: &PointSet<D>,
    i: usize,
) -> Option<Vector<D>> {
    let xi = set.position[i];
    let mut b = SMatrix::<f64, D, D>::zeros();
    let mut rhs = Vector::<D>::zeros();
    for j in 0..set.position.len() {
        let dx = xi - set.position[j];
        let grad = kernel.gradient(&dx, dx.norm(), h) * set.volume[j];
        rhs += grad * (set.value[j] - set.value[i]);
        b += grad * (-dx).transpose();
    }
    // a D×D system; the dynamic form sidesteps nalgebra's trait bounds on generic Const<D>
    let b = nalgebra::DMatrix::from_column_slice(D, D, b.as_slice());
    let rhs = nalgebra::DVector::from_column_slice(rhs.as_slice());
    b.lu()
        .solve(&rhs)
        .map(|g| Vector::<D>::from_column_slice(g.as_slice()))
}
