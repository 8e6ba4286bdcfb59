//! TNT equivalence: the mass of TNT that gives the same blast as a kilogram of another
//! explosive, kept apart for pressure and for impulse where the source gives both.

use crate::VerifyError;

/// An explosive and its TNT equivalence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Explosive {
    pub name: &'static str,
    /// kg TNT per kg for peak pressure (and particle velocity in soil).
    pub pressure_factor: f64,
    /// kg TNT per kg for impulse.
    pub impulse_factor: f64,
    pub source: &'static str,
}

/// The explosives whose equivalence has a checked source. Composition C-4's factors are those
/// the ground-shock relations are written with (`drake1983_conwep_ground_shock_equations.csv`,
/// verified in the MSB transcription). PETN, Composition B and ANFO are left out until their
/// factors are read in a checkable source.
pub const EXPLOSIVES: [Explosive; 2] = [
    Explosive {
        name: "tnt",
        pressure_factor: 1.0,
        impulse_factor: 1.0,
        source: "the reference explosive",
    },
    Explosive {
        name: "c4",
        pressure_factor: 1.37,
        impulse_factor: 1.19,
        source: "MSB B02-301 / MSB344 (Laine), as used with Drake (1983) / TM 5-855-1",
    },
];

/// The explosive called `name`.
pub fn explosive(name: &str) -> Result<&'static Explosive, VerifyError> {
    EXPLOSIVES.iter().find(|e| e.name == name).ok_or_else(|| {
        let names: Vec<&str> = EXPLOSIVES.iter().map(|e| e.name).collect();
        VerifyError::bad_value("explosive", name, &names.join(", "))
    })
}

impl Explosive {
    /// The TNT mass that gives the same peak pressure as `mass_kg` of this explosive.
    pub fn tnt_for_pressure(&self, mass_kg: f64) -> f64 {
        mass_kg * self.pressure_factor
    }

    /// The TNT mass that gives the same impulse as `mass_kg` of this explosive.
    pub fn tnt_for_impulse(&self, mass_kg: f64) -> f64 {
        mass_kg * self.impulse_factor
    }
}

/// The C-4 masses that match a TNT charge of `tnt_kg`: for peak stress and velocity, and for
/// impulse (the ground-shock relations' W is a C-4 mass).
pub fn c4_equivalent(tnt_kg: f64) -> (f64, f64) {
    let c4 = &EXPLOSIVES[1];
    (tnt_kg / c4.pressure_factor, tnt_kg / c4.impulse_factor)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// C-4 → TNT → C-4 returns the same mass for each of pressure and impulse; unknown names
    /// are refused with the list of known ones.
    #[test]
    fn c4_round_trips_and_unknown_names_are_refused() {
        let c4 = explosive("c4").unwrap();
        let (for_pressure, _) = c4_equivalent(c4.tnt_for_pressure(125.0));
        assert!((for_pressure - 125.0).abs() < 1e-12);
        let (_, back) = c4_equivalent(c4.tnt_for_impulse(125.0));
        assert!((back - 125.0).abs() < 1e-12);
        // 125 kg TNT is 91.2 kg C-4 for stress and velocity, 105.0 kg for impulse
        let (p, i) = c4_equivalent(125.0);
        assert!(
            (p - 91.24).abs() < 0.01 && (i - 105.04).abs() < 0.01,
            "{p} {i}"
        );
        let error = explosive("semtex").unwrap_err().to_string();
        assert!(error.contains("tnt, c4"), "{error}");
    }
}
