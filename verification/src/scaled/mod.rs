//! Scaled-distance relations: what a charge of W kg TNT does at range R, from fits to
//! measurements, in SI units (W in kg, R in m, pressures in Pa, times in s, impulses in Pa·s).
//!
//! Hopkinson–Cranz (cube-root) scaling: two charges of the same explosive and shape, W₁ and
//! W₂, give the same pressure at the same scaled distance Z = R/W^(1/3), with times and
//! impulses in the ratio (W₂/W₁)^(1/3). Every relation here is a function of Z.
//!
//! - [`air_blast`]: Kingery & Bulmash (1984) for hemispherical surface bursts and spherical
//!   free-air bursts, with Swisdak's (1994) form of the hemispherical fits as a cross-check;
//! - [`ground_shock`]: the free-field ground-shock relations of Drake (1983) / TM 5-855-1 /
//!   ConWep, with their soil table and coupling factor;
//! - [`explosives`]: TNT equivalence.
//!
//! Outside a fit's range of validity every function returns a named error, never an
//! extrapolation.

pub mod air_blast;
pub mod arrivals;
pub mod explosives;
pub mod ground_shock;
pub mod query;

use crate::VerifyError;

/// Z = R/W^(1/3) (m/kg^(1/3)) of range `range_m` from a charge of `charge_kg`, both checked:
/// finite and positive.
pub fn scaled_distance(range_m: f64, charge_kg: f64) -> Result<f64, VerifyError> {
    positive("charge mass (kg)", charge_kg)?;
    positive("range (m)", range_m)?;
    Ok(range_m / charge_kg.cbrt())
}

/// The Hopkinson–Cranz factor (W₂/W₁)^(1/3) by which lengths, times and impulses grow from a
/// charge of W₁ to one of W₂ at the same scaled distance.
pub fn cube_root_ratio(from_kg: f64, to_kg: f64) -> Result<f64, VerifyError> {
    positive("charge mass (kg)", from_kg)?;
    positive("charge mass (kg)", to_kg)?;
    Ok((to_kg / from_kg).cbrt())
}

/// `value` if it is finite and > 0, else the error naming `field`.
fn positive(field: &str, value: f64) -> Result<f64, VerifyError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(VerifyError::bad_value(field, value, "finite and > 0"))
    }
}

/// The rows of a reference CSV whose first line is a `#` comment naming its source.
fn reference_rows(table: &'static str) -> Vec<csv::StringRecord> {
    crate::reference_table(table)
        .records()
        .collect::<Result<_, _>>()
        .expect("the reference table parses")
}

/// A reference table's cell as a number; an empty cell is `None`.
fn cell(row: &csv::StringRecord, index: usize) -> Option<f64> {
    let text = row.get(index)?.trim();
    (!text.is_empty()).then(|| text.parse().expect("a number in the reference table"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_distance_and_its_bad_inputs() {
        assert!((scaled_distance(10.0, 1000.0).unwrap() - 1.0).abs() < 1e-15);
        assert!((cube_root_ratio(1.0, 8.0).unwrap() - 2.0).abs() < 1e-15);
        for (range, charge) in [(10.0, -1.0), (10.0, 0.0), (-1.0, 1.0), (f64::NAN, 1.0)] {
            let error = scaled_distance(range, charge).unwrap_err().to_string();
            assert!(error.contains("finite and > 0"), "{error}");
        }
    }
}
