//! `ground-shock-spherical`: a fully buried TNT sphere in dry sand against the free-field
//! ground-shock relations (Drake 1983 / TM 5-855-1 / ConWep, [`crate::scaled::ground_shock`])
//! for dry sand with coupling factor f = 1.
//!
//! Set-up: W kg of TNT (JWL, LLNL set, lit at its centre and burnt at D_CJ) as a sphere of
//! radius R_c = (3W/(4πρ_TNT))^{1/3} inside the library's `dry-sand` (Laine & Sandvik 2001
//! compaction EOS: the plastic compaction path of their Table 1, elastic unloading at the
//! tabulated bulk sound speed c(ρ), no tension), 1D spherical shells with continuity density
//! and h floored at its start (the sand beside the growing cavity is stretched in the hoop
//! directions and thinned radially: without the floor its h, and with it the time step,
//! collapse), and XSPH's drift (ε = 0.5, Monaghan 1989, J. Comput. Phys. 82, 1) against
//! shells passing through one another where the unloaded sand carries no pressure. The
//! charge holds n shells of width R_c/n; the sand's shells are
//! max(R_c/n, g·r/n) wide (the pulse lengthens with range) out to twice the last gauge, an
//! open edge whose reflection cannot reach the last gauge within the run (it travels out and
//! back through unloaded sand at ≤ 400 m/s, see [`OUTER_OVER_LAST_GAUGE`]).
//!
//! Two variants of the sand:
//! - `drucker-prager`: with shear strength, Drucker–Prager on the Mohr–Coulomb compression
//!   meridian with the cohesion c and friction angle φ of the parameters (defaults: a dry sand
//!   has no cohesion, c = 0; φ = 30°, the lower end of the 30–45° that handbooks give for
//!   sands, e.g. Look 2007, *Handbook of Geotechnical Investigation and Design Tables*, table
//!   of non-cohesive soils: loose sand 30–35°; the DEM calibration of this project
//!   (`biaxial`) is 2D disks, whose 18° is a property of disks, not of sand). The shear
//!   modulus G = 3K(1 − 2ν)/(2(1 + ν)) from the bulk modulus of the unloaded sand,
//!   K = ρ0 c(ρ0)², and Poisson's ratio ν = 0.22 (the value of the Sjöbo-sand input example
//!   of Altair Radioss' granular law /MAT/LAW133). G is constant: the Sjöbo data give G(ρ)
//!   only as a figure (Laine & Sandvik 2001 Fig. 7, not verified here);
//! - `no-shear`: the sand as a fluid, the classic hydrocode set-up, reported beside it and not
//!   gated. Laine & Larsen (2012) found that the compaction EOS alone attenuates the ground
//!   shock far too little beyond about 1 m/kg^{1/3}; the record shows whether this one does.
//!
//! Gauges at fixed ranges read the compressive radial stress −σ_rr and the radial velocity
//! after every step. Checked, for the `drucker-prager` variant at the finest resolution,
//! against the relations for dry sand and backfill (ρ = 1630 kg/m³, c = 305 m/s, n = 2.75,
//! the TM 5-855-1 soil whose density is nearest Sjöbo sand's 1674 kg/m³): arrival within 30 %
//! and peak stress and velocity within a factor 3. The relations are single power laws fitted
//! to scattered field data for design estimates, one per soil class; a factor 3 is the band
//! this project asks of a hydrocode against them (no published comparison that quantifies
//! the usual band was found among the sources held here; the record gives every ratio, so a
//! reader can apply a tighter one). The attenuation exponent n fitted to the peak velocities
//! beyond the first gauge is recorded for both variants beside the relations'.

use super::airblast::{
    charge_in_shells, charge_radius, health_checks, relative_error, shell_edges, viscosity,
    viscosity_switched_down_to,
};
use crate::gauges::{history_table, GaugeTrace};
use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{
    Check, Conservation, ProblemOutput, Qualification, Record, Refinement, Run, Table,
};
use crate::scaled::arrivals::fastest_shock_speed;
use crate::scaled::explosives::explosive;
use crate::scaled::ground_shock::{ground_shock, soil, GroundShock, Soil};
use crate::scene::current_index;
use crate::svg::{Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::{Level, VerifyError};
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Domain, EnergyEquation, Formulation, KernelShape, Material, ShellDensity,
    Simulation, SimulationConfig, SmoothingLength, Strength,
};

pub const SPHERICAL: &str = "ground-shock-spherical";

/// The TM 5-855-1 soils this problem can simulate, each with the library material that models
/// it: dry sand and backfill (ρ = 1630 kg/m³) by Sjöbo sand (1674 kg/m³), the table's soil
/// nearest it in density and description.
pub const MODELLED_SOILS: [(&str, &str); 1] = [("dry-sand-backfill", "dry-sand")];

/// The library material that models the TM 5-855-1 soil `name`.
pub fn soil_model(name: &str) -> Result<&'static str, VerifyError> {
    MODELLED_SOILS
        .iter()
        .find(|(soil, _)| *soil == name)
        .map(|(_, material)| *material)
        .ok_or_else(|| {
            let names: Vec<&str> = MODELLED_SOILS.iter().map(|(soil, _)| *soil).collect();
            VerifyError::bad_value(
                "soil",
                name,
                &format!("one with a material model: {}", names.join(", ")),
            )
        })
}
/// A fully buried charge: the relations' coupling factor.
const COUPLING: f64 = 1.0;
/// Limits against the relations: arrival within 30 %, peaks within a factor 3 (see the
/// module's comment).
const ARRIVAL_LIMIT: f64 = 0.30;
const PEAK_FACTOR_LIMIT: f64 = 3.0;
/// The open outer edge, in units of the last gauge's range: the loading wave reaches it at
/// 2r/c0 and its reflection comes back to the last gauge at 3r/c, later than the run's end
/// (1.5 r/c_ref, [`END_MARGIN`]) while the sand carries it slower than 2 c_ref ≈ 610 m/s; the
/// unloaded sand's sound speed is 265 m/s and its P-wave speed with shear 367 m/s.
const OUTER_OVER_LAST_GAUGE: f64 = 2.0;
/// The run ends at this multiple of the relations' arrival at the last gauge: their rise time
/// is a tenth of the arrival, so the peak has passed even with an arrival 30 % late.
const END_MARGIN: f64 = 1.5;
/// From this scaled range (m/kg^{1/3}, TNT) out, a peak above the relations is the known
/// shortfall of the compaction EOS's attenuation (Laine & Larsen 2012, see the module's
/// comment).
const FAR_FIELD_SCALED_RANGE: f64 = 1.0;
/// The largest far-field peak over the relations that the known shortfall of attenuation is
/// taken to explain: twice the band. Beyond a decade of range, exponents that differ by 0.3
/// (the spread of TM 5-855-1's sands, 2.5–3.1) give a factor 10^0.3 = 2, so a peak more than
/// twice the band above the relations needs another explanation than this soil's class.
const FAR_PEAK_QUALIFIED_FACTOR: f64 = 2.0 * PEAK_FACTOR_LIMIT;
/// Poisson's ratio of the sand (see the module's comment).
pub const POISSON: f64 = 0.22;

/// The sand's two models.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Sand {
    DruckerPrager,
    NoShear,
}

impl Sand {
    fn name(self) -> &'static str {
        match self {
            Sand::DruckerPrager => "drucker-prager",
            Sand::NoShear => "no-shear",
        }
    }
}

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: SPHERICAL,
        summary: "buried TNT sphere in dry sand (1D spherical; Drucker-Prager and no-shear sand) against the TM 5-855-1 ground-shock relations",
        params: vec![
            ParamSpec::new("charge", 125.0, "TNT mass W (kg)"),
            ParamSpec::new("gauges", "2,5,10,25,40", "gauge ranges from the charge's centre (m)"),
            ParamSpec::new(
                "soil",
                MODELLED_SOILS[0].0,
                "the TM 5-855-1 soil (the library material that models it is simulated)",
            ),
            ParamSpec::per_level(
                "variants",
                "drucker-prager",
                "drucker-prager,no-shear",
                "the sand's models: drucker-prager (gated), no-shear (reported)",
            ),
            ParamSpec::per_level(
                "n",
                "5,10",
                "5,10,20",
                "shells across the charge radius (one run each)",
            ),
            ParamSpec::new(
                "grading",
                0.1,
                "far from the charge the sand's shells are grading·r/n wide",
            ),
            ParamSpec::new("cohesion", 0.0, "the sand's cohesion c (Pa)"),
            ParamSpec::new("friction_angle", 30.0, "the sand's friction angle φ (degrees)"),
            ParamSpec::new("ramp", 2.0, "burn ramp width (smoothing lengths)"),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            ParamSpec::new(
                "alpha_min",
                0.1,
                "Morris-Monaghan switch: the viscosity's alpha away from shocks (1: off)",
            ),
            ParamSpec::new("eta", 2.0, "smoothing length h = η·(shell width)"),
            // Monaghan's (1989) ε against particle penetration. Measured at 500 kg, gauges
            // 10/15/20 m, n = 10 → 20: sand shells crossed 7 → 14 without it, 4 → 8 with it;
            // the 20 m peak 1.750e5 → 1.999e5 Pa without, 1.846e5 → 1.992e5 with (the finer
            // run hardly moves, the coarser comes towards it); ε = 0.25: 1.748e5 → 1.962e5;
            // ε = 1 runs the crushed sand apart (88 crossed at n = 10, collapse at n = 20)
            ParamSpec::new(
                "xsph",
                0.5,
                "XSPH ε: shells drift with a share of their neighbours' mean motion",
            ),
            // individual steps: the sand far out steps up to 64 times longer than the crushed
            // sand by the charge, which sets the global step; at n = 10 a third fewer seconds
            // and a sixth of the particle updates, the gauges' peaks within 1 % of global
            // steps' (halving the global Courant number moves them 4 %)
            ParamSpec::step_ratio(64),
        ],
    }
}

#[derive(Clone)]
struct Settings {
    charge_kg: f64,
    gauges_m: Vec<f64>,
    grading: f64,
    ramp: f64,
    cohesion: f64,
    friction_angle: f64,
    detonation_speed: f64,
    reference_soil: &'static Soil,
    /// The library material that models it.
    soil_material: &'static str,
    config: SimulationConfig,
}

fn settings(params: &Params) -> Result<Settings, VerifyError> {
    let library = Library::standard();
    let eta = params.number("eta", 0.5, 4.0)?;
    let charge_kg = params.number("charge", 1e-3, 1e6)?;
    let mut gauges_m = params.numbers("gauges", 1e-3, 1e3)?;
    gauges_m.sort_by(f64::total_cmp);
    let detonation_speed = library.value("tnt", "d_cj")?;
    let radius = charge_radius(charge_kg, library.value("tnt", "rho0")?);
    Ok(Settings {
        charge_kg,
        gauges_m,
        grading: params.number("grading", 0.01, 1.0)?,
        ramp: params.number("ramp", 0.1, 10.0)?,
        cohesion: params.number("cohesion", 0.0, 1e9)?,
        friction_angle: params.number("friction_angle", 0.0, 59.0)?,
        detonation_speed,
        reference_soil: soil(&params.text("soil"))?,
        soil_material: soil_model(&params.text("soil"))?,
        config: SimulationConfig {
            time_steps: params.time_steps()?,
            formulation: Formulation::Spherical(ShellDensity::Continuity(
                SmoothingLength::FollowDensityFloored { eta },
            )),
            kernel: KernelShape::CubicSpline,
            viscosity: viscosity(params)?,
            energy: EnergyEquation::OwnPressure,
            cfl: params.cfl()?,
            min_time_step: 1e-9 * radius / detonation_speed,
            xsph: params.number("xsph", 0.0, 1.0)?,
            ..SimulationConfig::default()
        },
    })
}

/// The soil's library material, with Drucker–Prager strength or without.
fn sand(s: &Settings, model: Sand) -> Result<Material, VerifyError> {
    soil_material(
        s.soil_material,
        (model == Sand::DruckerPrager).then_some((s.cohesion, s.friction_angle)),
    )
}

/// The library material `name`, as a fluid or, given its cohesion c (Pa) and friction angle φ
/// (degrees), with Drucker–Prager strength whose shear modulus comes from the unloaded bulk
/// modulus and Poisson's ratio [`POISSON`]: G = 3K(1 − 2ν)/(2(1 + ν)), K = ρ0 c(ρ0)².
pub(super) fn soil_material(
    name: &str,
    drucker_prager: Option<(f64, f64)>,
) -> Result<Material, VerifyError> {
    let library = Library::standard();
    let soil = library.material(name)?;
    let Some((cohesion, friction_angle)) = drucker_prager else {
        return Ok(soil);
    };
    let rho0 = library.value(name, "rho0")?;
    let c0 = soil.eos.sound_speed(rho0, 0.0);
    let bulk = rho0 * c0 * c0;
    let shear = 3.0 * bulk * (1.0 - 2.0 * POISSON) / (2.0 * (1.0 + POISSON));
    let strength = Strength::drucker_prager(shear, cohesion, friction_angle, 0.0)?;
    Ok(soil.with_strength(strength))
}

/// Refuses gauges the relations do not cover (nearer than their scaled range) or that lie in
/// the charge, naming the gauge and the allowed range.
pub fn check_gauges(params: &Params) -> Result<(), VerifyError> {
    let s = settings(params)?;
    let radius = charge_radius(s.charge_kg, Library::standard().value("tnt", "rho0")?);
    for &r in &s.gauges_m {
        if r <= 2.0 * radius {
            return Err(VerifyError::bad_value(
                "gauge range (m)",
                r,
                &format!("beyond twice the charge radius, > {:.3} m", 2.0 * radius),
            ));
        }
        reference(&s, r)?;
    }
    Ok(())
}

/// The speed of a small compression from rest: √((K + 4G/3)/ρ0), with K = ρ0 c0² and G the
/// shear modulus of a solid (0 for a fluid).
pub(super) fn p_wave_speed(material: &Material, rho0: f64) -> f64 {
    let c0 = material.eos.sound_speed(rho0, 0.0);
    let shear = material
        .strength
        .as_ref()
        .map_or(0.0, |st| st.shear_modulus);
    (c0 * c0 + 4.0 * shear / (3.0 * rho0)).sqrt()
}

/// The relations' peaks and arrival at `range_m`.
fn reference(s: &Settings, range_m: f64) -> Result<GroundShock, VerifyError> {
    ground_shock(
        s.reference_soil,
        explosive("tnt")?,
        s.charge_kg,
        range_m,
        COUPLING,
    )
}

struct Measured {
    run: Run,
    traces: Vec<GaugeTrace>,
    snapshot: Option<Snapshot>,
}

fn run_one(
    s: &Settings,
    model: Sand,
    n: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let library = Library::standard();
    let rho_sand = library.value(s.soil_material, "rho0")?;
    let radius = charge_radius(s.charge_kg, library.value("tnt", "rho0")?);
    let last_gauge = *s.gauges_m.last().expect("at least one gauge");
    let edges = shell_edges(radius, n, s.grading, OUTER_OVER_LAST_GAUGE * last_gauge);
    let eta = s.config.formulation.eta().unwrap_or(2.0);
    let (init, burn) = charge_in_shells(
        &edges,
        n,
        eta,
        library.ambient_state("tnt")?,
        library.ambient_state(s.soil_material)?,
        s.detonation_speed,
        s.ramp,
    )?;
    let materials = vec![library.material("tnt")?, sand(s, model)?];
    let t_end = END_MARGIN * reference(s, last_gauge)?.arrival_s;
    let mut run = Run::new(
        format!("{} n = {n}", model.name()),
        "",
        init.len(),
        radius / n as f64,
    );
    let mut traces: Vec<GaugeTrace> = s
        .gauges_m
        .iter()
        .map(|&r| GaugeTrace::new(format!("r = {r} m"), r))
        .collect();
    let start = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<1>::with_programmed_burn(
        &init,
        materials,
        Domain::open(),
        s.config,
        burn,
    ))?
    else {
        return Ok(Measured {
            run,
            traces,
            snapshot: None,
        });
    };
    let books = Conservation::open(&sim);
    let attached: Vec<MaterialGauge> = s
        .gauges_m
        .iter()
        .map(|&r| MaterialGauge::at(&init, r))
        .collect();
    let read = |sim: &Simulation<1>, traces: &mut [GaugeTrace]| {
        let index = shell_index(sim);
        for (trace, gauge) in traces.iter_mut().zip(&attached) {
            let (stress, velocity) = gauge.read(sim, &index);
            trace.push(sim.time(), stress, velocity);
        }
    };
    read(&sim, &mut traces);
    let mut outcome = Ok(());
    while sim.time() < t_end {
        outcome = sim.step_toward(t_end);
        if outcome.is_err() {
            break;
        }
        read(&sim, &mut traces);
        progress(sim.time() / t_end);
    }
    run.record_work(&sim, start);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
    } else {
        books.close(&sim, &mut run.metrics);
    }
    for (name, material) in [("products", 0), ("sand", 1)] {
        run.metrics.insert(
            format!("crossed_shells_{name}"),
            crossed_shells(&sim, material) as f64,
        );
    }
    let mut peak_velocities = Vec::new();
    for trace in &traces {
        let gauge = trace.summary();
        run.metrics.insert(
            format!("peak_stress_time_over_arrival_r{}", trace.position_m),
            peak_time(trace) / gauge.arrival_s,
        );
        let relation = reference(s, trace.position_m)?;
        let r = trace.position_m;
        for (q, value, reference) in [
            (
                "peak_stress",
                gauge.peak_pressure_pa,
                relation.peak_stress_pa,
            ),
            (
                "peak_velocity",
                gauge.peak_velocity_m_s,
                relation.peak_velocity_m_s,
            ),
            ("arrival", gauge.arrival_s, relation.arrival_s),
        ] {
            run.errors
                .insert(format!("{q}_error_r{r}"), relative_error(value, reference));
            run.metrics
                .insert(format!("{q}_over_relations_r{r}"), value / reference);
        }
        peak_velocities.push((r, gauge.peak_velocity_m_s));
        run.gauges.push(gauge);
    }
    let log_ratios: Vec<f64> = peak_velocities
        .iter()
        .map(|&(r, u)| {
            (u / reference(s, r).map_or(f64::NAN, |g| g.peak_velocity_m_s))
                .ln()
                .abs()
        })
        .collect();
    run.errors.insert(
        "mean_log_peak_velocity_ratio".into(),
        log_ratios.iter().sum::<f64>() / log_ratios.len() as f64,
    );
    let arrivals: Vec<(f64, f64)> = run
        .gauges
        .iter()
        .map(|g| (g.position_m, g.arrival_s))
        .collect();
    if let [.., (r0, t0), (r1, t1)] = arrivals.as_slice() {
        run.metrics
            .insert("front_speed_far_m_s".into(), (r1 - r0) / (t1 - t0));
    }
    run.metrics.insert(
        "p_wave_speed_m_s".into(),
        p_wave_speed(&sand(s, model)?, rho_sand),
    );
    run.metrics.insert(
        "attenuation_exponent_fitted".into(),
        attenuation_exponent(&peak_velocities[1..]),
    );
    run.metrics.insert(
        "attenuation_exponent_relations".into(),
        s.reference_soil.attenuation,
    );
    run.metrics.insert("charge_radius_m".into(), radius);
    run.metrics.insert("t_end_s".into(), t_end);
    Ok(Measured {
        run,
        traces,
        snapshot: Some(Snapshot::of(&sim)),
    })
}

/// A gauge buried in the sand: it moves with the sand at its range, as a gauge placed in the
/// ground does. It reads the two shells that straddled its range at the start, weighted by
/// where it lay between their centres.
struct MaterialGauge {
    shells: (usize, usize),
    weight: f64,
}

impl MaterialGauge {
    fn at(init: &[ParticleInit<1>], range_m: f64) -> Self {
        let last = init.len() - 1;
        let outer = init
            .iter()
            .position(|q| q.position[0] >= range_m)
            .unwrap_or(last)
            .max(1);
        let (a, b) = (init[outer - 1].position[0], init[outer].position[0]);
        Self {
            shells: (outer - 1, outer),
            weight: ((range_m - a) / (b - a)).clamp(0.0, 1.0),
        }
    }

    /// The compressive radial stress −σ_rr = p − s_rr and the radial velocity.
    fn read(&self, sim: &Simulation<1>, index: &[usize]) -> (f64, f64) {
        let p = sim.particles();
        let stress = |i: usize| match p.deviatoric_stress.get(i) {
            Some(s) => p.pressure[i] - s[(0, 0)],
            None => p.pressure[i],
        };
        let (i, j) = (index[self.shells.0], index[self.shells.1]);
        let w = self.weight;
        (
            (1.0 - w) * stress(i) + w * stress(j),
            (1.0 - w) * p.velocity[i][0] + w * p.velocity[j][0],
        )
    }
}

/// Where each shell, by its id, is stored now (a radial run has no outflow side: every shell
/// stays).
fn shell_index(sim: &Simulation<1>) -> Vec<usize> {
    current_index(sim)
        .into_iter()
        .map(|i| i.expect("a radial run keeps every shell"))
        .collect()
}

/// How many shells of `material` lie inside the shell created next inside them: in a 1D
/// Lagrangian flow mass shells keep their order, so every crossing is a breakdown of the
/// discretisation.
fn crossed_shells(sim: &Simulation<1>, material: usize) -> usize {
    let p = sim.particles();
    let index = shell_index(sim);
    index
        .windows(2)
        .filter(|pair| {
            let (inner, outer) = (pair[0], pair[1]);
            p.material_of(inner) == material
                && p.material_of(outer) == material
                && p.position[outer][0] < p.position[inner][0]
        })
        .count()
}

/// When a gauge's stress is largest (s).
fn peak_time(trace: &GaugeTrace) -> f64 {
    trace
        .overpressure
        .iter()
        .zip(&trace.time)
        .fold((f64::NEG_INFINITY, f64::NAN), |best, (&p, &t)| {
            if p > best.0 {
                (p, t)
            } else {
                best
            }
        })
        .1
}

/// The exponent n of u ∝ r^(−n) fitted by least squares to (r, u) in logs (NaN with fewer
/// than two points or a non-positive value).
fn attenuation_exponent(points: &[(f64, f64)]) -> f64 {
    if points.len() < 2
        || points
            .iter()
            .any(|&(r, u)| r <= 0.0 || u.is_nan() || u <= 0.0)
    {
        return f64::NAN;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(r, u)| (r.ln(), u.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / k, b + y / k));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    -sxy / sxx
}

pub fn run(
    params: &Params,
    level: Level,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let s = settings(params)?;
    let variants = params.choices(
        "variants",
        &[Sand::DruckerPrager, Sand::NoShear],
        Sand::name,
    )?;
    let resolutions = params.integers("n", 4, 10_000)?;
    let parts = (variants.len() * resolutions.len()) as f64;
    let mut measured: Vec<(Sand, usize, Measured)> = Vec::new();
    for &model in &variants {
        for &n in &resolutions {
            let done = measured.len() as f64;
            let m = run_one(&s, model, n, &|f| progress((done + f) / parts))?;
            measured.push((model, n, m));
        }
    }
    let n_fine = *resolutions.iter().max().expect("at least one resolution");
    let mut checks: Vec<Check> = measured
        .iter()
        .flat_map(|(_, _, m)| health_checks(&m.run))
        .collect();
    let gated = measured
        .iter()
        .position(|(model, n, _)| *model == Sand::DruckerPrager && *n == n_fine);
    if let Some(k) = gated {
        let run = &measured[k].2.run;
        let metric = |key: String| run.metrics.get(&key).copied().unwrap_or(f64::NAN);
        // the same quantity in every drucker-prager run, coarsest first
        let by_resolution = |key: &str| -> Vec<f64> {
            let mut rows: Vec<(usize, f64)> = measured
                .iter()
                .filter(|(model, _, _)| *model == Sand::DruckerPrager)
                .map(|(_, n, m)| (*n, m.run.metrics.get(key).copied().unwrap_or(f64::NAN)))
                .collect();
            rows.sort_by_key(|row| row.0);
            rows.into_iter().map(|row| row.1).collect()
        };
        let exponents: Vec<String> = measured
            .iter()
            .filter(|(_, n, _)| *n == n_fine)
            .map(|(model, _, m)| {
                format!(
                    "{:.2} ({})",
                    m.run.metrics["attenuation_exponent_fitted"],
                    model.name()
                )
            })
            .collect();
        let library = Library::standard();
        let fastest_shock = fastest_shock_speed(&library, s.soil_material)?;
        let c_ref = s.reference_soil.wave_speed_m_s;
        let scale = s.charge_kg.cbrt();
        for &r in &s.gauges_m {
            let key = format!("arrival_over_relations_r{r}");
            let ratio = metric(key.clone());
            let check = Check::at_most(
                format!("arrival_error_r{r}_n_{n_fine}"),
                (ratio - 1.0).abs(),
                ARRIVAL_LIMIT,
            );
            checks.push(if !check.pass && ratio < 1.0 {
                check.qualified(Qualification {
                    reason: format!(
                        "the relations' arrival is r/c with the seismic c = {c_ref} m/s; the \
                         model sand carries its front{}, near its P-wave speed \
                         √((K + 4G/3)/ρ0) = {:.0} m/s, and faster near the charge, where its \
                         Hugoniot (Laine & Sandvik 2001 Table 1) runs shocks at up to \
                         {fastest_shock:.0} m/s; no front can come earlier than at that speed",
                        match metric("front_speed_far_m_s".into()) {
                            speed if speed.is_finite() => {
                                format!(" at {speed:.0} m/s between the last two gauges")
                            }
                            _ => String::new(),
                        },
                        metric("p_wave_speed_m_s".into()),
                    ),
                    quantity: format!("arrival / relations at {r} m"),
                    value: ratio,
                    bound: [c_ref / fastest_shock, 1.0],
                    effect: "none on the safe depth, which rests on peaks, not times; the \
                             study's free field is the surface burst's, gated on its own"
                        .into(),
                    refinement: Refinement::of_resolutions(&by_resolution(&key)),
                })
            } else {
                check
            });
            for q in ["peak_stress", "peak_velocity"] {
                let key = format!("{q}_over_relations_r{r}");
                let ratio = metric(key.clone());
                let check = Check::at_most(
                    format!("{q}_factor_from_relations_r{r}_n_{n_fine}"),
                    ratio.max(1.0 / ratio),
                    PEAK_FACTOR_LIMIT,
                );
                let far = r / scale >= FAR_FIELD_SCALED_RANGE;
                checks.push(if !check.pass && ratio > 1.0 && far {
                    check.qualified(Qualification {
                        reason: format!(
                            "the model attenuates too little, fitted exponent {} against the \
                             relations' {}; the compaction EOS unloads at nearly its loading \
                             slope at low stress, so the far field loses little to \
                             hysteresis, as Laine & Larsen (2012) found for this EOS beyond \
                             about 1 m/kg^(1/3) (their pressure-dependent unloading, which the \
                             library lacks, lowered the peak by 65–74 % at 5–8 m/kg^(1/3))",
                            exponents.join(", "),
                            s.reference_soil.attenuation,
                        ),
                        quantity: format!("{q} / relations at {r} m"),
                        value: ratio,
                        bound: [1.0, FAR_PEAK_QUALIFIED_FACTOR],
                        effect: "this buried charge is not the study's configuration; the \
                                 same EOS in the study's free field makes its deeper peaks too \
                                 high, which errs towards a deeper (conservative) safe depth"
                            .into(),
                        refinement: Refinement::of_resolutions(&by_resolution(&key)),
                    })
                } else {
                    check
                });
            }
        }
        let deepest = s.gauges_m.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let deepest_peak = Refinement::of_resolutions(&by_resolution(&format!(
            "peak_stress_over_relations_r{deepest}"
        )));
        for (model, n, m) in &measured {
            checks.push(shell_order_check(
                &s,
                model.name(),
                *n,
                &m.run,
                &deepest_peak,
            ));
        }
    } else {
        for (model, n, m) in &measured {
            let none = Refinement::of_resolutions(&[]);
            checks.push(shell_order_check(&s, model.name(), *n, &m.run, &none));
        }
    }
    let headline = gated.unwrap_or(measured.len() - 1);
    let mut runs: Vec<Run> = measured.iter().map(|(_, _, m)| m.run.clone()).collect();
    if level == Level::Full && variants.contains(&Sand::DruckerPrager) {
        runs.extend(sensitivity(&s, params, &resolutions)?);
    }
    let (profile, figure) = outputs(&s, &measured, n_fine)?;
    Ok(ProblemOutput {
        record: Record::new(SPHERICAL, level, runs, Default::default(), checks, headline),
        profile,
        figure,
        snapshot: measured[headline].2.snapshot.clone(),
    })
}

/// The gated variant at the coarsest resolution with the viscosity's floor α_min and XSPH's ε
/// each halved and doubled. Both were chosen with the gauges in view, and the far field
/// depends on them: away from the shock the switch holds α at α_min, and the pulse travels
/// tens of charge radii through that residual viscosity, which takes a share of its peak that
/// shrinks only as the shells refine; ε sets how strongly the unloaded, pressureless sand's
/// shells are kept from passing through one another.
fn sensitivity(
    s: &Settings,
    params: &Params,
    resolutions: &[usize],
) -> Result<Vec<Run>, VerifyError> {
    let n = *resolutions.iter().min().expect("at least one resolution");
    let alpha_max = ArtificialViscosity::default().alpha;
    let alpha_min = params.number("alpha_min", 0.0, alpha_max)?;
    let mut varied = Vec::new();
    for factor in [0.5, 2.0] {
        let alpha = (factor * alpha_min).min(alpha_max);
        varied.push((
            format!("alpha_min = {alpha} (default {alpha_min})"),
            SimulationConfig {
                viscosity: viscosity_switched_down_to(alpha),
                ..s.config
            },
        ));
        let xsph = (factor * s.config.xsph).min(1.0);
        varied.push((
            format!("xsph = {xsph} (default {})", s.config.xsph),
            SimulationConfig { xsph, ..s.config },
        ));
    }
    let mut rows = Vec::new();
    for (what, config) in varied {
        let settings = Settings {
            config,
            ..s.clone()
        };
        let mut row = run_one(&settings, Sand::DruckerPrager, n, &|_| {})?.run;
        row.label = format!("{} n = {n}, {what}", Sand::DruckerPrager.name());
        row.sensitivity = Some(what);
        rows.push(row);
    }
    Ok(rows)
}

/// Whether a run's shells kept their order. Where they did not, a qualification: the sand
/// that the charge crushed unloads below its zero-pressure density as the cavity grows (the
/// hoop stretching), carries no stress there (the EOS has no tension), and its shells crowd
/// and cross; the clumps ring, and the ringing runs out behind the first pulse, where it can
/// set a gauge's largest stress (its time over the arrival is given per gauge). It is bounded
/// to as many crossed shells as the charge's radius holds, and its evidence is that the
/// deepest gauge's peak (`deepest_peak`, over the resolutions) is settled despite it.
fn shell_order_check(
    s: &Settings,
    model: &str,
    n: usize,
    run: &Run,
    deepest_peak: &Refinement,
) -> Check {
    let count = |name: &str| {
        run.metrics
            .get(&format!("crossed_shells_{name}"))
            .copied()
            .unwrap_or(f64::NAN)
    };
    let (sand, products) = (count("sand"), count("products"));
    let crossed = sand + products;
    let check = Check::at_most(format!("crossed_shells_{model}_n_{n}"), crossed, 0.0);
    if check.pass || run.failure.is_some() {
        return check;
    }
    let peak_times: Vec<String> = s
        .gauges_m
        .iter()
        .map(|r| {
            let key = format!("peak_stress_time_over_arrival_r{r}");
            format!(
                "{:.2} at {r} m",
                run.metrics.get(&key).copied().unwrap_or(f64::NAN)
            )
        })
        .collect();
    check.qualified(Qualification {
        reason: format!(
            "shells inside their inner neighbour at the end: {sand} of the sand, {products} of \
             the products. The crushed sand around the cavity unloads below its zero-pressure \
             density as the cavity grows, carries no stress there (no tension), and its shells \
             crowd onto each other; the clumps ring and the ringing follows the first pulse \
             out. Largest stress at time/arrival {} (from 5 m out the first pulse peaks at \
             1.1–1.3 times its arrival). The evidence is the deepest gauge's peak stress over \
             the relations, settled under refinement despite the crossing",
            peak_times.join(", ")
        ),
        quantity: "crossed shells".into(),
        value: crossed,
        bound: [0.0, n as f64],
        effect: "none on the safe depth: the study runs no buried charge and no 1D shells".into(),
        refinement: deepest_peak.clone(),
    })
}

/// The finest runs' gauge histories (stress per gauge and variant), and a figure per gauge
/// with both variants beside the relations' arrival and peak stress.
fn outputs(
    s: &Settings,
    measured: &[(Sand, usize, Measured)],
    n_fine: usize,
) -> Result<(Table, Figure), VerifyError> {
    let finest: Vec<&(Sand, usize, Measured)> =
        measured.iter().filter(|(_, n, _)| *n == n_fine).collect();
    let mut tables = Vec::new();
    for (model, _, m) in &finest {
        let variant = model.name().replace('-', "_");
        tables.push(history_table(&m.traces, |trace| {
            let r = trace.position_m;
            [
                format!("stress_{variant}_r{r}"),
                format!("velocity_{variant}_r{r}"),
            ]
        }));
    }
    let profile = tables
        .into_iter()
        .next()
        .unwrap_or_else(|| Table::new(&["t"]));
    let mut panels = Vec::new();
    for (k, &r) in s.gauges_m.iter().enumerate() {
        let relation = reference(s, r)?;
        let mut series: Vec<Series> = finest
            .iter()
            .enumerate()
            .map(|(j, (model, _, m))| Series {
                label: model.name().into(),
                points: m.traces[k]
                    .time
                    .iter()
                    .zip(&m.traces[k].overpressure)
                    .map(|(&t, &p)| (1e3 * t, 1e-3 * p))
                    .collect(),
                style: if j == 0 { Style::Line } else { Style::Markers },
            })
            .collect();
        series.push(Series {
            label: "TM 5-855-1 arrival, peak".into(),
            points: vec![(1e3 * relation.arrival_s, 1e-3 * relation.peak_stress_pa)],
            style: Style::Markers,
        });
        panels.push(Panel {
            title: format!("r = {r} m"),
            x_label: "t (ms)".into(),
            y_label: "radial stress (kPa)".into(),
            series,
            ..Panel::default()
        });
    }
    let figure = Figure {
        title: format!(
            "{SPHERICAL}: {} kg TNT buried in dry sand, n = {n_fine}",
            s.charge_kg
        ),
        panels,
    };
    Ok((profile, figure))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fitted_exponent_of_a_power_law_is_its_own() {
        let points: Vec<(f64, f64)> = [5.0, 10.0, 25.0, 40.0]
            .iter()
            .map(|&r: &f64| (r, 3.0 * r.powf(-2.75)))
            .collect();
        assert!((attenuation_exponent(&points) - 2.75).abs() < 1e-12);
        assert!(attenuation_exponent(&points[..1]).is_nan());
    }
}
