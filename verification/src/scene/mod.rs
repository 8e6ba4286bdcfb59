//! Scenes from TOML files: the geometry, the domain and its sides, materials (the library's,
//! optionally with a strength model), bodies built from primitives each at its own particle
//! spacing, charges (bodies of an explosive with detonation points), gauges and the run's
//! times. [`Scene::parse`] reads and checks a file; an error names the key, its line and what
//! is allowed. [`run`] builds the particles and runs the scene (see `run.rs`).
//!
//! A scene file, by example (plane strain, the last axis vertical):
//!
//! ```toml
//! [scene]
//! name = "lined tunnel"
//! geometry = "plane-strain"   # or "axisymmetric" (r, z; the axis at r = 0) or "3d"
//! end_time = 0.02             # s
//! output_interval = 0.005     # s between particle snapshots (optional)
//!
//! [domain]
//! min = [-20.0, -30.0]
//! max = [20.0, 1.0]
//! sides = { x_min = "transmitting", x_max = "transmitting", y_min = "transmitting", y_max = "open" }
//!
//! [[material]]
//! name = "sand"
//! library = "dry-sand"
//! drucker_prager = { cohesion = 0.0, friction_angle = 30.0 }
//!
//! [[body]]
//! name = "soil"
//! material = "sand"
//! spacing = 0.5
//! shape = { kind = "box", min = [-20.0, -30.0], max = [20.0, 0.0] }
//! subtract = [{ kind = "sphere", centre = [0.0, -10.0], radius = 3.35 }]
//!
//! [[gauge]]
//! name = "crown"
//! position = [0.0, -6.8]
//! ```
//!
//! An axisymmetric scene with `[gravity]` may add the air blast of a TNT charge lying on the
//! surface at the axis, `[air_blast]` with `charge` (kg) and optionally `shells` (see
//! [`AirBlast`]); a gauge above the surface then reads the air's overpressure.

mod run;

pub use run::{
    current_index, particles, run, run_checkpointed, run_with, Checkpoints, Observer, Prescribe,
    RunSummary, CHECKPOINT_FILE,
};

use crate::materials::Library;
use crate::VerifyError;
use blastsph_solver::{Boundary, Material, Strength};
use serde::Deserialize;
use std::ops::Range;
use toml::Spanned;

/// What the particles stand for: a plane-strain section (x, y), rings about the axis (r, z), or
/// three dimensions (x, y, z). The last axis is vertical in each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Geometry {
    PlaneStrain,
    Axisymmetric,
    #[serde(rename = "3d")]
    ThreeD,
}

impl Geometry {
    pub fn dimension(self) -> usize {
        match self {
            Geometry::PlaneStrain | Geometry::Axisymmetric => 2,
            Geometry::ThreeD => 3,
        }
    }
}

/// One side of the domain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum Side {
    /// A free surface.
    Open,
    /// A mirror: a rigid, frictionless wall or a symmetry plane.
    Wall,
    /// Waves leave through it (Lysmer–Kuhlemeyer's viscous traction).
    Transmitting,
    /// Matter leaves through it: a particle beyond it leaves the run, what it carries booked.
    Outflow,
}

impl From<Side> for Boundary {
    fn from(side: Side) -> Self {
        match side {
            Side::Open => Boundary::Open,
            Side::Wall => Boundary::Wall,
            Side::Transmitting => Boundary::Transmitting,
            Side::Outflow => Boundary::Outflow,
        }
    }
}

/// A primitive shape. The vertical is the last axis; in plane strain a sphere is a disc (a
/// cylinder seen end on), in 3D an annulus is a tube along y.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Shape {
    /// min ≤ x < max on every axis.
    Box { min: Vec<f64>, max: Vec<f64> },
    /// bottom ≤ vertical < top, across the whole domain.
    Layer { bottom: f64, top: f64 },
    /// |x − centre| < radius; `mass` (kg) instead of `radius` for a sphere of the body's
    /// material.
    Sphere {
        centre: Vec<f64>,
        radius: Option<f64>,
        mass: Option<f64>,
    },
    /// The half of a sphere above its centre.
    Hemisphere {
        centre: Vec<f64>,
        radius: Option<f64>,
        mass: Option<f64>,
    },
    /// inner_radius ≤ distance from the centre (in the vertical plane across y) < outer_radius.
    Annulus {
        centre: Vec<f64>,
        inner_radius: f64,
        outer_radius: f64,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    scene: Header,
    domain: DomainFile,
    #[serde(default)]
    numerics: Option<Spanned<NumericsFile>>,
    gravity: Option<Spanned<GravityFile>>,
    #[serde(default)]
    material: Vec<Spanned<MaterialFile>>,
    #[serde(default)]
    body: Vec<Spanned<BodyFile>>,
    #[serde(default)]
    gauge: Vec<Spanned<GaugeFile>>,
    air_blast: Option<Spanned<AirBlastFile>>,
}

/// A TNT charge lying on the ground at the axis whose air blast loads the ground's surface
/// (the air itself is not in the scene).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AirBlastFile {
    charge: f64,
    shells: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Header {
    name: String,
    geometry: Spanned<Geometry>,
    end_time: Spanned<f64>,
    output_interval: Option<Spanned<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DomainFile {
    min: Spanned<Vec<f64>>,
    max: Spanned<Vec<f64>>,
    sides: Spanned<Sides>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Sides {
    x_min: Side,
    x_max: Side,
    y_min: Side,
    y_max: Side,
    z_min: Option<Side>,
    z_max: Option<Side>,
}

/// Gravity along the vertical axis and the height of the ground's surface: the bodies start
/// in their geostatic state, held in equilibrium.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct GravityFile {
    acceleration: f64,
    surface: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct NumericsFile {
    cfl: Option<f64>,
    eta: Option<f64>,
    alpha_min: Option<f64>,
    time_steps: Option<StepChoice>,
}

/// How a scene's particles share time: one global step, or each its own (power-of-two
/// block steps within a factor 4 of its neighbours', the longest at most
/// [`INDIVIDUAL_MAX_RATIO`] times the shortest).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepChoice {
    #[default]
    Global,
    Individual,
}

/// The longest individual step in a scene over the shortest: a tunnel lining's steps are
/// about twenty times shorter than its soil's.
pub const INDIVIDUAL_MAX_RATIO: u64 = 64;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    name: String,
    library: Spanned<String>,
    drucker_prager: Option<DruckerPragerFile>,
    von_mises: Option<VonMisesFile>,
}

/// Drucker–Prager strength fitted to Mohr–Coulomb's c and φ; G from the unloaded bulk modulus
/// and Poisson's ratio.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DruckerPragerFile {
    cohesion: f64,
    friction_angle: f64,
    #[serde(default = "default_poisson")]
    poisson: f64,
}

/// Von Mises strength with a constant yield stress; G from the unloaded bulk modulus and
/// Poisson's ratio.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct VonMisesFile {
    #[serde(rename = "yield")]
    yield_stress: f64,
    #[serde(default = "default_poisson")]
    poisson: f64,
    /// A brittle solid's tensile strength (Pa): it cracks where the largest principal stress
    /// reaches it.
    tensile_strength: Option<f64>,
}

/// Poisson's ratio of a soil or concrete when a scene gives none (the value `ground-shock`'s
/// sand takes).
fn default_poisson() -> f64 {
    crate::problems::ground_shock::POISSON
}

/// What a body leaves out: another body of the scene (by name), or a shape.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum HoleFile {
    Body(String),
    Shape(Shape),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyFile {
    name: String,
    material: Spanned<String>,
    spacing: Spanned<f64>,
    shape: Spanned<Shape>,
    subtract: Option<Spanned<Vec<HoleFile>>>,
    detonation_points: Option<Spanned<Vec<Vec<f64>>>>,
    velocity: Option<Spanned<Vec<f64>>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct GaugeFile {
    name: String,
    position: Spanned<Vec<f64>>,
}

/// A material of the scene: its name there, the library material it is, and the strength the
/// scene gives it.
#[derive(Clone, Debug)]
pub struct SceneMaterial {
    pub name: String,
    pub library: String,
    pub strength: Option<Strength>,
    /// Unloaded density and specific internal energy (the library's ambient state).
    pub ambient: (f64, f64),
    /// The detonation speed of an explosive (m/s).
    pub detonation_speed: Option<f64>,
    /// The coefficient of earth pressure at rest K0 = σ_h/σ_v of a geostatic state: Jaky's
    /// 1 − sin φ for a Drucker–Prager soil, ν/(1 − ν) for an elastic solid (no lateral strain
    /// under its own weight), 1 for a fluid.
    pub at_rest_ratio: f64,
}

#[derive(Clone, Debug)]
pub struct Body {
    pub name: String,
    /// Index into [`Scene::materials`].
    pub material: usize,
    pub spacing: f64,
    pub shape: Shape,
    pub subtract: Vec<Shape>,
    pub detonation_points: Vec<Vec<f64>>,
    /// Its initial velocity (m/s).
    pub velocity: Vec<f64>,
    /// Where the body stands in the file.
    pub line: usize,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity {
    pub acceleration: f64,
    pub surface: f64,
}

/// The air blast of a TNT charge lying on the ground's surface at the axis (a hemispherical
/// surface burst), which the scene does not hold as particles: its overpressure on a rigid
/// ground, from the one-dimensional scene of `airblast-surface` (see
/// [`crate::problems::airblast::ground_overpressure`]), presses on the top layer of the ground
/// wherever the air, not the products, covers it. The coupling is one way: the ground's
/// motion does not reach back into the air, whose acoustic impedance (about 400 Pa·s/m) is a
/// thousandth of a soil's. A gauge above the surface, in no body, reads this overpressure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirBlast {
    pub charge_kg: f64,
    /// Shells across the charge's radius in the one-dimensional air blast.
    pub shells: usize,
}

/// Where an air blast's numbers may lie.
pub const AIR_BLAST_CHARGE_RANGE: (f64, f64) = (1e-3, 1e6);
pub const AIR_BLAST_SHELLS_RANGE: (f64, f64) = (4.0, 200.0);
/// The shells across the charge of the air blast that loads a scene: the quick level of
/// `airblast-surface`, whose overpressure at Z ≥ 1 lies within its gate there.
pub const AIR_BLAST_SHELLS: usize = 20;

#[derive(Clone, Debug)]
pub struct GaugePoint {
    pub name: String,
    pub position: Vec<f64>,
    pub line: usize,
}

/// A checked scene.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub geometry: Geometry,
    pub end_time: f64,
    pub output_interval: Option<f64>,
    pub cfl: f64,
    pub eta: f64,
    pub alpha_min: f64,
    pub time_steps: StepChoice,
    /// Gravity's magnitude (m/s², acting down the vertical axis) and the ground surface's
    /// height: the bodies start in the geostatic state (see `run.rs`).
    pub gravity: Option<Gravity>,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// (lower, upper) side per axis.
    pub sides: Vec<(Boundary, Boundary)>,
    pub materials: Vec<SceneMaterial>,
    pub bodies: Vec<Body>,
    pub gauges: Vec<GaugePoint>,
    pub air_blast: Option<AirBlast>,
}

/// Where a scene's numbers may lie.
pub const END_TIME_RANGE: (f64, f64) = (1e-9, 10.0);
pub const SPACING_RANGE: (f64, f64) = (1e-5, 1e3);
pub const ETA_RANGE: (f64, f64) = (0.8, 3.0);
const COORDINATE_LIMIT: f64 = 1e5;
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The 1-based line of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

struct Context<'a> {
    text: &'a str,
}

impl Context<'_> {
    fn error(&self, span: Range<usize>, key: &str, message: impl Into<String>) -> VerifyError {
        self.error_at_line(line_of(self.text, span.start), key, message)
    }

    fn error_at_line(&self, line: usize, key: &str, message: impl Into<String>) -> VerifyError {
        VerifyError::Scene {
            line,
            key: key.to_string(),
            message: message.into(),
        }
    }

    /// `value` within `range` (inclusive), else an error naming `key`.
    fn within(
        &self,
        span: Range<usize>,
        key: &str,
        value: f64,
        (lo, hi): (f64, f64),
        unit: &str,
    ) -> Result<f64, VerifyError> {
        if (lo..=hi).contains(&value) {
            Ok(value)
        } else {
            Err(self.error(
                span,
                key,
                format!("{value} is outside the allowed {lo} ≤ {key} ≤ {hi} {unit}"),
            ))
        }
    }

    /// A point or extent with one finite coordinate per axis.
    fn point(
        &self,
        span: Range<usize>,
        key: &str,
        values: &[f64],
        dimension: usize,
    ) -> Result<(), VerifyError> {
        if values.len() != dimension {
            return Err(self.error(
                span,
                key,
                format!(
                    "{} coordinates given; this scene has {dimension} axes",
                    values.len()
                ),
            ));
        }
        if let Some(v) = values
            .iter()
            .find(|v| !v.is_finite() || v.abs() > COORDINATE_LIMIT)
        {
            return Err(self.error(
                span,
                key,
                format!("coordinate {v} is outside ±{COORDINATE_LIMIT:e} m"),
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// Reads and checks a scene file's text.
    pub fn parse(text: &str) -> Result<Self, VerifyError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(0, |span| line_of(text, span.start));
            VerifyError::Scene {
                line,
                key: "file".into(),
                message: e.message().to_string(),
            }
        })?;
        let cx = Context { text };
        let geometry = *file.scene.geometry.get_ref();
        let dimension = geometry.dimension();
        let end_time = cx.within(
            file.scene.end_time.span(),
            "end_time",
            *file.scene.end_time.get_ref(),
            END_TIME_RANGE,
            "s",
        )?;
        let output_interval = file
            .scene
            .output_interval
            .as_ref()
            .map(|o| {
                cx.within(
                    o.span(),
                    "output_interval",
                    *o.get_ref(),
                    (end_time / 1e4, end_time),
                    "s (at most 10⁴ snapshots)",
                )
            })
            .transpose()?;
        let (cfl, eta, alpha_min) = numerics(&cx, file.numerics.as_ref())?;

        let gravity = file
            .gravity
            .as_ref()
            .map(|g| {
                let span = g.span();
                let g = g.get_ref();
                Ok::<_, VerifyError>(Gravity {
                    acceleration: cx.within(
                        span.clone(),
                        "gravity.acceleration",
                        g.acceleration,
                        (0.0, 100.0),
                        "m/s²",
                    )?,
                    surface: cx.within(
                        span,
                        "gravity.surface",
                        g.surface,
                        (-COORDINATE_LIMIT, COORDINATE_LIMIT),
                        "m",
                    )?,
                })
            })
            .transpose()?;
        let domain = &file.domain;
        cx.point(
            domain.min.span(),
            "domain.min",
            domain.min.get_ref(),
            dimension,
        )?;
        cx.point(
            domain.max.span(),
            "domain.max",
            domain.max.get_ref(),
            dimension,
        )?;
        let (lo, hi) = (domain.min.get_ref().clone(), domain.max.get_ref().clone());
        if let Some(a) = (0..dimension).find(|&a| lo[a] >= hi[a]) {
            return Err(cx.error(
                domain.max.span(),
                "domain.max",
                format!("axis {a}: max {} must exceed min {}", hi[a], lo[a]),
            ));
        }
        let sides = sides(&cx, &file.domain.sides, geometry, &lo)?;
        let time_steps = file
            .numerics
            .as_ref()
            .and_then(|n| n.get_ref().time_steps)
            .unwrap_or_default();

        let library = Library::standard();
        let mut materials: Vec<SceneMaterial> = Vec::new();
        for m in &file.material {
            let line = line_of(text, m.span().start);
            let entry = m.get_ref();
            if materials.iter().any(|known| known.name == entry.name) {
                return Err(cx.error_at_line(
                    line,
                    "material.name",
                    format!("'{}' is defined twice", entry.name),
                ));
            }
            materials.push(scene_material(&cx, &library, entry, line)?);
        }

        let mut bodies = Vec::new();
        for b in &file.body {
            let line = line_of(text, b.span().start);
            let body = b.get_ref();
            if bodies.iter().any(|known: &Body| known.name == body.name) {
                return Err(cx.error_at_line(
                    line,
                    "body.name",
                    format!("'{}' is used twice", body.name),
                ));
            }
            let material = material_index(&cx, &library, &mut materials, &body.material)?;
            let spacing = cx.within(
                body.spacing.span(),
                "body.spacing",
                *body.spacing.get_ref(),
                SPACING_RANGE,
                "m",
            )?;
            let shape = checked_shape(
                &cx,
                body.shape.span(),
                body.shape.get_ref(),
                geometry,
                &materials[material],
            )?;
            let detonation_points = detonation_points(&cx, body, &materials[material], dimension)?;
            let velocity = match &body.velocity {
                Some(v) => {
                    cx.point(v.span(), "body.velocity", v.get_ref(), dimension)?;
                    v.get_ref().clone()
                }
                None => vec![0.0; dimension],
            };
            bodies.push(Body {
                name: body.name.clone(),
                material,
                spacing,
                shape,
                subtract: Vec::new(),
                detonation_points,
                velocity,
                line,
            });
        }
        // the holes, once every body's shape is known
        for (k, b) in file.body.iter().enumerate() {
            let Some(subtract) = &b.get_ref().subtract else {
                continue;
            };
            let span = subtract.span();
            let mut holes = Vec::new();
            for hole in subtract.get_ref() {
                holes.push(match hole {
                    HoleFile::Body(name) => {
                        let other = bodies.iter().position(|o: &Body| &o.name == name);
                        match other {
                            Some(o) if o != k => bodies[o].shape.clone(),
                            _ => {
                                return Err(cx.error(
                                    span,
                                    "body.subtract",
                                    format!("'{name}' is not another body of the scene"),
                                ))
                            }
                        }
                    }
                    HoleFile::Shape(shape) => {
                        if matches!(
                            shape,
                            Shape::Sphere { mass: Some(_), .. }
                                | Shape::Hemisphere { mass: Some(_), .. }
                        ) {
                            return Err(cx.error(
                                span,
                                "body.subtract",
                                "a hole has no material to weigh: give its radius, or subtract \
                                 the body by name",
                            ));
                        }
                        checked_shape(
                            &cx,
                            span.clone(),
                            shape,
                            geometry,
                            &materials[bodies[k].material],
                        )?
                    }
                });
            }
            bodies[k].subtract = holes;
        }
        if bodies.is_empty() {
            return Err(cx.error_at_line(1, "body", "a scene needs at least one [[body]]"));
        }
        for body in &bodies {
            inside_domain(&cx, body, geometry, (&lo, &hi), &sides)?;
        }

        let mut gauges = Vec::new();
        for g in &file.gauge {
            let gauge = g.get_ref();
            cx.point(
                gauge.position.span(),
                "gauge.position",
                gauge.position.get_ref(),
                dimension,
            )?;
            if gauges
                .iter()
                .any(|known: &GaugePoint| known.name == gauge.name)
            {
                return Err(cx.error(
                    g.span(),
                    "gauge.name",
                    format!("'{}' is used twice", gauge.name),
                ));
            }
            if gauge.name.is_empty()
                || !gauge
                    .name
                    .chars()
                    .all(|c| c.is_alphanumeric() || "-_".contains(c))
            {
                return Err(cx.error(
                    g.span(),
                    "gauge.name",
                    format!(
                        "'{}': letters, digits, '-' and '_' only (it names a file)",
                        gauge.name
                    ),
                ));
            }
            gauges.push(GaugePoint {
                name: gauge.name.clone(),
                position: gauge.position.get_ref().clone(),
                line: line_of(text, g.span().start),
            });
        }

        let air_blast = file
            .air_blast
            .as_ref()
            .map(|a| {
                let span = a.span();
                if geometry != Geometry::Axisymmetric || gravity.is_none() {
                    return Err(cx.error(
                        span,
                        "air_blast",
                        "an air blast loads the ground of an axisymmetric scene with [gravity] \
                         (whose surface it lies on, at the axis)",
                    ));
                }
                let a = a.get_ref();
                let charge_kg = cx.within(
                    span.clone(),
                    "air_blast.charge",
                    a.charge,
                    AIR_BLAST_CHARGE_RANGE,
                    "kg TNT",
                )?;
                let shells = cx.within(
                    span,
                    "air_blast.shells",
                    a.shells.unwrap_or(AIR_BLAST_SHELLS) as f64,
                    AIR_BLAST_SHELLS_RANGE,
                    "shells across the charge's radius",
                )? as usize;
                Ok(AirBlast { charge_kg, shells })
            })
            .transpose()?;

        Ok(Scene {
            name: file.scene.name,
            geometry,
            end_time,
            output_interval,
            cfl,
            eta,
            alpha_min,
            time_steps,
            gravity,
            lo,
            hi,
            sides,
            materials,
            bodies,
            gauges,
            air_blast,
        })
    }

    /// An upper estimate of the number of particles: each body's shape volume (clipped to the
    /// domain's box) over its spacing^D, before a single particle is made.
    pub fn particle_estimate(&self) -> f64 {
        let d = self.geometry.dimension();
        self.bodies
            .iter()
            .map(|b| {
                let (lo, hi) = self.bounds(&b.shape);
                (0..d)
                    .map(|a| ((hi[a] - lo[a]) / b.spacing).max(0.0) + 1.0)
                    .product::<f64>()
            })
            .sum()
    }

    /// Refuses a scene whose particles would not fit in the memory available, with the
    /// estimate, before any particle is made.
    pub fn check_memory(&self) -> Result<(), VerifyError> {
        let particles = self.particle_estimate();
        let need = particles * crate::memory::bytes_per_particle(self.geometry.dimension());
        match crate::memory::available_bytes() {
            Some(available) if need > available => Err(VerifyError::Scene {
                line: self.bodies[0].line,
                key: "body.spacing".into(),
                message: format!(
                    "the bodies need up to {particles:.3e} particles, about {:.1} GiB; {:.1} GiB \
                     are available: coarsen the spacings",
                    need / GIB,
                    available / GIB
                ),
            }),
            _ => Ok(()),
        }
    }

    /// The box that holds `shape`, clipped to the domain.
    pub fn bounds(&self, shape: &Shape) -> (Vec<f64>, Vec<f64>) {
        let d = self.geometry.dimension();
        let (mut lo, mut hi) = (self.lo.clone(), self.hi.clone());
        let mut clip = |a: usize, l: f64, h: f64| {
            lo[a] = lo[a].max(l);
            hi[a] = hi[a].min(h);
        };
        match shape {
            Shape::Box { min, max } => (0..d).for_each(|a| clip(a, min[a], max[a])),
            Shape::Layer { bottom, top } => clip(d - 1, *bottom, *top),
            Shape::Sphere { centre, radius, .. } | Shape::Hemisphere { centre, radius, .. } => {
                let r = radius.expect("checked shapes carry their radius");
                (0..d).for_each(|a| clip(a, centre[a] - r, centre[a] + r));
            }
            Shape::Annulus {
                centre,
                outer_radius,
                ..
            } => {
                // the tube runs along y in 3D: x and the vertical are bounded
                for a in [0, d - 1] {
                    clip(a, centre[a] - outer_radius, centre[a] + outer_radius);
                }
            }
        }
        (lo, hi)
    }
}

/// The point `x` lies inside `shape` (half-open, so that bodies meeting along a face share no
/// particle).
pub fn contains(shape: &Shape, x: &[f64]) -> bool {
    let d = x.len();
    let distance = |centre: &[f64], axes: &[usize]| {
        axes.iter()
            .map(|&a| (x[a] - centre[a]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let all = &[0, 1, 2][..d];
    match shape {
        Shape::Box { min, max } => (0..d).all(|a| min[a] <= x[a] && x[a] < max[a]),
        Shape::Layer { bottom, top } => *bottom <= x[d - 1] && x[d - 1] < *top,
        Shape::Sphere { centre, radius, .. } => distance(centre, all) < radius.unwrap_or(0.0),
        Shape::Hemisphere { centre, radius, .. } => {
            x[d - 1] >= centre[d - 1] && distance(centre, all) < radius.unwrap_or(0.0)
        }
        Shape::Annulus {
            centre,
            inner_radius,
            outer_radius,
        } => {
            let r = distance(centre, &[0, d - 1]);
            *inner_radius <= r && r < *outer_radius
        }
    }
}

/// Refuses a body that reaches beyond the domain, except across a wall, which is a symmetry
/// plane (the axis of an axisymmetric scene is one): the body is cut there and its mirror image
/// stands for the rest. A layer spans the domain across; an annulus in 3D runs through it
/// along y. In an axisymmetric scene a sphere must lie on the axis (elsewhere it would be a
/// torus).
fn inside_domain(
    cx: &Context,
    body: &Body,
    geometry: Geometry,
    (lo, hi): (&[f64], &[f64]),
    sides: &[(Boundary, Boundary)],
) -> Result<(), VerifyError> {
    let d = lo.len();
    let outside = |axis: usize, from: f64, to: f64| {
        let (lower, upper) = sides[axis];
        (from < lo[axis] && lower != Boundary::Wall) || (to > hi[axis] && upper != Boundary::Wall)
    };
    let refuse = |message: String| Err(cx.error_at_line(body.line, "body.shape", message));
    let round = |centre: &[f64], radius: f64, axes: &[usize]| {
        axes.iter()
            .find(|&&a| outside(a, centre[a] - radius, centre[a] + radius))
            .copied()
    };
    let all: Vec<usize> = (0..d).collect();
    let axis = match &body.shape {
        Shape::Box { min, max } => (0..d).find(|&a| outside(a, min[a], max[a])),
        Shape::Layer { bottom, top } => outside(d - 1, *bottom, *top).then_some(d - 1),
        Shape::Sphere { centre, radius, .. } | Shape::Hemisphere { centre, radius, .. } => {
            if geometry == Geometry::Axisymmetric && centre[0] != 0.0 {
                return refuse(format!(
                    "body '{}': in an axisymmetric scene a sphere's centre lies on the axis \
                     (r = 0), not at r = {}",
                    body.name, centre[0]
                ));
            }
            round(centre, radius.unwrap_or(0.0), &all)
        }
        Shape::Annulus {
            centre,
            outer_radius,
            ..
        } => round(centre, *outer_radius, &[0, d - 1]),
    };
    match axis {
        Some(a) => refuse(format!(
            "body '{}' reaches beyond the domain [{}, {}] on axis {a}",
            body.name, lo[a], hi[a]
        )),
        None => Ok(()),
    }
}

fn numerics(
    cx: &Context,
    numerics: Option<&Spanned<NumericsFile>>,
) -> Result<(f64, f64, f64), VerifyError> {
    let default_cfl = 0.3;
    // h = 1.3 Δ: the smoothing the multi-material problems (ground shock, Taylor bars) run at
    let default_eta = 1.3;
    let default_alpha_min = 0.1;
    let Some(n) = numerics else {
        return Ok((default_cfl, default_eta, default_alpha_min));
    };
    let span = n.span();
    let n = n.get_ref();
    let (lo, hi) = blastsph_solver::step::CFL_RANGE;
    Ok((
        cx.within(
            span.clone(),
            "numerics.cfl",
            n.cfl.unwrap_or(default_cfl),
            (lo, hi),
            "",
        )?,
        cx.within(
            span.clone(),
            "numerics.eta",
            n.eta.unwrap_or(default_eta),
            ETA_RANGE,
            "",
        )?,
        cx.within(
            span,
            "numerics.alpha_min",
            n.alpha_min.unwrap_or(default_alpha_min),
            (0.0, 1.0),
            "",
        )?,
    ))
}

fn sides(
    cx: &Context,
    sides: &Spanned<Sides>,
    geometry: Geometry,
    lo: &[f64],
) -> Result<Vec<(Boundary, Boundary)>, VerifyError> {
    let s = sides.get_ref();
    let mut list = vec![
        (s.x_min.into(), s.x_max.into()),
        (s.y_min.into(), s.y_max.into()),
    ];
    match (geometry.dimension(), s.z_min, s.z_max) {
        (3, Some(lower), Some(upper)) => list.push((lower.into(), upper.into())),
        (3, _, _) => {
            return Err(cx.error(
                sides.span(),
                "domain.sides",
                "a 3d scene needs z_min and z_max",
            ))
        }
        (_, None, None) => {}
        _ => {
            return Err(cx.error(
                sides.span(),
                "domain.sides",
                "z_min and z_max only in a 3d scene",
            ))
        }
    }
    if geometry == Geometry::Axisymmetric && (list[0].0 != Boundary::Wall || lo[0] != 0.0) {
        return Err(cx.error(
            sides.span(),
            "domain.sides.x_min",
            "an axisymmetric scene has its axis at r = 0: domain.min[0] = 0 and x_min = \"wall\"",
        ));
    }
    Ok(list)
}

fn scene_material(
    cx: &Context,
    library: &Library,
    entry: &MaterialFile,
    line: usize,
) -> Result<SceneMaterial, VerifyError> {
    let base = library_material(cx, library, &entry.library)?;
    let named = |e: VerifyError| cx.error_at_line(line, "material", e.to_string());
    let rho0 = base.ambient.0;
    let eos = base.material().map_err(named)?.eos;
    // G = 3K(1 − 2ν)/(2(1 + ν)) with K = ρ0 c0², the unloaded bulk modulus
    let shear = |poisson: f64| {
        let c0 = eos.sound_speed(rho0, base.ambient.1);
        let bulk = rho0 * c0 * c0;
        3.0 * bulk * (1.0 - 2.0 * poisson) / (2.0 * (1.0 + poisson))
    };
    let poisson_ok = |poisson: f64| {
        if (0.0..0.5).contains(&poisson) {
            Ok(poisson)
        } else {
            Err(cx.error_at_line(
                line,
                "material.poisson",
                format!("{poisson} is outside the allowed 0 ≤ poisson < 0.5"),
            ))
        }
    };
    let strength = match (&entry.drucker_prager, &entry.von_mises) {
        (Some(_), Some(_)) => {
            return Err(cx.error_at_line(
                line,
                "material",
                "one strength model: drucker_prager or von_mises",
            ))
        }
        (Some(dp), None) => Some(
            Strength::drucker_prager(
                shear(poisson_ok(dp.poisson)?),
                dp.cohesion,
                dp.friction_angle,
                0.0,
            )
            .map_err(|e| named(e.into()))?,
        ),
        (None, Some(vm)) => {
            let strength = Strength::new(shear(poisson_ok(vm.poisson)?), vm.yield_stress, 0.0)
                .map_err(|e| named(e.into()))?;
            Some(match vm.tensile_strength {
                Some(f_t) => strength
                    .with_tensile_strength(f_t)
                    .map_err(|e| named(e.into()))?,
                None => strength,
            })
        }
        (None, None) => None,
    };
    if strength.is_some() && base.detonation_speed.is_some() {
        return Err(cx.error_at_line(line, "material", "an explosive has no strength model"));
    }
    let at_rest_ratio = match (&entry.drucker_prager, &entry.von_mises) {
        (Some(dp), _) => 1.0 - dp.friction_angle.to_radians().sin(),
        (_, Some(vm)) => vm.poisson / (1.0 - vm.poisson),
        (None, None) => base.at_rest_ratio,
    };
    Ok(SceneMaterial {
        name: entry.name.clone(),
        strength,
        at_rest_ratio,
        ..base
    })
}

impl SceneMaterial {
    /// The solver's material (the library's equation of state, checked when the scene was
    /// read, with the scene's strength).
    pub fn material(&self) -> Result<Material, VerifyError> {
        let mut material = Library::standard().material(&self.library)?;
        material.name = self.name.clone();
        Ok(match &self.strength {
            Some(strength) => material.with_strength(strength.clone()),
            None => material,
        })
    }
}

fn library_material(
    cx: &Context,
    library: &Library,
    name: &Spanned<String>,
) -> Result<SceneMaterial, VerifyError> {
    let named = |e: VerifyError| cx.error(name.span(), "material", e.to_string());
    let key = name.get_ref();
    library.material(key).map_err(named)?;
    let ambient = library.ambient_state(key).map_err(named)?;
    let explosive = library.entry(key).map_err(named)?.model == "jwl";
    let at_rest_ratio = match library.value(key, "poisson") {
        Ok(poisson) => poisson / (1.0 - poisson),
        Err(_) => 1.0,
    };
    Ok(SceneMaterial {
        name: key.clone(),
        library: key.clone(),
        strength: None,
        at_rest_ratio,
        ambient,
        detonation_speed: if explosive {
            Some(library.value(key, "d_cj").map_err(named)?)
        } else {
            None
        },
    })
}

/// The index of a body's material: a scene material by name, else a library material (added
/// to the scene's list once).
fn material_index(
    cx: &Context,
    library: &Library,
    materials: &mut Vec<SceneMaterial>,
    name: &Spanned<String>,
) -> Result<usize, VerifyError> {
    if let Some(k) = materials.iter().position(|m| &m.name == name.get_ref()) {
        return Ok(k);
    }
    let material = library_material(cx, library, name).map_err(|_| {
        let scene: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
        cx.error(
            name.span(),
            "body.material",
            format!(
                "unknown material '{}'; the scene's: [{}]; the library's: {}",
                name.get_ref(),
                scene.join(", "),
                library.names().join(", ")
            ),
        )
    })?;
    materials.push(material);
    Ok(materials.len() - 1)
}

/// `shape` with its coordinates checked and its radius worked out from a mass.
fn checked_shape(
    cx: &Context,
    span: Range<usize>,
    shape: &Shape,
    geometry: Geometry,
    material: &SceneMaterial,
) -> Result<Shape, VerifyError> {
    let d = geometry.dimension();
    let positive = |key: &str, v: f64| {
        if v > 0.0 && v <= COORDINATE_LIMIT {
            Ok(v)
        } else {
            Err(cx.error(
                span.clone(),
                key,
                format!("{v}: allowed 0 < {key} ≤ {COORDINATE_LIMIT:e} m"),
            ))
        }
    };
    let radius_of = |centre: &Vec<f64>, radius: &Option<f64>, mass: &Option<f64>, half: bool| {
        cx.point(span.clone(), "shape.centre", centre, d)?;
        match (radius, mass) {
            (Some(r), None) => positive("shape.radius", *r),
            (None, Some(m)) => {
                if geometry == Geometry::PlaneStrain {
                    return Err(cx.error(
                        span.clone(),
                        "shape.mass",
                        "a plane-strain disc is a cylinder per unit length: give its radius",
                    ));
                }
                let m = positive("shape.mass", *m)?;
                // a sphere of m (or a hemisphere: half a sphere of 2m) at the material's density
                let whole = if half { 2.0 * m } else { m };
                Ok((3.0 * whole / (4.0 * std::f64::consts::PI * material.ambient.0)).cbrt())
            }
            _ => Err(cx.error(span.clone(), "shape", "give radius or mass, not both")),
        }
    };
    Ok(match shape {
        Shape::Box { min, max } => {
            cx.point(span.clone(), "shape.min", min, d)?;
            cx.point(span.clone(), "shape.max", max, d)?;
            if let Some(a) = (0..d).find(|&a| min[a] >= max[a]) {
                return Err(cx.error(span, "shape.max", format!("axis {a}: max must exceed min")));
            }
            shape.clone()
        }
        Shape::Layer { bottom, top } => {
            if !(bottom < top && bottom.abs() <= COORDINATE_LIMIT && top.abs() <= COORDINATE_LIMIT)
            {
                return Err(cx.error(
                    span,
                    "shape.top",
                    format!("top {top} must exceed bottom {bottom}"),
                ));
            }
            shape.clone()
        }
        Shape::Sphere {
            centre,
            radius,
            mass,
        } => Shape::Sphere {
            centre: centre.clone(),
            radius: Some(radius_of(centre, radius, mass, false)?),
            mass: None,
        },
        Shape::Hemisphere {
            centre,
            radius,
            mass,
        } => Shape::Hemisphere {
            centre: centre.clone(),
            radius: Some(radius_of(centre, radius, mass, true)?),
            mass: None,
        },
        Shape::Annulus {
            centre,
            inner_radius,
            outer_radius,
        } => {
            cx.point(span.clone(), "shape.centre", centre, d)?;
            if !(*inner_radius >= 0.0 && inner_radius < outer_radius) {
                return Err(cx.error(
                    span,
                    "shape.outer_radius",
                    format!(
                        "0 ≤ inner_radius < outer_radius; given {inner_radius}, {outer_radius}"
                    ),
                ));
            }
            positive("shape.outer_radius", *outer_radius)?;
            shape.clone()
        }
    })
}

fn detonation_points(
    cx: &Context,
    body: &BodyFile,
    material: &SceneMaterial,
    dimension: usize,
) -> Result<Vec<Vec<f64>>, VerifyError> {
    match (&body.detonation_points, material.detonation_speed) {
        (Some(points), Some(_)) => {
            if points.get_ref().is_empty() {
                return Err(cx.error(
                    points.span(),
                    "body.detonation_points",
                    "at least one point",
                ));
            }
            for p in points.get_ref() {
                cx.point(points.span(), "body.detonation_points", p, dimension)?;
            }
            Ok(points.get_ref().clone())
        }
        (None, Some(_)) => Err(cx.error(
            body.material.span(),
            "body.detonation_points",
            format!(
                "body '{}' is an explosive: give its detonation points",
                body.name
            ),
        )),
        (Some(points), None) => Err(cx.error(
            points.span(),
            "body.detonation_points",
            format!(
                "only for an explosive; '{}' is not one",
                body.material.get_ref()
            ),
        )),
        (None, None) => Ok(Vec::new()),
    }
}

#[cfg(test)]
mod tests;
