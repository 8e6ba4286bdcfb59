//! `tnt-slab`: planar detonation of a TNT slab (JWL, programmed burn) that then expands into
//! air, in 1D.
//!
//! Set-up (m): TNT on [0, L] against a rigid wall at x = 0 (equivalently the centre plane of a
//! slab 2L thick lit on that plane), air on [L, 2L], equal particle spacing (masses differ by the
//! density ratio 1630/1.225), continuity density in the volume form, lit at x = 0 at t = 0.
//!
//! Exact answer while the front is inside the charge: the Chapman–Jouguet detonation from a
//! wall (Zel'dovich–Taylor): unreacted TNT ahead of x = D t, the CJ state at the front, the
//! Taylor rarefaction x/t = u + c along the products' isentrope through the CJ point down to
//! rest, and products at rest near the wall. The CJ state is the one the JWL parameters imply
//! (`Jwl::chapman_jouguet`, 21.0 GPa at 6929 m/s for the LLNL set); the fan comes from
//! [`crate::impedance::right_fan`].
//!
//! Measured: the front (where the pressure crosses half of p_CJ) at 0.4 and
//! 0.9 L/D, giving the front speed; the peak pressure at 0.9 L/D against p_CJ; the L1 error of
//! the pressure profile against the exact one at 0.9 L/D; then the products expand into the
//! air until 1.3 L/D (the run must stay stable), and the air shock's position is reported.

use crate::impedance::{self, MaterialState};
use crate::materials::Library;
use crate::norms::l1_error;
use crate::params::{ParamSpec, Params};
use crate::record::{
    conservation_checks, observed_orders, Check, Conservation, ProblemOutput, Record, Run, Table,
};
use crate::svg::{Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::{Level, VerifyError};
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Boundary, Density, Domain, EnergyEquation, Formulation, Jwl, KernelShape,
    ProgrammedBurn, Simulation, SimulationConfig, SmoothingLength, Vector,
};

pub const NAME: &str = "tnt-slab";

/// Times, in units of the transit time L/D, of the two front measurements and of the end.
const FIRST_LOOK: f64 = 0.4;
const SECOND_LOOK: f64 = 0.9;
const END: f64 = 1.3;
/// The resolution (particles across the slab) at which the error limits hold.
const LIMIT_RESOLUTION: usize = 200;

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "planar TNT detonation (JWL, programmed burn) from a wall, then into air",
        params: vec![
            ParamSpec::new("length", 0.1, "slab thickness L (m)"),
            ParamSpec::per_level(
                "n",
                "100,200",
                "100,200,400,800",
                "particles across the slab (one run each)",
            ),
            ParamSpec::new("ramp", 2.0, "burn ramp width (smoothing lengths)"),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            // η = 2 as in the other 1D problems (the shock tubes give the measured reason)
            ParamSpec::new("eta", 2.0, "smoothing length h = η·m/ρ"),
        ],
    }
}

/// The Chapman–Jouguet detonation from a wall.
struct Detonation {
    speed: f64,
    cj: MaterialState,
    rho0: f64,
    /// The Taylor wave (ξ = u + c decreasing from D to the stagnant state's c, ρ, u, p).
    fan: Vec<(f64, f64, f64, f64)>,
}

impl Detonation {
    fn new(jwl: &Jwl, detonation_energy: f64) -> Self {
        let (speed, p_cj, v_cj) = jwl.chapman_jouguet(detonation_energy);
        let rho_cj = jwl.rho0 / v_cj;
        // Rankine–Hugoniot from the unreacted state (e0 = E0/ρ0, p = 0, at rest)
        let e_cj = detonation_energy / jwl.rho0 + 0.5 * p_cj * (1.0 / jwl.rho0 - 1.0 / rho_cj);
        let cj = MaterialState {
            density: rho_cj,
            internal_energy: e_cj,
            pressure: p_cj,
            velocity: speed * (1.0 - v_cj),
        };
        // the fan down the isentrope until the products come to rest
        let mut fan = impedance::right_fan(jwl, &cj, 0.05 * p_cj, 4000);
        if let Some(k) = fan.iter().position(|f| f.2 <= 0.0) {
            fan.truncate(k + 1);
        }
        Self {
            speed,
            cj,
            rho0: jwl.rho0,
            fan,
        }
    }

    /// The products at rest between the wall and the tail of the Taylor wave: the tail's
    /// speed x/t (its sound speed) and their pressure.
    fn rest(&self) -> (f64, f64) {
        let tail = self.fan[self.fan.len() - 1];
        (tail.0, tail.3)
    }

    /// (ρ, u, p) at x, t (x ≥ 0, before the front reaches the air).
    fn sample(&self, x: f64, t: f64) -> (f64, f64, f64) {
        let xi = x / t;
        if xi >= self.speed {
            return (self.rho0, 0.0, 0.0);
        }
        // ξ falls along the fan; beyond its end the products are at rest
        match self.fan.windows(2).position(|w| xi >= w[1].0) {
            Some(k) => {
                let (a, b) = (self.fan[k], self.fan[k + 1]);
                let f = ((xi - a.0) / (b.0 - a.0)).clamp(0.0, 1.0);
                (
                    a.1 + f * (b.1 - a.1),
                    (a.2 + f * (b.2 - a.2)).max(0.0),
                    a.3 + f * (b.3 - a.3),
                )
            }
            None => {
                let rest = self.fan[self.fan.len() - 1];
                (rest.1, 0.0, rest.3)
            }
        }
    }
}

/// x, ρ, u, p, volume, material of the particles, sorted by x.
type Sample = (f64, f64, f64, f64, f64, usize);

fn snapshot(sim: &Simulation<1>) -> Vec<Sample> {
    let p = sim.particles();
    let mut rows: Vec<Sample> = (0..p.n_real())
        .map(|i| {
            (
                p.position[i][0],
                p.density[i],
                p.velocity[i][0],
                p.pressure[i],
                p.mass[i] / p.density[i],
                p.material_of(i),
            )
        })
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    rows
}

/// Where the pressure, scanning in from the right, first rises through `level`: linear
/// interpolation between the two particles that straddle it (NaN if it never does).
fn crossing(samples: &[Sample], level: f64) -> f64 {
    samples
        .windows(2)
        .rev()
        .find(|w| w[0].3 >= level && w[1].3 < level)
        .map_or(f64::NAN, |w| {
            w[0].0 + (w[0].3 - level) / (w[0].3 - w[1].3) * (w[1].0 - w[0].0)
        })
}

struct Settings {
    length: f64,
    detonation: Detonation,
    ramp: f64,
    config: SimulationConfig,
    eta: f64,
}

fn settings(params: &Params) -> Result<Settings, VerifyError> {
    let library = Library::standard();
    let entry = library.entry("tnt")?;
    let value = |k: &str| {
        entry
            .parameters
            .get(k)
            .map(|p| p.value)
            .ok_or_else(|| VerifyError::MissingParameter {
                material: "tnt".into(),
                model: entry.model.clone(),
                parameter: k.into(),
            })
    };
    let jwl = Jwl::new(
        value("rho0")?,
        value("a")?,
        value("b")?,
        value("r1")?,
        value("r2")?,
        value("omega")?,
    )?;
    let detonation = Detonation::new(&jwl, value("e0")?);
    let length = params.number("length", 1e-4, 10.0)?;
    let eta = params.number("eta", 0.5, 4.0)?;
    let config = SimulationConfig {
        time_steps: blastsph_solver::TimeSteps::Global,
        formulation: Formulation::Cartesian(Density::Continuity(SmoothingLength::FollowDensity {
            eta,
        })),
        kernel: KernelShape::CubicSpline,
        viscosity: ArtificialViscosity::default(),
        energy: EnergyEquation::OwnPressure,
        cfl: params.cfl()?,
        min_time_step: 1e-9 * length / detonation.speed,
        ..SimulationConfig::default()
    };
    Ok(Settings {
        length,
        detonation,
        ramp: params.number("ramp", 0.1, 10.0)?,
        config,
        eta,
    })
}

struct Measured {
    run: Run,
    snapshot: Option<Snapshot>,
    /// The profile at the second look, inside the charge.
    profile: Vec<Sample>,
    /// The profile at the end, in the air.
    end: Vec<Sample>,
}

fn run_one(
    s: &Settings,
    n: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let library = Library::standard();
    let dx = s.length / n as f64;
    let (rho_tnt, e_tnt) = library.ambient_state("tnt")?;
    let (rho_air, e_air) = library.ambient_state("air")?;
    let init: Vec<ParticleInit<1>> = (0..2 * n)
        .map(|k| {
            let (rho, e, material) = if k < n {
                (rho_tnt, e_tnt, 0)
            } else {
                (rho_air, e_air, 1)
            };
            ParticleInit {
                position: Vector::<1>::new((k as f64 + 0.5) * dx),
                velocity: Vector::<1>::zeros(),
                mass: rho * dx,
                smoothing_length: s.eta * dx,
                density: rho,
                internal_energy: e,
                material,
            }
        })
        .collect();
    let positions: Vec<Vector<1>> = init.iter().map(|p| p.position).collect();
    let burn = ProgrammedBurn::from_points(
        &positions,
        |i| init[i].material == 0,
        &[Vector::<1>::zeros()],
        s.detonation.speed,
        s.ramp,
    )?;
    let domain = Domain::with_sides(
        Vector::<1>::new(0.0),
        Vector::<1>::new(10.0 * s.length),
        [Boundary::Wall],
        [Boundary::Open],
    )?;
    let materials = vec![library.material("tnt")?, library.material("air")?];
    let transit = s.length / s.detonation.speed;
    let mut run = Run::new(format!("n = {n}"), "", init.len(), dx);
    let empty = |run: Run| Measured {
        run,
        snapshot: None,
        profile: Vec::new(),
        end: Vec::new(),
    };
    let start = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<1>::with_programmed_burn(
        &init, materials, domain, s.config, burn,
    ))?
    else {
        return Ok(empty(run));
    };
    let books = Conservation::open(&sim);
    let p_cj = s.detonation.cj.pressure;
    let mut looks = Vec::new();
    let mut outcome = Ok(());
    for fraction in [FIRST_LOOK, SECOND_LOOK, END] {
        outcome = sim.run_until(fraction * transit, |t| progress(t / (END * transit)));
        if outcome.is_err() {
            break;
        }
        looks.push(snapshot(&sim));
    }
    run.record_work(&sim, start);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
        return Ok(empty(run));
    }
    books.close(&sim, &mut run.metrics);
    let m = &mut run.metrics;
    // the detonation front: where the pressure crosses half of p_CJ
    let (first, second) = (
        crossing(&looks[0], 0.5 * p_cj),
        crossing(&looks[1], 0.5 * p_cj),
    );
    // reported only: the programmed burn lights each particle at the time D_CJ sets, so the
    // front runs at D_CJ by construction
    let speed = (second - first) / ((SECOND_LOOK - FIRST_LOOK) * transit);
    m.insert("front_speed".into(), speed);
    m.insert(
        "front_speed_relative".into(),
        (speed / s.detonation.speed - 1.0).abs(),
    );
    let peak = looks[1]
        .iter()
        .filter(|q| q.5 == 0)
        .map(|q| q.3)
        .fold(0.0, f64::max);
    m.insert("peak_pressure".into(), peak);
    m.insert("peak_pressure_over_p_cj".into(), peak / p_cj);
    let t2 = SECOND_LOOK * transit;
    let in_charge: Vec<&Sample> = looks[1].iter().filter(|q| q.5 == 0).collect();
    let volume: Vec<f64> = in_charge.iter().map(|q| q.4).collect();
    let pressure: Vec<f64> = in_charge.iter().map(|q| q.3 / p_cj).collect();
    let exact: Vec<f64> = in_charge
        .iter()
        .map(|q| s.detonation.sample(q.0, t2).2 / p_cj)
        .collect();
    // relative to p_CJ and per unit length of the slab
    run.errors.insert(
        "l1_p_over_p_cj".into(),
        l1_error(&pressure, &exact, &volume) * volume.iter().sum::<f64>() / s.length,
    );
    // the products at rest behind the Taylor wave, 0 ≤ x ≤ c_rest t: their pressure, averaged
    // over the middle of that region (clear of the wall's kernel and of the fan's tail)
    let (rest_speed, rest_pressure) = s.detonation.rest();
    let plateau: Vec<f64> = in_charge
        .iter()
        .filter(|q| q.0 > 0.2 * rest_speed * t2 && q.0 < 0.8 * rest_speed * t2)
        .map(|q| q.3)
        .collect();
    m.insert("plateau_particles".into(), plateau.len() as f64);
    m.insert("exact_plateau_pressure".into(), rest_pressure);
    run.errors.insert(
        "plateau_pressure_relative".into(),
        (plateau.iter().sum::<f64>() / plateau.len() as f64 / rest_pressure - 1.0).abs(),
    );
    // after the break-out: the air shock, where the pressure crosses ten atmospheres (the air's
    // open far end, at one atmosphere, expands on its own and stays below that)
    let air_shock = crossing(&looks[2], 1.01325e6);
    m.insert("air_shock_position_at_end".into(), air_shock);
    m.insert(
        "min_density_at_end".into(),
        looks[2].iter().map(|q| q.1).fold(f64::INFINITY, f64::min),
    );
    let end = looks.pop().expect("three looks");
    let profile = looks.pop().expect("three looks");
    Ok(Measured {
        run,
        snapshot: Some(Snapshot::of(&sim)),
        profile,
        end,
    })
}

pub fn run(params: &Params, progress: &(dyn Fn(f64) + Sync)) -> Result<ProblemOutput, VerifyError> {
    let s = settings(params)?;
    let resolutions = params.integers("n", 10, 100_000)?;
    let mut measured = Vec::new();
    for (k, &n) in resolutions.iter().enumerate() {
        let part = |f: f64| progress((k as f64 + f) / resolutions.len() as f64);
        measured.push(run_one(&s, n, &part)?);
    }
    let order_of = |k: usize| resolutions[k];
    let finest = (0..resolutions.len()).max_by_key(|&k| order_of(k)).unwrap();
    let coarsest = (0..resolutions.len()).min_by_key(|&k| order_of(k)).unwrap();
    let mut checks = Vec::new();
    for m in &measured {
        checks.push(Check::at_least(
            format!(
                "completed_without_blow_up_{}",
                m.run.label.replace(" = ", "_")
            ),
            f64::from(m.run.failure.is_none()),
            1.0,
        ));
    }
    let get = |k: usize, key: &str| {
        let run = &measured[k].run;
        run.errors
            .get(key)
            .or_else(|| run.metrics.get(key))
            .copied()
            .unwrap_or(f64::NAN)
    };
    let fine = &measured[finest].run;
    if fine.failure.is_none() {
        let n_fine = order_of(finest);
        // Limits at LIMIT_RESOLUTION particles and finer (a coarser run's errors grow at first
        // order, its limits with them): about twice the values measured there. L1(p)/p_CJ:
        // 3.1e-3, 1.6e-3, 8.7e-4, 5.3e-4 at 100–800 particles. The plateau: 0.04 %, 0.43 %,
        // 0.49 %, 0.57 %, a bias that does not shrink with h (likely because the burn releases
        // its energy along the viscous ramp rather than on the Rayleigh line, which leaves the
        // products on a slightly different isentrope than the CJ point's; not yet shown).
        let coarseness = (LIMIT_RESOLUTION as f64 / n_fine as f64).max(1.0);
        checks.push(Check::at_most(
            format!("l1_p_over_p_cj_n_{n_fine}"),
            get(finest, "l1_p_over_p_cj"),
            3.5e-3 * coarseness,
        ));
        checks.push(Check::at_most(
            format!("plateau_pressure_relative_n_{n_fine}"),
            get(finest, "plateau_pressure_relative"),
            1e-2 * coarseness,
        ));
    }
    for m in measured.iter().filter(|m| m.run.failure.is_none()) {
        // the chemical energy is in e from the start; measured 9e-5–1.1e-4 at 100–800
        // particles
        checks.extend(conservation_checks(&m.run, 1e-3));
    }
    let order = observed_orders(measured.iter().map(|m| &m.run), &["l1_p_over_p_cj"]);
    if measured.len() >= 2 {
        // the peak approaches p_CJ as the ramp (2h) and the viscous spread shrink with h
        checks.push(Check::at_most(
            "peak_pressure_error_finest_over_coarsest",
            (get(finest, "peak_pressure_over_p_cj") - 1.0).abs()
                / (get(coarsest, "peak_pressure_over_p_cj") - 1.0).abs(),
            1.0,
        ));
        // first order at the front (measured 0.86)
        checks.push(Check::at_least(
            "observed_order_l1_p",
            order.get("l1_p_over_p_cj").copied().unwrap_or(f64::NAN),
            0.5,
        ));
    }
    let mut runs: Vec<Run> = measured.iter().map(|m| m.run.clone()).collect();
    for run in &mut runs {
        run.metrics
            .insert("exact_p_cj".into(), s.detonation.cj.pressure);
        run.metrics.insert("exact_d_cj".into(), s.detonation.speed);
    }
    let (profile, figure) = outputs(&s, &measured[finest]);
    Ok(ProblemOutput {
        record: Record::new(NAME, Level::Quick, runs, order, checks, finest),
        profile,
        figure,
        snapshot: measured[finest].snapshot.clone(),
    })
}

fn outputs(s: &Settings, m: &Measured) -> (Table, Figure) {
    let transit = s.length / s.detonation.speed;
    let t2 = SECOND_LOOK * transit;
    let mut table = Table::new(&[
        "x",
        "material",
        "rho",
        "rho_exact",
        "u",
        "u_exact",
        "p",
        "p_exact",
    ]);
    for q in &m.profile {
        let (rho, u, p) = if q.5 == 0 {
            s.detonation.sample(q.0, t2)
        } else {
            (f64::NAN, 0.0, f64::NAN)
        };
        table
            .rows
            .push(vec![q.0, q.5 as f64, q.1, rho, q.2, u, q.3, p]);
    }
    let fine: Vec<f64> = (0..=1000).map(|k| s.length * k as f64 / 1000.0).collect();
    let sph = |samples: &[Sample], k: usize| -> Vec<(f64, f64)> {
        samples.iter().map(|q| (q.0, [q.1, q.2, q.3][k])).collect()
    };
    let mut panels: Vec<Panel> = [
        ("density", "rho (kg/m3)"),
        ("velocity", "u (m/s)"),
        ("pressure", "p (Pa)"),
    ]
    .iter()
    .enumerate()
    .map(|(k, (title, y))| Panel {
        title: format!("{title} at 0.9 L/D"),
        x_label: "x (m)".into(),
        y_label: y.to_string(),
        series: vec![
            Series {
                label: "SPH".into(),
                points: sph(&m.profile, k),
                style: Style::Markers,
            },
            Series {
                label: "exact (CJ + Taylor wave)".into(),
                points: fine
                    .iter()
                    .map(|&x| {
                        let v = s.detonation.sample(x, t2);
                        (x, [v.0, v.1, v.2][k])
                    })
                    .collect(),
                style: Style::Line,
            },
        ],
        ..Panel::default()
    })
    .collect();
    panels.push(Panel {
        title: "pressure at 1.3 L/D (products in air)".into(),
        x_label: "x (m)".into(),
        y_label: "p (Pa)".into(),
        series: vec![Series {
            label: "SPH".into(),
            points: sph(&m.end, 2),
            style: Style::Markers,
        }],
        ..Panel::default()
    });
    let figure = Figure {
        title: format!(
            "{NAME}: TNT slab {} m, JWL CJ state p = {:.3e} Pa, D = {:.0} m/s",
            s.length, s.detonation.cj.pressure, s.detonation.speed
        ),
        panels,
    };
    (table, figure)
}
