//! Compaction equation of state of a porous solid (the AUTODYN-style "compaction" law used for
//! sand by Laine & Sandvik 2001): pressure depends on density and on the highest density the
//! material has reached, not on internal energy.
//!
//! - Loading (ρ ≥ ρ_max so far): the piecewise-linear plastic compaction curve p_c(ρ); the pores
//!   collapse and ρ_max moves up with ρ.
//! - Unloading and reloading (ρ < ρ_max): elastic along the straight line
//!   p = p_c(ρ_max) + c(ρ_max)² (ρ − ρ_max), with c(ρ_max) the bulk sound speed of the compacted
//!   material (piecewise linear in ρ_max). Reloading retraces that line until it meets the
//!   compaction curve again at ρ_max.
//! - Pressures below the tensile cutoff p_min are clamped to it (a granular material carries
//!   almost no tension).
//!
//! The unloading line must be at least as steep as the loading curve at every ρ_max (checked at
//! construction): otherwise it would rise above the curve and a load–unload cycle would return
//! more work than it took.

use super::EquationOfState;
use crate::error::SolverError;

#[derive(Clone, Debug, PartialEq)]
pub struct Compaction {
    /// Loading curve knots (ρ_k, p_k), density strictly increasing, pressure non-decreasing;
    /// the first knot is the initial (uncompacted) state.
    loading: Vec<(f64, f64)>,
    /// Bulk sound speed knots (ρ_k, c_k) as a function of the maximum density reached.
    sound_speed: Vec<(f64, f64)>,
    /// Tensile cutoff (Pa, ≤ 0).
    p_min: f64,
}

/// Linear interpolation in a table of (x, y) knots with x increasing, extended beyond the last
/// knot along the last segment, and clamped to the first value below the first knot. Returns the
/// value and the slope.
fn interpolate(table: &[(f64, f64)], x: f64) -> (f64, f64) {
    if table.len() == 1 || x <= table[0].0 {
        return (table[0].1, 0.0);
    }
    let k = table
        .windows(2)
        .position(|w| x <= w[1].0)
        .unwrap_or(table.len() - 2);
    let ((x0, y0), (x1, y1)) = (table[k], table[k + 1]);
    let slope = (y1 - y0) / (x1 - x0);
    (y0 + slope * (x - x0), slope)
}

impl Compaction {
    pub fn new(
        loading: Vec<(f64, f64)>,
        sound_speed: Vec<(f64, f64)>,
        p_min: f64,
    ) -> Result<Self, SolverError> {
        check_table("compaction curve", &loading, "pressure", |p| p >= 0.0)?;
        check_table("unloading sound speed", &sound_speed, "sound speed", |c| {
            c > 0.0
        })?;
        if loading.len() < 2 {
            return Err(SolverError::invalid(
                "compaction curve",
                format!("{} knots", loading.len()),
                "at least 2 (ρ, p) knots",
            ));
        }
        if loading.windows(2).any(|w| !(w[1].1 > w[0].1)) {
            return Err(SolverError::invalid(
                "compaction curve pressure",
                format!("{:?}", loading.iter().map(|k| k.1).collect::<Vec<_>>()),
                "strictly increasing with density",
            ));
        }
        if !(p_min <= 0.0) {
            return Err(SolverError::invalid(
                "p_min",
                p_min,
                "≤ 0 (a tensile cutoff)",
            ));
        }
        let eos = Self {
            loading,
            sound_speed,
            p_min,
        };
        // the unloading line at the end of each loading segment must be at least as steep as it
        for w in eos.loading.windows(2) {
            let slope = (w[1].1 - w[0].1) / (w[1].0 - w[0].0);
            for rho in [w[0].0, w[1].0] {
                let c = interpolate(&eos.sound_speed, rho).0;
                if c * c < slope * (1.0 - 1e-12) {
                    return Err(SolverError::invalid(
                        "unloading sound speed",
                        format!("{c} m/s at {rho} kg/m³"),
                        &format!(
                            "≥ {:.1} m/s, the loading curve's slope √(dp/dρ) there",
                            slope.sqrt()
                        ),
                    ));
                }
            }
        }
        Ok(eos)
    }

    /// The initial (uncompacted) density.
    pub fn initial_density(&self) -> f64 {
        self.loading[0].0
    }

    /// Pressure on the loading curve.
    pub fn loading_pressure(&self, density: f64) -> f64 {
        interpolate(&self.loading, density).0
    }

    fn unloading_speed(&self, peak_density: f64) -> f64 {
        interpolate(&self.sound_speed, peak_density).0
    }
}

/// A table is non-empty, finite, with density > 0 strictly increasing and values allowed by `ok`.
fn check_table(
    field: &str,
    table: &[(f64, f64)],
    value_name: &str,
    ok: impl Fn(f64) -> bool,
) -> Result<(), SolverError> {
    if table.is_empty() {
        return Err(SolverError::invalid(field, "empty", "at least one knot"));
    }
    if let Some(&(rho, _)) = table
        .iter()
        .find(|(rho, _)| !(*rho > 0.0 && rho.is_finite()))
    {
        return Err(SolverError::invalid(
            &format!("{field} density"),
            rho,
            "finite and > 0",
        ));
    }
    if let Some(&(_, v)) = table.iter().find(|(_, v)| !(ok(*v) && v.is_finite())) {
        return Err(SolverError::invalid(
            &format!("{field} {value_name}"),
            v,
            "finite, and > 0 (sound speed) or ≥ 0 (pressure)",
        ));
    }
    if table.windows(2).any(|w| !(w[1].0 > w[0].0)) {
        return Err(SolverError::invalid(
            &format!("{field} density"),
            format!("{:?}", table.iter().map(|k| k.0).collect::<Vec<_>>()),
            "strictly increasing",
        ));
    }
    Ok(())
}

impl EquationOfState for Compaction {
    /// Virgin material (ρ_max = max(ρ, ρ_initial)).
    fn pressure(&self, density: f64, internal_energy: f64) -> f64 {
        self.pressure_after(density, internal_energy, density)
    }

    fn sound_speed(&self, density: f64, internal_energy: f64) -> f64 {
        self.sound_speed_after(density, internal_energy, density)
    }

    fn pressure_after(&self, density: f64, _internal_energy: f64, peak_density: f64) -> f64 {
        let peak = peak_density.max(density).max(self.initial_density());
        let c = self.unloading_speed(peak);
        (self.loading_pressure(peak) + c * c * (density - peak)).max(self.p_min)
    }

    /// The elastic (unloading) bulk sound speed c(ρ_max): the fastest signal the material
    /// carries, which sets the time step whether it is loading or unloading.
    fn sound_speed_after(&self, density: f64, _internal_energy: f64, peak_density: f64) -> f64 {
        self.unloading_speed(peak_density.max(density).max(self.initial_density()))
    }

    fn min_pressure(&self) -> f64 {
        self.p_min
    }

    fn remembers_peak_density(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Laine & Sandvik (2001) Table 1 compaction path (kg/m³, Pa) with the unloading sound speed
    /// of Laine & Larsen (2009) Table 3 ('old EOS'), c(1674) = 265.2 m/s: the dry sand of
    /// reference_data/materials.toml.
    fn sand() -> Compaction {
        let loading = [
            (1674.0, 0.0),
            (1739.5, 4.577e6),
            (1873.8, 14.98e6),
            (1997.0, 29.15e6),
            (2143.8, 59.18e6),
            (2250.0, 98.1e6),
            (2380.0, 179.4e6),
            (2485.0, 289.4e6),
            (2585.0, 450.2e6),
            (2671.3, 650.7e6),
        ];
        let speed = [
            (1674.0, 265.2),
            (1796.6, 994.0),
            (1880.9, 1200.0),
            (1944.4, 1380.0),
            (2013.4, 1550.0),
            (2086.2, 1750.0),
            (2151.5, 1890.0),
            (2671.3, 4636.0),
        ];
        Compaction::new(loading.to_vec(), speed.to_vec(), -1e-3).unwrap()
    }

    proptest! {
        /// Loading pressure never decreases with density.
        #[test]
        fn loading_is_monotone(a in 1674.0f64..2800.0, b in 1674.0f64..2800.0) {
            let eos = sand();
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            prop_assert!(eos.pressure(lo, 0.0) <= eos.pressure(hi, 0.0));
        }

        /// Unloading from ρ_max to ρ and reloading to ρ_max returns to the loading curve, and
        /// every state on the way back is the same on the way down (reversible elastic path).
        #[test]
        fn unloading_and_reloading_retrace_one_line(peak in 1700.0f64..2700.0, f in 0.0f64..1.0) {
            let eos = sand();
            let rho = eos.initial_density() + f * (peak - eos.initial_density());
            let down = eos.pressure_after(rho, 0.0, peak);
            let up = eos.pressure_after(rho, 0.0, peak.max(rho));
            prop_assert_eq!(down, up);
            let back = eos.pressure_after(peak, 0.0, peak);
            prop_assert!((back - eos.pressure(peak, 0.0)).abs() <= 1e-9 * back.max(1.0));
            prop_assert!(down <= back);
        }

        /// A load to ρ_max and unload to zero pressure takes work ∫p dv on loading and returns
        /// at most as much on unloading: the cycle creates no energy. Both integrals by the
        /// midpoint rule on 4000 steps (error ~1e-7 of the work; the margin is 1e-6).
        #[test]
        fn a_load_unload_cycle_creates_no_energy(peak in 1700.0f64..2700.0) {
            let eos = sand();
            let work = |from: f64, to: f64, peak: f64| {
                let n = 4000;
                (0..n).map(|k| {
                    let rho_a = from + (to - from) * k as f64 / n as f64;
                    let rho_b = from + (to - from) * (k + 1) as f64 / n as f64;
                    let p = eos.pressure_after(0.5 * (rho_a + rho_b), 0.0, peak);
                    // work done on the material: −∫ p dv, v = 1/ρ
                    -p * (1.0 / rho_b - 1.0 / rho_a)
                }).sum::<f64>()
            };
            let rho0 = eos.initial_density();
            let taken = work(rho0, peak, 0.0);
            let returned = -work(peak, rho0, peak);
            prop_assert!(returned <= taken * (1.0 + 1e-6), "{returned} > {taken}");
            prop_assert!(returned >= 0.0);
        }
    }

    #[test]
    fn tension_is_cut_off_and_the_sound_speed_follows_the_peak() {
        let eos = sand();
        assert_eq!(eos.pressure_after(1700.0, 0.0, 2400.0), -1e-3);
        assert_eq!(eos.sound_speed(1674.0, 0.0), 265.2);
        assert_eq!(eos.sound_speed_after(1800.0, 0.0, 2151.5), 1890.0);
    }

    /// Virgin sand pulled below its initial density unloads from ρ0 itself: p = c(ρ0)²(ρ − ρ0)
    /// down to the tensile cutoff, which the health check reads as the floor; a one-knot
    /// unloading table is a constant sound speed at every peak density.
    #[test]
    fn tension_below_the_initial_density_and_a_constant_sound_speed() {
        let loading = vec![(1600.0, 0.0), (1700.0, 5e6), (1800.0, 20e6)];
        let eos = Compaction::new(loading, vec![(1600.0, 500.0)], -1e5).unwrap();
        assert_eq!(eos.initial_density(), 1600.0);
        assert_eq!(eos.min_pressure(), -1e5);
        let p = eos.pressure_after(1599.9, 0.0, 1599.9);
        assert!((p - 500.0 * 500.0 * -0.1).abs() < 1e-6, "{p}");
        assert_eq!(eos.pressure_after(1500.0, 0.0, 1500.0), -1e5);
        for peak in [1600.0, 1750.0, 2000.0] {
            assert_eq!(eos.sound_speed_after(peak, 0.0, peak), 500.0);
        }
    }

    #[test]
    fn non_physical_tables_are_rejected_by_name() {
        let falling = vec![(1600.0, 0.0), (1700.0, 5e6), (1800.0, 4e6)];
        let speed = vec![(1600.0, 3000.0)];
        let err = Compaction::new(falling, speed.clone(), 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("compaction curve pressure"), "{err}");
        let backwards = vec![(1700.0, 0.0), (1600.0, 5e6)];
        let err = Compaction::new(backwards, speed.clone(), 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("compaction curve density"), "{err}");
        let soft = vec![(1600.0, 0.0), (1700.0, 50e6)];
        let err = Compaction::new(soft, vec![(1600.0, 100.0)], 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("unloading sound speed"), "{err}");
        let err = Compaction::new(vec![(-1.0, 0.0), (1.0, 1.0)], speed.clone(), 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("density") && err.contains("> 0"), "{err}");
        // a knot at zero density, a repeated density (a vertical step in the curve) and
        // non-finite entries
        let err = Compaction::new(vec![(0.0, 0.0), (1.0, 1.0)], speed.clone(), 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("density") && err.contains("> 0"), "{err}");
        let repeated = vec![(1600.0, 0.0), (1700.0, 5e6), (1700.0, 6e6)];
        let err = Compaction::new(repeated, speed.clone(), 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("strictly increasing"), "{err}");
        let infinite = vec![(1600.0, 0.0), (1700.0, f64::INFINITY)];
        let err = Compaction::new(infinite, speed, 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("compaction curve pressure"), "{err}");
        let err = Compaction::new(
            vec![(1600.0, 0.0), (1700.0, 5e6)],
            vec![(1600.0, f64::NAN)],
            0.0,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("unloading sound speed"), "{err}");
    }
}
