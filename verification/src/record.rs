//! What a problem run returns: the record (written as JSON), the final profiles (CSV) and a
//! figure (SVG).

use crate::svg::Figure;
use crate::Level;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a check, a record or a gate comes to. Ordered from best to worst, so that the
/// outcome of many is the largest of theirs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Outcome {
    /// Every check within its limit.
    Pass,
    /// Every check within its limit or at a qualified limit of the modelled physics: outside
    /// the limit, inside the qualification's bound, with its evidence met.
    Qualified,
    /// A check outside its limit and not qualified, or qualified outside its bound or without
    /// its evidence.
    Fail,
}

impl Outcome {
    pub fn name(self) -> &'static str {
        match self {
            Self::Pass => "PASS",
            Self::Qualified => "QUALIFIED",
            Self::Fail => "FAIL",
        }
    }

    /// The worst of `outcomes` (PASS where there are none).
    pub fn worst(outcomes: impl IntoIterator<Item = Outcome>) -> Outcome {
        outcomes.into_iter().max().unwrap_or(Outcome::Pass)
    }
}

/// The largest change under refinement, between a quantity's values at the two finest
/// resolutions, that lets a qualification call a gap the model's rather than the numerics':
/// a gap that still moves by more is not yet known to be either.
pub const REFINEMENT_TOLERANCE: f64 = 0.10;

/// The machine-checked evidence that a gap is the model's: the qualified quantity at the two
/// finest resolutions changes by at most `tolerance` (relative).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Refinement {
    /// The quantity at the second finest and at the finest resolution (NaN where the problem
    /// ran one resolution only: then there is no evidence).
    #[serde(deserialize_with = "number_or_nan")]
    pub coarse: f64,
    #[serde(deserialize_with = "number_or_nan")]
    pub fine: f64,
    /// |fine / coarse − 1|.
    #[serde(deserialize_with = "number_or_nan")]
    pub change: f64,
    pub tolerance: f64,
}

impl Refinement {
    /// The evidence of the values at the two finest resolutions, against
    /// [`REFINEMENT_TOLERANCE`].
    pub fn between(coarse: f64, fine: f64) -> Self {
        Self {
            coarse,
            fine,
            change: (fine / coarse - 1.0).abs(),
            tolerance: REFINEMENT_TOLERANCE,
        }
    }

    /// The evidence of a problem's resolutions, ordered coarse to fine: the last two, or none
    /// where there is one.
    pub fn of_resolutions(values: &[f64]) -> Self {
        match values {
            [.., coarse, fine] => Self::between(*coarse, *fine),
            [fine] => Self::between(f64::NAN, *fine),
            [] => Self::between(f64::NAN, f64::NAN),
        }
    }

    /// The change is known and within the tolerance (a NaN is not).
    pub fn holds(&self) -> bool {
        self.change <= self.tolerance
    }
}

/// A limit of the modelled physics that a failed check meets: why the gap is the model's, the
/// bound within which that explanation holds, its effect on the study's answer, and the
/// evidence that refinement does not close it. A check so qualified moves its record to
/// QUALIFIED, not PASS, and only while the measured value lies inside the bound and the
/// evidence holds; otherwise it fails like any other.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Qualification {
    /// What the model lacks or does otherwise, and the physics that explains the gap.
    pub reason: String,
    /// What the bound is on ("arrival / relations") and its measured value.
    pub quantity: String,
    #[serde(deserialize_with = "number_or_nan")]
    pub value: f64,
    /// The range [low, high] of `value` that the reason explains.
    pub bound: [f64; 2],
    /// The direction and size of the gap's effect on the safe depth.
    pub effect: String,
    pub refinement: Refinement,
}

impl Qualification {
    /// The measured value lies inside the bound (a NaN does not).
    pub fn within_bound(&self) -> bool {
        self.bound[0] <= self.value && self.value <= self.bound[1]
    }

    /// Inside the bound with its evidence met.
    pub fn holds(&self) -> bool {
        self.within_bound() && self.refinement.holds()
    }

    /// Why the qualification does not hold, where it does not.
    pub fn failure(&self) -> Option<&'static str> {
        if !self.within_bound() {
            Some("outside the qualification's bound")
        } else if self.refinement.coarse.is_nan() {
            Some("no evidence: one resolution only")
        } else if !self.refinement.holds() {
            Some("not settled: it changes under refinement by more than the tolerance")
        } else {
            None
        }
    }

    /// The qualification in one paragraph: the quantity against its bound, the evidence, the
    /// effect and the reason, and why it does not hold where it does not.
    pub fn describe(&self) -> String {
        let r = &self.refinement;
        let verdict = self
            .failure()
            .map_or(String::new(), |why| format!(" NOT QUALIFIED: {why}."));
        format!(
            "{} = {:.3} (bound {:.3}–{:.3}); refined {:.3} → {:.3}, change {:.1} % \
             (tolerance {:.0} %); effect: {}. {}.{verdict}",
            self.quantity,
            self.value,
            self.bound[0],
            self.bound[1],
            r.coarse,
            r.fine,
            100.0 * r.change,
            100.0 * r.tolerance,
            self.effect,
            self.reason,
        )
    }
}

/// A number as JSON writes it, `null` for a NaN (serde's `deserialize_with`).
pub(crate) fn number_or_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// One check: a value against a limit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Check {
    pub name: String,
    #[serde(deserialize_with = "number_or_nan")]
    pub value: f64,
    #[serde(deserialize_with = "number_or_nan")]
    pub limit: f64,
    /// "<=" or ">=": how value must relate to limit.
    pub relation: String,
    pub pass: bool,
    /// A limit of the physics the problem models (see [`Qualification`]): shown like any
    /// other check; its failure qualifies the record instead of failing it while the
    /// qualification holds.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub qualification: Option<Qualification>,
}

impl Check {
    /// Qualifies the check with a limit of the modelled physics (see [`Qualification`]).
    pub fn qualified(self, qualification: Qualification) -> Self {
        Self {
            qualification: Some(qualification),
            ..self
        }
    }

    /// PASS within the limit; QUALIFIED outside it where a qualification holds; else FAIL.
    pub fn outcome(&self) -> Outcome {
        match (&self.qualification, self.pass) {
            (_, true) => Outcome::Pass,
            (Some(q), false) if q.holds() => Outcome::Qualified,
            _ => Outcome::Fail,
        }
    }

    /// Passes, or fails at a qualified limit of the physics.
    pub fn holds(&self) -> bool {
        self.outcome() != Outcome::Fail
    }

    /// Passes when value ≤ limit (a NaN never passes).
    pub fn at_most(name: impl Into<String>, value: f64, limit: f64) -> Self {
        Self {
            name: name.into(),
            value,
            limit,
            relation: "<=".into(),
            pass: value <= limit,
            qualification: None,
        }
    }

    /// Passes when value ≥ limit (a NaN never passes).
    pub fn at_least(name: impl Into<String>, value: f64, limit: f64) -> Self {
        Self {
            name: name.into(),
            value,
            limit,
            relation: ">=".into(),
            pass: value >= limit,
            qualification: None,
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
    /// The worst of the checks' outcomes (FAIL without checks).
    pub outcome: Outcome,
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
    /// and the outcome.
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
            outcome: Outcome::Fail,
            wall_s: 0.0,
            headline_run,
        }
    }

    /// Sets the outcome from the checks (a record without checks fails).
    pub fn settle(&mut self) {
        self.outcome = if self.checks.is_empty() {
            Outcome::Fail
        } else {
            Outcome::worst(self.checks.iter().map(Check::outcome))
        };
    }

    /// Not FAIL: every check passed or is qualified.
    pub fn holds(&self) -> bool {
        self.outcome != Outcome::Fail
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

    fn qualified(value: f64, refinement: Refinement) -> Check {
        Check::at_most("arrival_error", 0.5, 0.3).qualified(Qualification {
            reason: "a stiffer sand".into(),
            quantity: "arrival / relations".into(),
            value,
            bound: [0.3, 1.0],
            effect: "none".into(),
            refinement,
        })
    }

    /// A failed check is QUALIFIED only inside its bound and with its evidence: the quantity
    /// at the two finest resolutions within the tolerance. Outside the bound, at one
    /// resolution, or still moving under refinement, it is a FAIL; a passing check is a PASS
    /// whatever it carries.
    #[test]
    fn a_qualification_holds_only_inside_its_bound_with_its_evidence() {
        let settled = Refinement::between(0.52, 0.5);
        assert!((settled.change - 0.02 / 0.52).abs() < 1e-15);
        assert_eq!(
            qualified(0.5, settled.clone()).outcome(),
            Outcome::Qualified
        );
        // at the bound's edges, and just outside them
        assert_eq!(
            qualified(0.3, settled.clone()).outcome(),
            Outcome::Qualified
        );
        assert_eq!(
            qualified(1.0, settled.clone()).outcome(),
            Outcome::Qualified
        );
        assert_eq!(qualified(0.299, settled.clone()).outcome(), Outcome::Fail);
        assert_eq!(qualified(1.001, settled.clone()).outcome(), Outcome::Fail);
        assert_eq!(
            qualified(f64::NAN, settled.clone()).outcome(),
            Outcome::Fail
        );
        // the evidence: one resolution, or a change of more than the tolerance
        let single = Refinement::of_resolutions(&[0.5]);
        assert_eq!(qualified(0.5, single.clone()).outcome(), Outcome::Fail);
        assert_eq!(
            qualified(0.5, single).qualification.unwrap().failure(),
            Some("no evidence: one resolution only")
        );
        let moving = Refinement::of_resolutions(&[0.3, 0.4, 0.5]);
        assert!((moving.change - 0.25).abs() < 1e-15, "{moving:?}");
        assert_eq!(qualified(0.5, moving).outcome(), Outcome::Fail);
        let at_tolerance = Refinement::between(1.0, 1.0 + REFINEMENT_TOLERANCE);
        assert!(at_tolerance.holds() == (at_tolerance.change <= REFINEMENT_TOLERANCE));
        // a check within its limit passes
        let mut passing = qualified(0.5, Refinement::of_resolutions(&[]));
        passing.pass = true;
        assert_eq!(passing.outcome(), Outcome::Pass);
        assert_eq!(Check::at_most("plain", 2.0, 1.0).outcome(), Outcome::Fail);
    }

    /// A record is the worst of its checks; without checks it fails.
    #[test]
    fn a_record_is_the_worst_of_its_checks() {
        let settle = |checks: Vec<Check>| {
            let mut record = Record::new("demo", Level::Quick, vec![], BTreeMap::new(), checks, 0);
            record.settle();
            record.outcome
        };
        let pass = || Check::at_most("fine", 0.0, 1.0);
        let settled = || qualified(0.5, Refinement::between(0.5, 0.5));
        assert_eq!(settle(vec![]), Outcome::Fail);
        assert_eq!(settle(vec![pass()]), Outcome::Pass);
        assert_eq!(settle(vec![pass(), settled()]), Outcome::Qualified);
        assert_eq!(
            settle(vec![settled(), Check::at_most("bad", 2.0, 1.0)]),
            Outcome::Fail
        );
        assert_eq!(Outcome::worst([]), Outcome::Pass);
    }

    /// A check comes back from JSON as it went, a NaN value (null) included.
    #[test]
    fn checks_round_trip_through_json() {
        let check = qualified(0.5, Refinement::of_resolutions(&[0.5]));
        let text = serde_json::to_string(&check).unwrap();
        let back: Check = serde_json::from_str(&text).unwrap();
        assert_eq!(back.name, check.name);
        assert!(back
            .qualification
            .as_ref()
            .unwrap()
            .refinement
            .coarse
            .is_nan());
        assert_eq!(back.outcome(), Outcome::Fail);
        let nan = Check::at_most("nan", f64::NAN, 1.0);
        let back: Check = serde_json::from_str(&serde_json::to_string(&nan).unwrap()).unwrap();
        assert!(back.value.is_nan() && !back.pass);
    }
}
