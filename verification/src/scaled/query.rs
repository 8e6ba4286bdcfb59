//! One question a user asks of the scaled-distance relations: what does this charge, placed
//! so, do at this range: in the air (Kingery–Bulmash) and, given a soil, in the ground
//! (TM 5-855-1). What `blastsph scaled` prints.

use super::air_blast::{air_blast, Burst};
use super::explosives::{c4_equivalent, Explosive};
use super::ground_shock::{coupling_factor, ground_shock, GroundShock, Soil, IN_AIR};
use super::{positive, scaled_distance};
use crate::VerifyError;
use serde::Serialize;

/// Where the charge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// On the ground: a hemispherical surface burst in the air; in the ground, the coupling
    /// factor of its depth of burst (0 by default: the charge's centre at the surface,
    /// f = 0.40).
    Surface,
    /// In the air, far from the ground: the spherical free-air fits; f = 0.14 in the ground.
    FreeAir,
    /// Under the ground at a depth of burst: no air blast; f from the scaled depth.
    Buried,
}

impl Placement {
    pub const ALL: [Placement; 3] = [Placement::Surface, Placement::FreeAir, Placement::Buried];

    pub fn name(self) -> &'static str {
        match self {
            Placement::Surface => "surface",
            Placement::FreeAir => "free-air",
            Placement::Buried => "buried",
        }
    }
}

/// The answer: the air blast where there is one, the ground shock where a soil was given.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScaledReport {
    pub charge_kg: f64,
    pub explosive: &'static str,
    pub range_m: f64,
    pub burst: &'static str,
    /// Z = R/W^(1/3) with W the TNT mass equivalent for pressure (m/kg^(1/3)).
    pub z: f64,
    pub incident_overpressure_pa: Option<f64>,
    pub reflected_overpressure_pa: Option<f64>,
    pub arrival_s: Option<f64>,
    pub duration_s: Option<f64>,
    pub incident_impulse_pa_s: Option<f64>,
    pub reflected_impulse_pa_s: Option<f64>,
    pub soil: Option<&'static str>,
    pub ground_shock: Option<GroundShock>,
}

/// The report for `charge_kg` of `explosive` placed at `placement` (with its depth of burst,
/// m, positive downwards) seen at `range_m`, with the ground shock in `soil` if given.
pub fn scaled_report(
    charge_kg: f64,
    explosive: &'static Explosive,
    range_m: f64,
    placement: Placement,
    depth_of_burst_m: Option<f64>,
    soil: Option<&'static Soil>,
) -> Result<ScaledReport, VerifyError> {
    positive("charge mass (kg)", charge_kg)?;
    let tnt_pressure = explosive.tnt_for_pressure(charge_kg);
    let tnt_impulse = explosive.tnt_for_impulse(charge_kg);
    let z = scaled_distance(range_m, tnt_pressure)?;
    let burst = match placement {
        Placement::Surface => Some(Burst::Hemispherical),
        Placement::FreeAir => Some(Burst::FreeAir),
        Placement::Buried => None,
    };
    let (pressure_side, impulse_side) = match burst {
        Some(burst) => (
            Some(air_blast(burst, tnt_pressure, range_m)?),
            Some(air_blast(burst, tnt_impulse, range_m)?),
        ),
        None => (None, None),
    };
    let depth = match (placement, depth_of_burst_m) {
        (Placement::Buried, Some(d)) if d > 0.0 && d.is_finite() => Some(d),
        (Placement::Buried, other) => {
            return Err(VerifyError::bad_value(
                "depth of burst (m)",
                other.map_or("none".to_string(), |d| d.to_string()),
                "finite and > 0 for a buried charge",
            ))
        }
        (Placement::FreeAir, Some(d)) => {
            return Err(VerifyError::bad_value(
                "depth of burst (m)",
                d,
                "none for a free-air burst (its coupling factor is 0.14)",
            ))
        }
        (Placement::Surface, Some(d)) if !d.is_finite() => {
            return Err(VerifyError::bad_value("depth of burst (m)", d, "finite"))
        }
        (_, depth) => depth,
    };
    let ground = match soil {
        Some(soil) => {
            let coupling = match placement {
                Placement::FreeAir => IN_AIR,
                _ => coupling_factor(depth.unwrap_or(0.0) / c4_equivalent(tnt_pressure).0.cbrt()),
            };
            Some(ground_shock(soil, explosive, charge_kg, range_m, coupling)?)
        }
        None => None,
    };
    Ok(ScaledReport {
        charge_kg,
        explosive: explosive.name,
        range_m,
        burst: placement.name(),
        z,
        incident_overpressure_pa: pressure_side.map(|a| a.incident_overpressure_pa),
        reflected_overpressure_pa: pressure_side.map(|a| a.reflected_overpressure_pa),
        arrival_s: pressure_side.map(|a| a.arrival_s),
        duration_s: pressure_side.and_then(|a| a.duration_s),
        incident_impulse_pa_s: impulse_side.map(|a| a.incident_impulse_pa_s),
        reflected_impulse_pa_s: impulse_side.map(|a| a.reflected_impulse_pa_s),
        soil: soil.map(|s| s.name),
        ground_shock: ground,
    })
}

#[cfg(test)]
mod tests {
    use super::super::explosives::explosive;
    use super::super::ground_shock::soil;
    use super::*;

    /// A surface burst's air blast is Kingery–Bulmash's at the TNT mass; C-4 is converted
    /// (1.37 for pressure, 1.19 for impulse); a buried charge has no air blast and needs a
    /// depth; a free-air burst couples at 0.14 and takes no depth.
    #[test]
    fn placements_and_conversions() {
        let (tnt, c4) = (explosive("tnt").unwrap(), explosive("c4").unwrap());
        let sand = soil("dry-sand-backfill").unwrap();
        let report = scaled_report(500.0, tnt, 40.0, Placement::Surface, None, Some(sand)).unwrap();
        let direct = air_blast(Burst::Hemispherical, 500.0, 40.0).unwrap();
        assert_eq!(
            report.incident_overpressure_pa,
            Some(direct.incident_overpressure_pa)
        );
        assert_eq!(report.ground_shock.unwrap().coupling_factor, 0.4033);
        let from_c4 = scaled_report(100.0, c4, 40.0, Placement::Surface, None, None).unwrap();
        let as_tnt = air_blast(Burst::Hemispherical, 137.0, 40.0).unwrap();
        let impulse_as_tnt = air_blast(Burst::Hemispherical, 119.0, 40.0).unwrap();
        assert!(
            (from_c4.incident_overpressure_pa.unwrap() / as_tnt.incident_overpressure_pa - 1.0)
                .abs()
                < 1e-12
        );
        assert!(
            (from_c4.incident_impulse_pa_s.unwrap() / impulse_as_tnt.incident_impulse_pa_s - 1.0)
                .abs()
                < 1e-12
        );
        let buried =
            scaled_report(125.0, c4, 5.0, Placement::Buried, Some(4.0), Some(sand)).unwrap();
        assert_eq!(buried.incident_overpressure_pa, None);
        assert_eq!(buried.ground_shock.unwrap().coupling_factor, 1.0);
        let error = scaled_report(125.0, c4, 5.0, Placement::Buried, None, Some(sand)).unwrap_err();
        assert!(error.to_string().contains("depth of burst"), "{error}");
        let error = scaled_report(1.0, tnt, 5.0, Placement::FreeAir, Some(1.0), None).unwrap_err();
        assert!(error.to_string().contains("free-air"), "{error}");
        let in_air = scaled_report(100.0, tnt, 20.0, Placement::FreeAir, None, Some(sand)).unwrap();
        assert_eq!(in_air.ground_shock.unwrap().coupling_factor, 0.14);
    }
}
