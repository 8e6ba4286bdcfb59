//! Air blast from a TNT charge against Kingery & Bulmash (see [`crate::scaled::air_blast`]),
//! and Hopkinson–Cranz scaling:
//! - `airblast-free-air`: a sphere of W kg in free air against the free-air relations;
//! - `airblast-surface`: a hemisphere of W kg on the ground against the hemispherical
//!   (surface-burst) relations. A rigid, frictionless ground is a mirror: the hemisphere and
//!   its image are a sphere of 2W in free air, so the scene is the free-air one at 2W, exactly.
//!   The measured surface bursts lost some energy to the ground (cratering, ground shock),
//!   which the rigid mirror does not: the relations themselves put a 2W sphere in free air
//!   4–16 % above the hemispherical burst in peak overpressure at Z = 1–8 (recorded per
//!   gauge), so this scene is expected to lie at or above them; the record gives the ratio
//!   to them per gauge;
//! - `hopkinson-cranz`: the free-air scene at W and at 8W with every length doubled and the
//!   same shells per charge radius; each gauge's overpressure against t/W^{1/3} at matched
//!   Z = R/W^{1/3} must agree within 1 % of its peak. Any length or time fixed in metres or
//!   seconds (rather than in charge radii) breaks the similarity and fails this check.
//!
//! Set-up: W kg of TNT (JWL, LLNL set, lit at its centre and burnt at D_CJ) as a sphere of
//! radius R_c = (3W/(4πρ_TNT))^{1/3} in air (ideal gas, γ = 1.4, 1.225 kg/m³, 101.325 kPa),
//! 1D spherical shells with continuity density (the products meet the air at a density ratio
//! of 1330, which a summed density would smear into a spurious pressure). The charge holds n
//! shells of width R_c/n; the air's shells are max(R_c/n, g·r/n) wide, so that they grow
//! geometrically by (1 + g/n) per shell beyond r = R_c/g: the blast wave's length grows with
//! r (Hopkinson–Cranz), and this keeps the shells per wave length nearly constant with about
//! 46 n shells out to Z = 20 (g = 0.1), where a uniform spacing would need 380 n. The outer
//! edge at Z = 20 is open: its rarefaction reaches the Z = 8 gauge only after the positive
//! phase there has passed. The products and the air out to twice the contact are remapped
//! conservatively onto fresh shells at 5 charge transit times and then at every doubling of
//! the time (see [`rezone`]): the first strong shock leaves the air shells at the contact
//! bunched far closer than their densities say (continuity density with h floored does not
//! see it), and the expanding products' shells grow coarse.
//!
//! Individual time steps (`step_ratio`, 64 by default): the hot products and the fine shells
//! by the contact set the shortest steps, the wide shells far out step up to 64 times longer.
//! At n = 80 (free air) they do 8 % of the global steps' particle updates in two thirds of
//! the time, every gated peak within 1 % of the global run's.
//!
//! The viscosity carries Morris & Monaghan's switch (α from 1 at the shock down to
//! α_min = 0.1 behind it): with a constant α = 1 a weak shock is smeared over about
//! α c/Δu smoothing lengths, some 20 at Z = 8 (overpressure ≈ 10 kPa, Δu ≈ 0.06 c), which
//! cut the Z = 8 peak by a third at n = 40; with the switch the shock's own compression
//! sets α, and the peak comes within 10 %.
//!
//! Gauges at Z = R/W^{1/3} = 0.5, 1, 2, 4, 8 read the overpressure (linear interpolation
//! between the shells that straddle the gauge) after every step; arrival, peak and positive
//! impulse against Kingery–Bulmash. Ideal-gas air with γ = 1.4 ignores the dissociation of
//! the air the fireball heats, so the closest gauge (Z = 0.5, inside the fireball's reach) is
//! reported, not gated.

use crate::gauges::{interpolate, Gauge, GaugeTrace};
use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{
    conservation_checks, phase_seconds, Check, Conservation, ProblemOutput, Qualification, Record,
    Refinement, Run, Table,
};
use crate::scaled::air_blast::{air_blast, AirBlast, Burst};
use crate::svg::{Figure, Panel, Series, Style};
use crate::vtk::Snapshot;
use crate::{Level, VerifyError};
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Domain, EnergyEquation, Formulation, Geometry, KernelShape,
    ProgrammedBurn, ShellDensity, Simulation, SimulationConfig, SmoothingLength, Vector,
    ViscositySwitch,
};
use std::collections::BTreeMap;
use std::f64::consts::PI;

pub const FREE_AIR: &str = "airblast-free-air";
pub const SURFACE: &str = "airblast-surface";
pub const HOPKINSON_CRANZ: &str = "hopkinson-cranz";
pub const NAMES: [&str; 3] = [FREE_AIR, SURFACE, HOPKINSON_CRANZ];

/// The gauges' scaled distances (m/kg^{1/3}).
const GAUGE_Z: [f64; 5] = [0.5, 1.0, 2.0, 4.0, 8.0];
/// The gauges from this scaled distance from the simulated sphere out are checked against
/// Kingery–Bulmash: nearer, the fireball heats the air beyond what an ideal gas with γ = 1.4
/// describes (it dissociates). For the surface burst the sphere is 2W, so its Z = 1 gauge
/// (0.79 from the 2W sphere) is reported, not gated.
const GATED_FROM_Z: f64 = 1.0;
/// Limits on the relative difference from Kingery–Bulmash at Z ≥ 1: peak incident
/// overpressure, arrival time and positive impulse. The fits reproduce their own test data to
/// about 10–20 % (Kingery & Bulmash 1984 quote the scatter of the data they fit), so a code
/// that agrees within these bands is as close as the measurements can tell.
const PEAK_LIMIT: f64 = 0.20;
const ARRIVAL_LIMIT: f64 = 0.10;
const IMPULSE_LIMIT: f64 = 0.25;
/// From this Z out, a failed positive impulse is qualified (a limit of the model, bounded by
/// [`AFTERBURN_IMPULSE_FLOOR`]): measured at 0.71–0.80
/// of Kingery–Bulmash at every resolution from n = 20 to 80 (and with every rezone tried),
/// falling slightly as the shells refine while the peaks rise towards the relations. The
/// products here release the detonation energy alone (JWL's E₀ = 4.3 MJ/kg); the measured
/// TNT charges' products also burnt in the air they mixed with, which lengthens the positive
/// phase more than it raises the peak. The check is kept, evaluated and shown with this
/// evidence (see [`impulse_qualification`]).
const IMPULSE_QUALIFIED_FROM_Z: f64 = 4.0;
/// The lowest impulse over Kingery–Bulmash that missing afterburning is taken to explain. Far
/// from the charge the impulse at a fixed range grows as W^(2/3) (I = W^(1/3) f(Z) with
/// f ∝ 1/Z), so a source carrying half the energy that drives the measured positive phase
/// reads 0.5^(2/3) = 0.63 of it: the bound assumes afterburning at most doubles that energy.
/// No afterburning can raise the impulse, so the bound's top is the relations themselves.
const AFTERBURN_IMPULSE_FLOOR: f64 = 0.63;
/// The run goes on until the Z = 8 gauge's positive phase has passed, by this factor on its
/// Kingery–Bulmash end (arrival + duration).
const END_MARGIN: f64 = 1.3;

pub fn infos() -> Vec<super::ProblemInfo> {
    let scene = |n_quick: &str, n_full: &str| {
        vec![
            ParamSpec::new("charge", 1.0, "TNT mass W (kg)"),
            ParamSpec::per_level(
                "n",
                n_quick,
                n_full,
                "shells across the charge radius (one run each)",
            ),
            ParamSpec::new(
                "grading",
                0.1,
                "far from the charge the air's shells are grading·r/n wide",
            ),
            ParamSpec::new(
                "outer_z",
                20.0,
                "the open outer edge's R/W^(1/3) (m/kg^(1/3))",
            ),
            ParamSpec::new("ramp", 2.0, "burn ramp width (smoothing lengths)"),
            ParamSpec::new("cfl", 0.3, "Courant number C"),
            ParamSpec::new(
                "alpha_min",
                0.1,
                "Morris-Monaghan switch: the viscosity's alpha away from shocks (1: off)",
            ),
            // η = 2 as in the other 1D problems
            ParamSpec::new("eta", 2.0, "smoothing length h = η·(shell width)"),
            ParamSpec::step_ratio(64),
        ]
    };
    vec![
        super::ProblemInfo {
            name: FREE_AIR,
            summary: "TNT sphere in free air (1D spherical, JWL + ideal gas) against Kingery–Bulmash",
            params: scene("20,40", "20,40,80"),
        },
        super::ProblemInfo {
            name: SURFACE,
            summary: "TNT hemisphere on rigid ground (its mirror image: a 2W sphere) against Kingery–Bulmash hemispherical",
            params: scene("20,40", "20,40,80"),
        },
        super::ProblemInfo {
            name: HOPKINSON_CRANZ,
            summary: "the free-air scene at W and 8W: overpressure against t/W^(1/3) at matched Z",
            params: scene("20", "40"),
        },
    ]
}

/// What the scene needs besides the shells: the charge, the burst it stands for and the
/// solver's settings.
struct Settings {
    /// W, the charge the gauges' Z and the relations refer to.
    charge_kg: f64,
    burst: Burst,
    grading: f64,
    outer_z: f64,
    ramp: f64,
    detonation_speed: f64,
    ambient_pressure: f64,
    config: SimulationConfig,
}

impl Settings {
    /// The TNT sphere the scene holds: W in free air, the hemisphere and its mirror image
    /// (2W) for a burst on rigid ground.
    fn simulated_charge_kg(&self) -> f64 {
        match self.burst {
            Burst::FreeAir => self.charge_kg,
            Burst::Hemispherical => 2.0 * self.charge_kg,
        }
    }
}

fn settings(params: &Params, burst: Burst, charge_kg: f64) -> Result<Settings, VerifyError> {
    let library = Library::standard();
    let eta = params.number("eta", 0.5, 4.0)?;
    let outer_z = params.number("outer_z", 10.0, 40.0)?;
    let detonation_speed = library.value("tnt", "d_cj")?;
    let radius = charge_radius(charge_kg, library.value("tnt", "rho0")?);
    Ok(Settings {
        charge_kg,
        burst,
        grading: params.number("grading", 0.01, 1.0)?,
        outer_z,
        ramp: params.number("ramp", 0.1, 10.0)?,
        detonation_speed,
        ambient_pressure: library.value("air", "p0")?,
        config: SimulationConfig {
            time_steps: params.time_steps()?,
            formulation: Formulation::Spherical(ShellDensity::Continuity(
                SmoothingLength::FollowDensityFloored { eta },
            )),
            kernel: KernelShape::CubicSpline,
            viscosity: viscosity(params)?,
            energy: EnergyEquation::OwnPressure,
            cfl: params.cfl()?,
            // a scale of the charge's own, so that the scene has no length or time of its own
            min_time_step: 1e-9 * radius / detonation_speed,
            ..SimulationConfig::default()
        },
    })
}

pub(super) fn viscosity(params: &Params) -> Result<ArtificialViscosity, VerifyError> {
    let alpha_min = params.number("alpha_min", 0.0, ArtificialViscosity::default().alpha)?;
    Ok(viscosity_switched_down_to(alpha_min))
}

/// The default viscosity with Morris & Monaghan's switch letting α fall to `alpha_min` away
/// from shocks (no switch where `alpha_min` is the full α).
pub(crate) fn viscosity_switched_down_to(alpha_min: f64) -> ArtificialViscosity {
    let viscosity = ArtificialViscosity::default();
    ArtificialViscosity {
        switch: (alpha_min < viscosity.alpha).then_some(ViscositySwitch {
            alpha_min,
            decay: ViscositySwitch::DECAY,
        }),
        ..viscosity
    }
}

/// The first rezone, in charge transit times R_c/D_CJ (the burn is over by 1 + its ramp);
/// then one at every doubling of the time.
const REZONE_FIRST: f64 = 5.0;

/// The scene mapped onto a fresh lattice out to twice the contact's radius, conserving each
/// material's mass, momentum and total energy. The shells are stacked, products first and then
/// air, each in radial order and each keeping its volume m/ρ (where the two materials
/// interleave at the contact they are stacked apart); each old shell's mass is spread evenly
/// over its stacked cell and each new cell takes what overlaps it (its velocity the momentum
/// over the mass, its e the rest of the total energy), so the remapped densities, and with
/// them the pressures, are the old ones. The products get n equal shells; the air's shells
/// grade geometrically from contact/n wide at the contact to the width of the first shell
/// kept beyond; beyond, the shells keep their state and move as one to where
/// the stack ends. Refused (`Err`) where a new cell would be empty.
fn rezone(sim: &Simulation<1>, n: usize, eta: f64) -> Result<Vec<ParticleInit<1>>, String> {
    let p = sim.particles();
    // products first, then air, each in its own radial order: where the two interleave at the
    // contact they are stacked apart, each shell keeping its volume m/ρ
    let mut order: Vec<usize> = (0..p.n_real()).collect();
    order.sort_by(|&a, &b| {
        (p.material_of(a), p.position[a][0])
            .partial_cmp(&(p.material_of(b), p.position[b][0]))
            .expect("finite radii")
    });
    let products = order.iter().take_while(|&&i| p.material_of(i) == 0).count();
    let ball = |volume: f64| (3.0 * volume / (4.0 * std::f64::consts::PI)).cbrt();
    let stacked = |scale: f64| -> Vec<f64> {
        let mut total = 0.0;
        let mut edges = vec![0.0];
        for &i in &order {
            total += scale * p.mass[i] / p.density[i];
            edges.push(ball(total));
        }
        edges
    };
    let edges = stacked(1.0);
    let contact = edges[products];
    // the remapped air ends at the first stacked edge beyond twice the contact
    let end = (products..order.len())
        .find(|&k| edges[k] >= 2.0 * contact)
        .unwrap_or(order.len());
    // the shells beyond move as one by the difference between the stack's edge and where
    // they began (midway between the last remapped shell and the first kept one): where the
    // summed volumes and the positions disagree, a stretched stack would change every
    // remapped density (and send out a pressure pulse), a shift changes none
    let shift = if end < order.len() {
        edges[end] - 0.5 * (p.position[order[end - 1]][0] + p.position[order[end]][0])
    } else {
        0.0
    };
    let inner = contact / n as f64;
    let mut fresh_edges: Vec<f64> = (0..=n).map(|k| k as f64 * inner).collect();
    fresh_edges[n] = contact;
    let outer = edges[end];
    // the air's widths go geometrically from the products' to that of the first kept shell
    // (the lattice the scene began with), so that no shell is more than a few per cent wider
    // than its neighbour: a jump in width (and h) at the stack's end sends out a pressure
    // pulse of its own
    let kept_width = if end < order.len() {
        edges[end + 1] - edges[end]
    } else {
        inner
    };
    let width = |x: f64| inner * (kept_width / inner).powf((x - contact) / (outer - contact));
    let mut x = contact;
    while x < outer {
        let w = width(x);
        x = (x + w).min(outer);
        if outer - x < 0.5 * width(x) {
            x = outer;
        }
        fresh_edges.push(x);
    }
    let volume = |a: f64, b: f64| Geometry::Spherical.volume_between(a, b);
    let mut init = Vec::new();
    // old cells 0..products map onto new cells 0..n, old products..end onto the rest
    let regions = [
        (0, products, 0, n),
        (products, end, n, fresh_edges.len() - 1),
    ];
    for (old_lo, old_hi, new_lo, new_hi) in regions {
        let mut k = old_lo;
        for j in new_lo..new_hi {
            let (a, b) = (fresh_edges[j], fresh_edges[j + 1]);
            let (mut mass, mut momentum, mut energy) = (0.0, 0.0, 0.0);
            while k < old_hi {
                let (lo, hi) = (edges[k], edges[k + 1]);
                let overlap = volume(lo.max(a), hi.min(b));
                if hi > a && lo < b && overlap > 0.0 {
                    let i = order[k];
                    let share = p.mass[i] * overlap / volume(lo, hi);
                    let v = p.velocity[i][0];
                    mass += share;
                    momentum += share * v;
                    energy += share * (p.internal_energy[i] + 0.5 * v * v);
                }
                if hi <= b {
                    k += 1;
                } else {
                    break;
                }
            }
            if mass <= 0.0 {
                return Err(format!("empty cell [{a}, {b}]"));
            }
            let v = momentum / mass;
            init.push(ParticleInit {
                position: Vector::<1>::new(0.5 * (a + b)),
                velocity: Vector::<1>::new(v),
                mass,
                smoothing_length: eta * (b - a),
                density: mass / volume(a, b),
                internal_energy: energy / mass - 0.5 * v * v,
                material: if j < n { 0 } else { 1 },
            });
        }
    }
    for &i in &order[end..] {
        init.push(ParticleInit {
            position: Vector::<1>::new(p.position[i][0] + shift),
            velocity: p.velocity[i],
            mass: p.mass[i],
            smoothing_length: p.smoothing_length[i],
            density: p.density[i],
            internal_energy: p.internal_energy[i],
            material: p.material_of(i) as u16,
        });
    }
    Ok(init)
}

/// The radius of a TNT sphere of `mass` at density `rho`.
pub(super) fn charge_radius(mass: f64, rho: f64) -> f64 {
    (3.0 * mass / (4.0 * PI * rho)).cbrt()
}

/// A TNT sphere of the first n shells on `edges` inside shells of a second material (index
/// 1), at rest at their (density, internal energy) states, with h = η × the shell's width; and
/// the charge's programmed burn, lit at the centre.
pub(super) fn charge_in_shells(
    edges: &[f64],
    n: usize,
    eta: f64,
    (rho_charge, e_charge): (f64, f64),
    (rho_around, e_around): (f64, f64),
    detonation_speed: f64,
    ramp: f64,
) -> Result<(Vec<ParticleInit<1>>, ProgrammedBurn), VerifyError> {
    let init: Vec<ParticleInit<1>> = edges
        .windows(2)
        .enumerate()
        .map(|(k, w)| {
            let (rho, e, material) = if k < n {
                (rho_charge, e_charge, 0)
            } else {
                (rho_around, e_around, 1)
            };
            ParticleInit {
                position: Vector::<1>::new(0.5 * (w[0] + w[1])),
                velocity: Vector::<1>::zeros(),
                mass: rho * Geometry::Spherical.volume_between(w[0], w[1]),
                smoothing_length: eta * (w[1] - w[0]),
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
        detonation_speed,
        ramp,
    )?;
    Ok((init, burn))
}

/// The shells' edges: n equal shells across the charge, then the air's, each
/// max(R_c/n, g·r/n) wide, out to `outer`.
pub(super) fn shell_edges(radius: f64, n: usize, grading: f64, outer: f64) -> Vec<f64> {
    let inner = radius / n as f64;
    let mut edges: Vec<f64> = (0..=n).map(|k| k as f64 * inner).collect();
    let mut r = radius;
    while r < outer {
        r += inner.max(grading * r / n as f64);
        edges.push(r);
    }
    edges
}

struct Measured {
    run: Run,
    traces: Vec<GaugeTrace>,
    snapshot: Option<Snapshot>,
}

/// A run of the scene: its record, each gauge's trace, the simulation it ended with (none
/// where the solver refused the scene) and the fireball's radius, the farthest the products
/// reached (m).
struct Stepped {
    run: Run,
    traces: Vec<GaugeTrace>,
    sim: Option<Simulation<1>>,
    fireball_m: f64,
}

/// The scene of `s` at n shells across the charge's radius, run to `t_end` and rezoned as
/// [`rezone`] says; the gauges of `traces` read after every step.
fn simulate(
    s: &Settings,
    n: usize,
    mut traces: Vec<GaugeTrace>,
    t_end: f64,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Stepped, VerifyError> {
    let library = Library::standard();
    let scale = s.charge_kg.cbrt();
    let radius = charge_radius(s.simulated_charge_kg(), library.value("tnt", "rho0")?);
    let edges = shell_edges(radius, n, s.grading, s.outer_z * scale);
    let eta = s.config.formulation.eta().unwrap_or(2.0);
    let (init, burn) = charge_in_shells(
        &edges,
        n,
        eta,
        library.ambient_state("tnt")?,
        library.ambient_state("air")?,
        s.detonation_speed,
        s.ramp,
    )?;
    let materials = vec![library.material("tnt")?, library.material("air")?];
    let mut run = Run::new(format!("n = {n}"), "", init.len(), radius / n as f64);
    let start = std::time::Instant::now();
    let Some(mut sim) = run.started(Simulation::<1>::with_programmed_burn(
        &init,
        materials,
        Domain::open(),
        s.config,
        burn,
    ))?
    else {
        return Ok(Stepped {
            run,
            traces,
            sim: None,
            fireball_m: radius,
        });
    };
    let books = Conservation::open(&sim);
    let mut fireball_m = read_gauges(&sim, 0.0, s.ambient_pressure, &mut traces);
    let mut outcome = Ok(());
    // the time the current simulation started at, and when the next rezone is due
    let mut offset = 0.0;
    let mut rezone_at = REZONE_FIRST * radius / s.detonation_speed;
    let (mut rezones, mut refused_rezones) = (0, 0);
    // the work of the simulations before the last rezone
    let (mut steps, mut updates) = (0, 0);
    let mut phases = BTreeMap::<String, f64>::new();
    while offset + sim.time() < t_end {
        // the run stops exactly at each rezone, where every particle's step has ended
        let stop = rezone_at.min(t_end) - offset;
        outcome = sim.step_toward(stop);
        if outcome.is_err() {
            break;
        }
        let contact = read_gauges(&sim, offset, s.ambient_pressure, &mut traces);
        fireball_m = fireball_m.max(contact);
        progress((offset + sim.time()) / t_end);
        if sim.time() >= stop && rezone_at < t_end {
            let eta = s.config.formulation.eta().unwrap_or(2.0);
            let fresh = match rezone(&sim, n, eta) {
                Ok(fresh) => fresh,
                Err(_) => {
                    refused_rezones += 1;
                    rezone_at *= 2.0;
                    continue;
                }
            };
            steps += sim.steps();
            updates += sim.particle_updates();
            for (phase, seconds) in phase_seconds(&sim.phase_times()) {
                *phases.entry(phase).or_default() += seconds;
            }
            offset += sim.time();
            let materials = vec![library.material("tnt")?, library.material("air")?];
            let built = Simulation::<1>::new(&fresh, materials, Domain::open(), s.config);
            let Some(fresh_sim) = run.started(built)? else {
                break;
            };
            sim = fresh_sim;
            rezones += 1;
            rezone_at *= 2.0;
        }
    }
    run.record_work(&sim, start);
    run.steps += steps;
    if let Some(total) = run.metrics.get_mut("particle_updates") {
        *total += updates as f64;
    }
    for (phase, seconds) in phases {
        *run.phase_s.entry(phase).or_default() += seconds;
    }
    run.metrics.insert("rezones".into(), rezones as f64);
    run.metrics
        .insert("refused_rezones".into(), refused_rezones as f64);
    if let Err(e) = outcome {
        run.failure = Some(e.to_string());
    } else {
        books.close(&sim, &mut run.metrics);
    }
    run.metrics.insert("charge_radius_m".into(), radius);
    run.metrics.insert("t_end_s".into(), t_end);
    Ok(Stepped {
        run,
        traces,
        sim: Some(sim),
        fireball_m,
    })
}

/// The scene at n shells with its gauges at [`GAUGE_Z`], against Kingery–Bulmash.
fn run_one(
    s: &Settings,
    n: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Measured, VerifyError> {
    let scale = s.charge_kg.cbrt();
    let t_end = END_MARGIN * {
        let last = reference(s, GAUGE_Z[GAUGE_Z.len() - 1])?;
        last.arrival_s + last.duration_s.unwrap_or(0.0)
    };
    let traces = GAUGE_Z
        .iter()
        .map(|&z| GaugeTrace::new(format!("Z = {z}"), z * scale))
        .collect();
    let Stepped {
        mut run,
        traces,
        sim,
        ..
    } = simulate(s, n, traces, t_end, progress)?;
    let Some(sim) = sim else {
        return Ok(Measured {
            run,
            traces,
            snapshot: None,
        });
    };
    for (trace, &z) in traces.iter().zip(&GAUGE_Z) {
        let gauge = trace.summary();
        let kb = reference(s, z)?;
        for (q, value, relation) in against_relations_of(&gauge, &kb) {
            run.errors
                .insert(format!("{q}_error_z{z}"), relative_error(value, relation));
            run.metrics
                .insert(format!("{q}_over_kingery_bulmash_z{z}"), value / relation);
        }
        // the free-air relation for the sphere the scene simulates: W in free air, or the
        // hemisphere with its mirror image, 2W
        let sphere = air_blast(Burst::FreeAir, s.simulated_charge_kg(), trace.position_m)?;
        run.errors.insert(
            format!("peak_overpressure_error_simulated_sphere_z{z}"),
            relative_error(gauge.peak_pressure_pa, sphere.incident_overpressure_pa),
        );
        if s.burst == Burst::Hemispherical {
            // how far the relations themselves put a rigid mirror (a 2W sphere in free air)
            // above the measured surface bursts, whose ground took up some of the energy
            run.metrics.insert(
                format!("kingery_bulmash_free_air_2w_over_hemispherical_peak_z{z}"),
                sphere.incident_overpressure_pa / kb.incident_overpressure_pa,
            );
        }
        run.gauges.push(gauge);
    }
    let gated = gated_z(s);
    let mean_over_gated = |q: &str| {
        gated
            .iter()
            .map(|z| run.errors[&format!("{q}_z{z}")])
            .sum::<f64>()
            / gated.len() as f64
    };
    let mean_peak_error = mean_over_gated("peak_overpressure_error");
    let mean_sphere_error = mean_over_gated("peak_overpressure_error_simulated_sphere");
    run.errors
        .insert("mean_peak_overpressure_error".into(), mean_peak_error);
    run.errors.insert(
        "mean_peak_overpressure_error_simulated_sphere".into(),
        mean_sphere_error,
    );
    Ok(Measured {
        run,
        traces,
        snapshot: Some(Snapshot::of(&sim)),
    })
}

/// A gauge's peak overpressure, arrival and positive impulse, each with its name and the
/// value Kingery–Bulmash give.
pub(crate) fn against_relations_of(gauge: &Gauge, kb: &AirBlast) -> [(&'static str, f64, f64); 3] {
    [
        (
            "peak_overpressure",
            gauge.peak_pressure_pa,
            kb.incident_overpressure_pa,
        ),
        ("arrival", gauge.arrival_s, kb.arrival_s),
        ("impulse", gauge.impulse_pa_s, kb.incident_impulse_pa_s),
    ]
}

/// The gauges' Z that are checked against Kingery–Bulmash: from Z = 1 of the simulated sphere
/// out (see [`GATED_FROM_Z`]).
fn gated_z(s: &Settings) -> Vec<f64> {
    let to_simulated = (s.charge_kg / s.simulated_charge_kg()).cbrt();
    GAUGE_Z
        .iter()
        .cloned()
        .filter(|&z| z * to_simulated >= GATED_FROM_Z - 1e-12)
        .collect()
}

/// Kingery–Bulmash for the settings' burst at scaled distance `z` from its charge.
fn reference(s: &Settings, z: f64) -> Result<AirBlast, VerifyError> {
    air_blast(s.burst, s.charge_kg, z * s.charge_kg.cbrt())
}

/// The qualification of the impulse at `z`: its ratio to Kingery–Bulmash per resolution and
/// what explains it.
fn impulse_qualification(
    s: &Settings,
    measured: &[Measured],
    resolutions: &[usize],
    z: f64,
) -> Result<Qualification, VerifyError> {
    let reference = reference(s, z)?.incident_impulse_pa_s;
    let mut ratios: Vec<(usize, f64)> = measured
        .iter()
        .zip(resolutions)
        .map(|(m, &n)| {
            let gauge = m.run.gauges.iter().find(|g| g.name == format!("Z = {z}"));
            (n, gauge.map_or(f64::NAN, |g| g.impulse_pa_s / reference))
        })
        .collect();
    ratios.sort_by_key(|row| row.0);
    let values: Vec<f64> = ratios.iter().map(|row| row.1).collect();
    Ok(Qualification {
        reason: "no afterburning of the products in air in this model: the products release \
                 the detonation energy alone (JWL's E₀ = 4.3 MJ/kg), while the measured TNT \
                 charges' products also burnt in the air they mixed with, which lengthens the \
                 positive phase more than it raises the peak"
            .into(),
        quantity: format!("impulse / Kingery–Bulmash at Z = {z}"),
        value: values.last().copied().unwrap_or(f64::NAN),
        bound: [AFTERBURN_IMPULSE_FLOOR, 1.0],
        effect: "none on the safe depth: the study's free field carries no air blast".into(),
        refinement: Refinement::of_resolutions(&values),
    })
}

/// |value/reference − 1| (NaN where the value is).
pub(super) fn relative_error(value: f64, reference: f64) -> f64 {
    (value / reference - 1.0).abs()
}

/// Appends each gauge's overpressure and velocity at the current time; returns the contact's
/// radius (the outermost product shell's).
fn read_gauges(sim: &Simulation<1>, offset: f64, ambient: f64, traces: &mut [GaugeTrace]) -> f64 {
    let p = sim.particles();
    let contact = (0..p.n_real())
        .filter(|&i| p.material_of(i) == 0)
        .map(|i| p.position[i][0])
        .fold(0.0, f64::max);
    let mut order: Vec<usize> = (0..p.n_real()).collect();
    order.sort_by(|&a, &b| p.position[a][0].total_cmp(&p.position[b][0]));
    let profile = |value: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
        order
            .iter()
            .map(|&i| (p.position[i][0], value(i)))
            .collect()
    };
    let pressure = profile(&|i| p.pressure[i] - ambient);
    let velocity = profile(&|i| p.velocity[i][0]);
    for trace in traces {
        let r = trace.position_m;
        trace.push(
            offset + sim.time(),
            interpolate(&pressure, r),
            interpolate(&velocity, r),
        );
    }
    contact
}

/// The air's overpressure on a rigid ground under a hemispherical surface burst of
/// `charge_kg` of TNT, at each of `radii` (m) from the burst from t = 0 to `end_s`: the scene
/// of `airblast-surface` (the hemisphere and its mirror image, a 2W sphere in free air) at
/// `n` shells across the charge's radius and its default settings. Within the fireball (the
/// farthest the products reached) it reads zero: the air's load alone.
pub fn ground_overpressure(
    charge_kg: f64,
    radii: &[f64],
    end_s: f64,
    n: usize,
) -> Result<Vec<GaugeTrace>, VerifyError> {
    let info = infos()
        .into_iter()
        .find(|info| info.name == SURFACE)
        .expect("the surface burst is a problem");
    let params = Params::new(SURFACE, &info.params, Level::Quick, &[])?;
    let s = settings(&params, Burst::Hemispherical, charge_kg)?;
    let traces = radii
        .iter()
        .map(|&r| GaugeTrace::new(format!("r = {r} m"), r))
        .collect();
    let mut stepped = simulate(&s, n, traces, end_s, &|_| {})?;
    for trace in &mut stepped.traces {
        if trace.position_m <= stepped.fireball_m {
            trace.overpressure.fill(0.0);
            trace.velocity.fill(0.0);
        }
    }
    match (&stepped.run.failure, &stepped.sim) {
        (None, Some(_)) => Ok(stepped.traces),
        (failure, _) => Err(VerifyError::Scene {
            line: 0,
            key: "air_blast".into(),
            message: format!(
                "the air blast of {charge_kg} kg on the ground failed at {n} shells: {}",
                failure.as_deref().unwrap_or("refused by the solver")
            ),
        }),
    }
}

pub fn run(
    name: &str,
    params: &Params,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let charge_kg = params.number("charge", 1e-3, 1e6)?;
    match name {
        HOPKINSON_CRANZ => scaling(params, charge_kg, progress),
        SURFACE => {
            let s = settings(params, Burst::Hemispherical, charge_kg)?;
            against_relations(name, &s, params, progress)
        }
        _ => {
            let s = settings(params, Burst::FreeAir, charge_kg)?;
            against_relations(name, &s, params, progress)
        }
    }
}

/// Every run completed, and (where it did) kept its energy: the chemical energy is in e from
/// the start (as in tnt-slab); radial momentum is not conserved in spherical symmetry, so only
/// the energy check applies.
pub(super) fn health_checks(run: &Run) -> Vec<Check> {
    let mut checks = vec![Check::at_least(
        format!(
            "completed_without_blow_up_{}",
            run.label.replace(" = ", "_").replace(' ', "_")
        ),
        f64::from(run.failure.is_none()),
        1.0,
    )];
    if run.failure.is_none() {
        let [_, energy] = conservation_checks(run, 1e-3);
        checks.push(energy);
    }
    checks
}

/// The scene at each resolution against the scaled-distance relations of its burst.
fn against_relations(
    name: &str,
    s: &Settings,
    params: &Params,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let resolutions = params.integers("n", 4, 10_000)?;
    let mut measured = Vec::new();
    for (k, &n) in resolutions.iter().enumerate() {
        let part = |f: f64| progress((k as f64 + f) / resolutions.len() as f64);
        measured.push(run_one(s, n, &part)?);
    }
    let finest = (0..resolutions.len())
        .max_by_key(|&k| resolutions[k])
        .expect("at least one resolution");
    let coarsest = (0..resolutions.len())
        .min_by_key(|&k| resolutions[k])
        .expect("at least one resolution");
    let mut checks: Vec<Check> = measured
        .iter()
        .flat_map(|m| health_checks(&m.run))
        .collect();
    let fine = &measured[finest].run;
    let n_fine = resolutions[finest];
    let gated = gated_z(s);
    let error = |run: &Run, q: &str, z: f64| {
        run.errors
            .get(&format!("{q}_error_z{z}"))
            .copied()
            .unwrap_or(f64::NAN)
    };
    for &z in &gated {
        for (q, limit) in [
            ("peak_overpressure", PEAK_LIMIT),
            ("arrival", ARRIVAL_LIMIT),
            ("impulse", IMPULSE_LIMIT),
        ] {
            let check = Check::at_most(
                format!("{q}_error_z{z}_n_{n_fine}"),
                error(fine, q, z),
                limit,
            );
            checks.push(
                if !check.pass && q == "impulse" && z >= IMPULSE_QUALIFIED_FROM_Z {
                    check.qualified(impulse_qualification(s, &measured, &resolutions, z)?)
                } else {
                    check
                },
            );
        }
    }
    if measured.len() >= 2 {
        // the peak is what resolution sharpens: the mean peak error over the gated gauges
        // must fall from the coarsest run to the finest. It is measured against the free-air
        // relation of the sphere the scene simulates, the answer its refinement approaches:
        // for the surface burst the rigid mirror's 2W sphere, which the relations put 4–16 %
        // above the measured hemispherical bursts (a peak converging there may move away
        // from the hemispherical relation as it sharpens)
        let mean_peak_error = |run: &Run| {
            run.errors
                .get("mean_peak_overpressure_error_simulated_sphere")
                .copied()
                .unwrap_or(f64::NAN)
        };
        checks.push(Check::at_most(
            "mean_peak_error_finest_over_coarsest",
            mean_peak_error(fine) / mean_peak_error(&measured[coarsest].run),
            1.0,
        ));
    }
    let runs: Vec<Run> = measured.iter().map(|m| m.run.clone()).collect();
    let (profile, figure) = outputs(name, s, &measured[finest])?;
    Ok(ProblemOutput {
        record: Record::new(name, Level::Quick, runs, Default::default(), checks, finest),
        profile,
        figure,
        snapshot: measured[finest].snapshot.clone(),
    })
}

/// Hopkinson–Cranz: the charge's mass ratio between the two scenes (every length doubles) and
/// the limit on the mismatch of the scaled histories. The two scenes are the same equations in
/// units of the charge radius and its transit time, so they agree up to round-off (measured
/// ≤ 1e-19 of the peak). The 1 % limit lies far above round-off and below what a length or
/// time fixed in metres or seconds does: a gauge 1 % off in Z moves the Z = 1 peak by 2–3 %
/// (the peak falls as about Z^−2.5 there), and a front 0.5 % late misses by its full height
/// (see the unit test).
const SCALING_MASS_RATIO: f64 = 8.0;
const SCALING_LIMIT: f64 = 0.01;

/// The largest |p_large(λt) − p_small(t)| over the large scene's samples, over the small
/// scene's peak: the two gauges' overpressure against t/W^{1/3} at matched Z, with λ the
/// length ratio of the scenes.
fn scaled_mismatch(small: &GaugeTrace, large: &GaugeTrace, length_ratio: f64) -> f64 {
    let history: Vec<(f64, f64)> = small
        .time
        .iter()
        .zip(&small.overpressure)
        .map(|(&t, &p)| (t, p))
        .collect();
    let peak = small.summary().peak_pressure_pa;
    large
        .time
        .iter()
        .zip(&large.overpressure)
        .map(|(&t, &p)| (p - interpolate(&history, t / length_ratio)).abs())
        .fold(0.0, f64::max)
        / peak
}

/// The free-air scene at W and at 8W, each resolution once; per gauge the scaled histories'
/// mismatch.
fn scaling(
    params: &Params,
    charge_kg: f64,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let small = settings(params, Burst::FreeAir, charge_kg)?;
    let large = settings(params, Burst::FreeAir, SCALING_MASS_RATIO * charge_kg)?;
    let length_ratio = SCALING_MASS_RATIO.cbrt();
    let resolutions = params.integers("n", 4, 10_000)?;
    let parts = 2.0 * resolutions.len() as f64;
    let (mut runs, mut checks, mut pairs) = (Vec::new(), Vec::new(), Vec::new());
    for (k, &n) in resolutions.iter().enumerate() {
        let a = run_one(&small, n, &|f| progress((2.0 * k as f64 + f) / parts))?;
        let b = run_one(&large, n, &|f| progress((2.0 * k as f64 + 1.0 + f) / parts))?;
        let mut run_a = a.run.clone();
        run_a.label = format!("n = {n} at W = {charge_kg} kg");
        let mut run_b = b.run.clone();
        run_b.label = format!("n = {n} at W = {} kg", SCALING_MASS_RATIO * charge_kg);
        checks.extend(health_checks(&run_a));
        checks.extend(health_checks(&run_b));
        for ((ta, tb), z) in a.traces.iter().zip(&b.traces).zip(GAUGE_Z) {
            let mismatch = scaled_mismatch(ta, tb, length_ratio);
            run_a
                .errors
                .insert(format!("scaled_overpressure_mismatch_z{z}"), mismatch);
            checks.push(Check::at_most(
                format!("scaled_overpressure_mismatch_z{z}_n_{n}"),
                mismatch,
                SCALING_LIMIT,
            ));
        }
        runs.push(run_a);
        runs.push(run_b);
        pairs.push((a, b));
    }
    let finest = (0..resolutions.len())
        .max_by_key(|&k| resolutions[k])
        .expect("at least one resolution");
    let (a, b) = &pairs[finest];
    let mut columns = vec!["t_scaled_s_per_kg3".to_string()];
    for z in GAUGE_Z {
        columns.push(format!("overpressure_z{z}_w"));
        columns.push(format!("overpressure_z{z}_8w"));
    }
    let names: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut table = Table::new(&names);
    let scale = charge_kg.cbrt();
    let sorted = |trace: &GaugeTrace| -> Vec<(f64, f64)> {
        trace
            .time
            .iter()
            .zip(&trace.overpressure)
            .map(|(&t, &p)| (t, p))
            .collect()
    };
    let large_histories: Vec<Vec<(f64, f64)>> = b.traces.iter().map(sorted).collect();
    if let Some(first) = a.traces.first() {
        for (k, &t) in first.time.iter().enumerate() {
            let mut row = vec![t / scale];
            for (trace, history) in a.traces.iter().zip(&large_histories) {
                row.push(trace.overpressure[k]);
                row.push(interpolate(history, t * length_ratio));
            }
            table.rows.push(row);
        }
    }
    let panels = a
        .traces
        .iter()
        .zip(&b.traces)
        .map(|(ta, tb)| {
            let series = |trace: &GaugeTrace, mass: f64, style| Series {
                label: format!("W = {mass} kg"),
                points: trace
                    .time
                    .iter()
                    .zip(&trace.overpressure)
                    .map(|(&t, &p)| (1e3 * t / mass.cbrt(), 1e-3 * p))
                    .collect(),
                style,
            };
            Panel {
                title: ta.name.clone(),
                x_label: "t/W^(1/3) (ms/kg^(1/3))".into(),
                y_label: "overpressure (kPa)".into(),
                series: vec![
                    series(ta, charge_kg, Style::Line),
                    series(tb, SCALING_MASS_RATIO * charge_kg, Style::Markers),
                ],
                ..Panel::default()
            }
        })
        .collect();
    let figure = Figure {
        title: format!(
            "{HOPKINSON_CRANZ}: {charge_kg} kg and {} kg of TNT in free air, n = {}",
            SCALING_MASS_RATIO * charge_kg,
            resolutions[finest]
        ),
        panels,
    };
    Ok(ProblemOutput {
        record: Record::new(
            HOPKINSON_CRANZ,
            Level::Quick,
            runs,
            Default::default(),
            checks,
            2 * finest,
        ),
        profile: table,
        figure,
        snapshot: a.snapshot.clone(),
    })
}

/// The gauges' histories at the finest resolution (one column per gauge), and a figure with
/// each history beside Kingery–Bulmash's arrival and peak.
fn outputs(name: &str, s: &Settings, m: &Measured) -> Result<(Table, Figure), VerifyError> {
    let names: Vec<String> = m
        .traces
        .iter()
        .map(|t| format!("overpressure_z{}", t.name.trim_start_matches("Z = ")))
        .collect();
    let mut columns = vec!["t"];
    columns.extend(names.iter().map(String::as_str));
    let mut table = Table::new(&columns);
    if let Some(first) = m.traces.first() {
        for (k, &t) in first.time.iter().enumerate() {
            let mut row = vec![t];
            row.extend(m.traces.iter().map(|trace| trace.overpressure[k]));
            table.rows.push(row);
        }
    }
    let mut panels = Vec::new();
    for (trace, &z) in m.traces.iter().zip(&GAUGE_Z) {
        let kb = reference(s, z)?;
        panels.push(Panel {
            title: format!("{} ({:.2} m)", trace.name, trace.position_m),
            x_label: "t (ms)".into(),
            y_label: "overpressure (kPa)".into(),
            series: vec![
                trace.overpressure_series("SPH"),
                Series {
                    label: "Kingery-Bulmash arrival, peak".into(),
                    points: vec![(1e3 * kb.arrival_s, 1e-3 * kb.incident_overpressure_pa)],
                    style: Style::Markers,
                },
            ],
            ..Panel::default()
        });
    }
    let gauges: Vec<&Gauge> = m.run.gauges.iter().collect();
    let figure = Figure {
        title: format!(
            "{name}: {} kg TNT {}, {} (gauges: {})",
            s.charge_kg,
            match s.burst {
                Burst::FreeAir => "in free air",
                Burst::Hemispherical => "on rigid ground",
            },
            m.run.label,
            gauges.len()
        ),
        panels,
    };
    Ok((table, figure))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Per material, the rezone keeps mass, momentum and total energy to round-off, the
    /// products end up inside the air, and the air's shell widths have no jump.
    #[test]
    fn rezone_conserves_each_materials_mass_momentum_and_energy() {
        let library = Library::standard();
        let edges = shell_edges(0.05, 10, 0.2, 1.0);
        let init: Vec<ParticleInit<1>> = edges
            .windows(2)
            .enumerate()
            .map(|(k, w)| {
                let r = 0.5 * (w[0] + w[1]);
                let products = k < 10;
                let rho = if products { 50.0 / (1.0 + r) } else { 1.2 + r };
                ParticleInit {
                    position: Vector::<1>::new(r),
                    velocity: Vector::<1>::new(300.0 * r * (1.0 + (7.0 * r).sin())),
                    mass: rho * Geometry::Spherical.volume_between(w[0], w[1]),
                    smoothing_length: 2.0 * (w[1] - w[0]),
                    density: rho,
                    internal_energy: 2e5 * (1.0 + r),
                    material: u16::from(!products),
                }
            })
            .collect();
        let materials = vec![
            library.material("tnt").unwrap(),
            library.material("air").unwrap(),
        ];
        let config = SimulationConfig {
            formulation: Formulation::Spherical(ShellDensity::Continuity(
                SmoothingLength::FollowDensityFloored { eta: 2.0 },
            )),
            ..SimulationConfig::default()
        };
        let sim = Simulation::<1>::new(&init, materials, Domain::open(), config).unwrap();
        let fresh = rezone(&sim, 10, 2.0).unwrap();
        let totals = |material: u16, shells: &mut dyn Iterator<Item = (u16, f64, f64, f64)>| {
            shells
                .filter(|s| s.0 == material)
                .fold((0.0, 0.0, 0.0), |(m, p, e), (_, mass, v, u)| {
                    (m + mass, p + mass * v, e + mass * (u + 0.5 * v * v))
                })
        };
        for material in [0, 1] {
            let before = totals(
                material,
                &mut init
                    .iter()
                    .map(|q| (q.material, q.mass, q.velocity[0], q.internal_energy)),
            );
            let after = totals(
                material,
                &mut fresh
                    .iter()
                    .map(|q| (q.material, q.mass, q.velocity[0], q.internal_energy)),
            );
            for (b, a) in [
                (before.0, after.0),
                (before.1, after.1),
                (before.2, after.2),
            ] {
                assert!(
                    (a / b - 1.0).abs() < 1e-12,
                    "material {material}: {b} -> {a}"
                );
            }
        }
        let outermost_products = fresh
            .iter()
            .filter(|q| q.material == 0)
            .map(|q| q.position[0])
            .fold(0.0, f64::max);
        let innermost_air = fresh
            .iter()
            .filter(|q| q.material == 1)
            .map(|q| q.position[0])
            .fold(f64::INFINITY, f64::min);
        assert!(outermost_products < innermost_air);
        // no jump in the air's shell widths (h/η), the stack's end included, where the fresh
        // shells by the contact (contact/n = 0.0125 m with n = 4, as after the products have
        // expanded) are 2.5 times wider than the kept air shells (0.005 m) and the stack is
        // 0.05 m long: graded geometrically, neighbours differ by (0.4)^(0.0125/0.05) → 1.26,
        // the last fresh shell by up to half a width more; a width of contact/n throughout
        // jumps by 2.5 at the stack's end
        let coarse = rezone(&sim, 4, 2.0).unwrap();
        let mut air: Vec<(f64, f64)> = coarse
            .iter()
            .filter(|q| q.material == 1)
            .map(|q| (q.position[0], q.smoothing_length))
            .collect();
        air.sort_by(|a, b| a.0.total_cmp(&b.0));
        let largest_ratio = air
            .windows(2)
            .map(|w| (w[1].1 / w[0].1).max(w[0].1 / w[1].1))
            .fold(1.0, f64::max);
        assert!(largest_ratio < 1.6, "{largest_ratio}");
    }

    /// The scaled comparison sees what a length or time fixed in metres or seconds would do:
    /// a blast wave (a jump to 100 kPa decaying over 2 ms) against itself at twice the lengths
    /// and times matches to round-off, and misses by more than the 1 % limit if either its
    /// time is off by 0.5 % or the larger scene's time scale were not doubled.
    #[test]
    fn scaled_mismatch_sees_a_scale_that_does_not_scale() {
        let wave = |name: &str, time_scale: f64, arrival: f64| {
            let mut trace = GaugeTrace::new(name, 1.0);
            for k in 0..4000 {
                let t = time_scale * k as f64 * 2e-6;
                let local = t / time_scale - arrival;
                let p = if local < 0.0 {
                    0.0
                } else {
                    1e5 * (1.0 - local / 2e-3) * (-local / 2e-3).exp()
                };
                trace.push(t, p, 0.0);
            }
            trace
        };
        let small = wave("small", 1.0, 2e-3);
        assert!(scaled_mismatch(&small, &wave("large", 2.0, 2e-3), 2.0) < 1e-12);
        assert!(scaled_mismatch(&small, &wave("late", 2.0, 2.01e-3), 2.0) > 0.01);
        assert!(scaled_mismatch(&small, &wave("large", 2.0, 2e-3), 1.0) > 0.01);
    }

    #[test]
    fn shells_fill_the_charge_evenly_then_grow_geometrically() {
        let edges = shell_edges(0.05, 10, 0.2, 20.0);
        assert!((edges[10] - 0.05).abs() < 1e-15);
        let widths: Vec<f64> = edges.windows(2).map(|w| w[1] - w[0]).collect();
        // uniform out to R_c/g = 0.25 m, then each shell 2 % wider than the last
        assert!(widths[..40].iter().all(|&w| (w - 0.005).abs() < 1e-12));
        let last = widths.len() - 1;
        assert!((widths[last] / widths[last - 1] - 1.02).abs() < 1e-9);
        assert!(*edges.last().unwrap() >= 20.0);
        // about 27 shells per n out to Z = 20 for 1 kg (R_c = 0.0527 m)
        assert!(edges.len() < 30 * 10, "{}", edges.len());
    }
}
