//! `transmitting-boundary`: how much of a plane wave a transmitting side sends back.
//!
//! A column 40 m long, 1D uniaxial strain, at rest, with a Gaussian compression centred at
//! 20 m (density 4e-4 above ambient at its peak, width 1 m): it splits into two compressive
//! pulses of half the amplitude running out to either side. Gauges at 10 and 30 m see each
//! pulse go by, then whatever its side sends back. Three materials: the ground-shock problem's
//! sand (`dry-sand`) with its Drucker–Prager strength and without, and an elastic solid that
//! carries tension (the Taylor-bar copper, far below yield here). Each runs three times:
//! - with transmitting sides (Lysmer–Kuhlemeyer, `solver::boundary::Boundary::Transmitting`);
//! - between rigid walls, which send the whole pulse back: the measurement's positive control;
//! - twice as long with open ends half a length beyond, so far that nothing comes back within
//!   the run: the gauges' histories without any reflection.
//!
//! The reflection coefficient is the largest departure of a gauge's velocity from the
//! far-ended column's, over the incident peak. Measuring the departure rather than a peak after
//! the pulse has passed matters in the Drucker–Prager sand: its plastic flow leaves a slowly
//! decaying wake behind the pulse, 10–20 % of the peak, which is no reflection. What that sand
//! does send back (about 1.7 %) is what its impedance mismatch predicts: the traction is matched
//! to the elastic P-wave speed (367 m/s), the yielding sand carries the pulse at
//! √(1.8 K/ρ0) = 356 m/s (uniaxial strain on the φ = 30° cone, σ_xx = p + ⅔·1.2 p), and
//! (367 − 356)/(367 + 356) = 1.5 %.
//!
//! The run ends when the reflections from both sides have passed their gauges (the pulses'
//! centres back at the gauges plus four widths), before the pulse reflected at one side could
//! reach the other side's gauge.

use super::airblast::viscosity;
use super::ground_shock::{p_wave_speed, soil_material};
use crate::gauges::interpolate;
use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Figure, Panel, Series, Style};
use crate::{Level, VerifyError};
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Boundary, Density, Domain, Formulation, Simulation, SimulationConfig,
    SmoothingLength, Vector,
};

pub const NAME: &str = "transmitting-boundary";

const LENGTH: f64 = 40.0;
const CENTRE: f64 = 20.0;
const GAUGES: [f64; 2] = [10.0, 30.0];
/// The compression's peak density, relative to ambient.
const AMPLITUDE: f64 = 4e-4;
const WIDTH: f64 = 1.0;
const SAND: &str = "dry-sand";
const ELASTIC: &str = "cu-taylor-bar";
/// The soil's Drucker–Prager parameters, as in `ground-shock-spherical`.
const COHESION: f64 = 0.0;
const FRICTION_ANGLE: f64 = 30.0;
/// The largest reflection coefficient a transmitting side may have.
const REFLECTION_LIMIT: f64 = 0.10;
/// The smallest reflection a rigid wall must show, so that the measurement is seen to detect
/// one (a wall sends the whole pulse back: 1 less what the viscosity takes).
const WALL_REFLECTION: f64 = 0.5;

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "plane pulses in sand and an elastic solid through transmitting sides (Lysmer-Kuhlemeyer): reflection coefficient",
        params: vec![
            ParamSpec::per_level(
                "n",
                "800",
                "400,800,1600",
                "particles along the 40 m column (20 per pulse width at 800)",
            ),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            ParamSpec::new(
                "alpha_min",
                0.1,
                "Morris-Monaghan switch: the viscosity's alpha away from shocks (1: off), as in ground-shock-spherical",
            ),
        ],
    }
}

/// The column's material and ends.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Variant {
    material: Column,
    ends: Ends,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Column {
    DruckerPragerSand,
    NoShearSand,
    Elastic,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ends {
    Transmitting,
    Walls,
    /// The column twice as long, its ends so far that nothing comes back within the run: the
    /// gauges' histories without any reflection.
    Far,
}

impl Variant {
    fn label(self) -> String {
        format!(
            "{}, {}",
            match self.material {
                Column::DruckerPragerSand => "drucker-prager sand",
                Column::NoShearSand => "no-shear sand",
                Column::Elastic => "elastic copper",
            },
            match self.ends {
                Ends::Transmitting => "transmitting sides",
                Ends::Walls => "walls",
                Ends::Far => "far ends",
            }
        )
    }
}

struct Measured {
    run: Run,
    /// (t, v at each gauge)
    history: Vec<(f64, [f64; 2])>,
}

fn run_one(
    variant: Variant,
    n: usize,
    cfl: f64,
    viscosity: ArtificialViscosity,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let library = Library::standard();
    let (name, material) = match variant.material {
        Column::DruckerPragerSand => (SAND, soil_material(SAND, Some((COHESION, FRICTION_ANGLE)))?),
        Column::NoShearSand => (SAND, soil_material(SAND, None)?),
        Column::Elastic => (ELASTIC, library.material(ELASTIC)?),
    };
    let (rho0, e0) = library.ambient_state(name)?;
    let speed = p_wave_speed(&material, rho0);
    let dx = LENGTH / n as f64;
    // the far-ended column reaches half a length beyond either end
    let (start, count, boundary) = match variant.ends {
        Ends::Transmitting => (0.0, n, Boundary::Transmitting),
        Ends::Walls => (0.0, n, Boundary::Wall),
        Ends::Far => (-0.5 * LENGTH, 2 * n, Boundary::Open),
    };
    let init: Vec<ParticleInit<1>> = (0..count)
        .map(|k| {
            let x = start + (k as f64 + 0.5) * dx;
            let density = rho0 * (1.0 + AMPLITUDE * (-((x - CENTRE) / WIDTH).powi(2)).exp());
            ParticleInit {
                position: Vector::<1>::new(x),
                velocity: Vector::<1>::zeros(),
                mass: density * dx,
                smoothing_length: 2.0 * dx,
                density,
                internal_energy: e0,
                material: 0,
            }
        })
        .collect();
    let domain = Domain::new(
        Vector::<1>::new(start),
        Vector::<1>::new(start + count as f64 * dx),
        [boundary],
    );
    // each reflection's centre back at its gauge, plus four widths
    let t_end = ((LENGTH - CENTRE) + (LENGTH - GAUGES[1]) + 4.0 * WIDTH) / speed;
    let config = SimulationConfig {
        formulation: Formulation::Cartesian(Density::Continuity(SmoothingLength::FollowDensity {
            eta: 2.0,
        })),
        cfl,
        viscosity,
        min_time_step: 1e-9 * t_end,
        ..SimulationConfig::default()
    };
    let mut run = Run::new(variant.label() + &format!(" n = {n}"), "", count, dx);
    let clock = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<1>::new(&init, vec![material], domain, config))?
    else {
        return Ok(Measured {
            run,
            history: Vec::new(),
        });
    };
    // the pulses' energy: twice their kinetic energy once they have parted (a plane wave
    // carries as much as strain energy), the largest kinetic energy of the run
    let kinetic = |sim: &Simulation<1>| {
        let p = sim.particles();
        (0..p.n_real())
            .map(|i| 0.5 * p.mass[i] * p.velocity[i].norm_squared())
            .sum::<f64>()
    };
    let mut pulse_energy = 0.0_f64;
    let energy0 = sim.particles().total_energy();
    let read = |sim: &Simulation<1>| -> (f64, [f64; 2]) {
        let p = sim.particles();
        let mut profile: Vec<(f64, f64)> = (0..p.n_real())
            .map(|i| (p.position[i][0], p.velocity[i][0]))
            .collect();
        profile.sort_by(|a, b| a.0.total_cmp(&b.0));
        (sim.time(), GAUGES.map(|x| interpolate(&profile, x)))
    };
    let mut history = vec![read(&sim)];
    let mut outcome = Ok(());
    while sim.time() < t_end {
        outcome = sim.step_toward(t_end);
        if outcome.is_err() {
            break;
        }
        history.push(read(&sim));
        pulse_energy = pulse_energy.max(2.0 * kinetic(&sim));
        progress(sim.time() / t_end);
    }
    run.record_work(&sim, clock);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
        return Ok(Measured { run, history });
    }
    run.metrics.insert(
        "energy_change_over_pulse_energy".into(),
        (sim.particles().total_energy() + sim.transmitted_energy() - energy0).abs() / pulse_energy,
    );
    run.metrics.insert(
        "transmitted_over_pulse_energy".into(),
        sim.transmitted_energy() / pulse_energy,
    );
    run.metrics.insert("p_wave_speed_m_s".into(), speed);
    Ok(Measured { run, history })
}

/// Per gauge, the largest departure of `history` from the reflection-free `far` history (at
/// the same times, interpolated) over the incident peak, and that peak.
fn reflection_coefficients(
    history: &[(f64, [f64; 2])],
    far: &[(f64, [f64; 2])],
) -> [(f64, f64); 2] {
    [0, 1].map(|g| {
        let reference: Vec<(f64, f64)> = far.iter().map(|(t, v)| (*t, v[g])).collect();
        let incident = reference.iter().map(|(_, v)| v.abs()).fold(0.0, f64::max);
        let departure = history
            .iter()
            .map(|(t, v)| (v[g] - interpolate(&reference, *t)).abs())
            .fold(0.0, f64::max);
        (departure / incident, incident)
    })
}

pub fn run(params: &Params, progress: &(dyn Fn(f64) + Sync)) -> Result<ProblemOutput, VerifyError> {
    let resolutions = params.integers("n", 40, 1_000_000)?;
    let cfl = params.cfl()?;
    let viscosity = viscosity(params)?;
    let variants: Vec<Variant> = [
        Column::DruckerPragerSand,
        Column::NoShearSand,
        Column::Elastic,
    ]
    .iter()
    .flat_map(|&material| {
        [Ends::Far, Ends::Transmitting, Ends::Walls].map(|ends| Variant { material, ends })
    })
    .collect();
    let parts = (variants.len() * resolutions.len()) as f64;
    let mut measured: Vec<(Variant, usize, Measured)> = Vec::new();
    for &n in &resolutions {
        for &variant in &variants {
            let done = measured.len() as f64;
            let m = run_one(variant, n, cfl, viscosity, &|f| {
                progress((done + f) / parts)
            })?;
            measured.push((variant, n, m));
        }
    }
    // each column's reflections: its gauges' departures from the far-ended column's
    for k in 0..measured.len() {
        let (variant, n) = (measured[k].0, measured[k].1);
        if variant.ends == Ends::Far {
            continue;
        }
        let far = measured
            .iter()
            .find(|(v, m, _)| *m == n && v.material == variant.material && v.ends == Ends::Far);
        let Some((_, _, far)) = far else { continue };
        let reflections = reflection_coefficients(&measured[k].2.history, &far.history);
        let run = &mut measured[k].2.run;
        for (x, (coefficient, incident)) in GAUGES.iter().zip(reflections) {
            run.metrics
                .insert(format!("reflection_coefficient_x{x}"), coefficient);
            run.metrics
                .insert(format!("incident_peak_velocity_x{x}"), incident);
        }
        if variant.ends == Ends::Transmitting {
            let largest = reflections.iter().map(|r| r.0).fold(0.0, f64::max);
            run.errors.insert("reflection_coefficient".into(), largest);
        }
    }
    let n_fine = *resolutions.iter().max().expect("a resolution");
    let mut checks = Vec::new();
    for (variant, n, m) in &measured {
        let label = m.run.label.replace(" = ", "_").replace([' ', ','], "_");
        checks.push(Check::at_least(
            format!("completed_{label}"),
            f64::from(m.run.failure.is_none()),
            1.0,
        ));
        if m.run.failure.is_some() {
            continue;
        }
        // the books include what left through the sides; the leapfrog and the viscous
        // heating (which stays in the total) keep them to about 1e-4 of the pulses' energy
        checks.push(Check::at_most(
            format!("energy_change_over_pulse_energy_{label}"),
            m.run.metrics["energy_change_over_pulse_energy"],
            1e-3,
        ));
        if *n != n_fine || variant.ends == Ends::Far {
            continue;
        }
        for x in GAUGES {
            let key = format!("reflection_coefficient_x{x}");
            let coefficient = m.run.metrics.get(&key).copied().unwrap_or(f64::NAN);
            let name = format!("{key}_{label}");
            checks.push(if variant.ends == Ends::Transmitting {
                Check::at_most(name, coefficient, REFLECTION_LIMIT)
            } else {
                Check::at_least(name, coefficient, WALL_REFLECTION)
            });
        }
    }
    let runs: Vec<Run> = measured.iter().map(|(_, _, m)| m.run.clone()).collect();
    let finest: Vec<&(Variant, usize, Measured)> =
        measured.iter().filter(|(_, n, _)| *n == n_fine).collect();
    let mut table = Table::new(&["t", "v_x10", "v_x30"]);
    if let Some((_, _, m)) = finest.first() {
        table.rows = m
            .history
            .iter()
            .map(|(t, v)| vec![*t, v[0], v[1]])
            .collect();
    }
    // one panel per material at the gauge 10 m inside the upper side, velocity over the
    // incident peak: the pulse, the walls' full reflection, the transmitting sides' flat line
    let materials = [
        Column::DruckerPragerSand,
        Column::NoShearSand,
        Column::Elastic,
    ];
    let panels = materials
        .iter()
        .filter_map(|&material| {
            let of_material: Vec<_> = finest
                .iter()
                .filter(|(v, _, _)| v.material == material)
                .collect();
            let (far, _, _) = of_material.first()?;
            let incident = of_material
                .iter()
                .find(|(v, _, _)| v.ends == Ends::Far)
                .map(|(_, _, m)| {
                    m.history
                        .iter()
                        .map(|(_, v)| v[1].abs())
                        .fold(0.0, f64::max)
                })?;
            Some(Panel {
                title: format!("{} at x = {} m", far.label().split(", ").next()?, GAUGES[1]),
                x_label: "t (ms)".into(),
                y_label: "velocity / incident peak".into(),
                series: of_material
                    .iter()
                    .map(|(variant, _, m)| Series {
                        label: variant.label().split(", ").nth(1).unwrap_or("").into(),
                        points: m
                            .history
                            .iter()
                            .map(|(t, v)| (1e3 * t, v[1] / incident))
                            .collect(),
                        style: if variant.ends == Ends::Walls {
                            Style::Markers
                        } else {
                            Style::Line
                        },
                    })
                    .collect(),
                ..Panel::default()
            })
        })
        .collect();
    let figure = Figure {
        title: format!("{NAME}: plane pulses through transmitting sides, n = {n_fine}"),
        panels,
    };
    let headline = measured
        .iter()
        .position(|(v, n, _)| *n == n_fine && v.ends == Ends::Transmitting)
        .unwrap_or(0);
    Ok(ProblemOutput {
        record: Record::new(
            NAME,
            Level::Quick,
            runs,
            Default::default(),
            checks,
            headline,
        ),
        profile: table,
        figure,
        snapshot: None,
    })
}
