//! Error norms and observed convergence order.

/// L1 error ∫|q − q_exact| dx approximated by Σ_i |q_i − q_exact,i| V_i over the points kept.
pub fn l1_error(values: &[f64], exact: &[f64], volumes: &[f64]) -> f64 {
    values
        .iter()
        .zip(exact)
        .zip(volumes)
        .map(|((q, e), v)| (q - e).abs() * v)
        .sum()
}

/// Observed order p from the least-squares fit log E = p log Δx + c; `None` with fewer than two
/// usable points (a zero or non-finite error cannot be logged).
pub fn observed_order(spacing: &[f64], error: &[f64]) -> Option<f64> {
    let points: Vec<(f64, f64)> = spacing
        .iter()
        .zip(error)
        .filter(|(dx, e)| **dx > 0.0 && **e > 0.0 && e.is_finite())
        .map(|(dx, e)| (dx.ln(), e.ln()))
        .collect();
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_of_an_exact_power_law_is_recovered() {
        let dx = [0.1, 0.05, 0.025, 0.0125];
        let e: Vec<f64> = dx.iter().map(|h: &f64| 3.0 * h.powf(1.7)).collect();
        assert!((observed_order(&dx, &e).unwrap() - 1.7).abs() < 1e-12);
        assert_eq!(observed_order(&dx[..1], &e[..1]), None);
    }
}
