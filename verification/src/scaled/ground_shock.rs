//! Free-field ground shock from a buried or surface charge: the peak relations of Drake
//! (1983) / TM 5-855-1 / ConWep in the SI form of the MSB transcription
//! (`reference_data/drake1983_conwep_ground_shock_equations.csv`), with their soil table
//! (`tm5_855_1_soil_table_via_msb.csv`) and coupling factor
//! (`coupling_factor_msb_bulson1997.csv`). With the C-4 mass W (TNT / 1.37 for stress and
//! velocity, TNT / 1.19 for impulse) and ζ = 2.520811 r/W^(1/3) (r/W^(1/3) in ft/lb^(1/3)):
//!
//!   u0 = f·48.768·ζ^(−n) m/s,   P0 = ρ c u0,
//!   I0 = f·9.870892 (ρ/515.3179) W^(1/3) ζ^(1−n) kPa·s,
//!   a0 = f·1236.4578 (c/W^(1/3)) ζ^(−n−1) m/s²,   d0 = f·60.4567 (W^(1/3)/c) ζ^(1−n) m,
//!   t_a = r/c,   t_r = 0.1 t_a,
//!
//! valid for r/W^(1/3) ≥ 0.4 m/kg^(1/3). The coupling factor f multiplies every peak: the
//! MSB transcription shows it on velocity, stress, acceleration and displacement and not on
//! impulse, where f is applied here as on the others (no difference for a buried charge,
//! f = 1).

use super::explosives::{c4_equivalent, Explosive};
use super::{cell, positive, reference_rows};
use crate::VerifyError;
use serde::Serialize;
use std::sync::OnceLock;

/// A soil of the TM 5-855-1 table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Soil {
    /// Kebab-case name.
    pub name: &'static str,
    /// The table's description.
    pub description: String,
    pub density_kg_m3: f64,
    /// Seismic (loading) wave speed c.
    pub wave_speed_m_s: f64,
    /// The attenuation exponent n.
    pub attenuation: f64,
}

/// The names of the table's soils, in its order.
pub const SOIL_NAMES: [&str; 6] = [
    "loose-dry-sand",
    "dry-sand-backfill",
    "dense-sand",
    "wet-sandy-clay",
    "saturated-sandy-clay",
    "saturated-clay",
];

/// The soils of the TM 5-855-1 table (as transcribed by MSB).
pub fn soils() -> &'static [Soil] {
    static SOILS: OnceLock<Vec<Soil>> = OnceLock::new();
    SOILS.get_or_init(|| {
        let rows = reference_rows(include_str!(
            "../../../reference_data/tm5_855_1_soil_table_via_msb.csv"
        ));
        assert_eq!(rows.len(), SOIL_NAMES.len(), "one name per soil row");
        rows.iter()
            .zip(SOIL_NAMES)
            .map(|(row, name)| Soil {
                name,
                description: row.get(0).expect("a description").to_string(),
                density_kg_m3: cell(row, 2).expect("rho"),
                wave_speed_m_s: cell(row, 3).expect("c"),
                attenuation: cell(row, 5).expect("n"),
            })
            .collect()
    })
}

/// The soil called `name`.
pub fn soil(name: &str) -> Result<&'static Soil, VerifyError> {
    soils()
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| VerifyError::bad_value("soil", name, &SOIL_NAMES.join(", ")))
}

/// Scaled depth of burst (m/kg^(1/3)) from which a charge counts as fully buried (f = 1).
pub const FULLY_BURIED: f64 = 0.55;
/// The coupling factor of a burst in the air above the ground.
pub const IN_AIR: f64 = 0.14;

/// The ground-shock coupling factor f at scaled depth of burst D = d/W^(1/3) (m/kg^(1/3), d
/// the depth of the charge's centre, negative above the surface): the polynomial fit of the
/// Bulson (1997) data in MSB344, f = −100.23 D⁶ + 207.37 D⁵ − 167.52 D⁴ + 67.86 D³
/// − 16.011 D² + 3.3003 D + 0.4033, within [0.14, 1]: 0.40 with the charge's centre at the
/// surface, 1 from D = 0.55 (fully buried), 0.14 in the air (D ≤ −0.06, where the fit falls
/// below it).
pub fn coupling_factor(scaled_depth: f64) -> f64 {
    if scaled_depth >= FULLY_BURIED {
        return 1.0;
    }
    let d = scaled_depth;
    let fit = [0.4033, 3.3003, -16.011, 67.86, -167.52, 207.37, -100.23]
        .iter()
        .rev()
        .fold(0.0, |sum, c| sum * d + c);
    if d < -0.06 {
        IN_AIR
    } else {
        fit.clamp(IN_AIR, 1.0)
    }
}

/// Peak free-field ground-shock values at one range, SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GroundShock {
    pub peak_velocity_m_s: f64,
    pub peak_stress_pa: f64,
    pub impulse_pa_s: f64,
    pub acceleration_m_s2: f64,
    pub displacement_m: f64,
    pub arrival_s: f64,
    pub rise_s: f64,
    pub coupling_factor: f64,
}

/// Where the relations hold: r/W^(1/3) ≥ 0.4 m/kg^(1/3) (W the C-4 mass).
pub const MIN_SCALED_RANGE: f64 = 0.4;

/// The scaled range r/W^(1/3) of the relations (m/kg^(1/3), W the C-4 mass for stress and
/// velocity); they hold from [`MIN_SCALED_RANGE`] out.
pub fn scaled_range(explosive: &Explosive, mass_kg: f64, range_m: f64) -> f64 {
    let (w_stress, _) = c4_equivalent(explosive.tnt_for_pressure(mass_kg));
    range_m / w_stress.cbrt()
}

/// The ground shock at `range_m` from `mass_kg` of `explosive` in `soil` with coupling
/// factor `coupling`.
pub fn ground_shock(
    soil: &Soil,
    explosive: &Explosive,
    mass_kg: f64,
    range_m: f64,
    coupling: f64,
) -> Result<GroundShock, VerifyError> {
    positive("charge mass (kg)", mass_kg)?;
    positive("range (m)", range_m)?;
    if !(IN_AIR..=1.0).contains(&coupling) {
        return Err(VerifyError::bad_value(
            "coupling factor",
            coupling,
            "0.14 ≤ f ≤ 1",
        ));
    }
    let (w_stress, _) = c4_equivalent(explosive.tnt_for_pressure(mass_kg));
    let (_, w_impulse) = c4_equivalent(explosive.tnt_for_impulse(mass_kg));
    let scaled = scaled_range(explosive, mass_kg, range_m);
    if scaled < MIN_SCALED_RANGE {
        return Err(VerifyError::bad_value(
            "scaled range r/W^(1/3) (m/kg^(1/3), W in kg C-4)",
            scaled,
            &format!("≥ {MIN_SCALED_RANGE} (the ground-shock relations' range)"),
        ));
    }
    // ζ: the scaled range in ft/lb^(1/3), the relations' own variable
    let zeta = |w: f64| 2.520811 * range_m / w.cbrt();
    let (rho, c, n) = (soil.density_kg_m3, soil.wave_speed_m_s, soil.attenuation);
    let f = coupling;
    let velocity = f * 48.768 * zeta(w_stress).powf(-n);
    let arrival = range_m / c;
    Ok(GroundShock {
        peak_velocity_m_s: velocity,
        peak_stress_pa: rho * c * velocity,
        impulse_pa_s: f
            * 9.870892e3
            * (rho / 515.3179)
            * w_impulse.cbrt()
            * zeta(w_impulse).powf(1.0 - n),
        acceleration_m_s2: f * 1236.4578 * (c / w_stress.cbrt()) * zeta(w_stress).powf(-n - 1.0),
        displacement_m: f * 60.4567 * (w_stress.cbrt() / c) * zeta(w_stress).powf(1.0 - n),
        arrival_s: arrival,
        rise_s: 0.1 * arrival,
        coupling_factor: f,
    })
}

/// The factor by which a peak lies outside the relations' range [R(f_low), R(f_high)], from
/// its ratios to each end: `over_high` = peak / R(f_high) when above it, R(f_low) / peak
/// when below the lower end, 1 between them; NaN where either ratio is (a NaN never passes).
pub fn factor_from_range(over_high: f64, over_low: f64) -> f64 {
    if over_high.is_nan() || over_low.is_nan() {
        f64::NAN
    } else if over_high > 1.0 {
        over_high
    } else if over_low < 1.0 {
        1.0 / over_low
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::explosives::explosive;
    use super::*;

    /// MSB B04-401's worked example: 125 kg C-4 fully buried (depth 4 m, f = 1), r = 5 m in dry
    /// sand and backfill gives u0 = 3.84 m/s, P0 = 1907 kPa, I0 = 31.0 kPa·s, t_a = 16.4 ms;
    /// matched to the digits printed (half a unit in the last one).
    #[test]
    fn the_msb_worked_example() {
        let sand = soil("dry-sand-backfill").unwrap();
        let c4 = explosive("c4").unwrap();
        let f = coupling_factor(4.0 / 125f64.cbrt());
        assert_eq!(f, 1.0);
        let shock = ground_shock(sand, c4, 125.0, 5.0, f).unwrap();
        assert!((shock.peak_velocity_m_s - 3.84).abs() <= 0.005, "{shock:?}");
        assert!((shock.peak_stress_pa - 1907e3).abs() <= 0.5e3, "{shock:?}");
        assert!((shock.impulse_pa_s - 31.0e3).abs() <= 0.05e3, "{shock:?}");
        assert!((shock.arrival_s - 16.4e-3).abs() <= 0.05e-3, "{shock:?}");
        assert!((shock.rise_s - 1.64e-3).abs() <= 0.005e-3);
    }

    /// The same stress and velocity from 125 kg C-4 and from 1.37 × 125 kg TNT; the same impulse
    /// from 1.19 × 125 kg TNT.
    #[test]
    fn tnt_is_converted_to_c4() {
        let sand = soil("dry-sand-backfill").unwrap();
        let (c4, tnt) = (explosive("c4").unwrap(), explosive("tnt").unwrap());
        let from_c4 = ground_shock(sand, c4, 125.0, 10.0, 1.0).unwrap();
        let for_stress = ground_shock(sand, tnt, 1.37 * 125.0, 10.0, 1.0).unwrap();
        let for_impulse = ground_shock(sand, tnt, 1.19 * 125.0, 10.0, 1.0).unwrap();
        assert!((for_stress.peak_stress_pa / from_c4.peak_stress_pa - 1.0).abs() < 1e-12);
        assert!((for_impulse.impulse_pa_s / from_c4.impulse_pa_s - 1.0).abs() < 1e-12);
    }

    /// The coupling factor's anchor points from its source: 0.40 at the surface (0.403 the
    /// fit), 1 fully buried, 0.14 in the air; the fit's printed values in between (to the
    /// three digits printed).
    #[test]
    fn coupling_factor_follows_its_table() {
        assert!((coupling_factor(0.0) - 0.4033).abs() < 1e-12);
        assert_eq!(coupling_factor(0.55), 1.0);
        assert_eq!(coupling_factor(3.0), 1.0);
        assert_eq!(coupling_factor(-0.07), 0.14);
        assert_eq!(coupling_factor(-5.0), 0.14);
        let table = reference_rows(include_str!(
            "../../../reference_data/coupling_factor_msb_bulson1997.csv"
        ));
        for row in &table {
            let (d, recommended) = (cell(row, 0).unwrap(), cell(row, 3).unwrap());
            if d < FULLY_BURIED {
                assert!(
                    (coupling_factor(d) - recommended).abs() <= 0.0005,
                    "D = {d}: {} vs {recommended}",
                    coupling_factor(d)
                );
            }
        }
    }

    /// Bad input: a soil name, a range inside 0.4 m/kg^(1/3), a negative mass, a coupling
    /// factor outside [0.14, 1]; each refused naming the value and the allowed range.
    #[test]
    fn bad_input_is_named() {
        let error = soil("peat").unwrap_err().to_string();
        assert!(
            error.contains("peat") && error.contains("dense-sand"),
            "{error}"
        );
        let sand = soil("dense-sand").unwrap();
        let tnt = explosive("tnt").unwrap();
        let error = ground_shock(sand, tnt, 1000.0, 1.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("scaled range") && error.contains("0.4"),
            "{error}"
        );
        let error = ground_shock(sand, tnt, -1.0, 10.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(error.contains("charge mass"), "{error}");
        let error = ground_shock(sand, tnt, 100.0, 10.0, 1.5)
            .unwrap_err()
            .to_string();
        assert!(error.contains("coupling"), "{error}");
    }

    /// Peaks fall with range as r^(−n) (velocity, stress) and r^(1−n) (impulse).
    #[test]
    fn peaks_attenuate_with_the_soils_exponent() {
        let tnt = explosive("tnt").unwrap();
        for soil in soils() {
            let near = ground_shock(soil, tnt, 500.0, 10.0, 1.0).unwrap();
            let far = ground_shock(soil, tnt, 500.0, 20.0, 1.0).unwrap();
            let exponent = (near.peak_velocity_m_s / far.peak_velocity_m_s).log2();
            assert!((exponent - soil.attenuation).abs() < 1e-12, "{}", soil.name);
            let exponent = (near.impulse_pa_s / far.impulse_pa_s).log2();
            assert!((exponent - (soil.attenuation - 1.0)).abs() < 1e-12);
            assert!((far.arrival_s - 20.0 / soil.wave_speed_m_s).abs() < 1e-15);
        }
    }

    /// A peak between the relations at the two ends of the coupling range is 1 from them;
    /// above the upper end by its ratio to it, below the lower end by the inverse of its
    /// ratio to that; a NaN stays NaN, so that it fails.
    #[test]
    fn the_factor_from_the_relations_range() {
        assert_eq!(factor_from_range(0.9, 1.05), 1.0);
        assert_eq!(factor_from_range(4.0, 4.6), 4.0);
        assert_eq!(factor_from_range(0.2, 0.25), 4.0);
        assert!(factor_from_range(f64::NAN, 1.0).is_nan());
        assert!(factor_from_range(1.0, f64::NAN).is_nan());
    }
}
