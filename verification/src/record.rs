//! What a problem run returns: the record (written as JSON), the final profiles (CSV) and a
//! figure (SVG).

use crate::svg::Figure;
use crate::Level;
use serde::Serialize;
use std::collections::BTreeMap;

/// One check: a value against a limit.
#[derive(Clone, Debug, Serialize)]
pub struct Check {
    pub name: String,
    pub value: f64,
    pub limit: f64,
    /// "<=" or ">=": how value must relate to limit.
    pub relation: &'static str,
    pub pass: bool,
    /// A limit of the physics the problem models, with the evidence for it: the check is
    /// evaluated and shown like any other, but its failure does not fail the record (see
    /// [`Check::known_limit`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub known_limit: Option<String>,
}

impl Check {
    /// Marks the check as measuring a known limit of the modelled physics, with `evidence`:
    /// what was measured that shows the gap is the model's and not the numerics' (for
    /// example, an error that resolution does not change while the others converge). Reports
    /// list it with the evidence wherever they list failed checks, so it is never hidden;
    /// it just does not fail the record.
    pub fn known_limit(self, evidence: impl Into<String>) -> Self {
        Self {
            known_limit: Some(evidence.into()),
            ..self
        }
    }

    /// Passes, or fails at a known limit of the physics.
    pub fn holds(&self) -> bool {
        self.pass || self.known_limit.is_some()
    }

    /// Passes when value ≤ limit (a NaN never passes).
    pub fn at_most(name: impl Into<String>, value: f64, limit: f64) -> Self {
        Self {
            name: name.into(),
            value,
            limit,
            relation: "<=",
            pass: value <= limit,
            known_limit: None,
        }
    }

    /// Passes when value ≥ limit (a NaN never passes).
    pub fn at_least(name: impl Into<String>, value: f64, limit: f64) -> Self {
        Self {
            name: name.into(),
            value,
            limit,
            relation: ">=",
            pass: value >= limit,
            known_limit: None,
        }
    }
}

/// One resolution (or variant) of a problem.
#[derive(Clone, Debug, Serialize)]
pub struct Run {
    pub label: String,
    /// The formulation the run used (smoothing length and density method), which names its
    /// series in the work–precision plot; empty where a problem has only one.
    pub formulation: String,
    pub n_particles: usize,
    pub steps: u64,
    pub wall_s: f64,
    /// Characteristic particle spacing, the abscissa of the convergence fit.
    pub spacing: f64,
    pub errors: BTreeMap<String, f64>,
    /// Conservation and positivity figures.
    pub metrics: BTreeMap<String, f64>,
    /// Wall seconds per phase of the steps (neighbours, density, forces, integration).
    pub phase_s: BTreeMap<String, f64>,
    /// The solver's diagnosis if the run stopped early.
    pub failure: Option<String>,
    /// For a sensitivity row, what it varied from the problem's defaults (a parameter chosen
    /// while its check was in view, run halved and doubled); None for the problem's own
    /// runs. Sensitivity rows enter neither the checks, the observed orders nor the
    /// work–precision plot: they show how much a result owes to the choice.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<String>,
    /// What the run's gauges read (blast problems); empty elsewhere.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub gauges: Vec<crate::gauges::Gauge>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Record {
    pub problem: String,
    pub level: Level,
    pub parameters: BTreeMap<String, String>,
    pub overrides: BTreeMap<String, String>,
    pub runs: Vec<Run>,
    pub order: BTreeMap<String, f64>,
    pub checks: Vec<Check>,
    pub pass: bool,
    pub wall_s: f64,
    /// The run a one-line summary shows (the finest resolution, or the thesis' case).
    pub headline_run: usize,
}

impl Run {
    /// Records what the simulation cost: wall seconds since `start`, steps and seconds per
    /// phase; with individual time steps also the particle updates (a global step updates
    /// every particle, so there they are steps × particles).
    pub fn record_work<const D: usize>(
        &mut self,
        sim: &blastsph_solver::Simulation<D>,
        start: std::time::Instant,
    ) {
        self.wall_s = start.elapsed().as_secs_f64();
        self.steps = sim.steps();
        self.phase_s = phase_seconds(&sim.phase_times());
        if sim.config().time_steps != blastsph_solver::TimeSteps::Global {
            self.metrics
                .insert("particle_updates".into(), sim.particle_updates() as f64);
        }
    }

    /// Builds the scene and runs it to `t_end` (progress as a fraction of it), booking the
    /// work; `None`, with the solver's diagnosis in `failure`, where it refused the scene or
    /// stopped early.
    pub fn simulate<const D: usize>(
        &mut self,
        scene: (
            &[blastsph_solver::particles::ParticleInit<D>],
            Vec<blastsph_solver::Material>,
            blastsph_solver::Domain<D>,
            blastsph_solver::SimulationConfig,
        ),
        t_end: f64,
        progress: &(dyn Fn(f64) + Sync),
    ) -> Result<Option<blastsph_solver::Simulation<D>>, crate::VerifyError> {
        let (init, materials, domain, config) = scene;
        let start = std::time::Instant::now();
        let built = blastsph_solver::Simulation::new(init, materials, domain, config);
        let Some(mut sim) = self.started(built)? else {
            return Ok(None);
        };
        let outcome = sim.run_until(t_end, |t| progress(t / t_end));
        self.record_work(&sim, start);
        match outcome {
            Ok(()) => Ok(Some(sim)),
            Err(e) => {
                self.failure = Some(e.to_string());
                Ok(None)
            }
        }
    }

    /// The simulation a scene built, or `None` with the solver's refusal as the run's failure
    /// (a refusal of bad input is returned as the error instead, see
    /// [`crate::VerifyError::from_scene`]).
    pub fn started<const D: usize>(
        &mut self,
        built: Result<blastsph_solver::Simulation<D>, blastsph_solver::SolverError>,
    ) -> Result<Option<blastsph_solver::Simulation<D>>, crate::VerifyError> {
        match built {
            Ok(sim) => Ok(Some(sim)),
            Err(refused) => {
                self.failure = Some(crate::VerifyError::from_scene(refused)?);
                Ok(None)
            }
        }
    }

    /// A run not yet started (no steps, errors or metrics yet).
    pub fn new(
        label: impl Into<String>,
        formulation: impl Into<String>,
        n_particles: usize,
        spacing: f64,
    ) -> Self {
        Self {
            label: label.into(),
            formulation: formulation.into(),
            n_particles,
            steps: 0,
            wall_s: 0.0,
            spacing,
            errors: BTreeMap::new(),
            metrics: BTreeMap::new(),
            phase_s: BTreeMap::new(),
            failure: None,
            sensitivity: None,
            gauges: Vec::new(),
        }
    }
}

/// The books of a run's conserved quantities: taken at the start, closed at the end.
///
/// Momentum changes only by what walls deliver, since pair forces are antisymmetric; what is
/// left is round-off, an error of about ε relative to Σ m (|v| + c) per step, of random sign,
/// which adds up as a random walk: √steps · ε. Energy, with the chemical energy of an
/// explosive counted in e from the start, is conserved to the time integration's error.
#[derive(Clone, Copy, Debug)]
pub struct Conservation<const D: usize> {
    momentum: blastsph_solver::Vector<D>,
    momentum_scale: f64,
    energy: f64,
}

impl<const D: usize> Conservation<D> {
    pub fn open(sim: &blastsph_solver::Simulation<D>) -> Self {
        let p = sim.particles();
        let momentum_scale = (0..p.n_real())
            .map(|i| p.mass[i] * (p.velocity[i].norm() + p.sound_speed[i]))
            .sum();
        Self {
            momentum: p.total_momentum() - sim.wall_impulse(),
            momentum_scale,
            energy: p.total_energy() + sim.transmitted_energy(),
        }
    }

    /// Books into `metrics`: `energy_relative_change`, `momentum_balance_residual` (the change
    /// of momentum less the walls' impulse, over Σ m (|v| + c) at the start) and
    /// `momentum_round_off_bound`, ten times the random walk √steps · ε.
    pub fn close(&self, sim: &blastsph_solver::Simulation<D>, metrics: &mut BTreeMap<String, f64>) {
        let p = sim.particles();
        metrics.insert(
            "energy_relative_change".into(),
            ((p.total_energy() + sim.transmitted_energy() - self.energy) / self.energy).abs(),
        );
        metrics.insert(
            "momentum_balance_residual".into(),
            (p.total_momentum() - sim.wall_impulse() - self.momentum).norm() / self.momentum_scale,
        );
        metrics.insert(
            "momentum_round_off_bound".into(),
            momentum_round_off_bound(sim.steps()),
        );
    }
}

/// Ten times the random walk of per-step round-off, 10 √steps · ε: the limit on a relative
/// momentum residual (see [`Conservation`]).
pub fn momentum_round_off_bound(steps: u64) -> f64 {
    10.0 * (steps as f64).sqrt() * f64::EPSILON
}

/// The two conservation checks of a run booked by [`Conservation::close`]: momentum within its
/// round-off bound, energy within `energy_limit`.
pub fn conservation_checks(run: &Run, energy_limit: f64) -> [Check; 2] {
    let label = run.label.replace(" = ", "_").replace(' ', "_");
    let metric = |key: &str| run.metrics.get(key).copied().unwrap_or(f64::NAN);
    [
        Check::at_most(
            format!("momentum_balance_residual_{label}"),
            metric("momentum_balance_residual"),
            metric("momentum_round_off_bound"),
        ),
        Check::at_most(
            format!("energy_relative_change_{label}"),
            metric("energy_relative_change"),
            energy_limit,
        ),
    ]
}

/// The observed order of each named error over `runs` (least squares in log error against log
/// spacing; errors a run lacks count as missing), for the keys where there are two usable runs.
pub fn observed_orders<'a>(
    runs: impl IntoIterator<Item = &'a Run> + Clone,
    keys: &[&str],
) -> BTreeMap<String, f64> {
    let spacing: Vec<f64> = runs.clone().into_iter().map(|r| r.spacing).collect();
    keys.iter()
        .filter_map(|&key| {
            let errors: Vec<f64> = runs
                .clone()
                .into_iter()
                .map(|r| r.errors.get(key).copied().unwrap_or(f64::NAN))
                .collect();
            crate::norms::observed_order(&spacing, &errors).map(|p| (key.to_string(), p))
        })
        .collect()
}

/// The phase timings of a simulation as a name → seconds map.
pub fn phase_seconds(times: &blastsph_solver::PhaseTimes) -> BTreeMap<String, f64> {
    [
        ("neighbours", times.neighbours),
        ("density", times.density),
        ("forces", times.forces),
        ("integration", times.integration),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

/// The errors that stand for a run's accuracy, the first a run has: the L1 density error (shock
/// tubes, Sedov, the water–air tube), the L1 velocity error over the impact speed (interface
/// problems), the L1 pressure error over p_CJ (detonation), the mean peak-overpressure error
/// of the gated gauges against the scaled-distance relations (blast waves), the mean
/// |ln(peak velocity / relations)| of the ground-shock gauges (factors, as the relations'
/// bands are), the larger reflection coefficient of a transmitting column's two sides, the
/// Taylor bar's footprint radius against the benchmark (its slower-converging measure), the
/// elastic wave's speed.
pub const HEADLINE_ERRORS: [&str; 8] = [
    "l1_rho",
    "l1_u_over_v",
    "l1_p_over_p_cj",
    "mean_peak_overpressure_error",
    "mean_log_peak_velocity_ratio",
    "reflection_coefficient",
    "footprint_radius_relative",
    "wave_speed_relative",
];

impl Run {
    /// The run's headline error and its name (see [`HEADLINE_ERRORS`]), the one the
    /// work–precision figure plots and the summaries show first.
    pub fn headline_error(&self) -> Option<(&'static str, f64)> {
        HEADLINE_ERRORS
            .iter()
            .find_map(|&name| self.errors.get(name).map(|&e| (name, e)))
    }
}

impl Record {
    /// The record of one problem's runs; `problems::run` fills in the parameters, the wall time
    /// and `pass`.
    pub fn new(
        problem: &str,
        level: Level,
        runs: Vec<Run>,
        order: BTreeMap<String, f64>,
        checks: Vec<Check>,
        headline_run: usize,
    ) -> Self {
        Self {
            problem: problem.to_string(),
            level,
            parameters: BTreeMap::new(),
            overrides: BTreeMap::new(),
            runs,
            order,
            checks,
            pass: false,
            wall_s: 0.0,
            headline_run,
        }
    }

    /// Sets `pass` from the checks (a record without checks does not pass; a check at a known
    /// limit of the physics does not fail it).
    pub fn settle(&mut self) {
        self.pass = !self.checks.is_empty() && self.checks.iter().all(Check::holds);
    }

    pub fn headline(&self) -> Option<&Run> {
        self.runs.get(self.headline_run)
    }

    /// The errors a one-line summary shows: the headline run's headline error (see
    /// [`Run::headline_error`]) and then the others by name, three in all.
    pub fn headline_errors(&self) -> impl Iterator<Item = (&String, &f64)> {
        self.headline().into_iter().flat_map(|run| {
            let first = run.headline_error().map(|(name, _)| name);
            let lead = first.and_then(|name| run.errors.get_key_value(name));
            lead.into_iter()
                .chain(
                    run.errors
                        .iter()
                        .filter(move |(k, _)| Some(k.as_str()) != first),
                )
                .take(3)
        })
    }

    pub fn check(&self, name: &str) -> Option<&Check> {
        self.checks.iter().find(|c| c.name == name)
    }
}

/// A table of numbers with named columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    pub fn new(columns: &[&str]) -> Self {
        Self {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.columns.iter().position(|c| c == name)?;
        Some(self.rows.iter().map(|r| r[k]).collect())
    }
}

/// Everything a problem run produces.
#[derive(Clone, Debug)]
pub struct ProblemOutput {
    pub record: Record,
    pub profile: Table,
    pub figure: Figure,
    /// The particles at the end of the finest run, for `--vtk`; None where the problem runs no
    /// simulation.
    pub snapshot: Option<crate::vtk::Snapshot>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A summary leads with the run's headline error, whatever its name sorts as, then the
    /// others by name, three in all; a run without one shows its first three by name.
    #[test]
    fn summaries_lead_with_the_headline_error() {
        let mut run = Run::new("n = 10", "", 10, 0.1);
        for (name, value) in [
            ("arrival", 1.0),
            ("impulse", 2.0),
            ("l1_e", 3.0),
            ("l1_rho", 4.0),
        ] {
            run.errors.insert(name.into(), value);
        }
        let record =
            |run: Run| Record::new("demo", Level::Quick, vec![run], BTreeMap::new(), vec![], 0);
        let names = |record: &Record| -> Vec<String> {
            record.headline_errors().map(|(k, _)| k.clone()).collect()
        };
        assert_eq!(run.headline_error(), Some(("l1_rho", 4.0)));
        assert_eq!(
            names(&record(run.clone())),
            ["l1_rho", "arrival", "impulse"]
        );
        run.errors.remove("l1_rho");
        assert_eq!(run.headline_error(), None);
        assert_eq!(names(&record(run)), ["arrival", "impulse", "l1_e"]);
    }
}
