//! `elastic-wave`: a small longitudinal velocity pulse in the Taylor-bar copper (`cu-taylor-bar`:
//! E 117 GPa, ν 0.35, ρ 8930 kg/m³), under uniaxial strain: in 1D, and in 2D plane strain (a
//! periodic strip, the pulse varying along x only). The pulse v = A exp(−((x − x0)/w)²) with
//! zero stress splits into two halves running at the P-wave speed c_P = √((K + 4G/3)/ρ)
//! (4586 m/s here), the exact answer.
//!
//! Beside them a 3D bar with free sides (3 × 3 particles across, open lateral boundaries), whose
//! pulse should approach the bar speed √(E/ρ) (3620 m/s) as the bar gets slender: reported.
//!
//! Measured: the right-going peak (parabola through the fastest particle and its neighbours)
//! at 50 % and 100 % of the run, giving the wave speed; the peak amplitude against A/2; total
//! energy (kinetic + internal, which holds the elastic energy) over the run.

use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{observed_orders, Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::{Level, VerifyError};
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Boundary, Density, Domain, Formulation, Simulation, SimulationConfig,
    SmoothingLength, Strength, Vector,
};
use std::collections::BTreeMap;

pub const NAME: &str = "elastic-wave";
const MATERIAL: &str = "cu-taylor-bar";
/// The bar is 0.1 m long and periodic; the pulse starts at its centre.
const LENGTH: f64 = 0.1;
/// Rows of the 2D strip: enough for the kernel's reach across the periodic direction.
const STRIP_ROWS: usize = 8;
/// Particles across each side of the square 3D bar: slender against the pulse (3 spacings
/// against a 10 mm pulse at 200 particles per 0.1 m).
const BAR_ROWS: usize = 3;

/// The cross-section of a run: particles per lateral axis and the lateral boundary (periodic:
/// uniaxial strain; open: a bar with free sides).
#[derive(Clone, Copy)]
struct Lateral {
    rows: usize,
    boundary: Boundary,
    /// The speed the pulse should run at.
    reference_speed: f64,
    formulation: &'static str,
}

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary:
            "longitudinal elastic pulse (uniaxial strain, 1D and 2D plane strain): P-wave speed",
        params: vec![
            ParamSpec::new("amplitude", 1.0, "velocity amplitude A of the pulse (m/s)"),
            // w = 10 mm: 20 particles per w at the coarsest quick resolution, and the two
            // half pulses 3w apart at the first look
            ParamSpec::new("width", 0.01, "pulse half-width w (m)"),
            ParamSpec::new("travel", 0.03, "distance the pulse runs (m)"),
            ParamSpec::per_level(
                "n",
                "200,400",
                "200,400,800,1600",
                "particles along the 0.1 m bar (one run each, in 1D and in 2D)",
            ),
            // the 3D bar's speed is reported, not checked: the quick level runs it once
            ParamSpec::per_level(
                "n_bar",
                "200",
                "200,400,800,1600",
                "particles along the 3D bar (one run each)",
            ),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            // A 1 m/s elastic wave carries no shock, so it runs without the shock viscosity:
            // at α = 1 the pulse is damped and delayed (measured 3.8 %, 3.6 % slow at 400
            // particles in 1D, 2D, converging at order 0.4)
            ParamSpec::new("alpha", 0.0, "artificial viscosity α"),
            ParamSpec::new("beta", 0.0, "artificial viscosity β"),
            // η = 2 in 2D too: at η = 1.2 the discrete kernel-gradient sum leaves the wave
            // 0.9 % slow at every resolution (1.2 %, 0.97 %, 0.91 % at 200, 400, 800), as η = 1.2
            // does in 1D (see the impedance problems); at η = 2 it converges (0.96 %, 0.29 %)
            ParamSpec::new("eta_2d", 2.0, "smoothing length h = η·(m/ρ)^(1/2) in 2D"),
        ],
    }
}

struct Settings {
    amplitude: f64,
    width: f64,
    travel: f64,
    cfl: f64,
    viscosity: ArtificialViscosity,
    eta_2d: f64,
    density: f64,
    p_wave_speed: f64,
    /// √(E/ρ), the long-wave speed in a bar with free sides.
    bar_speed: f64,
}

fn settings(params: &Params) -> Result<Settings, VerifyError> {
    let library = Library::standard();
    let entry = library.entry(MATERIAL)?;
    let value = |k: &str| entry.parameters[k].value;
    let (shear, bulk) = Strength::elastic_moduli(value("young"), value("poisson"))?;
    let density = value("rho0");
    let width = params.number("width", 1e-4, 0.02)?;
    Ok(Settings {
        amplitude: params.number("amplitude", 1e-3, 50.0)?,
        width,
        travel: params.number("travel", 2.0 * width, 0.04)?,
        cfl: params.cfl()?,
        viscosity: ArtificialViscosity {
            alpha: params.number("alpha", 0.0, 10.0)?,
            beta: params.number("beta", 0.0, 10.0)?,
            ..ArtificialViscosity::default()
        },
        eta_2d: params.number("eta_2d", 0.5, 4.0)?,
        density,
        p_wave_speed: ((bulk + 4.0 * shear / 3.0) / density).sqrt(),
        bar_speed: (value("young") / density).sqrt(),
    })
}

/// The right-going peak: the fastest particle right of the centre, refined by a parabola
/// through it and its two neighbours along x. Returns (position, velocity).
fn peak(samples: &[(f64, f64)]) -> (f64, f64) {
    let centre = 0.5 * LENGTH;
    let k = (1..samples.len() - 1)
        .filter(|&k| samples[k].0 > centre)
        .max_by(|&a, &b| samples[a].1.total_cmp(&samples[b].1))
        .expect("particles right of the centre");
    let ((x0, y0), (x1, y1), (x2, y2)) = (samples[k - 1], samples[k], samples[k + 1]);
    // vertex of the parabola through three points
    let d1 = (y1 - y0) / (x1 - x0);
    let d2 = (y2 - y1) / (x2 - x1);
    let curvature = (d2 - d1) / (x2 - x0);
    if curvature >= 0.0 {
        return (x1, y1);
    }
    let x = 0.5 * (x0 + x1) - d1 / (2.0 * curvature);
    let y = y1 + d1 * (x - 0.5 * (x0 + x1)) + curvature * (x - x0) * (x - x1);
    (x.clamp(x0, x2), y.max(y1))
}

/// One run: its record, the final velocity profile (x, u) and the particles.
type PulseRun = (Run, Vec<(f64, f64)>, Option<Snapshot>);

/// Velocity along x against x, averaged over the particles of each column (2D) and sorted.
fn profile<const D: usize>(sim: &Simulation<D>, per_column: usize) -> Vec<(f64, f64)> {
    let p = sim.particles();
    let mut rows: Vec<(f64, f64)> = (0..p.n_real())
        .map(|i| (p.position[i][0], p.velocity[i][0]))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    if D == 1 {
        return rows;
    }
    // the cross-sections: consecutive groups of `per_column` particles along x
    rows.chunks(per_column)
        .map(|c| {
            let n = c.len() as f64;
            (
                c.iter().map(|q| q.0).sum::<f64>() / n,
                c.iter().map(|q| q.1).sum::<f64>() / n,
            )
        })
        .collect()
}

fn run_one<const D: usize>(
    s: &Settings,
    n: usize,
    lateral: Lateral,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<PulseRun, VerifyError> {
    let library = Library::standard();
    let dx = LENGTH / n as f64;
    let rows = if D == 1 { 1 } else { lateral.rows };
    let per_column = rows.pow(D as u32 - 1);
    let init: Vec<ParticleInit<D>> = (0..n * per_column)
        .map(|k| {
            let x = ((k % n) as f64 + 0.5) * dx;
            let mut position = Vector::<D>::zeros();
            position[0] = x;
            let mut lateral_index = k / n;
            for a in 1..D {
                position[a] = ((lateral_index % rows) as f64 + 0.5) * dx;
                lateral_index /= rows;
            }
            let mut velocity = Vector::<D>::zeros();
            velocity[0] = s.amplitude * (-((x - 0.5 * LENGTH) / s.width).powi(2)).exp();
            ParticleInit {
                position,
                velocity,
                mass: s.density * dx.powi(D as i32),
                smoothing_length: 1.2 * dx,
                density: s.density,
                internal_energy: 0.0,
                material: 0,
            }
        })
        .collect();
    let mut upper = Vector::<D>::repeat(rows as f64 * dx);
    upper[0] = LENGTH;
    let mut sides = [lateral.boundary; D];
    sides[0] = Boundary::Periodic;
    let domain = Domain::new(Vector::<D>::zeros(), upper, sides);
    let t_end = s.travel / s.p_wave_speed;
    let config = SimulationConfig {
        // η = 2 in 1D, as in the other 1D problems; 1.2 in 2D (about 20 neighbours)
        formulation: Formulation::Cartesian(Density::Continuity(SmoothingLength::FollowDensity {
            eta: if D == 1 { 2.0 } else { s.eta_2d },
        })),
        cfl: s.cfl,
        viscosity: s.viscosity,
        min_time_step: 1e-9 * t_end,
        ..SimulationConfig::default()
    };
    let label = format!("{} n = {n}", lateral.formulation);
    let mut run = Run::new(label, lateral.formulation, init.len(), dx);
    let start = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<D>::new(
        &init,
        vec![library.material(MATERIAL)?],
        domain,
        config,
    ))?
    else {
        return Ok((run, Vec::new(), None));
    };
    let energy0 = sim.particles().total_energy();
    let t_first = 0.5 * t_end;
    let mut outcome = sim.run_until(t_first, |t| progress(t / t_end));
    let first = peak(&profile(&sim, per_column));
    if outcome.is_ok() {
        outcome = sim.run_until(t_end, |t| progress(t / t_end));
    }
    run.record_work(&sim, start);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
        return Ok((run, Vec::new(), None));
    }
    let samples = profile(&sim, per_column);
    let last = peak(&samples);
    let speed = (last.0 - first.0) / (t_end - t_first);
    let m = &mut run.metrics;
    m.insert("wave_speed".into(), speed);
    m.insert("reference_speed".into(), lateral.reference_speed);
    m.insert(
        "peak_over_half_amplitude".into(),
        last.1 / (0.5 * s.amplitude),
    );
    let kinetic0 = 0.5
        * s.density
        * s.amplitude.powi(2)
        * s.width
        * (std::f64::consts::PI / 2.0).sqrt()
        * (rows as f64 * dx).powi(D as i32 - 1);
    m.insert(
        "energy_change_over_pulse_energy".into(),
        (sim.particles().total_energy() - energy0).abs() / kinetic0,
    );
    run.errors.insert(
        "wave_speed_relative".into(),
        (speed / lateral.reference_speed - 1.0).abs(),
    );
    Ok((run, samples, Some(Snapshot::of(&sim))))
}

pub fn run(params: &Params, progress: &(dyn Fn(f64) + Sync)) -> Result<ProblemOutput, VerifyError> {
    let s = settings(params)?;
    let resolutions = params.integers("n", 20, 100_000)?;
    let bar_resolutions = params.integers("n_bar", 20, 100_000)?;
    let total = 2 * resolutions.len() + bar_resolutions.len();
    let uniaxial = |formulation| Lateral {
        rows: STRIP_ROWS,
        boundary: Boundary::Periodic,
        reference_speed: s.p_wave_speed,
        formulation,
    };
    let bar = Lateral {
        rows: BAR_ROWS,
        boundary: Boundary::Open,
        reference_speed: s.bar_speed,
        formulation: "3D bar",
    };
    let mut runs = Vec::new();
    let mut profiles = Vec::new();
    // the finest 2D run's particles
    let mut snapshot = None;
    for (k, &n) in resolutions.iter().enumerate() {
        let part = |f: f64| progress(((2 * k) as f64 + f) / total as f64);
        let (run, samples, _) = run_one::<1>(&s, n, uniaxial("1D"), &part)?;
        runs.push(run);
        profiles.push(("1D", n, samples));
        let part = |f: f64| progress(((2 * k + 1) as f64 + f) / total as f64);
        let (run, samples, last) = run_one::<2>(&s, n, uniaxial("2D"), &part)?;
        snapshot = last;
        runs.push(run);
        profiles.push(("2D", n, samples));
    }
    // the finest 2D run
    let headline = runs.len() - 1;
    for (k, &n) in bar_resolutions.iter().enumerate() {
        let part = |f: f64| progress(((2 * resolutions.len() + k) as f64 + f) / total as f64);
        runs.push(run_one::<3>(&s, n, bar, &part)?.0);
    }
    let mut checks = Vec::new();
    let mut order = BTreeMap::new();
    for dim in ["1D", "2D", "3D bar"] {
        let of_dim: Vec<&Run> = runs.iter().filter(|r| r.formulation == dim).collect();
        for run in &of_dim {
            let label = run.label.replace(' ', "_").replace("_=_", "_");
            checks.push(Check::at_least(
                format!("completed_{label}"),
                f64::from(run.failure.is_none()),
                1.0,
            ));
            // energy: the pulse's own energy is the scale; the leapfrog and the viscous heating
            // (which stays in the total) leave it to 1e-4
            checks.push(Check::at_most(
                format!("energy_change_over_pulse_energy_{label}"),
                run.metrics
                    .get("energy_change_over_pulse_energy")
                    .copied()
                    .unwrap_or(f64::NAN),
                1e-4,
            ));
        }
        let finest = of_dim
            .iter()
            .max_by(|a, b| b.spacing.total_cmp(&a.spacing))
            .expect("one run per dimension");
        // the P-wave speed within 1 % (measured 0.2–0.3 %; the bar's approach to √(E/ρ) is
        // reported, not checked: a bar of finite thickness is dispersive)
        if dim != "3D bar" {
            checks.push(Check::at_most(
                format!("wave_speed_relative_{dim}"),
                finest
                    .errors
                    .get("wave_speed_relative")
                    .copied()
                    .unwrap_or(f64::NAN),
                0.01,
            ));
        }
        if let Some(p) = observed_orders(of_dim.iter().copied(), &["wave_speed_relative"])
            .remove("wave_speed_relative")
        {
            order.insert(format!("wave_speed_relative_{dim}"), p);
        }
    }
    let mut table = Table::new(&["x", "u_1d", "u_2d_column_mean"]);
    let finest_1d = &profiles[profiles.len() - 2].2;
    let finest_2d = &profiles[profiles.len() - 1].2;
    for (k, q) in finest_1d.iter().enumerate() {
        table
            .rows
            .push(vec![q.0, q.1, finest_2d.get(k).map_or(f64::NAN, |c| c.1)]);
    }
    let t_end = s.travel / s.p_wave_speed;
    let exact: Vec<(f64, f64)> = (0..=1000)
        .map(|k| {
            let x = LENGTH * k as f64 / 1000.0;
            let pulse = |centre: f64| 0.5 * s.amplitude * (-((x - centre) / s.width).powi(2)).exp();
            (
                x,
                pulse(0.5 * LENGTH + s.p_wave_speed * t_end)
                    + pulse(0.5 * LENGTH - s.p_wave_speed * t_end),
            )
        })
        .collect();
    let figure = Figure {
        title: format!(
            "{NAME}: {MATERIAL}, c_P = {:.1} m/s, after {} m of travel",
            s.p_wave_speed, s.travel
        ),
        panels: vec![Panel {
            title: "velocity".into(),
            x_label: "x (m)".into(),
            y_label: "u (m/s)".into(),
            series: vec![
                Series {
                    label: "SPH 1D".into(),
                    points: finest_1d.clone(),
                    style: Style::Markers,
                },
                Series {
                    label: "SPH 2D (column means)".into(),
                    points: finest_2d.clone(),
                    style: Style::Markers,
                },
                Series {
                    label: "exact (two half pulses at c_P)".into(),
                    points: exact,
                    style: Style::Line,
                },
            ],
            ..Panel::default()
        }],
    };
    Ok(ProblemOutput {
        record: Record::new(NAME, Level::Quick, runs, order, checks, headline),
        profile: table,
        figure,
        snapshot,
    })
}
