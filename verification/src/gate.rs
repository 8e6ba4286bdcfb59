//! The free-field gate: before a study reports a number for a charge in a soil, the free-field
//! physics it rests on must have passed its checks against independent answers at that charge,
//! in that soil, at the study's resolution:
//! - `airblast-surface` at the charge: the surface burst's air blast against Kingery–Bulmash
//!   hemispherical;
//! - `ground-shock-spherical` at the charge, in the soil, with gauges at the study's depths
//!   (Drucker–Prager sand) against the TM 5-855-1 relations, at two resolutions;
//! - `ground-shock-surface` at the charge, in the soil, with gauges at the study's depths: the
//!   free field the study runs (the charge on the ground, axisymmetric) against the same
//!   relations with the coupling factor of a surface burst;
//! - `hopkinson-cranz`: the scene has no length or time of its own;
//! - resolution convergence: the two finest resolutions' peak stress at the deepest gauge
//!   within [`CONVERGENCE_LIMIT`].
//!
//! What the gate cannot check yet is named under `not_covered`, so that a study shows it: the
//! ground shock that the surface burst's air blast induces (the study's free field does not
//! carry it; `ground-shock-surface` checks the air blast on the ground against Kingery–Bulmash
//! and reports what it adds, against no reference).
//!
//! A gate's result is written as JSON with a hash of its inputs: the request, the problems'
//! parameters and the bytes of the program that ran them. The same request with the same
//! program reuses it instead of running again; any change of the code or of the request runs
//! it afresh.

use crate::problems;
use crate::record::{Check, Record};
use crate::report::write_atomic;
use crate::scaled::ground_shock::soil;
use crate::{Level, VerifyError};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The largest relative difference between the peak stress at the deepest gauge at the two
/// finest resolutions: a study whose answer moves by more when the resolution doubles has not
/// converged to the precision its checks (factors of 2–3 on the peaks) need.
pub const CONVERGENCE_LIMIT: f64 = 0.10;

/// What the gate is asked.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GateRequest {
    /// TNT mass (kg).
    pub charge_kg: f64,
    /// A TM 5-855-1 soil with a material model (see `problems::ground_shock`).
    pub soil: String,
    /// The study's gauge depths below the charge (m).
    pub depths_m: Vec<f64>,
    pub level: Level,
}

/// One check as the gate reports it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GateCheck {
    pub name: String,
    pub value: f64,
    pub limit: f64,
    pub relation: String,
    pub pass: bool,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub known_limit: Option<String>,
}

impl From<&Check> for GateCheck {
    fn from(c: &Check) -> Self {
        Self {
            name: c.name.clone(),
            value: c.value,
            limit: c.limit,
            relation: c.relation.to_string(),
            pass: c.pass,
            known_limit: c.known_limit.clone(),
        }
    }
}

impl GateCheck {
    /// Passes, or fails at a known limit of the physics.
    pub fn holds(&self) -> bool {
        self.pass || self.known_limit.is_some()
    }
}

/// One problem the gate ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GateProblem {
    pub problem: String,
    /// The parameters the gate set (the rest are the level's defaults).
    pub overrides: Vec<(String, String)>,
    pub pass: bool,
    pub wall_s: f64,
    pub checks: Vec<GateCheck>,
}

/// The gate's verdict.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GateReport {
    pub pass: bool,
    /// SHA-256 of the request, the problems' parameters and the program.
    pub inputs_hash: String,
    pub request: GateRequest,
    pub problems: Vec<GateProblem>,
    /// The gate's own checks (resolution convergence).
    pub checks: Vec<GateCheck>,
    /// What the gate should check and cannot yet.
    pub not_covered: Vec<String>,
}

/// The problems the gate runs for `request`, each with the parameters it sets.
fn plan(request: &GateRequest) -> Vec<(&'static str, Vec<(String, String)>)> {
    let list = |values: &[f64]| {
        values
            .iter()
            .map(f64::to_string)
            .collect::<Vec<_>>()
            .join(",")
    };
    let charge = request.charge_kg.to_string();
    let resolutions = match request.level {
        Level::Quick => "10,20",
        Level::Full => "10,20,40",
    };
    let set = |pairs: &[(&str, &str)]| -> Vec<(String, String)> {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    };
    vec![
        ("airblast-surface", set(&[("charge", &charge)])),
        (
            "ground-shock-spherical",
            set(&[
                ("charge", &charge),
                ("soil", &request.soil),
                ("gauges", &list(&request.depths_m)),
                ("variants", "drucker-prager"),
                ("n", resolutions),
            ]),
        ),
        (
            "ground-shock-surface",
            set(&[
                ("charge", &charge),
                ("soil", &request.soil),
                ("depths", &list(&request.depths_m)),
            ]),
        ),
        ("hopkinson-cranz", Vec::new()),
    ]
}

/// Refuses a request the gate cannot run, naming the field: a charge or depth out of range, a
/// soil without a material model, a parameter a problem rejects.
pub fn validate(request: &GateRequest) -> Result<(), VerifyError> {
    if !(request.charge_kg > 0.0 && request.charge_kg <= 1e6) {
        return Err(VerifyError::bad_value(
            "charge (kg TNT)",
            request.charge_kg,
            "0 < W ≤ 1e6",
        ));
    }
    if request.depths_m.is_empty() {
        return Err(VerifyError::bad_value(
            "depths (m)",
            "none",
            "at least one depth",
        ));
    }
    soil(&request.soil)?;
    problems::ground_shock::soil_model(&request.soil)?;
    for (name, overrides) in plan(request) {
        problems::preflight(name, request.level, &overrides)?;
    }
    Ok(())
}

/// The hash of what decides the gate's result: the request, the problems and parameters it
/// runs, and the program's own bytes.
pub fn inputs_hash(request: &GateRequest) -> Result<String, VerifyError> {
    crate::cache::inputs_hash(&[
        &serde_json::to_vec(request).expect("a request serialises"),
        &serde_json::to_vec(&plan(request)).expect("a plan serialises"),
    ])
}

/// Where the gate's result for `hash` is kept in `dir`.
pub fn report_path(dir: &Path, hash: &str) -> PathBuf {
    dir.join(format!("gate-{}.json", &hash[..16]))
}

/// The peak stress at the deepest gauge of the two finest drucker-prager runs (sensitivity rows
/// left out), and their relative difference.
fn convergence(record: &Record, deepest: f64) -> GateCheck {
    let peak = |run: &crate::record::Run| {
        run.gauges
            .iter()
            .find(|g| (g.position_m - deepest).abs() < 1e-9)
            .map_or(f64::NAN, |g| g.peak_pressure_pa)
    };
    let mut runs: Vec<&crate::record::Run> = record
        .runs
        .iter()
        .filter(|run| run.sensitivity.is_none())
        .collect();
    runs.sort_by(|a, b| b.spacing.total_cmp(&a.spacing));
    let difference = match runs.as_slice() {
        [.., coarse, fine] => (peak(fine) / peak(coarse) - 1.0).abs(),
        _ => f64::NAN,
    };
    GateCheck::from(&Check::at_most(
        format!("peak_stress_change_two_finest_r{deepest}"),
        difference,
        CONVERGENCE_LIMIT,
    ))
}

/// Runs the gate for `request` (or reuses its result from `dir`), writes its result there and
/// returns it with whether it was reused. `progress` gets the fraction done.
pub fn run_gate(
    request: &GateRequest,
    dir: &Path,
    progress: &(dyn Fn(&str, f64) + Sync),
) -> Result<(GateReport, bool), VerifyError> {
    validate(request)?;
    let hash = inputs_hash(request)?;
    let path = report_path(dir, &hash);
    if let Ok(text) = std::fs::read_to_string(&path) {
        if let Ok(report) = serde_json::from_str::<GateReport>(&text) {
            if report.inputs_hash == hash && &report.request == request {
                return Ok((report, true));
            }
        }
    }
    let mut report = GateReport {
        pass: false,
        inputs_hash: hash,
        request: request.clone(),
        problems: Vec::new(),
        checks: Vec::new(),
        not_covered: vec![
            "air-induced ground shock: the study's free field does not carry the surface \
             burst's air blast on the ground; ground-shock-surface runs it, checks the blast \
             against Kingery–Bulmash and reports what it adds to the soil's peaks, against no \
             reference"
                .into(),
        ],
    };
    let deepest = request
        .depths_m
        .iter()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max);
    for (name, overrides) in plan(request) {
        let label = format!("{name} {} kg", request.charge_kg);
        let output = problems::run(name, request.level, &overrides, &|f| progress(&label, f))?;
        let record = &output.record;
        if name == "ground-shock-spherical" {
            report.checks.push(convergence(record, deepest));
        }
        report.problems.push(GateProblem {
            problem: name.to_string(),
            overrides,
            pass: record.pass,
            wall_s: record.wall_s,
            checks: record.checks.iter().map(GateCheck::from).collect(),
        });
    }
    report.pass =
        report.problems.iter().all(|p| p.pass) && report.checks.iter().all(GateCheck::holds);
    std::fs::create_dir_all(dir).map_err(|source| VerifyError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let text = serde_json::to_string_pretty(&report).expect("a report serialises");
    write_atomic(&path, text.as_bytes())?;
    Ok((report, false))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gauges::Gauge;
    use crate::record::Run;

    fn request() -> GateRequest {
        GateRequest {
            charge_kg: 500.0,
            soil: "dry-sand-backfill".into(),
            depths_m: vec![10.0, 20.0],
            level: Level::Quick,
        }
    }

    /// A result kept under the request's hash is reused without running anything; a result
    /// whose request differs is not.
    #[test]
    fn a_kept_result_with_the_same_inputs_is_reused() {
        let dir = std::env::temp_dir().join(format!("blastsph-gate-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let hash = inputs_hash(&request()).unwrap();
        let kept = GateReport {
            pass: true,
            inputs_hash: hash.clone(),
            request: request(),
            problems: Vec::new(),
            checks: Vec::new(),
            not_covered: Vec::new(),
        };
        let text = serde_json::to_string(&kept).unwrap();
        std::fs::write(report_path(&dir, &hash), text).unwrap();
        let (report, reused) = run_gate(&request(), &dir, &|_, _| {}).unwrap();
        assert!(reused);
        assert_eq!(report, kept);
        // another charge hashes differently
        let other = GateRequest {
            charge_kg: 1000.0,
            ..request()
        };
        assert_ne!(inputs_hash(&other).unwrap(), hash);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The convergence check compares the deepest gauge's peak at the two finest runs; a
    /// sensitivity row (a parameter varied at some resolution) is not one of them.
    #[test]
    fn convergence_compares_the_two_finest_runs_at_the_deepest_gauge() {
        let run = |spacing: f64, peak: f64| {
            let mut run = Run::new("r", "", 10, spacing);
            run.gauges.push(Gauge {
                name: "r = 20 m".into(),
                position_m: 20.0,
                arrival_s: 0.1,
                peak_pressure_pa: peak,
                peak_velocity_m_s: 1.0,
                impulse_pa_s: 1.0,
                positive_phase_ended: true,
            });
            run
        };
        let record = Record::new(
            "ground-shock-spherical",
            Level::Quick,
            vec![run(0.04, 50.0), run(0.02, 100.0), run(0.01, 108.0), {
                let mut varied = run(0.005, 300.0);
                varied.sensitivity = Some("alpha_min = 0.05 (default 0.1)".into());
                varied
            }],
            Default::default(),
            Vec::new(),
            0,
        );
        let check = convergence(&record, 20.0);
        assert!((check.value - 0.08).abs() < 1e-12, "{check:?}");
        assert!(check.pass);
    }
}
