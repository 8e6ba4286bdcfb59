//! The surface burst's free field as a scene: a TNT hemisphere lying on the ground (its flat
//! face on the surface, lit at the centre of that face), the soil below in its geostatic
//! state, axisymmetric about the vertical through the charge. `ground-shock-surface` checks
//! this scene against the ground-shock relations, and the tunnel study drives its sections
//! with it, so that what the gate checks is the free field the study rests on.
//!
//! The soil's spacing grows from the charge's outwards in three boxes (each three times the
//! last, the spacing doubling from box to box) up to a far spacing given by the caller; the
//! bottom and the far side transmit (Lysmer–Kuhlemeyer), the axis is a wall. The air above
//! the ground is not held as particles: the products expand into vacuum, and once higher than
//! twice the charge's radius they leave the run through the top, an outflow side, what they
//! carry booked as having left (followed instead, they fly on at 3.4 km/s and stretch the
//! neighbour grid over hundreds of metres; with the top twice as high a soil gauge 10 m down
//! reads the same peaks to five digits). The air blast loads the ground instead (the scene's
//! `[air_blast]`, see [`crate::scene::AirBlast`]): its overpressure on a rigid ground, from the
//! one-dimensional hemispherical burst, presses on the top layer of the soil wherever the air,
//! not the products, covers it. Held as particles beside the charge's, the air failed: each
//! product particle carries about 1360 times an air particle's mass and crosses the air as a
//! projectile rather than pushing it as a gas.
//!
//! Each particle takes its own time step (power-of-two blocks): the products' and the near
//! soil's steps are far shorter than those of the coarse far soil, which waits at rest for
//! most of the run.

use crate::scene::{Scene, StepChoice};
use crate::VerifyError;
use serde::Serialize;

/// The soil: a library material with Drucker–Prager strength.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Soil {
    pub library: String,
    pub cohesion_pa: f64,
    pub friction_angle_degrees: f64,
}

impl Default for Soil {
    fn default() -> Self {
        // the gated sand of `ground-shock-spherical`
        Self {
            library: "dry-sand".into(),
            cohesion_pa: 0.0,
            friction_angle_degrees: 30.0,
        }
    }
}

const GRAVITY: f64 = 9.81;
const TNT_DENSITY: f64 = 1630.0;
/// Smoothing length over spacing in every scene built here (the scenes' default).
pub const ETA: f64 = 1.3;

/// The radius of a TNT hemisphere of `charge_kg`.
pub fn hemisphere_radius(charge_kg: f64) -> f64 {
    (3.0 * charge_kg / (2.0 * std::f64::consts::PI * TNT_DENSITY)).cbrt()
}

/// What every scene of the ground shares: gravity with the ground's surface at z = 0, the
/// smoothing, the time steps, and the soil as material "soil".
pub fn ground(soil: &Soil, time_steps: StepChoice) -> String {
    let time_steps = match time_steps {
        StepChoice::Global => "global",
        StepChoice::Individual => "individual",
    };
    format!(
        r#"[gravity]
acceleration = {GRAVITY}
surface = 0.0

[numerics]
eta = {ETA}
time_steps = "{time_steps}"

[[material]]
name = "soil"
library = "{library}"
drucker_prager = {{ cohesion = {c}, friction_angle = {phi} }}
"#,
        library = soil.library,
        c = soil.cohesion_pa,
        phi = soil.friction_angle_degrees,
    )
}

/// The surface burst's scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceBurst<'a> {
    pub charge_kg: f64,
    pub soil: &'a Soil,
    /// Particles across the charge's radius.
    pub across_charge: usize,
    /// How far the soil reaches: out from the axis and down from the surface (m).
    pub radius_m: f64,
    pub depth_m: f64,
    /// The largest soil spacing (m).
    pub far_spacing_m: f64,
    /// Gauges: name and (r, z) (m).
    pub gauges: &'a [(String, [f64; 2])],
    pub end_time_s: f64,
    /// The charge's air blast loads the ground (the scene's `[air_blast]`).
    pub air_blast: bool,
}

impl SurfaceBurst<'_> {
    /// The scene's text (see the module's comment).
    pub fn text(&self) -> String {
        let gauges: String = self
            .gauges
            .iter()
            .map(|(name, [r, z])| {
                format!("\n[[gauge]]\nname = \"{name}\"\nposition = [{r}, {z}]\n")
            })
            .collect();
        let charge_kg = self.charge_kg;
        let rc = hemisphere_radius(charge_kg);
        let s0 = rc / self.across_charge as f64;
        // spacing doubles from box to box, up to the far spacing; each box is three times the
        // last
        let (a1, a2) = (10.0 * s0, 30.0 * s0);
        let spacing = |k: f64| (k * s0).min(self.far_spacing_m).max(s0);
        format!(
            r#"[scene]
name = "free field, {charge_kg} kg TNT on {library}"
geometry = "axisymmetric"
end_time = {end_time}

[domain]
min = [0.0, {zmin}]
max = [{radius_m}, {ztop}]
sides = {{ x_min = "wall", x_max = "transmitting", y_min = "transmitting", y_max = "outflow" }}

{ground}
[[body]]
name = "charge"
material = "tnt"
spacing = {s0}
shape = {{ kind = "hemisphere", centre = [0.0, 0.0], mass = {charge_kg} }}
detonation_points = [[0.0, 0.0]]
{air_blast}
[[body]]
name = "soil-near"
material = "soil"
spacing = {s1}
shape = {{ kind = "box", min = [0.0, {za1}], max = [{a1}, 0.0] }}

[[body]]
name = "soil-mid"
material = "soil"
spacing = {s2}
shape = {{ kind = "box", min = [0.0, {za2}], max = [{a2}, 0.0] }}
subtract = ["soil-near"]

[[body]]
name = "soil-far"
material = "soil"
spacing = {s3}
shape = {{ kind = "layer", bottom = {zmin}, top = 0.0 }}
subtract = ["soil-near", "soil-mid"]

{gauges}"#,
            library = self.soil.library,
            air_blast = if self.air_blast {
                format!("\n[air_blast]\ncharge = {charge_kg}\n")
            } else {
                String::new()
            },
            ground = ground(self.soil, StepChoice::Individual),
            end_time = self.end_time_s,
            radius_m = self.radius_m,
            zmin = -self.depth_m,
            ztop = 2.0 * rc,
            s1 = spacing(2.0),
            s2 = spacing(4.0),
            s3 = spacing(8.0),
            za1 = -a1,
            za2 = -a2,
        )
    }

    pub fn scene(&self) -> Result<Scene, VerifyError> {
        Scene::parse(&self.text())
    }
}

/// The soil's P-wave speed √((K + 4G/3)/ρ0) at rest.
pub fn p_wave_speed(soil: &Soil) -> Result<f64, VerifyError> {
    let scene = SurfaceBurst {
        charge_kg: 1.0,
        soil,
        across_charge: 1,
        radius_m: 10.0,
        depth_m: 10.0,
        far_spacing_m: 1.0,
        gauges: &[],
        end_time_s: 1e-3,
        air_blast: false,
    }
    .scene()?;
    let m = &scene.materials[0];
    let material = m.material()?;
    let rho0 = m.ambient.0;
    let c0 = material.eos.sound_speed(rho0, 0.0);
    let shear = material.strength.map_or(0.0, |st| st.shear_modulus);
    Ok((c0 * c0 + 4.0 * shear / (3.0 * rho0)).sqrt())
}

/// The relations' soil in the simulated sand's own terms: its density at rest and its
/// small-strain (seismic) P-wave speed √((K + 4G/3)/ρ0), with the attenuation exponent of the
/// TM 5-855-1 class it stands for. The relations are laws in a soil's ρ, c and n; the class
/// fixes how the soil attenuates, the thing under test, while its handbook ρ and c describe
/// the class's typical soil, not this one: compared with them, any model sand of another
/// seismic speed would be early or late by construction.
pub fn relations_soil(
    class: &crate::scaled::ground_shock::Soil,
    soil: &Soil,
) -> Result<crate::scaled::ground_shock::Soil, VerifyError> {
    let density = crate::materials::Library::standard().value(&soil.library, "rho0")?;
    Ok(crate::scaled::ground_shock::Soil {
        name: "simulated",
        description: format!(
            "the simulated {} (its own density and small-strain P-wave speed) with the \
             attenuation exponent of {}",
            soil.library, class.name
        ),
        density_kg_m3: density,
        wave_speed_m_s: p_wave_speed(soil)?,
        attenuation: class.attenuation,
    })
}
