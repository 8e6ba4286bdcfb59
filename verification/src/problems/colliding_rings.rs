//! `colliding-rings`: the two elastic rubber rings of Gray, Monaghan & Swift (2001, CMAME 190,
//! 6641), the test of SPH's tensile instability. Rings of inner radius 3 cm and outer radius
//! 4 cm (material `rubber-rings`: ρ0 1, E 1e7, ν 0.3975), centres 8.2 cm apart, each moving
//! towards the other at 0.059 c0 (c0 = √(K/ρ0)); a square lattice of spacing Δp, h = 1.5 Δp
//! (theirs), continuity density, Monaghan's artificial stress ε = 0.3, n = 4 (theirs). The rings
//! meet, flatten, and bounce apart; the tension in the rebounding rings clumps particles and
//! tears the rings unless the artificial stress holds them. Each level runs the rings with the
//! artificial stress (checked) and without it (reported).
//!
//! Measured at the end: each ring's centre-of-mass velocity (bounced: reversed), the gap between
//! the rings, how intact each ring is (every particle's nearest neighbour in its ring, in units
//! of Δp: a torn-off particle or a crack has none near, a clump has one too near), total energy
//! and momentum.

use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Field, Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::VerifyError;
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialStress, ArtificialViscosity, Density, Domain, Formulation, SimulationConfig,
    SmoothingLength, Vector,
};

pub const NAME: &str = "colliding-rings";
const MATERIAL: &str = "rubber-rings";
const INNER_RADIUS: f64 = 0.03;
const OUTER_RADIUS: f64 = 0.04;
/// Each centre's distance from the midplane: a 2 mm gap between the rings.
const CENTRE_OFFSET: f64 = 0.041;
/// Each ring's speed over c0.
const SPEED_FRACTION: f64 = 0.059;

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "two elastic rubber rings collide and bounce apart (tensile instability)",
        params: vec![
            // 5 and 10 particles through the ring's 1 cm wall; Gray, Monaghan & Swift used
            // 0.5 mm (20), 16 times the work of 1 mm
            ParamSpec::per_level("spacing", 2e-3, 1e-3, "lattice spacing Δp (m)"),
            // the rings touch at 4 µs, are flattened most at about 120 µs and apart by 400 µs
            ParamSpec::new("t_end", 4e-4, "end time (s)"),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            ParamSpec::new("alpha", 1.0, "artificial viscosity α"),
            ParamSpec::new("beta", 2.0, "artificial viscosity β"),
            ParamSpec::new(
                "artificial_stress",
                0.3,
                "Monaghan's artificial stress ε of the checked run (n = 4)",
            ),
        ],
    }
}

/// What one run of the rings measured.
struct Measured {
    run: Run,
    snapshot: Option<Snapshot>,
    /// Final (x, y, ring) of every particle.
    particles: Vec<(f64, f64, f64)>,
}

/// Nearest same-ring neighbour distance of every particle, by a cell grid of one spacing.
fn nearest_neighbour_distances(points: &[(Vector<2>, bool)], spacing: f64) -> Vec<f64> {
    use std::collections::HashMap;
    let cell = |x: &Vector<2>| {
        (
            (x[0] / spacing).floor() as i64,
            (x[1] / spacing).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (k, (x, _)) in points.iter().enumerate() {
        grid.entry(cell(x)).or_default().push(k);
    }
    points
        .iter()
        .enumerate()
        .map(|(k, (x, ring))| {
            let (cx, cy) = cell(x);
            // widen the search ring by ring of cells until a neighbour is found and no nearer
            // one can lie farther out
            let mut best = f64::INFINITY;
            for reach in 1..=64i64 {
                for i in cx - reach..=cx + reach {
                    for j in cy - reach..=cy + reach {
                        if (i - cx).abs() < reach && (j - cy).abs() < reach && reach > 1 {
                            continue; // inner cells were searched before
                        }
                        for &m in grid.get(&(i, j)).into_iter().flatten() {
                            if m != k && points[m].1 == *ring {
                                best = best.min((points[m].0 - x).norm());
                            }
                        }
                    }
                }
                if best <= (reach - 1) as f64 * spacing {
                    break;
                }
            }
            best
        })
        .collect()
}

fn run_one(
    spacing: f64,
    settings: (f64, f64, ArtificialViscosity),
    label: &str,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let (t_end, cfl, viscosity) = settings;
    let library = Library::standard();
    let material = library.material(MATERIAL)?;
    let rho0 = library.ambient_state(MATERIAL)?.0;
    let entry = library.entry(MATERIAL)?;
    let (_, bulk) = blastsph_solver::Strength::elastic_moduli(
        entry.parameters["young"].value,
        entry.parameters["poisson"].value,
    )?;
    let speed = SPEED_FRACTION * (bulk / rho0).sqrt();
    // a square lattice through the ring's centre, the particles within the annulus
    let half = (OUTER_RADIUS / spacing).ceil() as i64;
    let mut ring = Vec::new();
    for i in -half..=half {
        for j in -half..=half {
            let x = Vector::<2>::new(i as f64 * spacing, j as f64 * spacing);
            let r2 = x.norm_squared();
            if (INNER_RADIUS * INNER_RADIUS..OUTER_RADIUS * OUTER_RADIUS).contains(&r2) {
                ring.push(x);
            }
        }
    }
    let per_ring = ring.len();
    let init: Vec<ParticleInit<2>> = [-1.0, 1.0]
        .iter()
        .flat_map(|&side: &f64| {
            ring.iter().map(move |x| ParticleInit {
                position: x + Vector::<2>::new(side * CENTRE_OFFSET, 0.0),
                // towards the other ring
                velocity: Vector::<2>::new(-side * speed, 0.0),
                mass: rho0 * spacing * spacing,
                smoothing_length: 1.5 * spacing,
                density: rho0,
                internal_energy: 0.0,
                material: 0,
            })
        })
        .collect();
    let config = SimulationConfig {
        formulation: Formulation::Cartesian(Density::Continuity(SmoothingLength::Fixed)),
        cfl,
        viscosity,
        min_time_step: 1e-9 * t_end,
        ..SimulationConfig::default()
    };
    let energy0: f64 = init.iter().map(|p| 0.5 * p.mass * speed * speed).sum();
    let mut run = Run::new(label, "", init.len(), spacing);
    let failed = |run: Run| Measured {
        run,
        snapshot: None,
        particles: Vec::new(),
    };
    let Some(sim) = run.simulate::<2>(
        (&init, vec![material], Domain::open(), config),
        t_end,
        progress,
    )?
    else {
        return Ok(failed(run));
    };
    let p = sim.particles();
    let n = p.n_real();
    // particle ids follow `init`: the first ring starts on the left
    let left = |i: usize| (p.id[i] as usize) < per_ring;
    let (mut mass, mut momentum) = ([0.0; 2], [Vector::<2>::zeros(); 2]);
    let (mut total_momentum, mut momentum_scale, mut energy) = (Vector::<2>::zeros(), 0.0, 0.0);
    for i in 0..n {
        let k = usize::from(!left(i));
        mass[k] += p.mass[i];
        momentum[k] += p.velocity[i] * p.mass[i];
        total_momentum += p.velocity[i] * p.mass[i];
        momentum_scale += p.mass[i] * speed;
        energy += p.mass[i] * (0.5 * p.velocity[i].norm_squared() + p.internal_energy[i]);
    }
    let kinetic: f64 = (0..n)
        .map(|i| 0.5 * p.mass[i] * p.velocity[i].norm_squared())
        .sum();
    // the gap: the rightmost particle of the left ring against the leftmost of the right one
    let left_edge = (0..n)
        .filter(|&i| left(i))
        .map(|i| p.position[i][0])
        .fold(f64::MIN, f64::max);
    let right_edge = (0..n)
        .filter(|&i| !left(i))
        .map(|i| p.position[i][0])
        .fold(f64::MAX, f64::min);
    let points: Vec<(Vector<2>, bool)> = (0..n).map(|i| (p.position[i], left(i))).collect();
    let nearest = nearest_neighbour_distances(&points, spacing);
    let widest = nearest.iter().cloned().fold(0.0, f64::max) / spacing;
    let closest = nearest.iter().cloned().fold(f64::INFINITY, f64::min) / spacing;
    let m = &mut run.metrics;
    // the left ring moved right at +speed: after the bounce its velocity is negative
    m.insert(
        "rebound_velocity_ratio".into(),
        -(momentum[0][0] / mass[0]) / speed,
    );
    m.insert(
        "rebound_velocity_ratio_right_ring".into(),
        (momentum[1][0] / mass[1]) / speed,
    );
    m.insert("kinetic_energy_fraction".into(), kinetic / energy0);
    m.insert(
        "gap_over_spacing".into(),
        (right_edge - left_edge) / spacing,
    );
    m.insert("widest_nearest_neighbour_over_spacing".into(), widest);
    m.insert("closest_nearest_neighbour_over_spacing".into(), closest);
    m.insert(
        "energy_balance_relative".into(),
        (energy - energy0).abs() / energy0,
    );
    m.insert(
        "momentum_relative".into(),
        total_momentum.norm() / momentum_scale,
    );
    m.insert("ring_speed".into(), speed);
    let particles = (0..n)
        .map(|i| {
            (
                p.position[i][0],
                p.position[i][1],
                f64::from(u8::from(!left(i))),
            )
        })
        .collect();
    Ok(Measured {
        run,
        snapshot: Some(Snapshot::of(&sim)),
        particles,
    })
}

pub fn run(params: &Params, progress: &(dyn Fn(f64) + Sync)) -> Result<ProblemOutput, VerifyError> {
    let spacing = params.number("spacing", 1e-4, 4e-3)?;
    let t_end = params.number("t_end", 1e-6, 1e-3)?;
    let cfl = params.cfl()?;
    let epsilon = params.number("artificial_stress", 0.01, 2.0)?;
    let base = ArtificialViscosity {
        alpha: params.number("alpha", 0.0, 10.0)?,
        beta: params.number("beta", 0.0, 10.0)?,
        ..ArtificialViscosity::default()
    };
    let with = ArtificialViscosity {
        artificial_stress: Some(ArtificialStress {
            epsilon,
            exponent: 4.0,
        }),
        ..base
    };
    let held = run_one(spacing, (t_end, cfl, with), "artificial stress", &|f| {
        progress(0.5 * f)
    })?;
    let free = run_one(spacing, (t_end, cfl, base), "no artificial stress", &|f| {
        progress(0.5 + 0.5 * f)
    })?;
    let metric = |m: &Measured, key: &str| m.run.metrics.get(key).copied().unwrap_or(f64::NAN);
    let checks = vec![
        Check::at_least("completed", f64::from(held.run.failure.is_none()), 1.0),
        // bounced: both rings move apart at the end (the sign of their velocity reversed)
        Check::at_least(
            "rebound_velocity_ratio",
            metric(&held, "rebound_velocity_ratio"),
            0.0,
        ),
        Check::at_least(
            "rebound_velocity_ratio_right_ring",
            metric(&held, "rebound_velocity_ratio_right_ring"),
            0.0,
        ),
        // apart: more than a kernel support (2h = 3Δp) between the rings, so no pair acts
        Check::at_least("gap_over_spacing", metric(&held, "gap_over_spacing"), 3.0),
        // intact: every particle keeps a neighbour in its ring within 1.5 Δp (the ring's
        // elastic strains are a few per cent; a crack or a torn-off particle leaves one
        // farther) and none closer than 0.5 Δp (a clump)
        Check::at_most(
            "widest_nearest_neighbour_over_spacing",
            metric(&held, "widest_nearest_neighbour_over_spacing"),
            1.5,
        ),
        Check::at_least(
            "closest_nearest_neighbour_over_spacing",
            metric(&held, "closest_nearest_neighbour_over_spacing"),
            0.5,
        ),
        // the viscous and artificial-stress heating is kept, so kinetic + internal is
        // conserved up to the time integration's error (measured 6e-6 at quick level)
        Check::at_most(
            "energy_balance_relative",
            metric(&held, "energy_balance_relative"),
            1e-4,
        ),
        // pair forces are antisymmetric: round-off only
        Check::at_most(
            "momentum_relative",
            metric(&held, "momentum_relative"),
            crate::record::momentum_round_off_bound(held.run.steps),
        ),
        // and the artificial stress is what holds them: without it the tension of the
        // rebound clumps particles into pairs (Gray, Monaghan & Swift's figure of the same
        // rings without it shows them fractured)
        Check::at_most(
            "closest_nearest_neighbour_over_spacing_without_artificial_stress",
            metric(&free, "closest_nearest_neighbour_over_spacing"),
            0.5,
        ),
    ];
    let mut table = Table::new(&["x", "y", "ring", "artificial_stress"]);
    for (m, flag) in [(&held, 1.0), (&free, 0.0)] {
        for q in &m.particles {
            table.rows.push(vec![q.0, q.1, q.2, flag]);
        }
    }
    let panel = |m: &Measured, title: &str| Panel {
        title: title.into(),
        x_label: "x (cm)".into(),
        y_label: "y (cm)".into(),
        series: vec![Series {
            label: "particles, coloured by ring".into(),
            points: m.particles.iter().map(|q| (1e2 * q.0, 1e2 * q.1)).collect(),
            style: Style::Coloured(Field {
                name: "ring (0: left, 1: right)".into(),
                values: m.particles.iter().map(|q| q.2).collect(),
            }),
        }],
        ..Panel::default()
    };
    let figure = Figure {
        title: format!(
            "{NAME}: the rings at {:.0} µs, with and without artificial stress",
            t_end * 1e6
        ),
        panels: vec![
            panel(&held, "artificial stress ε = 0.3, n = 4"),
            panel(&free, "no artificial stress"),
        ],
    };
    let snapshot = held.snapshot.clone();
    let runs = vec![held.run, free.run];
    Ok(ProblemOutput {
        record: Record::new(
            NAME,
            crate::Level::Quick,
            runs,
            Default::default(),
            checks,
            0,
        ),
        profile: table,
        figure,
        snapshot,
    })
}
