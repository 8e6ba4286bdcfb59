//! `sedov-spherical-1d`, `sedov-2d`, `sedov-3d`: a point release of energy in a cold uniform
//! gas against the exact Sedov–Taylor solution of [`crate::sedov`].
//!
//! - `sedov-spherical-1d`: spherical shells in r (radial SPH), the Kamm & Timmes standard case
//!   γ = 1.4, ρ0 = 1, E = 0.851072, t = 1 (shock at r = 1).
//! - `sedov-2d`, `sedov-3d`: the setups PySPH and SWIFT ship, γ = 5/3, E = 1, ρ0 = 1,
//!   t = 0.1 (2D, a line blast in the plane) and 0.05 (3D). By symmetry only the quadrant or
//!   octant x, y, z ≥ 0 is simulated: the symmetry planes are mirror walls, which is exact for
//!   a point blast on a mirror-symmetric lattice, and carries 1/4 or 1/8 of E.
//!
//! The energy goes into the particles near the origin with weights W(r_i, h_dep), h_dep =
//! `deposit_width` initial spacings; the background has p0 = 10⁻⁶ of the post-shock pressure scale (the
//! "near-zero" pressure of the exact solution; it sets the sound speed that limits the step
//! outside the blast). The shock radius is the peak of the radially binned mean density (bins
//! one spacing wide, the peak refined by a parabola through the three largest bins), and the
//! densest particle's radius is reported beside it.

use crate::norms::observed_order;
use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::sedov::SedovBlast;
use crate::svg::{Field, Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::{Level, VerifyError};
use blastsph_solver::formulation::ETA_RANGE;
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Boundary, Density, Domain, EnergyEquation, EquationOfState, Formulation,
    Geometry, IdealGas, Kernel, KernelShape, Material, ShellDensity, Simulation, SimulationConfig,
    TimeSteps, Vector,
};
use std::collections::BTreeMap;

/// What distinguishes the three problems.
#[derive(Clone, Copy, Debug)]
struct Variant {
    name: &'static str,
    summary: &'static str,
    /// Spatial dimension of the exact blast (1D radial scenes are spherical).
    blast_geometry: Geometry,
    gamma: f64,
    energy: f64,
    t_end: f64,
    /// Quick and full resolutions: shells, or particles per side of the quadrant or octant.
    resolutions: (&'static str, &'static str),
    /// Quick and full formulations (smoothing-length modes), one curve each.
    formulations: (&'static str, &'static str),
    eta: f64,
    /// The shock-radius limit at quick and full level (relative).
    radius_limit: (f64, f64),
    /// Individual time steps up to this many times the shortest (1: global steps).
    step_ratio: u64,
}

const VARIANTS: [Variant; 3] = [
    Variant {
        name: "sedov-spherical-1d",
        summary: "Sedov-Taylor spherical blast in radial 1D SPH (Kamm-Timmes standard case)",
        blast_geometry: Geometry::Spherical,
        gamma: 1.4,
        energy: 0.851072,
        t_end: 1.0,
        resolutions: ("100,200", "100,200,400,800"),
        // fixed h is available (--set smoothing=follow-density,fixed) but not run by default:
        // h cannot grow in the emptied centre, where the sound speed is huge, so the step
        // stays small: 55 000 steps and 108 s at 200 shells against 6 000 steps and 8 s
        formulations: ("follow-density", "follow-density"),
        eta: 1.2,
        // the same at both levels
        radius_limit: (0.01, 0.01),
        // global steps: with individual steps (step_ratio 64) the shock radius is as close
        // (0.48 % against 0.45 % at 200 shells) and L1(ρ) lower (0.025 against 0.039), but the
        // total energy drifts by 4.7e-3 against 6e-4, over the 1e-3 limit: a blast into cold
        // gas is where particles on long steps meet the shock
        step_ratio: 1,
    },
    Variant {
        name: "sedov-2d",
        summary: "Sedov-Taylor cylindrical blast in planar 2D (gamma 5/3, E = 1, t = 0.1)",
        blast_geometry: Geometry::Cylindrical,
        gamma: 5.0 / 3.0,
        energy: 1.0,
        t_end: 0.1,
        resolutions: ("40,60", "40,60,90,135"),
        formulations: ("grad-h", "grad-h,follow-density"),
        eta: 1.2,
        radius_limit: (0.04, 0.02),
        // individual steps: at the quick level's finer run the shock radius is as close
        // (1.47 % against 1.48 % at n = 60), L1(ρ) 1 % higher, the energy closer (2.2e-4
        // against 2.5e-4), in 0.36 of the particle updates
        step_ratio: 64,
    },
    Variant {
        name: "sedov-3d",
        summary: "Sedov-Taylor spherical blast in 3D (gamma 5/3, E = 1, t = 0.05)",
        blast_geometry: Geometry::Spherical,
        gamma: 5.0 / 3.0,
        energy: 1.0,
        t_end: 0.05,
        resolutions: ("16,22", "16,22,30,40"),
        formulations: ("grad-h", "grad-h,follow-density"),
        eta: 1.2,
        radius_limit: (0.04, 0.02),
        // individual steps: the same shock radius (2.08 % at n = 22, 1.32 % against 1.33 % at
        // n = 40) and L1(ρ), the energy closer (8.5e-5 against 4.3e-4 at n = 22), in 0.40 of
        // the particle updates
        step_ratio: 64,
    },
];

pub fn infos() -> Vec<super::ProblemInfo> {
    VARIANTS.iter().map(info).collect()
}

fn variant(name: &str) -> Option<&'static Variant> {
    VARIANTS.iter().find(|v| v.name == name)
}

pub fn is_sedov(name: &str) -> bool {
    variant(name).is_some()
}

fn info(v: &Variant) -> super::ProblemInfo {
    let mut params = vec![
        ParamSpec::per_level(
            "n",
            v.resolutions.0,
            v.resolutions.1,
            "shells (1D) or particles per side of the quadrant/octant, one run each",
        ),
        ParamSpec::per_level(
            "smoothing",
            v.formulations.0,
            v.formulations.1,
            "smoothing-length modes (fixed, follow-density, grad-h), one set of runs each",
        ),
        ParamSpec::new("gamma", v.gamma, "ratio of specific heats"),
        ParamSpec::new("energy", v.energy, "blast energy E (J, whole blast)"),
        ParamSpec::new("t_end", v.t_end, "output time (s)"),
        ParamSpec::new("rho0", 1.0, "background density (kg/m³)"),
        ParamSpec::new("eta", v.eta, "smoothing length h = η·(m/ρ)^(1/D)"),
        ParamSpec::new("cfl", 0.3, "Courant number C"),
        // 2.5 spacings: the deposit is resolved by a few particles, yet its reach 2h = 5
        // spacings is under 7 % of R at the coarsest quick resolution. A deposit within one
        // h (1.2 spacings) puts the energy into one or two shells, which ring about the
        // origin with ~10 steps per period at C = 0.3, and the leapfrog loses 4e-3 of E there
        // (measured in 1D radial, independent of resolution; 6e-4 at 2.5 spacings)
        ParamSpec::new(
            "deposit_width",
            2.5,
            "h of the kernel that spreads E over the central particles, in spacings",
        ),
        ParamSpec::new("alpha", 1.0, "artificial viscosity α"),
        ParamSpec::new("beta", 2.0, "artificial viscosity β"),
        ParamSpec::new("kernel", "cubic-spline", "kernel shape"),
    ];
    params.push(ParamSpec::step_ratio(v.step_ratio));
    super::ProblemInfo {
        name: v.name,
        summary: v.summary,
        params,
    }
}

/// Whether the variant runs in r alone (the spherical 1D one).
fn is_radial(v: &Variant) -> bool {
    v.name == "sedov-spherical-1d"
}

/// Everything one run needs besides its resolution and formulation.
#[derive(Clone, Copy, Debug)]
struct Settings {
    variant: &'static Variant,
    exact: SedovBlast,
    config: SimulationConfig,
    eta: f64,
    /// h of the deposit kernel, in initial spacings.
    deposit_width: f64,
    /// The simulated region extends to this radius (or half-side) from the origin.
    extent: f64,
    p0: f64,
}

fn settings(v: &'static Variant, params: &Params) -> Result<Settings, VerifyError> {
    let gamma = params.number("gamma", 1.0 + 1e-6, 10.0)?;
    let energy = params.number("energy", 1e-12, 1e30)?;
    let t_end = params.number("t_end", 1e-12, 1e6)?;
    let rho0 = params.number("rho0", 1e-12, 1e6)?;
    let eta = params.number("eta", ETA_RANGE.0, ETA_RANGE.1)?;
    let exact = SedovBlast::new(v.blast_geometry, gamma, energy, rho0, t_end)?;
    let config = SimulationConfig {
        time_steps: params.time_steps()?,
        formulation: formulation(v, "fixed", eta)?,
        kernel: params.choice("kernel", &KernelShape::ALL, KernelShape::name)?,
        viscosity: ArtificialViscosity {
            alpha: params.number("alpha", 0.0, 10.0)?,
            beta: params.number("beta", 0.0, 10.0)?,
            ..ArtificialViscosity::default()
        },
        energy: EnergyEquation::OwnPressure,
        cfl: params.cfl()?,
        min_time_step: 1e-9 * t_end,
        ..SimulationConfig::default()
    };
    Ok(Settings {
        variant: v,
        exact,
        config,
        eta,
        deposit_width: params.number("deposit_width", 0.5, 10.0)?,
        // the undisturbed gas beyond the shock must be deep enough for the binned peak and
        // for kernels near the shock: 30 % of R beyond it
        extent: 1.3 * exact.r_shock,
        p0: 1e-6 * exact.p2,
    })
}

/// Summation density with h found as `smoothing` names it (fixed, follow-density, grad-h): in
/// Cartesian coordinates, or in r for the spherical 1D variant (which has no grad-h).
fn formulation(v: &Variant, smoothing: &str, eta: f64) -> Result<Formulation, VerifyError> {
    let density = Density::from_names("summation", smoothing, eta)?;
    if !is_radial(v) {
        return Ok(Formulation::Cartesian(density));
    }
    Ok(Formulation::Spherical(ShellDensity::from_density(density)?))
}

/// The particles of the final state that the measurements need.
struct FinalState {
    radius: Vec<f64>,
    /// Unit vectors from the origin (empty in 1D).
    direction: Vec<Vec<f64>>,
    density: Vec<f64>,
    radial_velocity: Vec<f64>,
    pressure: Vec<f64>,
    volume: Vec<f64>,
    snapshot: Snapshot,
}

struct BlastRun {
    run: Run,
    state: Option<FinalState>,
}

/// Particles and domain at resolution n.
fn setup<const D: usize>(s: &Settings, n: usize) -> (Vec<ParticleInit<D>>, Domain<D>, f64) {
    let rho0 = s.exact.rho0;
    let gas = IdealGas::new(s.exact.gamma).expect("gamma validated");
    let e0 = gas.internal_energy(rho0, s.p0);
    let spacing = s.extent / n as f64;
    let h = s.eta * spacing;
    let geometry = s.config.formulation.geometry();
    let radial = geometry != Geometry::Planar;
    let mut init: Vec<ParticleInit<D>> = (0..n.pow(if radial { 1 } else { D as u32 }))
        .map(|k| {
            let index = |a: u32| (k / n.pow(a)) % n;
            let position = Vector::<D>::from_fn(|a, _| (index(a as u32) as f64 + 0.5) * spacing);
            let mass = if radial {
                let r0 = index(0) as f64 * spacing;
                geometry.volume_between(r0, r0 + spacing) * rho0
            } else {
                spacing.powi(D as i32) * rho0
            };
            ParticleInit {
                position,
                velocity: Vector::zeros(),
                mass,
                smoothing_length: h,
                density: rho0,
                internal_energy: e0,
                material: 0,
            }
        })
        .collect();
    // the share of E in the simulated region, spread with kernel weights W(r_i, h)
    let share = if radial { 1.0 } else { 0.5f64.powi(D as i32) };
    let kernel = Kernel::<D>::new(s.config.kernel);
    let weights: Vec<f64> = init
        .iter()
        .map(|p| kernel.value(p.position.norm(), s.deposit_width * spacing))
        .collect();
    let total: f64 = weights.iter().sum();
    for (p, w) in init.iter_mut().zip(&weights) {
        p.internal_energy += share * s.exact.energy * w / total / p.mass;
    }
    let domain = if radial {
        Domain::open()
    } else {
        Domain::new(
            Vector::zeros(),
            Vector::repeat(s.extent),
            [Boundary::Wall; D],
        )
    };
    (init, domain, spacing)
}

/// The blast of variant `v` at resolution n, in the variant's dimension.
fn run_variant(
    v: &Variant,
    s: &Settings,
    n: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<BlastRun, VerifyError> {
    match v.name {
        "sedov-2d" => run_blast::<2>(s, n, progress),
        "sedov-3d" => run_blast::<3>(s, n, progress),
        _ => run_blast::<1>(s, n, progress),
    }
}

fn run_blast<const D: usize>(
    s: &Settings,
    n: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<BlastRun, VerifyError> {
    let (init, domain, spacing) = setup::<D>(s, n);
    let gas = Material::new("ideal-gas", IdealGas::new(s.exact.gamma)?);
    let formulation = super::shock_tube::formulation(&s.config);
    let label = format!("{} n = {n}", s.config.formulation.smoothing_name());
    let mut run = Run {
        label,
        formulation,
        n_particles: init.len(),
        steps: 0,
        wall_s: 0.0,
        spacing,
        errors: BTreeMap::from([
            ("l1_rho".to_string(), f64::NAN),
            ("shock_radius".to_string(), f64::NAN),
        ]),
        metrics: BTreeMap::new(),
        phase_s: BTreeMap::new(),
        failure: None,
        sensitivity: None,
        gauges: Vec::new(),
    };
    let start = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<D>::new(&init, vec![gas], domain, s.config))?
    else {
        return Ok(BlastRun { run, state: None });
    };
    let energy0 = sim.particles().total_energy();
    let outcome = sim.run_until(s.exact.time, |t| progress(t / s.exact.time));
    run.record_work(&sim, start);
    let p = sim.particles();
    run.metrics.insert(
        "energy_relative_error".into(),
        (p.total_energy() - energy0).abs() / energy0,
    );
    run.metrics
        .insert("repeated_searches".into(), sim.repeated_searches() as f64);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
        return Ok(BlastRun { run, state: None });
    }
    let eos = IdealGas::new(s.exact.gamma)?;
    let n_real = p.n_real();
    let radius: Vec<f64> = (0..n_real).map(|i| p.position[i].norm()).collect();
    let state = FinalState {
        direction: if D == 1 {
            Vec::new()
        } else {
            (0..n_real)
                .map(|i| (p.position[i] / radius[i]).iter().copied().collect())
                .collect()
        },
        radial_velocity: (0..n_real)
            .map(|i| p.velocity[i].dot(&p.position[i]) / radius[i])
            .collect(),
        pressure: (0..n_real)
            .map(|i| eos.pressure(p.density[i], p.internal_energy[i]))
            .collect(),
        volume: (0..n_real).map(|i| p.mass[i] / p.density[i]).collect(),
        density: p.density[..n_real].to_vec(),
        radius,
        snapshot: Snapshot::of(&sim),
    };
    measure(s, &state, &mut run);
    Ok(BlastRun {
        run,
        state: Some(state),
    })
}

/// The peak of the mean density binned in r (bins of width `width`) over the particles that
/// `keep` selects, refined by a parabola through the largest bin and its neighbours:
/// (radius, binned peak density).
fn binned_peak(state: &FinalState, width: f64, keep: impl Fn(usize) -> bool) -> (f64, f64) {
    let bins = (state.radius.iter().cloned().fold(0.0, f64::max) / width) as usize + 1;
    let (mut sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
    for i in (0..state.radius.len()).filter(|&i| keep(i)) {
        let b = (state.radius[i] / width) as usize;
        sum[b] += state.density[i];
        count[b] += 1;
    }
    let mean: Vec<f64> = sum
        .iter()
        .zip(&count)
        .map(|(s, &c)| if c > 0 { s / c as f64 } else { 0.0 })
        .collect();
    let Some(k) = (0..bins).max_by(|&a, &b| mean[a].total_cmp(&mean[b])) else {
        return (f64::NAN, f64::NAN);
    };
    let centre = (k as f64 + 0.5) * width;
    if k == 0 || k + 1 >= bins {
        return (centre, mean[k]);
    }
    let (left, mid, right) = (mean[k - 1], mean[k], mean[k + 1]);
    let curvature = left - 2.0 * mid + right;
    let offset = if curvature < 0.0 {
        (0.5 * (left - right) / curvature).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    (centre + offset * width, mid)
}

/// Shock radius, peak density, L1 density error and the spread over directions.
fn measure(s: &Settings, state: &FinalState, run: &mut Run) {
    let exact = &s.exact;
    let width = run.spacing;
    let (r_binned, peak_binned) = binned_peak(state, width, |_| true);
    let densest = (0..state.density.len())
        .max_by(|&a, &b| state.density[a].total_cmp(&state.density[b]))
        .expect("particles");
    let r_densest = state.radius[densest];
    // volume-weighted mean |ρ − ρ_exact| over the blast and a layer of undisturbed gas
    let reach = 1.2 * exact.r_shock;
    let (mut error, mut volume) = (0.0, 0.0);
    for i in (0..state.radius.len()).filter(|&i| state.radius[i] <= reach) {
        error += (state.density[i] - exact.state_at(state.radius[i]).rho).abs() * state.volume[i];
        volume += state.volume[i];
    }
    run.errors
        .insert("l1_rho".into(), error / volume / exact.rho0);
    run.errors.insert(
        "shock_radius".into(),
        (r_binned - exact.r_shock).abs() / exact.r_shock,
    );
    let m = &mut run.metrics;
    m.insert("r_shock_binned".into(), r_binned);
    m.insert("r_shock_densest_particle".into(), r_densest);
    m.insert("r_shock_exact".into(), exact.r_shock);
    m.insert(
        "peak_density_binned_over_exact".into(),
        peak_binned / exact.rho2,
    );
    m.insert(
        "peak_density_max_over_exact".into(),
        state.density[densest] / exact.rho2,
    );
    if let Some(spread) = direction_spread(state, width) {
        m.insert("shock_radius_direction_spread".into(), spread);
    }
}

/// (max − min)/mean of the binned-peak shock radius over direction sectors of the quadrant
/// (six sectors of 15°) or octant (nine: three polar bands × three azimuth sectors).
fn direction_spread(state: &FinalState, width: f64) -> Option<f64> {
    let dim = state.direction.first()?.len();
    let sector = |i: usize| -> usize {
        let d = &state.direction[i];
        let azimuth = d[1].atan2(d[0]).clamp(0.0, std::f64::consts::FRAC_PI_2);
        if dim == 2 {
            ((azimuth / std::f64::consts::FRAC_PI_2 * 6.0) as usize).min(5)
        } else {
            let band = ((d[2].clamp(0.0, 1.0)) * 3.0) as usize; // equal solid angle in cos θ
            let slice = ((azimuth / std::f64::consts::FRAC_PI_2 * 3.0) as usize).min(2);
            3 * band.min(2) + slice
        }
    };
    let sectors = if dim == 2 { 6 } else { 9 };
    let radii: Vec<f64> = (0..sectors)
        .map(|k| binned_peak(state, width, |i| sector(i) == k).0)
        .collect();
    let mean = radii.iter().sum::<f64>() / sectors as f64;
    let (lo, hi) = radii.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
        (lo.min(r), hi.max(r))
    });
    Some((hi - lo) / mean)
}

/// The resolutions `n`, each refused where its run would not fit in memory: n shells in the
/// radial runs, an n^D lattice in the quadrant or octant.
pub fn resolutions(name: &str, params: &Params) -> Result<Vec<usize>, VerifyError> {
    let dimension = match name {
        "sedov-2d" => 2,
        "sedov-3d" => 3,
        _ => 1,
    };
    params.resolutions("n", 4, 100_000, dimension, |n| {
        (n as f64).powi(dimension as i32)
    })
}

pub fn run(
    name: &str,
    params: &Params,
    level: Level,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let v = variant(name).expect("a Sedov problem");
    let base = settings(v, params)?;
    let resolutions = resolutions(name, params)?;
    let formulations = params
        .choices("smoothing", &Density::SMOOTHING, |name| name)?
        .into_iter()
        .map(|smoothing| formulation(v, smoothing, base.eta))
        .collect::<Result<Vec<_>, _>>()?;
    let total = (resolutions.len() * formulations.len()) as f64;
    let mut blasts: Vec<(usize, BlastRun)> = Vec::new();
    for (f, &formulation) in formulations.iter().enumerate() {
        let s = Settings {
            config: SimulationConfig {
                formulation,
                ..base.config
            },
            ..base
        };
        for (k, &n) in resolutions.iter().enumerate() {
            let done = (f * resolutions.len() + k) as f64;
            let part = |x: f64| progress((done + x) / total);
            let blast = run_variant(v, &s, n, &part)?;
            blasts.push((f, blast));
        }
    }
    let mut order = BTreeMap::new();
    let mut checks = Vec::new();
    let completed = blasts
        .iter()
        .filter(|(_, b)| b.run.failure.is_none())
        .count();
    checks.push(Check::at_least(
        "runs_completed_without_blow_up",
        completed as f64,
        blasts.len() as f64,
    ));
    let radius_limit = match level {
        Level::Quick => v.radius_limit.0,
        Level::Full => v.radius_limit.1,
    };
    for (f, formulation) in formulations.iter().enumerate() {
        let runs: Vec<&Run> = blasts
            .iter()
            .filter(|(g, _)| *g == f)
            .map(|(_, b)| &b.run)
            .collect();
        let tag = formulation.smoothing_name();
        let spacing: Vec<f64> = runs.iter().map(|r| r.spacing).collect();
        let l1: Vec<f64> = runs.iter().map(|r| r.errors["l1_rho"]).collect();
        if let Some(p) = observed_order(&spacing, &l1) {
            order.insert(format!("l1_rho_{tag}"), p);
        }
        // only the first formulation is the problem's; the others are there to compare
        if f > 0 {
            continue;
        }
        if runs.len() >= 2 {
            // errors fall with resolution: a positive observed order of L1(ρ)
            checks.push(Check::at_least(
                format!("observed_order_l1_rho_{tag}"),
                order
                    .get(&format!("l1_rho_{tag}"))
                    .copied()
                    .unwrap_or(f64::NAN),
                0.0,
            ));
        }
        let finest = runs.last().expect("at least one resolution");
        let metric = |r: &Run, key: &str| r.metrics.get(key).copied().unwrap_or(f64::NAN);
        checks.push(Check::at_most(
            format!("shock_radius_relative_error_{tag}"),
            finest.errors["shock_radius"],
            radius_limit,
        ));
        for r in &runs {
            // the pair terms conserve energy exactly in time; what is left is the leapfrog's
            // error and, with h following the density, the change of h between steps
            checks.push(Check::at_most(
                format!("energy_relative_error_{}", r.label.replace(' ', "_")),
                metric(r, "energy_relative_error"),
                1e-3,
            ));
        }
        if runs.len() >= 2 {
            let coarse = runs[runs.len() - 2];
            checks.push(Check::at_least(
                format!("peak_density_rise_with_resolution_{tag}"),
                metric(finest, "peak_density_binned_over_exact")
                    - metric(coarse, "peak_density_binned_over_exact"),
                0.0,
            ));
        }
        // peak density floors: 70 % of (γ+1)/(γ−1)·ρ0 in 1D radial at every level,
        // 55 % (binned) in 2D/3D at full level; reported, not checked, in 2D/3D at quick level
        let peak_floor = match (v.name, level) {
            ("sedov-spherical-1d", _) => Some(0.70),
            (_, Level::Full) => Some(0.55),
            _ => None,
        };
        if let Some(floor) = peak_floor {
            checks.push(Check::at_least(
                format!("peak_density_binned_over_exact_{tag}"),
                metric(finest, "peak_density_binned_over_exact"),
                floor,
            ));
        }
        if v.name != "sedov-spherical-1d" {
            checks.push(Check::at_most(
                format!("shock_radius_direction_spread_{tag}"),
                metric(finest, "shock_radius_direction_spread"),
                0.03,
            ));
        }
    }
    let headline_run = resolutions.len() - 1;
    let mut runs: Vec<Run> = blasts.iter().map(|(_, b)| b.run.clone()).collect();
    if level == Level::Full {
        // The deposit width was chosen with the shock radius in view: the coarsest run of the
        // problem's formulation with it halved and doubled.
        let n = *resolutions.iter().min().expect("one resolution");
        let s = Settings {
            config: SimulationConfig {
                formulation: formulations[0],
                ..base.config
            },
            ..base
        };
        for factor in [0.5, 2.0] {
            let width = s.deposit_width * factor;
            let varied = Settings {
                deposit_width: width,
                ..s
            };
            let mut row = run_variant(v, &varied, n, &|_| {})?.run;
            let what = format!("deposit_width = {width} (default {})", s.deposit_width);
            row.label = format!("n = {n}, {what}");
            row.sensitivity = Some(what);
            runs.push(row);
        }
        // the time steps were chosen with the energy in view: the coarsest run stepped the
        // other way
        let (ratio, other) = match s.config.time_steps {
            TimeSteps::Global => (1, TimeSteps::Individual { max_ratio: 64 }),
            TimeSteps::Individual { max_ratio } => (max_ratio, TimeSteps::Global),
        };
        let varied = Settings {
            config: SimulationConfig {
                time_steps: other,
                ..s.config
            },
            ..s
        };
        let mut row = run_variant(v, &varied, n, &|_| {})?.run;
        let other_ratio = if ratio == 1 { 64 } else { 1 };
        let what = format!("step_ratio = {other_ratio} (default {ratio})");
        row.label = format!("n = {n}, {what}");
        row.sensitivity = Some(what);
        runs.push(row);
    }
    let finest_state = blasts[..resolutions.len()]
        .iter()
        .rev()
        .find_map(|(_, b)| b.state.as_ref());
    let (profile, figure) = profile_outputs(&base, finest_state);
    let snapshot = finest_state.map(|s| s.snapshot.clone());
    Ok(ProblemOutput {
        record: Record::new(name, level, runs, order, checks, headline_run),
        profile,
        figure,
        snapshot,
    })
}

/// The finest run of the first formulation as radial profiles (each particle in 1D, the
/// binned means in 2D/3D) beside the exact solution.
fn profile_outputs(s: &Settings, state: Option<&FinalState>) -> (Table, Figure) {
    let exact = &s.exact;
    let mut table = Table::new(&["r", "rho", "rho_exact", "u", "u_exact", "p", "p_exact"]);
    let mut points: Vec<[f64; 4]> = Vec::new();
    if let Some(state) = state {
        if state.direction.is_empty() {
            points = (0..state.radius.len())
                .map(|i| {
                    [
                        state.radius[i],
                        state.density[i],
                        state.radial_velocity[i],
                        state.pressure[i],
                    ]
                })
                .collect();
        } else {
            // bins as wide as the mean spacing over the blast, enough particles in each
            let bins = 100;
            let width = s.extent * 3f64.sqrt() / bins as f64;
            let mut sum = vec![[0.0; 4]; bins];
            let mut count = vec![0usize; bins];
            for i in 0..state.radius.len() {
                let b = ((state.radius[i] / width) as usize).min(bins - 1);
                for (k, q) in [
                    state.radius[i],
                    state.density[i],
                    state.radial_velocity[i],
                    state.pressure[i],
                ]
                .into_iter()
                .enumerate()
                {
                    sum[b][k] += q;
                }
                count[b] += 1;
            }
            points = sum
                .iter()
                .zip(&count)
                .filter(|(_, &c)| c > 0)
                .map(|(q, &c)| q.map(|x| x / c as f64))
                .collect();
        }
        points.sort_by(|a, b| a[0].total_cmp(&b[0]));
    }
    for q in &points {
        let e = exact.state_at(q[0]);
        table
            .rows
            .push(vec![q[0], q[1], e.rho, q[2], e.u, q[3], e.p]);
    }
    let r_max = s.extent;
    let fine: Vec<f64> = (0..=1000).map(|k| r_max * k as f64 / 1000.0).collect();
    let fields = [
        ("density", "rho"),
        ("radial velocity", "u"),
        ("pressure", "p"),
    ];
    let panels = fields
        .iter()
        .enumerate()
        .map(|(k, (title, symbol))| {
            let value = |r: f64| {
                let e = exact.state_at(r);
                [e.rho, e.u, e.p][k]
            };
            Panel {
                title: title.to_string(),
                x_label: "r".into(),
                y_label: symbol.to_string(),
                series: vec![
                    Series {
                        label: "SPH".into(),
                        points: points.iter().map(|q| (q[0], q[k + 1])).collect(),
                        style: Style::Markers,
                    },
                    Series {
                        label: "exact".into(),
                        points: fine.iter().map(|&r| (r, value(r))).collect(),
                        style: Style::Line,
                    },
                ],
                ..Panel::default()
            }
        })
        .collect();
    let mut panels: Vec<Panel> = panels;
    // a plane blast: its particles, coloured by density, show the shock's roundness
    if let Some(state) = state.filter(|st| st.direction.first().is_some_and(|d| d.len() == 2)) {
        panels.push(Panel {
            title: "particles".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![Series {
                label: "SPH, coloured by density".into(),
                points: state
                    .radius
                    .iter()
                    .zip(&state.direction)
                    .map(|(r, d)| (r * d[0], r * d[1]))
                    .collect(),
                style: Style::Coloured(Field {
                    name: "density".into(),
                    values: state.density.clone(),
                }),
            }],
            ..Panel::default()
        });
    }
    let figure = Figure {
        title: format!(
            "{} at t = {} (exact shock radius {:.4})",
            s.variant.name, exact.time, exact.r_shock
        ),
        panels,
    };
    (table, figure)
}
