//! `impedance-low-high`, `impedance-high-low`, `impedance-symmetric`: a shock meeting a
//! material interface in 1D (the thesis' §2-17 cases), against the exact interface state of
//! [`crate::impedance`].
//!
//! Set-up (x in m): a flyer of A (length 3L, moving at V) hits a target made of A (length
//! `target_a_mm`, L) bonded to B (length 2L), all at rest and at zero pressure, equal particle
//! spacing everywhere (so masses differ by the density ratio), open ends. The impact sends a
//! shock (u1 = V/2, symmetric impact) through the target's A layer; it reaches B at
//! t_hit = L/Us_1 and splits: transmitted shock into B, reflected shock or rarefaction into A.
//! With no A layer (`target_a_mm = 0`) the flyer hits B directly. The run ends when the
//! transmitted shock has crossed 60 % of B; the flyer's free back stays out of reach.
//!
//! Measured at the end: the interface pressure and particle velocity averaged over the plateau
//! between the two waves (excluding 6 spacings at each wave and at the interface), the
//! transmitted shock speed from its positions at half and full time, the reflected wave type
//! from the pressure on either side of it, the gap between the two materials' particles, and
//! the L1 error of the velocity profile.

use crate::impedance::{self, InterfaceSolution, MaterialState, Wave, WaveKind, WavePattern};
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
    ArtificialViscosity, Boundary, Density, Domain, EquationOfState, Formulation, InterfacePenalty,
    KernelShape, Simulation, SimulationConfig, SmoothingLength, Vector,
};

pub const NAMES: [&str; 3] = [
    "impedance-low-high",
    "impedance-high-low",
    "impedance-symmetric",
];

/// Fraction of B the transmitted shock crosses by the end of the run.
const END_FRACTION: f64 = 0.6;
/// Plateau windows stay this many initial spacings clear of waves and of the interface: a
/// shock spreads over about 4 smoothing lengths (h = 1.2 spacings here).
const MARGIN_SPACINGS: f64 = 6.0;

pub fn infos() -> Vec<super::ProblemInfo> {
    let cases = [
        (
            NAMES[0],
            "shock from Al 6061 into Cu OFHC: stronger transmitted shock, reflected shock",
            "al-6061",
            "cu-ofhc",
            10.0,
        ),
        (
            NAMES[1],
            "shock from Cu OFHC into Al 6061: weaker transmitted shock, reflected rarefaction",
            "cu-ofhc",
            "al-6061",
            10.0,
        ),
        (
            NAMES[2],
            "Cu OFHC flyer onto Cu OFHC at 1000 m/s: up = V/2 exactly",
            "cu-ofhc",
            "cu-ofhc",
            0.0,
        ),
    ];
    cases
        .into_iter()
        .map(|(name, summary, a, b, target_a)| super::ProblemInfo {
            name,
            summary,
            params: vec![
                ParamSpec::new("a", a, "material A (flyer and target layer)"),
                ParamSpec::new("b", b, "material B (at rest behind the A layer)"),
                ParamSpec::new("impact", 1000.0, "flyer velocity V (m/s)"),
                ParamSpec::new(
                    "target_a_mm",
                    target_a,
                    "thickness L of the A layer the shock crosses before B (mm; 0: flyer onto B)",
                ),
                ParamSpec::per_level(
                    "n_per_cm",
                    "100,200",
                    "100,200,400,800",
                    "particles per cm (one run each)",
                ),
                ParamSpec::new("cfl", 0.3, "Courant number C"),
                ParamSpec::new("alpha", 1.0, "artificial viscosity α"),
                ParamSpec::new("beta", 2.0, "artificial viscosity β"),
                ParamSpec::new(
                    "penalty",
                    0.0,
                    "interface penalty p̄ (m²/s², seed eq. 3-30 with n1 = 12, n2 = 6; 0: off)",
                ),
                // η = 2 (8 neighbours in 1D), as in the shock tubes: at η = 1.2 the discrete
                // kernel gradient sum misses its continuum value by ~0.2 % whatever the spacing,
                // so the continuity density overshoots the Hugoniot density and the transmitted
                // shock runs 1.9 % fast at every resolution (measured 100–800 per cm); at η = 2
                // the shock speed error is 5e-4 … 4e-5 and the profile converges at first order
                ParamSpec::new("eta", 2.0, "smoothing length h = η·m/ρ"),
            ],
        })
        .collect()
}

/// The exact solution: the impact, then (with an A layer) the interface.
struct Exact {
    impact_velocity: f64,
    /// Shock into the flyer (left-facing) and the incident shock (right-facing) from the impact.
    flyer_shock: Wave,
    incident: Wave,
    /// Where and when the incident shock meets B (0, 0 without an A layer).
    x_hit: f64,
    t_hit: f64,
    /// The waves leaving the interface, centred at (x_hit, t_hit).
    pattern: WavePattern,
    interface: InterfaceSolution,
    rho_a: f64,
}

impl Exact {
    fn new(
        eos_a: &dyn EquationOfState,
        eos_b: &dyn EquationOfState,
        (rho_a, rho_b): (f64, f64),
        v: f64,
        layer: f64,
    ) -> Result<Self, VerifyError> {
        let rest_a = MaterialState::new(eos_a, rho_a, 0.0, 0.0);
        let rest_b = MaterialState::new(eos_b, rho_b, 0.0, 0.0);
        let flyer = MaterialState {
            velocity: v,
            ..rest_a
        };
        let (impact, pattern, x_hit, t_hit) = if layer > 0.0 {
            let impact = impedance::solve(eos_a, flyer, eos_a, rest_a)?;
            let t_hit = layer / impact.into_b.head_speed;
            let pattern = WavePattern::new(eos_a, impact.into_b.behind, eos_b, rest_b)?;
            (impact, pattern, layer, t_hit)
        } else {
            let pattern = WavePattern::new(eos_a, flyer, eos_b, rest_b)?;
            (pattern.solution, pattern, 0.0, 0.0)
        };
        Ok(Self {
            impact_velocity: v,
            flyer_shock: impact.into_a,
            incident: impact.into_b,
            x_hit,
            t_hit,
            interface: pattern.solution,
            pattern,
            rho_a,
        })
    }

    /// The end time of a run with B of length `length_b`.
    fn end_time(&self, length_b: f64) -> f64 {
        self.t_hit + END_FRACTION * length_b / self.interface.into_b.head_speed
    }

    fn interface_position(&self, t: f64) -> f64 {
        self.x_hit + self.interface.velocity * (t - self.t_hit).max(0.0)
    }

    /// (ρ, u, p) at x, t.
    fn sample(&self, x: f64, t: f64) -> (f64, f64, f64) {
        let shocked = |w: &Wave| (w.behind.density, w.behind.velocity, w.behind.pressure);
        if x < self.flyer_shock.head_speed * t {
            (self.rho_a, self.impact_velocity, 0.0)
        } else if t <= self.t_hit {
            if x < self.incident.head_speed * t {
                shocked(&self.incident)
            } else {
                (self.rho_a, 0.0, 0.0)
            }
        } else {
            self.pattern.sample((x - self.x_hit) / (t - self.t_hit))
        }
    }
}

/// One particle at the end of a run.
#[derive(Clone, Copy, Debug)]
struct Sample {
    x: f64,
    density: f64,
    velocity: f64,
    pressure: f64,
    volume: f64,
    material: u16,
}

struct Settings {
    a: String,
    b: String,
    exact: Exact,
    /// Lengths of the flyer, the A layer and B (m).
    lengths: [f64; 3],
    config: SimulationConfig,
    eta: f64,
}

fn settings(params: &Params) -> Result<Settings, VerifyError> {
    let library = Library::standard();
    let a = params.text("a");
    let b = params.text("b");
    let (material_a, material_b) = (library.material(&a)?, library.material(&b)?);
    let (rho_a, e_a) = library.ambient_state(&a)?;
    let (rho_b, e_b) = library.ambient_state(&b)?;
    for (name, e) in [(&a, e_a), (&b, e_b)] {
        if e != 0.0 {
            return Err(VerifyError::bad_value(
                "material",
                name,
                "a condensed material at rest at zero pressure (mie-gruneisen or compaction)",
            ));
        }
    }
    let v = params.number("impact", 1.0, 1e4)?;
    let layer = 1e-3 * params.number("target_a_mm", 0.0, 100.0)?;
    // lengths scale with the A layer (10 mm where it is absent): flyer 3L, B 2L
    let unit = if layer > 0.0 { layer } else { 10e-3 };
    let exact = Exact::new(&*material_a.eos, &*material_b.eos, (rho_a, rho_b), v, layer)?;
    let eta = params.number("eta", 0.5, 4.0)?;
    let config = SimulationConfig {
        time_steps: blastsph_solver::TimeSteps::Global,
        // continuity density keeps the density jump at the interface sharp (see
        // Density::Continuity for the volume-weighted form used across materials)
        formulation: Formulation::Cartesian(Density::Continuity(SmoothingLength::FollowDensity {
            eta,
        })),
        kernel: KernelShape::CubicSpline,
        viscosity: ArtificialViscosity {
            alpha: params.number("alpha", 0.0, 10.0)?,
            beta: params.number("beta", 0.0, 10.0)?,
            interface_penalty: match params.number("penalty", 0.0, 1e12)? {
                0.0 => None,
                p_bar => Some(InterfacePenalty::seed(p_bar)),
            },
            ..ArtificialViscosity::default()
        },
        energy: blastsph_solver::EnergyEquation::OwnPressure,
        cfl: params.cfl()?,
        min_time_step: 1e-9 * exact.end_time(2.0 * unit),
        ..SimulationConfig::default()
    };
    Ok(Settings {
        a,
        b,
        exact,
        lengths: [3.0 * unit, layer, 2.0 * unit],
        config,
        eta,
    })
}

/// What one resolution measured.
struct Measured {
    run: Run,
    snapshot: Option<Snapshot>,
    /// Final (x, ρ, u, p, material) sorted by x.
    profile: Vec<Sample>,
    reflected: Option<WaveKind>,
}

fn setup(s: &Settings, dx: f64) -> Result<(Vec<ParticleInit<1>>, Domain<1>), VerifyError> {
    let [flyer, layer, length_b] = s.lengths;
    let library = Library::standard();
    let rho = [
        library.ambient_state(&s.a)?.0,
        library.ambient_state(&s.b)?.0,
    ];
    let mut init = Vec::new();
    let mut add = |from: f64, to: f64, material: u16, velocity: f64| {
        let n = ((to - from) / dx).round() as usize;
        for k in 0..n {
            init.push(ParticleInit {
                position: Vector::<1>::new(from + (k as f64 + 0.5) * dx),
                velocity: Vector::<1>::new(velocity),
                mass: rho[material as usize] * dx,
                smoothing_length: s.eta * dx,
                density: rho[material as usize],
                internal_energy: 0.0,
                material,
            });
        }
    };
    add(-flyer, 0.0, 0, s.exact.impact_velocity);
    add(0.0, layer, 0, 0.0);
    add(layer, layer + length_b, 1, 0.0);
    let domain = Domain::with_sides(
        Vector::<1>::new(-flyer - 1.0),
        Vector::<1>::new(layer + length_b + 1.0),
        [Boundary::Open],
        [Boundary::Open],
    )?;
    Ok((init, domain))
}

/// The transmitted shock's position: where the pressure in B first falls below half the
/// interface pressure, scanning from the interface (linear interpolation between particles).
fn shock_position(profile: &[Sample], p_star: f64) -> f64 {
    let half = 0.5 * p_star;
    let in_b: Vec<_> = profile.iter().filter(|q| q.material == 1).collect();
    let start = in_b.iter().position(|q| q.pressure >= half).unwrap_or(0);
    for w in in_b[start..].windows(2) {
        if w[0].pressure >= half && w[1].pressure < half {
            let f = (w[0].pressure - half) / (w[0].pressure - w[1].pressure);
            return w[0].x + f * (w[1].x - w[0].x);
        }
    }
    f64::NAN
}

fn snapshot(sim: &Simulation<1>) -> Vec<Sample> {
    let p = sim.particles();
    let mut rows: Vec<Sample> = (0..p.n_real())
        .map(|i| Sample {
            x: p.position[i][0],
            density: p.density[i],
            velocity: p.velocity[i][0],
            pressure: p.pressure[i],
            volume: p.mass[i] / p.density[i],
            material: p.material_of(i) as u16,
        })
        .collect();
    rows.sort_by(|a, b| a.x.total_cmp(&b.x));
    rows
}

/// Mean of `field` over the particles with x in [lo, hi] (NaN if none).
fn window_mean(profile: &[Sample], lo: f64, hi: f64, field: impl Fn(&Sample) -> f64) -> f64 {
    let values: Vec<f64> = profile
        .iter()
        .filter(|q| q.x >= lo && q.x <= hi)
        .map(field)
        .collect();
    values.iter().sum::<f64>() / values.len() as f64
}

fn run_one(
    s: &Settings,
    n_per_cm: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let dx = 1e-2 / n_per_cm as f64;
    let (init, domain) = setup(s, dx)?;
    let library = Library::standard();
    let materials = vec![library.material(&s.a)?, library.material(&s.b)?];
    let exact = &s.exact;
    let t_end = exact.end_time(s.lengths[2]);
    let t_mid = exact.t_hit + 0.5 * (t_end - exact.t_hit);
    let mut run = Run::new(format!("{n_per_cm} per cm"), "", init.len(), dx);
    let start = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<1>::new(&init, materials, domain, s.config))?
    else {
        return Ok(Measured {
            run,
            snapshot: None,
            profile: Vec::new(),
            reflected: None,
        });
    };
    let books = Conservation::open(&sim);
    let mut outcome = sim.run_until(t_mid, |t| progress(t / t_end));
    let mid = snapshot(&sim);
    if outcome.is_ok() {
        outcome = sim.run_until(t_end, |t| progress(t / t_end));
    }
    run.record_work(&sim, start);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
        return Ok(Measured {
            run,
            snapshot: None,
            profile: Vec::new(),
            reflected: None,
        });
    }
    let end = snapshot(&sim);
    books.close(&sim, &mut run.metrics);
    let m = &mut run.metrics;
    let s_int = &exact.interface;
    let tau = t_end - exact.t_hit;
    // interface: between the last A particle and the first B particle
    let last_a = end
        .iter()
        .filter(|q| q.material == 0)
        .map(|q| q.x)
        .fold(f64::MIN, f64::max);
    let first_b = end
        .iter()
        .filter(|q| q.material == 1)
        .map(|q| q.x)
        .fold(f64::MAX, f64::min);
    let x_interface = 0.5 * (last_a + first_b);
    // the exact gap between the two interface particles: half a compressed spacing on each side
    let gap_exact = 0.5 * dx * (exact.rho_a / s_int.into_a.behind.density)
        + 0.5 * dx * (exact.pattern.right.density / s_int.into_b.behind.density);
    m.insert(
        "interface_gap_over_exact".into(),
        (first_b - last_a) / gap_exact,
    );
    let mid_gap = {
        let last_a = mid
            .iter()
            .filter(|q| q.material == 0)
            .map(|q| q.x)
            .fold(f64::MIN, f64::max);
        let first_b = mid
            .iter()
            .filter(|q| q.material == 1)
            .map(|q| q.x)
            .fold(f64::MAX, f64::min);
        (first_b - last_a) / gap_exact
    };
    m.insert("interface_gap_over_exact_at_half_time".into(), mid_gap);
    m.insert(
        "interface_position_error_over_dx".into(),
        (x_interface - exact.interface_position(t_end)).abs() / dx,
    );
    // plateau: from the reflected wave's tail to the transmitted shock, clear of both and of
    // the interface
    let margin = MARGIN_SPACINGS * dx;
    let tail = exact.x_hit + s_int.into_a.tail_speed * tau;
    let front = exact.x_hit + s_int.into_b.head_speed * tau;
    let in_plateau = |q: &&Sample| {
        (q.x > tail + margin && q.x < x_interface - margin)
            || (q.x > x_interface + margin && q.x < front - margin)
    };
    let plateau: Vec<_> = end.iter().filter(in_plateau).collect();
    let mean =
        |f: fn(&Sample) -> f64| plateau.iter().map(|q| f(q)).sum::<f64>() / plateau.len() as f64;
    let (p_plateau, u_plateau) = (mean(|q| q.pressure), mean(|q| q.velocity));
    m.insert("plateau_particles".into(), plateau.len() as f64);
    m.insert("plateau_pressure".into(), p_plateau);
    m.insert("plateau_velocity".into(), u_plateau);
    run.errors.insert(
        "interface_pressure_relative".into(),
        (p_plateau / s_int.pressure - 1.0).abs(),
    );
    run.errors.insert(
        "interface_velocity_relative".into(),
        (u_plateau / s_int.velocity - 1.0).abs(),
    );
    // transmitted shock speed from its positions at half and full time
    let shock_speed = (shock_position(&end, s_int.pressure) - shock_position(&mid, s_int.pressure))
        / (t_end - t_mid);
    m.insert("transmitted_shock_speed".into(), shock_speed);
    run.errors.insert(
        "transmitted_shock_speed_relative".into(),
        (shock_speed / s_int.into_b.head_speed - 1.0).abs(),
    );
    // reflected wave type: pressure ahead of it (the incident state, or the flyer) against the
    // pressure behind it (the A side of the plateau); a rise is a shock, a fall a rarefaction
    let head = exact.x_hit + s_int.into_a.head_speed * tau;
    // (with an A layer the incident state lies between the flyer's shock and the reflected
    // wave; without one the reflected wave is the flyer's shock and the flyer lies ahead)
    let ahead_lo = if exact.t_hit > 0.0 {
        (head - 4.0 * margin).max(exact.flyer_shock.head_speed * t_end + margin)
    } else {
        head - 4.0 * margin
    };
    let p_ahead = window_mean(&end, ahead_lo, head - margin, |q| q.pressure);
    let p_behind = window_mean(&end, tail + margin, x_interface - margin, |q| q.pressure);
    m.insert("reflected_pressure_ahead".into(), p_ahead);
    m.insert("reflected_pressure_behind".into(), p_behind);
    let reflected = if !(p_ahead.is_finite() && p_behind.is_finite()) {
        None
    } else if p_behind > p_ahead {
        Some(WaveKind::Shock)
    } else {
        Some(WaveKind::Rarefaction)
    };
    // the L1 error of the velocity profile over the whole bar, relative to V
    let volume: Vec<f64> = end.iter().map(|q| q.volume).collect();
    let u: Vec<f64> = end.iter().map(|q| q.velocity).collect();
    let u_exact: Vec<f64> = end.iter().map(|q| exact.sample(q.x, t_end).1).collect();
    run.errors.insert(
        "l1_u_over_v".into(),
        l1_error(&u, &u_exact, &volume) / exact.impact_velocity,
    );
    Ok(Measured {
        run,
        snapshot: Some(Snapshot::of(&sim)),
        profile: end,
        reflected,
    })
}

pub fn run(
    name: &str,
    params: &Params,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let s = settings(params)?;
    let resolutions = params.integers("n_per_cm", 10, 100_000)?;
    let mut measured = Vec::new();
    for (k, &n) in resolutions.iter().enumerate() {
        let part = |f: f64| progress((k as f64 + f) / resolutions.len() as f64);
        measured.push(run_one(&s, n, &part)?);
    }
    let finest = (0..resolutions.len())
        .max_by_key(|&k| resolutions[k])
        .expect("at least one resolution");
    let exact = &s.exact;
    let expected = exact.interface.into_a.kind;
    let mut checks = Vec::new();
    let completed = measured.iter().filter(|m| m.run.failure.is_none()).count();
    checks.push(Check::at_least(
        "runs_completed_without_blow_up",
        completed as f64,
        measured.len() as f64,
    ));
    let fine = &measured[finest].run;
    let error = |key: &str| fine.errors.get(key).copied().unwrap_or(f64::NAN);
    // 3 % of the exact interface state and transmitted shock speed (measured at most 0.41 %
    // at 100 per cm)
    for key in [
        "interface_pressure_relative",
        "interface_velocity_relative",
        "transmitted_shock_speed_relative",
    ] {
        checks.push(Check::at_most(key, error(key), 0.03));
    }
    for m in measured.iter().filter(|m| m.run.failure.is_none()) {
        // open ends: momentum to round-off; energy measured 2.3e-5 at 100 per cm, falling
        // at first order
        checks.extend(conservation_checks(&m.run, 2.5e-4));
    }
    for m in &measured {
        let label = m.run.label.replace(' ', "_");
        checks.push(Check::at_least(
            format!("reflected_{}_detected_{label}", expected.name()),
            f64::from(m.reflected == Some(expected)),
            1.0,
        ));
        // no interpenetration: the two materials' particles keep at least half the exact gap
        // (a negative value would mean they have passed through each other)
        for key in [
            "interface_gap_over_exact",
            "interface_gap_over_exact_at_half_time",
        ] {
            checks.push(Check::at_least(
                format!("{key}_{label}"),
                m.run.metrics.get(key).copied().unwrap_or(f64::NAN),
                0.5,
            ));
        }
    }
    let order = observed_orders(
        measured.iter().map(|m| &m.run),
        &["l1_u_over_v", "interface_pressure_relative"],
    );
    if measured.len() >= 2 {
        // the error falls with resolution: shocks limit the L1 error of the velocity profile
        // to first order; 0.5 leaves room for the pre-asymptotic range of the quick level
        checks.push(Check::at_least(
            "observed_order_l1_u",
            order.get("l1_u_over_v").copied().unwrap_or(f64::NAN),
            0.5,
        ));
    }
    let mut record_runs: Vec<Run> = measured.iter().map(|m| m.run.clone()).collect();
    for run in &mut record_runs {
        run.metrics
            .insert("exact_interface_pressure".into(), exact.interface.pressure);
        run.metrics
            .insert("exact_interface_velocity".into(), exact.interface.velocity);
        run.metrics.insert(
            "exact_transmitted_shock_speed".into(),
            exact.interface.into_b.head_speed,
        );
    }
    let (profile, figure) = outputs(name, &s, &measured[finest].profile);
    Ok(ProblemOutput {
        record: Record::new(name, Level::Quick, record_runs, order, checks, finest),
        profile,
        figure,
        snapshot: measured[finest].snapshot.clone(),
    })
}

fn outputs(name: &str, s: &Settings, profile: &[Sample]) -> (Table, Figure) {
    let exact = &s.exact;
    let t_end = exact.end_time(s.lengths[2]);
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
    for q in profile {
        let (rho, u, p) = exact.sample(q.x, t_end);
        table.rows.push(vec![
            q.x,
            f64::from(q.material),
            q.density,
            rho,
            q.velocity,
            u,
            q.pressure,
            p,
        ]);
    }
    let x_lo = -s.lengths[0];
    let x_hi = s.lengths[1] + s.lengths[2];
    let fine: Vec<f64> = (0..=2000)
        .map(|k| x_lo + (x_hi - x_lo) * k as f64 / 2000.0)
        .collect();
    let labels = [
        ("density", "rho (kg/m3)"),
        ("velocity", "u (m/s)"),
        ("pressure", "p (Pa)"),
    ];
    let panels = labels
        .iter()
        .enumerate()
        .map(|(k, (title, y_label))| {
            let pick = |v: (f64, f64, f64)| [v.0, v.1, v.2][k];
            Panel {
                title: title.to_string(),
                x_label: "x (m)".into(),
                y_label: y_label.to_string(),
                series: vec![
                    Series {
                        label: "SPH".into(),
                        points: profile
                            .iter()
                            .map(|q| (q.x, pick((q.density, q.velocity, q.pressure))))
                            .collect(),
                        style: Style::Markers,
                    },
                    Series {
                        label: "exact".into(),
                        points: fine
                            .iter()
                            .map(|&x| (x, pick(exact.sample(x, t_end))))
                            .collect(),
                        style: Style::Line,
                    },
                ],
                ..Panel::default()
            }
        })
        .collect();
    let figure = Figure {
        title: format!(
            "{name}: {} onto {} at {} m/s, t = {:.3e} s (p* = {:.3e} Pa, u* = {:.1} m/s, reflected {})",
            s.a,
            s.b,
            exact.impact_velocity,
            t_end,
            exact.interface.pressure,
            exact.interface.velocity,
            exact.interface.into_a.kind.name()
        ),
        panels,
    };
    (table, figure)
}
