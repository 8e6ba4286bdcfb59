//! Mohr–Coulomb cohesion and friction angle from biaxial (or triaxial) failure states.
//!
//! At failure the Mohr circle of principal stresses σ1 ≥ σ3 (compression positive) touches the
//! line τ = c + σ tan φ, which in principal stresses reads σ1 = N σ3 + 2c√N with
//! N = (1 + sin φ)/(1 − sin φ). A least-squares line through the (σ3, σ1) failure points gives
//! the slope N and the intercept 2c√N, hence φ = asin((N − 1)/(N + 1)) and c = intercept/(2√N).

use crate::error::SolverError;

/// Cohesion (Pa) and friction angle (degrees) of a Mohr–Coulomb envelope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MohrCoulomb {
    pub cohesion: f64,
    pub friction_angle_degrees: f64,
}

/// The envelope through failure states (σ3, σ1) (Pa, compression positive), by least squares
/// on σ1 = N σ3 + 2c√N; at least two distinct confining stresses.
pub fn fit_mohr_coulomb(failures: &[(f64, f64)]) -> Result<MohrCoulomb, SolverError> {
    let n = failures.len() as f64;
    let mean3 = failures.iter().map(|p| p.0).sum::<f64>() / n;
    let mean1 = failures.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = failures.iter().map(|p| (p.0 - mean3).powi(2)).sum();
    if failures.len() < 2 || !(sxx > 0.0) {
        return Err(SolverError::invalid(
            "failure states",
            failures.len(),
            "at least two distinct confining stresses",
        ));
    }
    let sxy: f64 = failures.iter().map(|p| (p.0 - mean3) * (p.1 - mean1)).sum();
    let slope = sxy / sxx;
    let intercept = mean1 - slope * mean3;
    if !(slope >= 1.0) {
        return Err(SolverError::invalid(
            "Mohr-Coulomb slope N",
            slope,
            "≥ 1 (σ1 grows at least as fast as σ3 at failure)",
        ));
    }
    Ok(MohrCoulomb {
        cohesion: intercept / (2.0 * slope.sqrt()),
        friction_angle_degrees: ((slope - 1.0) / (slope + 1.0)).asin().to_degrees(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Failure states generated from c = 2 kPa, φ = 30° (N = 3) give them back.
    #[test]
    fn the_envelope_of_exact_failure_states_is_recovered() {
        let (c, phi) = (2e3, 30f64.to_radians());
        let n = (1.0 + phi.sin()) / (1.0 - phi.sin());
        let states: Vec<(f64, f64)> = [10e3, 25e3, 50e3]
            .iter()
            .map(|&s3| (s3, n * s3 + 2.0 * c * n.sqrt()))
            .collect();
        let fit = fit_mohr_coulomb(&states).unwrap();
        assert!((fit.cohesion - c).abs() < 1e-9 * c);
        assert!((fit.friction_angle_degrees - 30.0).abs() < 1e-9);
        assert!(fit_mohr_coulomb(&states[..1]).is_err());
        // two confining stresses fix the line exactly
        let two = fit_mohr_coulomb(&states[1..]).unwrap();
        assert!((two.cohesion - c).abs() < 1e-9 * c);
        assert!((two.friction_angle_degrees - 30.0).abs() < 1e-9);
    }

    /// Failure states at one confining stress admit no line: the error names them, not the
    /// slope that a division by zero would leave undefined.
    #[test]
    fn one_confining_stress_is_refused_by_name() {
        for states in [vec![(1e3, 4e3), (1e3, 5e3), (1e3, 4.5e3)], vec![(1e3, 4e3)]] {
            let message = fit_mohr_coulomb(&states).unwrap_err().to_string();
            assert!(message.contains("failure states"), "{message}");
        }
    }
}
