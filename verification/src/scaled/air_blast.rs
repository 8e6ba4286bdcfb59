//! Air blast from a TNT charge: Kingery & Bulmash (1984, ARBRL-TR-02555) as coded in ConWep
//! (`reference_data/kb_conwep_ufc_polynomials.csv`: U = K0 + K1·log10 Z,
//! log10 Y = Σ C_i U^i, by segments of Z), for a hemispherical charge on the ground and a
//! spherical charge in free air; and Swisdak's (1994) simplified form of the hemispherical fits
//! (`reference_data/kb_swisdak1994_hemispherical_metric.csv`: Y = exp Σ A_i (ln Z)^i), an
//! independent transcription of the same data used to cross-check the first.

use super::{cell, reference_rows, scaled_distance};
use crate::VerifyError;
use serde::Serialize;
use std::sync::OnceLock;

/// Where the charge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Burst {
    /// A hemisphere on a rigid ground (a surface burst).
    Hemispherical,
    /// A sphere far from any surface.
    FreeAir,
}

impl Burst {
    pub const ALL: [Burst; 2] = [Burst::Hemispherical, Burst::FreeAir];

    pub fn name(self) -> &'static str {
        match self {
            Burst::Hemispherical => "surface",
            Burst::FreeAir => "free-air",
        }
    }

    fn table_name(self) -> &'static str {
        match self {
            Burst::Hemispherical => "hemispherical",
            Burst::FreeAir => "free_air",
        }
    }

    /// The range of Z (m/kg^(1/3)) the fits cover (UFC 3-340-02 / Kingery & Bulmash).
    pub fn validity(self) -> (f64, f64) {
        match self {
            Burst::Hemispherical => (0.0674, 40.0),
            Burst::FreeAir => (0.0531, 40.0),
        }
    }
}

/// A blast-wave parameter, with its scaled SI unit: Pa for pressures, s/kg^(1/3) for times,
/// Pa·s/kg^(1/3) for impulses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    IncidentOverpressure,
    ReflectedOverpressure,
    ArrivalTime,
    PositiveDuration,
    IncidentImpulse,
    ReflectedImpulse,
}

impl Quantity {
    pub const ALL: [Quantity; 6] = [
        Quantity::IncidentOverpressure,
        Quantity::ReflectedOverpressure,
        Quantity::ArrivalTime,
        Quantity::PositiveDuration,
        Quantity::IncidentImpulse,
        Quantity::ReflectedImpulse,
    ];

    fn table_name(self) -> &'static str {
        match self {
            Quantity::IncidentOverpressure => "incident_overpressure",
            Quantity::ReflectedOverpressure => "reflected_overpressure",
            Quantity::ArrivalTime => "arrival_time_scaled",
            Quantity::PositiveDuration => "positive_duration_scaled",
            Quantity::IncidentImpulse => "incident_impulse_scaled",
            Quantity::ReflectedImpulse => "reflected_impulse_scaled",
        }
    }

    /// The factor from the tables' units (kPa, ms/kg^(1/3), kPa·ms/kg^(1/3)) to scaled SI.
    fn to_si(self) -> f64 {
        match self {
            Quantity::IncidentOverpressure | Quantity::ReflectedOverpressure => 1e3,
            Quantity::ArrivalTime | Quantity::PositiveDuration => 1e-3,
            // kPa·ms = Pa·s
            Quantity::IncidentImpulse | Quantity::ReflectedImpulse => 1.0,
        }
    }
}

/// One polynomial segment of the Kingery–Bulmash fits.
#[derive(Clone, Debug)]
struct KbSegment {
    quantity: &'static str,
    burst: &'static str,
    /// The Z range (m/kg^(1/3)) of the segment; open ends are 0 and ∞.
    z_range: (f64, f64),
    k0: f64,
    k1: f64,
    /// C0 (metric) … C11.
    coefficients: Vec<f64>,
}

fn kb_segments() -> &'static [KbSegment] {
    static SEGMENTS: OnceLock<Vec<KbSegment>> = OnceLock::new();
    SEGMENTS.get_or_init(|| {
        let table = include_str!("../../../reference_data/kb_conwep_ufc_polynomials.csv");
        let name = |row: &csv::StringRecord, k: usize, options: &[&'static str]| {
            let text = row.get(k).expect("a name column");
            *options
                .iter()
                .find(|o| **o == text)
                .expect("a known name in the Kingery–Bulmash table")
        };
        let quantities: Vec<&'static str> = Quantity::ALL.iter().map(|q| q.table_name()).collect();
        let bursts: Vec<&'static str> = Burst::ALL.iter().map(|b| b.table_name()).collect();
        reference_rows(table)
            .iter()
            .map(|row| KbSegment {
                quantity: name(row, 0, &quantities),
                burst: name(row, 1, &bursts),
                z_range: (
                    cell(row, 5).unwrap_or(0.0),
                    cell(row, 6).unwrap_or(f64::INFINITY),
                ),
                k0: cell(row, 11).expect("K0_metric"),
                k1: cell(row, 10).expect("K1"),
                // C0_metric, then C1 … C11 (column 13 is the imperial C0)
                coefficients: std::iter::once(cell(row, 12).expect("C0_metric"))
                    .chain((14..row.len()).filter_map(|k| cell(row, k)))
                    .collect(),
            })
            .collect()
    })
}

/// The Kingery–Bulmash value of `quantity` at scaled distance `z` (m/kg^(1/3)) for `burst`,
/// in scaled SI units; `None` for the positive duration below the Z where its fit starts
/// (0.18 m/kg^(1/3)), where Kingery & Bulmash give none. A Z outside the fits' range is an
/// error.
pub fn kingery_bulmash(
    burst: Burst,
    quantity: Quantity,
    z: f64,
) -> Result<Option<f64>, VerifyError> {
    let (lo, hi) = burst.validity();
    if !(lo..=hi).contains(&z) {
        return Err(VerifyError::bad_value(
            "scaled distance Z (m/kg^(1/3))",
            z,
            &format!(
                "{lo} ≤ Z ≤ {hi} for a {} burst (Kingery–Bulmash)",
                burst.name()
            ),
        ));
    }
    let segment = kb_segments().iter().find(|s| {
        s.quantity == quantity.table_name()
            && s.burst == burst.table_name()
            && s.z_range.0 <= z
            && (z < s.z_range.1 || (s.z_range.1 == hi && z == hi))
    });
    Ok(segment.map(|s| {
        let u = s.k0 + s.k1 * z.log10();
        // Horner's rule for Σ C_i U^i
        let log_y = s.coefficients.iter().rev().fold(0.0, |sum, c| sum * u + c);
        10f64.powf(log_y) * quantity.to_si()
    }))
}

/// The Swisdak (1994) value of `quantity` at `z` for a hemispherical surface burst, in scaled
/// SI units; an error outside the Z its segments cover.
pub fn swisdak_hemispherical(quantity: Quantity, z: f64) -> Result<f64, VerifyError> {
    static TABLE: OnceLock<Vec<csv::StringRecord>> = OnceLock::new();
    let rows = TABLE.get_or_init(|| {
        reference_rows(include_str!(
            "../../../reference_data/kb_swisdak1994_hemispherical_metric.csv"
        ))
    });
    let segments: Vec<&csv::StringRecord> = rows
        .iter()
        .filter(|row| row.get(0) == Some(quantity.table_name()))
        .collect();
    let range =
        |row: &csv::StringRecord| (cell(row, 2).expect("Z_lo"), cell(row, 3).expect("Z_hi"));
    let covered = (
        segments
            .iter()
            .map(|r| range(r).0)
            .fold(f64::INFINITY, f64::min),
        segments.iter().map(|r| range(r).1).fold(0.0, f64::max),
    );
    let segment = segments.iter().find(|row| {
        let (lo, hi) = range(row);
        lo <= z && (z < hi || (z == hi && hi == covered.1))
    });
    let Some(row) = segment else {
        return Err(VerifyError::bad_value(
            "scaled distance Z (m/kg^(1/3))",
            z,
            &format!("{} ≤ Z ≤ {} (Swisdak 1994)", covered.0, covered.1),
        ));
    };
    let ln_z = z.ln();
    let exponent = (4..=10)
        .rev()
        .fold(0.0, |sum, k| sum * ln_z + cell(row, k).unwrap_or(0.0));
    Ok(exponent.exp() * quantity.to_si())
}

/// The blast-wave parameters at one range from one charge (Kingery–Bulmash), in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AirBlast {
    /// Z = R/W^(1/3) (m/kg^(1/3)).
    pub z: f64,
    pub incident_overpressure_pa: f64,
    /// Normally reflected.
    pub reflected_overpressure_pa: f64,
    pub arrival_s: f64,
    /// The positive phase's duration; `None` below Z = 0.18 m/kg^(1/3), where the fits give
    /// none.
    pub duration_s: Option<f64>,
    pub incident_impulse_pa_s: f64,
    pub reflected_impulse_pa_s: f64,
}

/// Kingery–Bulmash at `range_m` from `charge_kg` of TNT.
pub fn air_blast(burst: Burst, charge_kg: f64, range_m: f64) -> Result<AirBlast, VerifyError> {
    let z = scaled_distance(range_m, charge_kg)?;
    let scale = charge_kg.cbrt();
    let value = |quantity| kingery_bulmash(burst, quantity, z);
    let always = |quantity| -> Result<f64, VerifyError> {
        Ok(value(quantity)?.expect("every quantity but the duration covers the whole range"))
    };
    Ok(AirBlast {
        z,
        incident_overpressure_pa: always(Quantity::IncidentOverpressure)?,
        reflected_overpressure_pa: always(Quantity::ReflectedOverpressure)?,
        arrival_s: always(Quantity::ArrivalTime)? * scale,
        duration_s: value(Quantity::PositiveDuration)?.map(|d| d * scale),
        incident_impulse_pa_s: always(Quantity::IncidentImpulse)? * scale,
        reflected_impulse_pa_s: always(Quantity::ReflectedImpulse)? * scale,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Z from `lo` to `hi`, `n` points evenly spaced in log Z.
    fn log_spaced(lo: f64, hi: f64, n: usize) -> impl Iterator<Item = f64> {
        (0..n).map(move |k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64))
    }

    /// The two independent transcriptions of the hemispherical fits agree within 2 % wherever
    /// both are defined, for every quantity but the reflected impulse: measured largest
    /// differences 1.3 % (incident overpressure), 1.0 % (reflected), 0.8 % (arrival), 1.6 %
    /// (duration), 1.9 % (incident impulse). The transcribed Swisdak reflected impulse agrees
    /// only for 0.4 ≤ Z ≤ 2.5 (within 2 % there); beyond, it departs to +140 % at Z = 30,
    /// where it would make the reflected impulse 5 times the incident one, against the
    /// acoustic limit of 2 that Kingery–Bulmash approach (1.8 at Z = 39): the Swisdak row is
    /// the suspect one, and it is tested only where it holds.
    #[test]
    fn kingery_bulmash_and_swisdak_agree() {
        for quantity in Quantity::ALL {
            let range = match quantity {
                Quantity::ReflectedImpulse => (0.4, 2.5),
                _ => Burst::Hemispherical.validity(),
            };
            for z in log_spaced(range.0, range.1, 400) {
                let (Ok(Some(kb)), Ok(swisdak)) = (
                    kingery_bulmash(Burst::Hemispherical, quantity, z),
                    swisdak_hemispherical(quantity, z),
                ) else {
                    continue;
                };
                let difference = (swisdak / kb - 1.0).abs();
                assert!(difference < 0.02, "{quantity:?} at Z = {z}: {difference}");
            }
        }
    }

    /// The published example of the `kingery-bulmash` package (PyPI, a Python implementation
    /// of Swisdak's form, from which the table was transcribed): 10 000 kg at 500 m gives
    /// arrival 1276.17 ms, incident 5.0550 kPa, reflected 10.2446 kPa, duration 133.233 ms,
    /// incident impulse 295.877 kPa·ms, reflected impulse 1063.03 kPa·ms. The table shares its
    /// source, so this checks how the table is read and evaluated here (segments, the ln Z
    /// polynomial, units), to 1e-6; the coefficients themselves are checked against
    /// Kingery–Bulmash above.
    #[test]
    fn swisdak_reproduces_a_published_example() {
        let z = 500.0 / 10_000f64.cbrt();
        let scale = 10_000f64.cbrt();
        let cases = [
            (Quantity::ArrivalTime, 1.2761650108864796 / scale),
            (Quantity::IncidentOverpressure, 5_054.963_965_502_846),
            (Quantity::ReflectedOverpressure, 10244.621193146642),
            (Quantity::PositiveDuration, 0.13323344980362697 / scale),
            (Quantity::IncidentImpulse, 295.87689480141484 / scale),
            (Quantity::ReflectedImpulse, 1063.0270073779907 / scale),
        ];
        for (quantity, published) in cases {
            let ours = swisdak_hemispherical(quantity, z).unwrap();
            assert!(
                (ours / published - 1.0).abs() < 1e-6,
                "{quantity:?}: {ours} vs {published}"
            );
        }
    }

    /// Outside the fits' range: a named error, never an extrapolation; the duration is absent
    /// below its fit.
    #[test]
    fn outside_the_range_is_an_error() {
        for burst in Burst::ALL {
            let (lo, hi) = burst.validity();
            for z in [0.5 * lo, 1.01 * hi] {
                let error = kingery_bulmash(burst, Quantity::IncidentOverpressure, z)
                    .unwrap_err()
                    .to_string();
                assert!(
                    error.contains("scaled distance") && error.contains("≤ Z ≤"),
                    "{error}"
                );
            }
            for z in [lo, hi] {
                assert!(kingery_bulmash(burst, Quantity::IncidentOverpressure, z)
                    .unwrap()
                    .is_some());
            }
            assert_eq!(
                kingery_bulmash(burst, Quantity::PositiveDuration, 0.1).unwrap(),
                None
            );
        }
        assert!(swisdak_hemispherical(Quantity::IncidentOverpressure, 0.1).is_err());
        let error = air_blast(Burst::FreeAir, 1000.0, 1000.0)
            .unwrap_err()
            .to_string();
        assert!(error.contains("100"), "{error}");
    }

    /// Physical sense that any transcription error would break: pressures fall and arrival
    /// grows with Z (not the impulse: Kingery & Bulmash's scaled incident impulse rises again
    /// between about Z = 0.5 and 1, near the fireball's edge); reflection at least doubles the overpressure (the acoustic
    /// limit) and, near the charge, gives much more; a surface burst (twice the energy in the
    /// half space) is stronger than the same charge in free air; each fit is continuous across
    /// its segment switches within 2 % (the fits' own jumps there, measured: hemispherical incident
    /// impulse −1.4 % at Z = 0.956, duration −1.7 % at 1.008 and +0.9 % at 2.777; free-air
    /// impulse −0.6 %, duration +1.0 % and +0.1 %: a transcription error would jump by more).
    #[test]
    fn the_fits_make_physical_sense() {
        for burst in Burst::ALL {
            let (lo, hi) = burst.validity();
            let mut previous: Option<[f64; 3]> = None;
            for z in log_spaced(lo, hi, 300) {
                let v = |q| kingery_bulmash(burst, q, z).unwrap().unwrap();
                let now = [
                    v(Quantity::IncidentOverpressure),
                    v(Quantity::ReflectedOverpressure),
                    v(Quantity::ArrivalTime),
                ];
                assert!(
                    now[1] >= 1.99 * now[0],
                    "{burst:?} Z = {z}: reflection {now:?}"
                );
                if let Some(before) = previous {
                    assert!(
                        now[0] < before[0] && now[1] < before[1],
                        "{burst:?} Z = {z}"
                    );
                    assert!(now[2] > before[2], "{burst:?} Z = {z}: arrival");
                }
                previous = Some(now);
            }
            for quantity in Quantity::ALL {
                for segment in kb_segments().iter().filter(|s| {
                    s.quantity == quantity.table_name() && s.burst == burst.table_name()
                }) {
                    let z = segment.z_range.1;
                    if z.is_finite() && z < hi {
                        let below = kingery_bulmash(burst, quantity, z * (1.0 - 1e-9)).unwrap();
                        let above = kingery_bulmash(burst, quantity, z).unwrap();
                        let (below, above) = (below.unwrap(), above.unwrap());
                        assert!(
                            (above / below - 1.0).abs() < 0.02,
                            "{burst:?} {quantity:?} at Z = {z}: {below} → {above}"
                        );
                    }
                }
            }
        }
        for z in [0.5, 1.0, 5.0, 20.0] {
            let surface = kingery_bulmash(Burst::Hemispherical, Quantity::IncidentOverpressure, z);
            let free = kingery_bulmash(Burst::FreeAir, Quantity::IncidentOverpressure, z);
            assert!(
                surface.unwrap().unwrap() > free.unwrap().unwrap(),
                "Z = {z}"
            );
        }
    }
}
