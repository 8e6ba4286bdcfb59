//! Arrival times that physics allows: a wave from a charge on the surface cannot reach a gauge
//! at depth d before d/c_max, where c_max is the fastest wave the ground and the lining can
//! carry. For a soil that compacts that is its fully compacted unloading (bulk) sound speed,
//! for the concrete lining its fastest tabulated speed; both from the material library
//! (`reference_data/materials.toml`: dry sand 4636 m/s, Laine & Sandvik 2001; concrete
//! 4150 m/s at full compaction, above the P-wave speed of Eurocode C35/45 concrete, 3970 m/s
//! from E = 34 GPa, ν = 0.2, ρ = 2400 kg/m³, so the bound is the lenient one).

use crate::materials::Library;
use crate::VerifyError;
use serde::{Deserialize, Serialize};

/// The lining material whose speed joins the soil's in c_max.
pub const LINING: &str = "concrete";

/// One reported first arrival.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct ReportedArrival {
    pub depth_m: f64,
    pub charge_kg: f64,
    pub gauge: String,
    pub arrival_ms: f64,
}

/// A reported arrival against the earliest physics allows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArrivalCheck {
    pub depth_m: f64,
    pub charge_kg: f64,
    pub gauge: String,
    pub arrival_s: f64,
    /// depth / arrival.
    pub implied_speed_m_s: f64,
    /// depth / c_max.
    pub min_possible_arrival_s: f64,
    pub possible: bool,
}

/// The verdict on a table of arrivals.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArrivalReport {
    pub soil: String,
    pub lining: &'static str,
    pub c_max_m_s: f64,
    pub entries: Vec<ArrivalCheck>,
}

impl ArrivalReport {
    pub fn all_possible(&self) -> bool {
        self.entries.iter().all(|e| e.possible)
    }
}

/// The fastest sound speed material `name` of the library can reach: the largest value of its
/// unloading sound-speed table (a compaction material).
pub fn fastest_wave_speed(library: &Library, name: &str) -> Result<f64, VerifyError> {
    let entry = library.entry(name)?;
    entry
        .tables
        .get("unloading_sound_speed")
        .map(|table| table.value.iter().cloned().fold(0.0, f64::max))
        .ok_or_else(|| {
            VerifyError::bad_value(
                "soil",
                name,
                "a compaction material of the library (with an unloading sound-speed table), e.g. dry-sand",
            )
        })
}

/// The fastest shock the loading path of compaction material `name` carries: the largest
/// Hugoniot shock speed U_s = √(p / (ρ0 (1 − ρ0/ρ))) over its loading table (mass and
/// momentum across a shock into material at rest at ρ0). No front in the material at rest
/// runs faster while the stress stays within the table.
pub fn fastest_shock_speed(library: &Library, name: &str) -> Result<f64, VerifyError> {
    let entry = library.entry(name)?;
    let not_compaction = || {
        VerifyError::bad_value(
            "soil",
            name,
            "a compaction material of the library (with a loading table), e.g. dry-sand",
        )
    };
    let rho0 = entry
        .parameters
        .get("rho0")
        .ok_or_else(not_compaction)?
        .value;
    let loading = entry.tables.get("loading").ok_or_else(not_compaction)?;
    Ok(loading
        .density
        .iter()
        .zip(&loading.value)
        .filter(|(&rho, _)| rho > rho0)
        .map(|(&rho, &p)| (p / (rho0 * (1.0 - rho0 / rho))).sqrt())
        .fold(0.0, f64::max))
}

/// Reads a table with the columns `depth_m,charge_kg,gauge,arrival_ms` (lines starting with
/// `#` are comments); `origin` names it in errors.
pub fn read_arrivals(text: &str, origin: &str) -> Result<Vec<ReportedArrival>, VerifyError> {
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut entries = Vec::new();
    for (k, row) in reader.deserialize::<ReportedArrival>().enumerate() {
        let row = row.map_err(|e| {
            VerifyError::bad_value(
                &format!("{origin} row {}", k + 1),
                e,
                "depth_m,charge_kg,gauge,arrival_ms with numbers where numbers belong",
            )
        })?;
        for (field, value) in [
            ("depth_m", row.depth_m),
            ("charge_kg", row.charge_kg),
            ("arrival_ms", row.arrival_ms),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(VerifyError::bad_value(
                    &format!("{origin} row {} {field}", k + 1),
                    value,
                    "finite and > 0",
                ));
            }
        }
        entries.push(row);
    }
    if entries.is_empty() {
        return Err(VerifyError::bad_value(
            origin,
            "no rows",
            "at least one arrival",
        ));
    }
    Ok(entries)
}

/// Each arrival against d/c_max for the library's `soil` and the concrete lining.
pub fn check_arrivals(
    library: &Library,
    soil: &str,
    arrivals: &[ReportedArrival],
) -> Result<ArrivalReport, VerifyError> {
    let c_max = fastest_wave_speed(library, soil)?.max(fastest_wave_speed(library, LINING)?);
    let entries = arrivals
        .iter()
        .map(|a| {
            let arrival_s = a.arrival_ms * 1e-3;
            let min_possible = a.depth_m / c_max;
            ArrivalCheck {
                depth_m: a.depth_m,
                charge_kg: a.charge_kg,
                gauge: a.gauge.clone(),
                arrival_s,
                implied_speed_m_s: a.depth_m / arrival_s,
                min_possible_arrival_s: min_possible,
                possible: arrival_s >= min_possible,
            }
        })
        .collect();
    Ok(ArrivalReport {
        soil: soil.to_string(),
        lining: LINING,
        c_max_m_s: c_max,
        entries,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// c_max for dry sand is its fully compacted speed, 4636 m/s; an arrival at exactly d/c_max
    /// is possible, one a hair earlier is not; the ground-shock relations' own arrival (r/c with
    /// the loading speed, 305 m/s in dry sand) is possible, as every real arrival must be.
    #[test]
    fn the_bound_is_depth_over_the_fastest_speed() {
        let library = Library::standard();
        let c_max = 4636.0;
        let at = |ms: f64| ReportedArrival {
            depth_m: 10.0,
            charge_kg: 500.0,
            gauge: "crown".into(),
            arrival_ms: ms,
        };
        let limit_ms = 1e3 * 10.0 / c_max;
        let report = check_arrivals(
            &library,
            "dry-sand",
            &[at(limit_ms), at(limit_ms * 0.999), at(1e3 * 10.0 / 305.0)],
        )
        .unwrap();
        assert_eq!(report.c_max_m_s, c_max);
        let possible: Vec<bool> = report.entries.iter().map(|e| e.possible).collect();
        assert_eq!(possible, [true, false, true]);
    }

    #[test]
    fn bad_tables_and_soils_are_named() {
        let error = read_arrivals(
            "depth_m,charge_kg,gauge,arrival_ms\n10,500,crown,fast\n",
            "f.csv",
        )
        .unwrap_err()
        .to_string();
        assert!(error.contains("f.csv row 1"), "{error}");
        let error = read_arrivals(
            "depth_m,charge_kg,gauge,arrival_ms\n-10,500,crown,1\n",
            "f.csv",
        )
        .unwrap_err()
        .to_string();
        assert!(
            error.contains("depth_m") && error.contains("> 0"),
            "{error}"
        );
        let error = read_arrivals("# nothing\ndepth_m,charge_kg,gauge,arrival_ms\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(error.contains("at least one"), "{error}");
        let error = check_arrivals(&Library::standard(), "air", &[])
            .unwrap_err()
            .to_string();
        assert!(error.contains("compaction"), "{error}");
    }
}
