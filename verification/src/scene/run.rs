//! A scene's particles and its run: each body filled with a lattice at its spacing, gauges
//! attached to the particle nearest them, the simulation stepped to the end time with every
//! gauge read after each step, particle snapshots at the output interval, and per material the
//! momentum and energy.
//!
//! Outputs in the run's folder, each written atomically: `gauges/<name>.csv` (one row per
//! step), `materials.csv` (momentum and energy per material at each snapshot time, or at a
//! hundredth of the run without snapshots), `snapshots/<k>.vtu` with `snapshots.pvd` (ParaView
//! plays the series), and last `scene.json`, the summary: a folder without it holds no
//! finished run. While it runs, a run may keep `checkpoint.bin`, everything it has gathered and
//! the simulation's state between two steps, from which it resumes bitwise (see
//! [`Checkpoints`]); a finished run removes it.

use super::{contains, AirBlast, Body, Geometry, Gravity, Scene, StepChoice, INDIVIDUAL_MAX_RATIO};
use crate::gauges::{Gauge, GaugeTrace, ARRIVAL_FRACTION};
use crate::problems::airblast::ground_overpressure;
use crate::problems::viscosity_switched_down_to;
use crate::report::write_atomic;
use crate::vtk::{status_code, Snapshot};
use crate::VerifyError;
use blastsph_solver::particles::ParticleInit;
use blastsph_solver::strength::von_mises;
use blastsph_solver::{
    Boundary, Density, Domain, EnergyEquation, ExternalLoad, Formulation, InitialState,
    KernelShape, Material, PrescribedMotion, ProgrammedBurn, Simulation, SimulationConfig,
    SmoothingLength, Tensor, Vector,
};
use blastsph_solver::{Checkpoint, Departed};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// What `scene.json` holds.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct RunSummary {
    pub scene: String,
    pub geometry: String,
    /// Particles per body.
    pub bodies: BTreeMap<String, usize>,
    pub particles: usize,
    pub steps: u64,
    pub end_time_s: f64,
    /// The time reached: the end time, or where a stopped run stopped.
    pub time_reached_s: f64,
    pub wall_s: f64,
    /// Why the run stopped early (a blow-up's diagnosis), or `None`.
    pub stopped: Option<String>,
    /// The change of the total energy over the run, with the energy that left (see
    /// `energy_exchanged_j`) counted (J), and its size over
    /// the energy at the start (none where that is zero: ground at rest without a charge).
    pub energy_change_j: f64,
    pub energy_relative_change: Option<f64>,
    /// With gravity: how closely the external accelerations that hold the geostatic state
    /// are gravity inside the bodies.
    pub gravity_balance: Option<GravityBalance>,
    /// The largest displacement of any particle at the end (m).
    pub max_displacement_m: f64,
    /// The energy that left through transmitting sides, carried out through outflow sides or
    /// as work against external forces (J; negative where external forces did work on the
    /// particles).
    pub energy_exchanged_j: f64,
    /// The particles that left through outflow sides, and their mass.
    pub departed: Departed,
    /// Per body with strength: particles that yielded (plastic strain above zero at the end)
    /// and that failed (reached the tensile cutoff at some step).
    pub yielded: BTreeMap<String, usize>,
    pub failed: BTreeMap<String, usize>,
    pub gauges: Vec<GaugeSummary>,
    /// The gauges above the ground, which read the overpressure of the scene's air blast.
    pub air_gauges: Vec<Gauge>,
}

/// A gauge's place, the particle it reads and its peaks.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GaugeSummary {
    pub name: String,
    pub body: String,
    /// Where the particle it reads started.
    pub particle_position_m: Vec<f64>,
    pub peak_pressure_pa: f64,
    pub peak_velocity_m_s: f64,
    pub peak_von_mises_pa: f64,
    pub peak_displacement_m: f64,
    /// The first time |v| reached [`ARRIVAL_FRACTION`] of its peak (NaN if it never moved).
    pub arrival_s: f64,
}

/// Builds and runs `scene`, writing its outputs into `out` (see the module's comment);
/// `progress` hears the fraction of the end time reached after each step. A scene the solver
/// refuses is an error; a run that blows up ends early with its diagnosis in the summary.
pub fn run(
    scene: &Scene,
    out: &Path,
    progress: &mut dyn FnMut(f64),
) -> Result<RunSummary, VerifyError> {
    run_checkpointed(scene, out, progress, &Checkpoints::default())
}

/// As [`run`], keeping checkpoints and resuming from one as `checkpoints` says.
pub fn run_checkpointed(
    scene: &Scene,
    out: &Path,
    progress: &mut dyn FnMut(f64),
    checkpoints: &Checkpoints,
) -> Result<RunSummary, VerifyError> {
    match scene.geometry.dimension() {
        2 => run_with::<2, ()>(scene, out, progress, &|_, _| None, &mut (), checkpoints),
        _ => run_with::<3, ()>(scene, out, progress, &|_, _| None, &mut (), checkpoints),
    }
}

/// The file in a run's folder that holds its latest checkpoint.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";

/// When a run keeps a checkpoint of itself, and whether it resumes from one. Taking a
/// checkpoint reads the state and changes nothing, so a run's results do not depend on when
/// its checkpoints were taken; a resumed run's outputs are bitwise those of a run that was
/// never stopped (with the same build: a checkpoint carries the program's hash).
#[derive(Clone, Debug, Default)]
pub struct Checkpoints {
    /// Wall time between two checkpoints (s); `None` keeps none.
    pub every_s: Option<f64>,
    /// Resume from the checkpoint in the run's folder where there is one; one of another
    /// scene, context or build is refused by name. Without it an old checkpoint is removed.
    pub resume: bool,
    /// What decides the run beyond its scene (e.g. the free field that drives its band), so
    /// that a checkpoint is never resumed under another.
    pub context: String,
}

/// What a caller gathers from a run after every step; it travels in the run's checkpoints.
pub trait Observer<const D: usize>: Serialize + DeserializeOwned {
    fn observe(&mut self, sim: &Simulation<D>);
}

impl<const D: usize> Observer<D> for () {
    fn observe(&mut self, _: &Simulation<D>) {}
}

/// A run between two steps: the simulation's state and what the run has gathered so far.
#[derive(Serialize, Deserialize)]
struct RunState<const D: usize> {
    inputs_hash: String,
    simulation: Checkpoint<D>,
    gauge_rows: Vec<Vec<Vec<f64>>>,
    ledger: Vec<Vec<f64>>,
    next_ledger: f64,
    written: Vec<(f64, String)>,
    ever_failed: Vec<bool>,
    wall_s: f64,
    observer: Vec<u8>,
}

/// The run state kept at `path` under `hash`; none where there is no file.
fn kept_state<const D: usize>(path: &Path, hash: &str) -> Result<Option<RunState<D>>, VerifyError> {
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(VerifyError::Io {
                path: path.display().to_string(),
                source,
            })
        }
    };
    let state: Option<RunState<D>> = bincode::deserialize(&bytes).ok();
    match state {
        Some(state) if state.inputs_hash == hash => Ok(Some(state)),
        _ => Err(VerifyError::bad_value(
            "checkpoint",
            path.display(),
            "a checkpoint of this scene written by this build (remove it to start afresh)",
        )),
    }
}

/// Marks, by id, the particles at the tensile cutoff.
fn mark_failed<const D: usize>(sim: &Simulation<D>, ever_failed: &mut [bool]) {
    let p = sim.particles();
    for i in 0..p.n_real() {
        if let Some(strength) = &sim.materials()[p.material_of(i)].strength {
            if strength.failed_in_tension(p.pressure[i], &p.deviatoric_stress[i]) {
                ever_failed[p.id[i] as usize] = true;
            }
        }
    }
}

/// The motion `prescribe` gives some particles of a scene, built from the particles' initial
/// state and bodies (indices into the scene's bodies) before the run starts.
pub type Prescribe<'a, const D: usize> =
    &'a dyn Fn(&[ParticleInit<D>], &[usize]) -> Option<Arc<dyn PrescribedMotion<D>>>;

/// The particles, the bodies they belong to, and the programmed burn if there is a charge.
struct Built<const D: usize> {
    init: Vec<ParticleInit<D>>,
    body_of: Vec<usize>,
    burn: Option<ProgrammedBurn>,
    /// The geostatic deviatoric stress of each particle, with gravity.
    deviatoric_stress: Option<Vec<Tensor<D>>>,
}

/// The overpressure of a scene's air blast on the top layer of its ground (see
/// [`super::AirBlast`]): each loaded particle is pressed down by p times its ring's upper face
/// 2π r Δ over its mass, p read at its starting radius and interpolated linearly in time.
#[derive(Debug)]
struct AirLoad {
    times: Vec<f64>,
    /// Overpressure at `times`, per radius.
    overpressure: Vec<Vec<f64>>,
    /// Per particle id: its radius's index, and face area over mass (m²/kg).
    loaded: Vec<Option<(usize, f64)>>,
}

impl AirLoad {
    /// The overpressure at radius `k` and `time`.
    fn overpressure_at(&self, k: usize, time: f64) -> f64 {
        let p = &self.overpressure[k];
        let after = self.times.partition_point(|&t| t <= time);
        match after {
            0 => p[0],
            a if a == self.times.len() => p[a - 1],
            a => {
                let (t0, t1) = (self.times[a - 1], self.times[a]);
                p[a - 1] + (time - t0) / (t1 - t0) * (p[a] - p[a - 1])
            }
        }
    }
}

impl<const D: usize> ExternalLoad<D> for AirLoad {
    fn acceleration(&self, id: u32, time: f64) -> Option<Vector<D>> {
        let (k, area_over_mass) = self.loaded.get(id as usize).copied().flatten()?;
        let mut a = Vector::<D>::zeros();
        a[D - 1] = -self.overpressure_at(k, time) * area_over_mass;
        Some(a)
    }
}

/// The ground's load from the scene's air blast and the traces of the gauges above the ground
/// at `air_gauges`' radii: the top layer of every body that is not an explosive (the
/// particles within one spacing below the surface) is loaded.
fn air_load<const D: usize>(
    scene: &Scene,
    air: AirBlast,
    gravity: Gravity,
    built: &Built<D>,
    air_gauges: &[f64],
) -> Result<(AirLoad, Vec<GaugeTrace>), VerifyError> {
    let mut radii = Vec::new();
    let mut loaded = vec![None; built.init.len()];
    for (k, q) in built.init.iter().enumerate() {
        let body = &scene.bodies[built.body_of[k]];
        let explosive = scene.materials[body.material].detonation_speed.is_some();
        if explosive || q.position[D - 1] + body.spacing <= gravity.surface {
            continue;
        }
        let face = 2.0 * PI * q.position[0] * body.spacing;
        loaded[k] = Some((radii.len(), face / q.mass));
        radii.push(q.position[0]);
    }
    let on_ground = radii.len();
    radii.extend_from_slice(air_gauges);
    let mut traces = ground_overpressure(air.charge_kg, &radii, scene.end_time, air.shells)?;
    let gauges = traces.split_off(on_ground);
    let load = AirLoad {
        times: traces.first().map_or_else(Vec::new, |t| t.time.clone()),
        overpressure: traces.into_iter().map(|t| t.overpressure).collect(),
        loaded,
    };
    Ok((load, gauges))
}

/// The point lies in `body`: in its shape and in none of its holes.
fn in_body(body: &Body, x: &[f64]) -> bool {
    contains(&body.shape, x) && !body.subtract.iter().any(|hole| contains(hole, x))
}

/// Lattice points (k + ½)Δ of `body`'s spacing inside it and inside the domain.
fn lattice<const D: usize>(scene: &Scene, body: &Body) -> Vec<Vector<D>> {
    let (lo, hi) = scene.bounds(&body.shape);
    let dx = body.spacing;
    let first: Vec<i64> = (0..D).map(|a| (lo[a] / dx - 0.5).ceil() as i64).collect();
    let last: Vec<i64> = (0..D).map(|a| (hi[a] / dx - 0.5).ceil() as i64).collect();
    let mut points = Vec::new();
    if (0..D).any(|a| last[a] <= first[a]) {
        return points;
    }
    let mut k = first.clone();
    loop {
        let x = Vector::<D>::from_fn(|a, _| (k[a] as f64 + 0.5) * dx);
        if in_body(body, x.as_slice()) {
            points.push(x);
        }
        // the next index, the first axis fastest
        let mut a = 0;
        loop {
            k[a] += 1;
            if k[a] < last[a] {
                break;
            }
            k[a] = first[a];
            a += 1;
            if a == D {
                return points;
            }
        }
    }
}

/// The free field's vertical stress σ_v = −g ∫ ρ dz at the height of `x`: the column from
/// there up to the ground's surface at the domain's far horizontal corner, each height taking
/// the ambient density of the body it lies in (above the domain, that of the body at its top),
/// summed by the midpoint rule in steps of `dz`.
/// A horizontally layered ground thus carries each layer's weight, while buried structures
/// and voids are wished into the free-field stress and cast no shadow (the stress the
/// surrounding ground would redistribute around them is not modelled).
fn overburden(scene: &Scene, gravity: Gravity, x: &[f64], dz: f64) -> f64 {
    let d = x.len();
    let depth = gravity.surface - x[d - 1];
    if depth <= 0.0 {
        return 0.0;
    }
    let steps = (depth / dz).ceil().max(1.0) as usize;
    let step = depth / steps as f64;
    let mut point: Vec<f64> = (0..d).map(|a| scene.hi[a] - 0.5 * dz).collect();
    let mut column = 0.0;
    // above the domain's top, up to a surface beyond it, the ground is the top body's
    let mut density = 0.0;
    for k in 0..steps {
        point[d - 1] = x[d - 1] + (k as f64 + 0.5) * step;
        if point[d - 1] < scene.hi[d - 1] {
            density = scene
                .bodies
                .iter()
                .find(|b| in_body(b, &point))
                .map_or(0.0, |body| scene.materials[body.material].ambient.0);
        }
        column += density * step;
    }
    -gravity.acceleration * column
}

/// The density at which `material`'s pressure is `pressure` at specific energy `e`, by
/// bisection between its ambient density and three times that (the pressure rises with
/// density on every loading path in the library).
fn density_at_pressure(
    material: &Material,
    (rho0, e): (f64, f64),
    pressure: f64,
) -> Result<f64, VerifyError> {
    let p = |rho: f64| material.eos.pressure(rho, e);
    let (mut lo, mut hi) = (rho0, 3.0 * rho0);
    if !(p(lo) <= pressure && pressure <= p(hi)) {
        return Err(VerifyError::bad_value(
            &format!("geostatic pressure in {} (Pa)", material.name),
            pressure,
            &format!(
                "between {:e} and {:e}, the pressures of ρ0 and 3ρ0",
                p(lo),
                p(hi)
            ),
        ));
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if p(mid) < pressure {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// The geostatic state of each particle below the ground's surface: σ_v from the overburden,
/// σ_h = K0 σ_v across, so p = −(σ_v + 2σ_h)/3 (the out-of-plane direction of a plane-strain
/// section and the hoop direction of rings are horizontal too) and the deviator s_v = σ_v + p,
/// s_h = σ_h + p; its density is where its equation of state gives p, its mass that density
/// times its cell, and a fluid's deviator is zero.
fn geostatic<const D: usize>(
    scene: &Scene,
    gravity: Gravity,
    materials: &[Material],
    init: &mut [ParticleInit<D>],
) -> Result<Vec<Tensor<D>>, VerifyError> {
    let finest = scene
        .bodies
        .iter()
        .map(|b| b.spacing)
        .fold(f64::INFINITY, f64::min);
    let mut stresses = Vec::with_capacity(init.len());
    for q in init.iter_mut() {
        let m = q.material as usize;
        let vertical = overburden(scene, gravity, q.position.as_slice(), 0.5 * finest);
        let horizontal = scene.materials[m].at_rest_ratio * vertical;
        let pressure = -(vertical + 2.0 * horizontal) / 3.0;
        let mut s = Tensor::<D>::zeros();
        if materials[m].strength.is_some() {
            for a in 0..D {
                s[(a, a)] = if a == D - 1 { vertical } else { horizontal } + pressure;
            }
        }
        stresses.push(s);
        if pressure > 0.0 {
            let rho = density_at_pressure(&materials[m], (q.density, q.internal_energy), pressure)?;
            q.mass *= rho / q.density;
            q.density = rho;
        }
    }
    Ok(stresses)
}

/// The particles a run of `scene` starts from (geostatic under gravity) and the index of each
/// one's body.
pub fn particles<const D: usize>(
    scene: &Scene,
) -> Result<(Vec<ParticleInit<D>>, Vec<usize>), VerifyError> {
    let built = build::<D>(scene)?;
    Ok((built.init, built.body_of))
}

fn build<const D: usize>(scene: &Scene) -> Result<Built<D>, VerifyError> {
    let mut init = Vec::new();
    let mut body_of = Vec::new();
    let mut lighting = Vec::new();
    let mut burn_speed: Option<f64> = None;
    for (b, body) in scene.bodies.iter().enumerate() {
        let material = &scene.materials[body.material];
        let (rho, e) = material.ambient;
        let dx = body.spacing;
        let points = lattice::<D>(scene, body);
        if points.is_empty() {
            return Err(VerifyError::Scene {
                line: body.line,
                key: "body.shape".into(),
                message: format!(
                    "body '{}' holds no particle at spacing {dx} m inside the domain",
                    body.name
                ),
            });
        }
        if let Some(speed) = material.detonation_speed {
            match burn_speed {
                Some(s) if s != speed => {
                    return Err(VerifyError::Scene {
                        line: body.line,
                        key: "body.material".into(),
                        message: "every charge of a scene is the same explosive".into(),
                    })
                }
                _ => burn_speed = Some(speed),
            }
        }
        for x in points {
            if let Some(other) = scene
                .bodies
                .iter()
                .take(b)
                .find(|other| in_body(other, x.as_slice()))
            {
                return Err(VerifyError::Scene {
                    line: body.line,
                    key: "body.shape".into(),
                    message: format!(
                        "body '{}' overlaps body '{}' at {:?}: subtract one from the other",
                        body.name,
                        other.name,
                        x.as_slice()
                    ),
                });
            }
            // a ring's mass in an axisymmetric scene: ρ 2π r Δ²
            let volume = match scene.geometry {
                Geometry::Axisymmetric => 2.0 * PI * x[0] * dx * dx,
                Geometry::PlaneStrain | Geometry::ThreeD => dx.powi(D as i32),
            };
            let lit = if material.detonation_speed.is_some() {
                body.detonation_points
                    .iter()
                    .map(|p| (x - Vector::<D>::from_column_slice(p)).norm())
                    .fold(f64::INFINITY, f64::min)
                    / material.detonation_speed.unwrap_or(1.0)
            } else {
                f64::NEG_INFINITY
            };
            lighting.push(lit);
            init.push(ParticleInit {
                position: x,
                velocity: Vector::<D>::from_column_slice(&body.velocity),
                mass: rho * volume,
                smoothing_length: scene.eta * dx,
                density: rho,
                internal_energy: e,
                material: body.material as u16,
            });
            body_of.push(b);
        }
    }
    check_spacing_ratios(scene, &init, &body_of)?;
    let burn = burn_speed.map(|speed| ProgrammedBurn {
        lighting_time: lighting,
        speed,
        ramp_lengths: blastsph_solver::burn::DEFAULT_RAMP_LENGTHS,
    });
    let deviatoric_stress = match scene.gravity {
        Some(gravity) => Some(geostatic(
            scene,
            gravity,
            &scene_materials(scene)?,
            &mut init,
        )?),
        None => None,
    };
    Ok(Built {
        init,
        body_of,
        burn,
        deviatoric_stress,
    })
}

/// The largest ratio of the spacings of two bodies in contact: a kernel spanning a jump of
/// more than this sees too few particles on the fine side, and the coarse side's
/// particles leave gaps the fine ones fall into.
pub const MAX_SPACING_RATIO: f64 = 2.0;

/// Refuses two bodies in contact (particles nearer than the sum of their spacings) whose
/// spacings differ by more than [`MAX_SPACING_RATIO`].
fn check_spacing_ratios<const D: usize>(
    scene: &Scene,
    init: &[ParticleInit<D>],
    body_of: &[usize],
) -> Result<(), VerifyError> {
    let bodies = &scene.bodies;
    for (a, fine) in bodies.iter().enumerate() {
        for (b, coarse) in bodies.iter().enumerate() {
            if coarse.spacing <= MAX_SPACING_RATIO * fine.spacing {
                continue;
            }
            let reach = fine.spacing + coarse.spacing;
            let cell = |x: &Vector<D>| -> [i64; 3] {
                std::array::from_fn(|k| {
                    if k < D {
                        (x[k] / reach).floor() as i64
                    } else {
                        0
                    }
                })
            };
            let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
            for i in (0..init.len()).filter(|&i| body_of[i] == b) {
                grid.entry(cell(&init[i].position)).or_default().push(i);
            }
            let touching = (0..init.len()).filter(|&i| body_of[i] == a).find(|&i| {
                let x = &init[i].position;
                let c = cell(x);
                let reach_of = |k: usize| if k < D { -1..=1 } else { 0..=0 };
                reach_of(0).any(|dx| {
                    reach_of(1).any(|dy| {
                        reach_of(2).any(|dz| {
                            grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                                .is_some_and(|list| {
                                    list.iter().any(|&j| (init[j].position - x).norm() < reach)
                                })
                        })
                    })
                })
            });
            if let Some(i) = touching {
                return Err(VerifyError::Scene {
                    line: coarse.line,
                    key: "body.spacing".into(),
                    message: format!(
                        "bodies '{}' ({} m) and '{}' ({} m) touch near {:?} with spacings {:.2} \
                         times apart: at most {MAX_SPACING_RATIO}, or a body of intermediate \
                         spacing between them",
                        coarse.name,
                        coarse.spacing,
                        fine.name,
                        fine.spacing,
                        init[i].position.as_slice(),
                        coarse.spacing / fine.spacing
                    ),
                });
            }
        }
    }
    Ok(())
}

fn scene_materials(scene: &Scene) -> Result<Vec<Material>, VerifyError> {
    scene.materials.iter().map(|m| m.material()).collect()
}

/// How well the geostatic state is the discrete equilibrium under gravity: the external
/// acceleration that holds each particle at rest against g, over particles whose kernel
/// support lies inside their own body, clear of the surface and the domain's sides (near
/// those it also carries the support the boundary gives).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct GravityBalance {
    pub gravity_m_s2: f64,
    pub interior_particles: usize,
    /// Mean and largest |a_ext − g|/|g| over them.
    pub interior_mean_departure: f64,
    pub interior_max_departure: f64,
}

impl GravityBalance {
    fn of<const D: usize>(
        scene: &Scene,
        gravity: Gravity,
        sim: &Simulation<D>,
        body_of: &[usize],
    ) -> Self {
        let p = sim.particles();
        let mut g = Vector::<D>::zeros();
        g[D - 1] = -gravity.acceleration;
        let support = |i: usize| 2.0 * p.smoothing_length[i];
        let interior = |i: usize| {
            let x = p.position[i];
            let body = &scene.bodies[body_of[p.id[i] as usize]];
            let r = support(i);
            x[D - 1] < gravity.surface - r
                && (0..D).all(|a| x[a] - r > scene.lo[a] && x[a] + r < scene.hi[a])
                && directions::<D>()
                    .iter()
                    .all(|n| in_body(body, (x + n * r).as_slice()))
        };
        let departures: Vec<f64> = (0..p.n_real())
            .filter(|&i| interior(i))
            .map(|i| (p.external_acceleration[i] - g).norm() / gravity.acceleration)
            .collect();
        let n = departures.len();
        Self {
            gravity_m_s2: gravity.acceleration,
            interior_particles: n,
            interior_mean_departure: departures.iter().sum::<f64>() / n.max(1) as f64,
            interior_max_departure: departures.iter().copied().fold(0.0, f64::max),
        }
    }
}

/// The 3^D − 1 unit vectors towards the faces, edges and corners of a cube about the origin.
fn directions<const D: usize>() -> Vec<Vector<D>> {
    (0..3_usize.pow(D as u32))
        .map(|k| Vector::<D>::from_fn(|a, _| ((k / 3_usize.pow(a as u32)) % 3) as f64 - 1.0))
        .filter(|v| v.norm() > 0.0)
        .map(|v| v.normalize())
        .collect()
}

fn config(scene: &Scene) -> SimulationConfig {
    let smoothing = SmoothingLength::FollowDensityFloored { eta: scene.eta };
    let finest = scene
        .bodies
        .iter()
        .map(|b| b.spacing)
        .fold(f64::INFINITY, f64::min);
    SimulationConfig {
        time_steps: match scene.time_steps {
            StepChoice::Global => blastsph_solver::TimeSteps::Global,
            StepChoice::Individual => blastsph_solver::TimeSteps::Individual {
                max_ratio: INDIVIDUAL_MAX_RATIO,
            },
        },
        // continuity density: several materials of very different densities side by side
        formulation: match scene.geometry {
            Geometry::Axisymmetric => Formulation::Axisymmetric(smoothing),
            Geometry::PlaneStrain | Geometry::ThreeD => {
                Formulation::Cartesian(Density::Continuity(smoothing))
            }
        },
        kernel: KernelShape::CubicSpline,
        viscosity: viscosity_switched_down_to(scene.alpha_min),
        energy: EnergyEquation::OwnPressure,
        cfl: scene.cfl,
        // a step below 1e-9 of the time a 10 km/s signal takes across the finest spacing
        min_time_step: 1e-9 * finest / 1e4,
        ..SimulationConfig::default()
    }
}

/// One gauge: the particle it reads (by id) and what it read after each step.
struct GaugeHistory {
    name: String,
    body: usize,
    id: u32,
    start: Vec<f64>,
    rows: Vec<Vec<f64>>,
}

/// Where each particle, by its id (its index at creation), is stored now: `None` once it has
/// left through an outflow side.
pub fn current_index<const D: usize>(sim: &Simulation<D>) -> Vec<Option<usize>> {
    let p = sim.particles();
    let mut index = vec![None; p.n_real() + sim.departed().particles];
    for i in 0..p.n_real() {
        index[p.id[i] as usize] = Some(i);
    }
    index
}

/// The particle whose id is `id`, looked up again only when reordering moved it; `None` once
/// it has left through an outflow side.
fn index_of<const D: usize>(sim: &Simulation<D>, id: u32, hint: &mut usize) -> Option<usize> {
    let ids = &sim.particles().id;
    if ids.get(*hint) != Some(&id) {
        *hint = ids.iter().position(|&k| k == id)?;
    }
    Some(*hint)
}

/// A gauge's row: the time, then its particle's readings (NaN once the particle has left
/// through an outflow side).
fn gauge_row<const D: usize>(sim: &Simulation<D>, i: Option<usize>, start: &[f64]) -> Vec<f64> {
    let Some(i) = i else {
        let mut row = vec![f64::NAN; gauge_columns(D).len()];
        row[0] = sim.time();
        return row;
    };
    let p = sim.particles();
    let mut row = vec![sim.time(), p.pressure[i]];
    row.extend(p.velocity[i].iter());
    row.extend((0..D).map(|a| p.position[i][a] - start[a]));
    let stressed = !p.deviatoric_stress.is_empty();
    row.push(if stressed {
        von_mises(&p.deviatoric_stress[i])
    } else {
        0.0
    });
    row.push(if stressed { p.plastic_strain[i] } else { 0.0 });
    row.push(p.density[i]);
    row.push(status_code(sim, i));
    row
}

fn gauge_columns(d: usize) -> Vec<String> {
    let axes = ["x", "y", "z"];
    let mut columns = vec!["time_s".to_string(), "pressure_pa".into()];
    columns.extend(axes[..d].iter().map(|a| format!("velocity_{a}_m_s")));
    columns.extend(axes[..d].iter().map(|a| format!("displacement_{a}_m")));
    columns.extend(["von_mises_pa", "plastic_strain", "density_kg_m3", "status"].map(String::from));
    columns
}

fn csv(columns: &[String], rows: &[Vec<f64>]) -> Vec<u8> {
    let mut s = columns.join(",");
    s.push('\n');
    for row in rows {
        let cells: Vec<String> = row.iter().map(|v| format!("{v:e}")).collect();
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s.into_bytes()
}

/// Per material: x, y (, z) momentum and kinetic plus internal energy.
fn material_ledger<const D: usize>(sim: &Simulation<D>, materials: usize) -> Vec<f64> {
    let p = sim.particles();
    let mut sums = vec![0.0; materials * (D + 1)];
    for i in 0..p.n_real() {
        let k = p.material_of(i) * (D + 1);
        for a in 0..D {
            sums[k + a] += p.mass[i] * p.velocity[i][a];
        }
        sums[k + D] += p.mass[i] * (0.5 * p.velocity[i].norm_squared() + p.internal_energy[i]);
    }
    let mut row = vec![sim.time()];
    row.extend(sums);
    row
}

/// As [`run`], in `D` dimensions, with the motion `prescribe` gives (see [`Prescribe`]),
/// `observer` shown the simulation after every step, and `checkpoints`.
pub fn run_with<const D: usize, O: Observer<D>>(
    scene: &Scene,
    out: &Path,
    progress: &mut dyn FnMut(f64),
    prescribe: Prescribe<D>,
    observer: &mut O,
    checkpoints: &Checkpoints,
) -> Result<RunSummary, VerifyError> {
    let io = |path: &Path| {
        let path = path.display().to_string();
        move |source| VerifyError::Io { path, source }
    };
    let summary_path = out.join("scene.json");
    // a summary left by an earlier run must not stand beside this run's partial outputs
    if summary_path.exists() {
        std::fs::remove_file(&summary_path).map_err(io(&summary_path))?;
    }
    let built = build::<D>(scene)?;
    let mut gauges = Vec::new();
    let mut air_gauges = Vec::new();
    for g in &scene.gauges {
        let above_ground = match (scene.air_blast, scene.gravity) {
            (Some(_), Some(gravity)) => g.position[D - 1] >= gravity.surface,
            _ => false,
        };
        let Some(body) = scene.bodies.iter().position(|b| in_body(b, &g.position)) else {
            if above_ground {
                air_gauges.push(g);
                continue;
            }
            return Err(VerifyError::Scene {
                line: g.line,
                key: "gauge.position".into(),
                message: format!(
                    "gauge '{}' at {:?} lies in no body{}",
                    g.name,
                    g.position,
                    if scene.air_blast.is_some() {
                        " and below the ground's surface"
                    } else {
                        ""
                    }
                ),
            });
        };
        let x = Vector::<D>::from_column_slice(&g.position);
        let nearest = (0..built.init.len())
            .filter(|&i| built.body_of[i] == body)
            .min_by(|&i, &j| {
                let di = (built.init[i].position - x).norm();
                let dj = (built.init[j].position - x).norm();
                di.total_cmp(&dj)
            })
            .expect("a body holds particles");
        gauges.push(GaugeHistory {
            name: g.name.clone(),
            body,
            id: nearest as u32,
            start: built.init[nearest].position.as_slice().to_vec(),
            rows: Vec::new(),
        });
    }

    let lower: [Boundary; D] = std::array::from_fn(|a| scene.sides[a].0);
    let upper: [Boundary; D] = std::array::from_fn(|a| scene.sides[a].1);
    let domain = Domain::with_sides(
        Vector::<D>::from_column_slice(&scene.lo),
        Vector::<D>::from_column_slice(&scene.hi),
        lower,
        upper,
    )?;
    let materials = scene_materials(scene)?;
    let config = config(scene);
    let started = Instant::now();
    let (load, air_traces) = match (scene.air_blast, scene.gravity) {
        (Some(air), Some(gravity)) => {
            let radii: Vec<f64> = air_gauges.iter().map(|g| g.position[0]).collect();
            let (load, mut traces) = air_load(scene, air, gravity, &built, &radii)?;
            for (trace, g) in traces.iter_mut().zip(&air_gauges) {
                trace.name = g.name.clone();
            }
            (Some(Arc::new(load) as Arc<dyn ExternalLoad<D>>), traces)
        }
        _ => (None, Vec::new()),
    };
    let state = InitialState {
        prescribed: prescribe(&built.init, &built.body_of),
        load,
        burn: built.burn,
        held_in_equilibrium: built.deviatoric_stress.is_some(),
        deviatoric_stress: built.deviatoric_stress,
    };
    let mut sim = Simulation::with_initial_state(&built.init, materials, domain, config, state)?;
    let balance = scene
        .gravity
        .map(|gravity| GravityBalance::of(scene, gravity, &sim, &built.body_of));
    let energy_at_start = sim.particles().total_energy() + sim.transmitted_energy();

    let snapshots = out.join("snapshots");
    for dir in [out.join("gauges"), snapshots.clone()] {
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    }
    let checkpoint_path = out.join(CHECKPOINT_FILE);
    let inputs_hash = crate::cache::inputs_hash(&[
        format!("{scene:?}").as_bytes(),
        checkpoints.context.as_bytes(),
    ])?;
    let resumed = if checkpoints.resume {
        kept_state::<D>(&checkpoint_path, &inputs_hash)?
    } else {
        if checkpoint_path.exists() {
            std::fs::remove_file(&checkpoint_path).map_err(io(&checkpoint_path))?;
        }
        None
    };
    let ledger_interval = scene.output_interval.unwrap_or(scene.end_time / 100.0);
    let write_snapshot = |sim: &Simulation<D>, written: &mut Vec<(f64, String)>| {
        let name = format!("{}.vtu", written.len());
        let path = snapshots.join(&name);
        write_atomic(&path, Snapshot::of(sim).to_vtu().as_bytes())?;
        written.push((sim.time(), name));
        Ok::<(), VerifyError>(())
    };
    let mut hints = vec![0usize; gauges.len()];
    // what the run gathers: gauge rows, the ledger, the snapshots written, and the particles
    // that reached the tensile cutoff (by id); from the checkpoint where the run resumes
    let (mut ledger, mut next_ledger, mut written, mut ever_failed, wall_before) = match resumed {
        Some(state) => {
            sim.resume(state.simulation)?;
            for (g, rows) in gauges.iter_mut().zip(state.gauge_rows) {
                g.rows = rows;
            }
            *observer = bincode::deserialize(&state.observer).map_err(|_| {
                VerifyError::bad_value(
                    "checkpoint",
                    checkpoint_path.display(),
                    "a checkpoint of this scene written by this build",
                )
            })?;
            (
                state.ledger,
                state.next_ledger,
                state.written,
                state.ever_failed,
                state.wall_s,
            )
        }
        None => {
            let mut written = Vec::new();
            if scene.output_interval.is_some() {
                write_snapshot(&sim, &mut written)?;
            }
            for (g, hint) in gauges.iter_mut().zip(&mut hints) {
                let i = index_of(&sim, g.id, hint);
                g.rows.push(gauge_row(&sim, i, &g.start));
            }
            let mut ever_failed = vec![false; built.init.len()];
            mark_failed(&sim, &mut ever_failed);
            let ledger = vec![material_ledger(&sim, scene.materials.len())];
            (ledger, ledger_interval, written, ever_failed, 0.0)
        }
    };
    let mut last_checkpoint = Instant::now();
    let mut stopped = None;
    while sim.time() < scene.end_time {
        let target = next_ledger.min(scene.end_time);
        if let Err(diagnosis) = sim.step_toward(target) {
            stopped = Some(diagnosis.to_string());
            break;
        }
        for (g, hint) in gauges.iter_mut().zip(&mut hints) {
            let i = index_of(&sim, g.id, hint);
            g.rows.push(gauge_row(&sim, i, &g.start));
        }
        observer.observe(&sim);
        mark_failed(&sim, &mut ever_failed);
        if sim.time() >= target {
            ledger.push(material_ledger(&sim, scene.materials.len()));
            next_ledger += ledger_interval;
            if scene.output_interval.is_some() {
                write_snapshot(&sim, &mut written)?;
            }
        }
        progress(sim.time() / scene.end_time);
        let due = checkpoints
            .every_s
            .is_some_and(|every| last_checkpoint.elapsed().as_secs_f64() >= every);
        if due && sim.time() < scene.end_time {
            let state = RunState {
                inputs_hash: inputs_hash.clone(),
                simulation: sim.checkpoint(),
                gauge_rows: gauges.iter().map(|g| g.rows.clone()).collect(),
                ledger: ledger.clone(),
                next_ledger,
                written: written.clone(),
                ever_failed: ever_failed.clone(),
                wall_s: wall_before + started.elapsed().as_secs_f64(),
                observer: bincode::serialize(observer).expect("an observer serialises"),
            };
            let bytes = bincode::serialize(&state).expect("a run state serialises");
            write_atomic(&checkpoint_path, &bytes)?;
            last_checkpoint = Instant::now();
        }
    }
    let wall_s = wall_before + started.elapsed().as_secs_f64();

    let columns = gauge_columns(D);
    for g in &gauges {
        write_atomic(
            &out.join("gauges").join(format!("{}.csv", g.name)),
            &csv(&columns, &g.rows),
        )?;
    }
    let mut ledger_columns = vec!["time_s".to_string()];
    for m in &scene.materials {
        ledger_columns
            .extend((0..D).map(|a| format!("{}_momentum_{}_kg_m_s", m.name, ["x", "y", "z"][a])));
        ledger_columns.push(format!("{}_energy_j", m.name));
    }
    write_atomic(&out.join("materials.csv"), &csv(&ledger_columns, &ledger))?;
    if !written.is_empty() {
        let mut pvd = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
        );
        for (time, name) in &written {
            let _ = writeln!(
                pvd,
                "<DataSet timestep=\"{time:e}\" file=\"snapshots/{name}\"/>"
            );
        }
        pvd.push_str("</Collection>\n</VTKFile>\n");
        write_atomic(&out.join("snapshots.pvd"), pvd.as_bytes())?;
    }

    let energy_change_j =
        sim.particles().total_energy() + sim.transmitted_energy() - energy_at_start;
    let strong_bodies: Vec<usize> = (0..scene.bodies.len())
        .filter(|&b| sim.materials()[scene.bodies[b].material].strength.is_some())
        .collect();
    let count_by_body = |counted: &dyn Fn(usize) -> bool| {
        let p = sim.particles();
        strong_bodies
            .iter()
            .map(|&b| {
                let n = (0..p.n_real())
                    .filter(|&i| built.body_of[p.id[i] as usize] == b && counted(i))
                    .count();
                (scene.bodies[b].name.clone(), n)
            })
            .collect::<BTreeMap<String, usize>>()
    };
    let mut bodies = BTreeMap::new();
    for (b, body) in scene.bodies.iter().enumerate() {
        bodies.insert(
            body.name.clone(),
            built.body_of.iter().filter(|&&k| k == b).count(),
        );
    }
    let peak = |rows: &[Vec<f64>], column: usize, magnitude: bool| {
        rows.iter()
            .map(|r| {
                if magnitude {
                    r[column..column + D]
                        .iter()
                        .map(|v| v * v)
                        .sum::<f64>()
                        .sqrt()
                } else {
                    r[column]
                }
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let summary = RunSummary {
        scene: scene.name.clone(),
        geometry: format!("{:?}", scene.geometry),
        bodies,
        particles: built.init.len(),
        steps: sim.steps(),
        end_time_s: scene.end_time,
        time_reached_s: sim.time(),
        wall_s,
        stopped,
        energy_change_j,
        energy_relative_change: (energy_at_start > 0.0)
            .then(|| energy_change_j.abs() / energy_at_start),
        gravity_balance: balance,
        max_displacement_m: (0..sim.particles().n_real())
            .map(|i| {
                let p = sim.particles();
                (p.position[i] - built.init[p.id[i] as usize].position).norm()
            })
            .fold(0.0, f64::max),
        gauges: gauges
            .iter()
            .map(|g| GaugeSummary {
                name: g.name.clone(),
                body: scene.bodies[g.body].name.clone(),
                particle_position_m: g.start.clone(),
                peak_pressure_pa: peak(&g.rows, 1, false),
                peak_velocity_m_s: peak(&g.rows, 2, true),
                peak_von_mises_pa: peak(&g.rows, 2 + 2 * D, false),
                peak_displacement_m: peak(&g.rows, 2 + D, true),
                arrival_s: arrival(&g.rows),
            })
            .collect(),
        air_gauges: air_traces.iter().map(GaugeTrace::summary).collect(),
        energy_exchanged_j: sim.transmitted_energy(),
        departed: sim.departed(),
        yielded: count_by_body(&|i| {
            let p = sim.particles();
            !p.plastic_strain.is_empty() && p.plastic_strain[i] > 0.0
        }),
        failed: count_by_body(&|i| ever_failed[sim.particles().id[i] as usize]),
    };
    let json = serde_json::to_vec_pretty(&summary).expect("the summary serialises");
    write_atomic(&summary_path, &json)?;
    if checkpoint_path.exists() {
        std::fs::remove_file(&checkpoint_path).map_err(io(&checkpoint_path))?;
    }
    Ok(summary)
}

/// The first time the speed (columns 2 .. 2 + D of a gauge row) reached
/// [`ARRIVAL_FRACTION`] of its peak; NaN if it never moved.
fn arrival(rows: &[Vec<f64>]) -> f64 {
    let d = (rows.first().map_or(0, Vec::len) - 6) / 2;
    let speed = |r: &Vec<f64>| r[2..2 + d].iter().map(|v| v * v).sum::<f64>().sqrt();
    let peak = rows.iter().map(speed).fold(0.0, f64::max);
    if peak <= 0.0 {
        return f64::NAN;
    }
    rows.iter()
        .find(|r| speed(r) >= ARRIVAL_FRACTION * peak)
        .map_or(f64::NAN, |r| r[0])
}
