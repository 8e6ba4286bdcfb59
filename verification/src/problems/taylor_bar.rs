//! `taylor-bar-3d`: the OFHC copper Taylor bar (reference_data/taylor_bar_copper_benchmark.csv:
//! L0 32.4 mm, R0 3.2 mm, 227 m/s onto a rigid frictionless wall, E 117 GPa, ν 0.35, yield
//! 400 MPa, hardening 100 MPa, ρ 8930, 80 µs) as a quarter model: mirror planes x = 0 and
//! y = 0, the wall at z = 0 (a mirror too: frictionless). Continuity density, η = 1.2, the
//! viscosity with Balsara's switch and Monaghan's artificial stress (see the parameters).
//!
//! Measured at 80 µs: the final length (highest particle plus half a spacing), the footprint
//! radius (the farthest particle of the bottom layer from the axis plus half a spacing; the mean
//! and least of the farthest per 15° sector are reported beside it), the
//! energy balance (kinetic + internal against the initial kinetic energy, with the internal
//! energy split into plastic work, elastic shear energy and the rest: bulk elastic and viscous
//! heating), the largest equivalent plastic strain and the largest excess over the yield
//! surface. Reference: final length 21.42 mm (Carina TET15, Foulk et al. ~21.43), footprint
//! radius 7.12 mm (Simo 1992; 7.11–7.23 across the published codes).

use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{observed_orders, Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::{Level, VerifyError};
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::strength::{full_contraction, von_mises};
use blastsph_solver::{
    ArtificialViscosity, Boundary, DensityMethod, Domain, Simulation, SimulationConfig,
    SmoothingLength, Vector,
};

pub const NAME: &str = "taylor-bar-3d";
const MATERIAL: &str = "cu-taylor-bar";
const LENGTH: f64 = 32.4e-3;
const RADIUS: f64 = 3.2e-3;
const SPEED: f64 = 227.0;
const END_TIME: f64 = 80e-6;
/// The published converged results.
const FINAL_LENGTH: f64 = 21.42e-3;
const FOOTPRINT_RADIUS: f64 = 7.12e-3;

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "copper Taylor bar, 227 m/s, quarter model with two symmetry planes",
        params: vec![
            ParamSpec::per_level(
                "n_radius",
                "4,5",
                "5,7,10",
                "particles across the radius (one run each)",
            ),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            ParamSpec::new("t_end", END_TIME, "end time (s)"),
            ParamSpec::new("alpha", 1.0, "artificial viscosity α"),
            ParamSpec::new("beta", 2.0, "artificial viscosity β"),
            // the solid stabilisation the problem needs, measured (issue 4 note): with the plain
            // viscosity α = 1 the viscous heating takes a quarter of the impact energy and the
            // bar stays 6 % too long; Balsara's switch spares the shear flow, but then the rim
            // of the foot clumps and splashes along the wall (footprint +25…39 %) until
            // Monaghan's artificial stress (Gray, Monaghan & Swift's ε = 0.3, n = 4) holds it
            ParamSpec::new(
                "artificial_stress",
                0.3,
                "Monaghan's artificial stress ε (n = 4; 0: off)",
            ),
            ParamSpec::new(
                "balsara",
                "on",
                "Balsara's switch on the viscosity: on or off",
            ),
        ],
    }
}

struct Measured {
    run: Run,
    snapshot: Option<Snapshot>,
    /// Final particle positions (x, y, z) and plastic strain, for the figure.
    particles: Vec<(f64, f64, f64, f64)>,
}

fn run_one(
    n_radius: usize,
    (cfl, viscosity): (f64, ArtificialViscosity),
    t_end: f64,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let library = Library::standard();
    let material = library.material(MATERIAL)?;
    let strength = material.strength.expect("an elastic-plastic material");
    let rho0 = library.ambient_state(MATERIAL)?.0;
    let dx = RADIUS / n_radius as f64;
    let layers = (LENGTH / dx).round() as usize;
    let mut init = Vec::new();
    for k in 0..layers {
        for i in 0..n_radius {
            for j in 0..n_radius {
                let (x, y) = ((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
                if x * x + y * y <= RADIUS * RADIUS {
                    init.push(ParticleInit {
                        position: Vector::<3>::new(x, y, (k as f64 + 0.5) * dx),
                        velocity: Vector::<3>::new(0.0, 0.0, -SPEED),
                        mass: rho0 * dx * dx * dx,
                        smoothing_length: 1.2 * dx,
                        density: rho0,
                        internal_energy: 0.0,
                        material: 0,
                    });
                }
            }
        }
    }
    let domain = Domain::with_sides(
        Vector::<3>::zeros(),
        Vector::<3>::new(4.0 * RADIUS, 4.0 * RADIUS, 2.0 * LENGTH),
        [Boundary::Wall; 3],
        [Boundary::Open; 3],
    )?;
    let config = SimulationConfig {
        density: DensityMethod::Continuity,
        smoothing: SmoothingLength::FollowDensity { eta: 1.2 },
        cfl,
        viscosity,
        min_time_step: 1e-9 * t_end,
        ..SimulationConfig::default()
    };
    // the quarter's kinetic energy, ×4 for the whole bar
    let kinetic0: f64 = init.iter().map(|p| 0.5 * p.mass * SPEED * SPEED).sum();
    let mut run = Run::new(format!("n_radius = {n_radius}"), "", init.len(), dx);
    let start = std::time::Instant::now();
    let mut sim = match Simulation::<3>::new(&init, vec![material], domain, config) {
        Ok(sim) => sim,
        Err(refused) => {
            run.failure = Some(VerifyError::from_scene(refused)?);
            return Ok(Measured {
                run,
                snapshot: None,
                particles: Vec::new(),
            });
        }
    };
    let outcome = sim.run_until(t_end, |t| progress(t / t_end));
    run.record_work(&sim, start);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
        return Ok(Measured {
            run,
            snapshot: None,
            particles: Vec::new(),
        });
    }
    let p = sim.particles();
    let n = p.n_real();
    let top = (0..n).map(|i| p.position[i][2]).fold(f64::MIN, f64::max);
    let final_length = top + 0.5 * dx;
    // the footprint: the farthest particle of the bottom layer (the checked value), and, to show
    // how round the foot is on the lattice, the farthest per 15° sector of the quarter
    let mut sector_max = [0.0f64; 6];
    for i in (0..n).filter(|&i| p.position[i][2] < dx) {
        let (x, y) = (p.position[i][0], p.position[i][1]);
        let sector = ((y.atan2(x) / std::f64::consts::FRAC_PI_2 * 6.0) as usize).min(5);
        sector_max[sector] = sector_max[sector].max(x.hypot(y));
    }
    let footprint = sector_max.iter().cloned().fold(0.0, f64::max) + 0.5 * dx;
    let sector_least = sector_max.iter().cloned().fold(f64::INFINITY, f64::min) + 0.5 * dx;
    let sector_mean = sector_max.iter().sum::<f64>() / 6.0 + 0.5 * dx;
    let kinetic: f64 = (0..n)
        .map(|i| 0.5 * p.mass[i] * p.velocity[i].norm_squared())
        .sum();
    let internal: f64 = (0..n).map(|i| p.mass[i] * p.internal_energy[i]).sum();
    let plastic: f64 = (0..n).map(|i| p.mass[i] * p.plastic_work[i]).sum();
    let shear_elastic: f64 = (0..n)
        .map(|i| {
            p.mass[i] * full_contraction(&p.deviatoric_stress[i])
                / (4.0 * strength.shear_modulus * p.density[i])
        })
        .sum();
    let max_plastic_strain = p.plastic_strain.iter().cloned().fold(0.0, f64::max);
    let yield_excess = (0..n)
        .map(|i| {
            von_mises(&p.deviatoric_stress[i]) / strength.current_yield(&p.yield_state(i)) - 1.0
        })
        .fold(f64::MIN, f64::max);
    let m = &mut run.metrics;
    m.insert("final_length_mm".into(), 1e3 * final_length);
    m.insert("footprint_radius_mm".into(), 1e3 * footprint);
    m.insert("footprint_sector_mean_mm".into(), 1e3 * sector_mean);
    m.insert("footprint_sector_least_mm".into(), 1e3 * sector_least);
    m.insert("initial_kinetic_energy_full_bar_j".into(), 4.0 * kinetic0);
    m.insert("kinetic_energy_j".into(), 4.0 * kinetic);
    m.insert("plastic_work_j".into(), 4.0 * plastic);
    m.insert("shear_elastic_energy_j".into(), 4.0 * shear_elastic);
    m.insert(
        "bulk_elastic_and_viscous_j".into(),
        4.0 * (internal - plastic - shear_elastic),
    );
    m.insert(
        "energy_balance_relative".into(),
        (kinetic + internal - kinetic0).abs() / kinetic0,
    );
    m.insert("max_plastic_strain".into(), max_plastic_strain);
    m.insert("max_yield_excess".into(), yield_excess);
    run.errors.insert(
        "final_length_relative".into(),
        (final_length / FINAL_LENGTH - 1.0).abs(),
    );
    run.errors.insert(
        "footprint_radius_relative".into(),
        (footprint / FOOTPRINT_RADIUS - 1.0).abs(),
    );
    let particles = (0..n)
        .map(|i| {
            let x = p.position[i];
            (x[0], x[1], x[2], p.plastic_strain[i])
        })
        .collect();
    Ok(Measured {
        run,
        snapshot: Some(Snapshot::of(&sim)),
        particles,
    })
}

pub fn run(
    params: &Params,
    level: Level,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let resolutions = params.integers("n_radius", 2, 40)?;
    let cfl = params.cfl()?;
    let t_end = params.number("t_end", 1e-7, 2e-4)?;
    let viscosity = ArtificialViscosity {
        alpha: params.number("alpha", 0.0, 10.0)?,
        beta: params.number("beta", 0.0, 10.0)?,
        balsara: params.choice(
            "balsara",
            &[true, false],
            |on| if on { "on" } else { "off" },
        )?,
        artificial_stress: match params.number("artificial_stress", 0.0, 2.0)? {
            0.0 => None,
            epsilon => Some(blastsph_solver::ArtificialStress {
                epsilon,
                exponent: 4.0,
            }),
        },
        ..ArtificialViscosity::default()
    };
    let mut measured = Vec::new();
    for (k, &n) in resolutions.iter().enumerate() {
        let part = |f: f64| progress((k as f64 + f) / resolutions.len() as f64);
        measured.push(run_one(n, (cfl, viscosity), t_end, &part)?);
    }
    let finest = (0..resolutions.len())
        .max_by_key(|&k| resolutions[k])
        .expect("one resolution");
    let fine = &measured[finest].run;
    let error = |key: &str| fine.errors.get(key).copied().unwrap_or(f64::NAN);
    let metric = |run: &Run, key: &str| run.metrics.get(key).copied().unwrap_or(f64::NAN);
    // the limits: 1.5 % and 3 % at full level, 4 % and 8 % at quick
    let (length_limit, footprint_limit) = match level {
        Level::Full => (0.015, 0.03),
        Level::Quick => (0.04, 0.08),
    };
    let mut checks = vec![
        Check::at_most(
            "final_length_relative",
            error("final_length_relative"),
            length_limit,
        ),
        Check::at_most(
            "footprint_radius_relative",
            error("footprint_radius_relative"),
            footprint_limit,
        ),
    ];
    for m in &measured {
        let label = m.run.label.replace(" = ", "_");
        checks.push(Check::at_least(
            format!("completed_{label}"),
            f64::from(m.run.failure.is_none()),
            1.0,
        ));
        checks.push(Check::at_most(
            format!("energy_balance_relative_{label}"),
            metric(&m.run, "energy_balance_relative"),
            0.02,
        ));
        checks.push(Check::at_most(
            format!("max_yield_excess_{label}"),
            metric(&m.run, "max_yield_excess"),
            1e-6,
        ));
    }
    let order = observed_orders(
        measured.iter().map(|m| &m.run),
        &["final_length_relative", "footprint_radius_relative"],
    );
    let runs: Vec<Run> = measured.iter().map(|m| m.run.clone()).collect();
    let mut table = Table::new(&["x", "y", "z", "plastic_strain"]);
    for q in &measured[finest].particles {
        table.rows.push(vec![q.0, q.1, q.2, q.3]);
    }
    let side: Vec<(f64, f64)> = measured[finest]
        .particles
        .iter()
        .filter(|q| q.1 < 0.6 * measured[finest].run.spacing)
        .map(|q| (1e3 * q.0, 1e3 * q.2))
        .collect();
    let figure = Figure {
        title: format!(
            "{NAME}: final shape at {:.0} µs (slice next to the y = 0 plane); reference length {} mm, footprint {} mm",
            t_end * 1e6,
            FINAL_LENGTH * 1e3,
            FOOTPRINT_RADIUS * 1e3
        ),
        panels: vec![Panel {
            title: "particles, x–z".into(),
            x_label: "x (mm)".into(),
            y_label: "z (mm)".into(),
            series: vec![Series {
                label: "SPH".into(),
                points: side,
                style: Style::Markers,
            }],
        }],
    };
    Ok(ProblemOutput {
        record: Record::new(NAME, level, runs, order, checks, finest),
        profile: table,
        figure,
        snapshot: measured[finest].snapshot.clone(),
    })
}
