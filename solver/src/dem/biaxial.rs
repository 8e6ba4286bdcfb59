//! The biaxial test on a moist disc sample, as in the source paper (seed 003): a graded sample
//! is prepared by radius expansion inside four rigid walls, its pore water is put into bridges
//! at the contacts, the side walls are replaced by a membrane (a chain of particles smaller
//! than the smallest grain) through which the confining stress σ3 acts as forces, and rigid
//! platens (the bottom and top walls) close at a constant speed. Records axial strain,
//! volumetric strain, σ1 and σ3 along the way.
//!
//! Stresses are forces over the layer thickness ([`Discs::layer_thickness`], one mean grain
//! diameter); strains are compression positive.

use super::capillary::{
    bridge_force as capillary_force, effective_radius, BridgeLaw, Liquid, RuptureCriterion,
};
use super::discs::{ContactModel, Discs, Wall, Wetting};
use super::sample::{expand_to_stress, graded_diameters, place_without_overlap};
use crate::error::SolverError;
use crate::random::SplitMix64;
use crate::Vector;

/// The membrane: two chains of particles, one per side, joined by tension-only links, with the
/// confining stress applied to each particle as the pressure on its share of the chain. The
/// links keep the particles from parting (no grain slips through) but go slack as the platens
/// close, so the membrane itself carries no axial load (a rubber membrane's is small too).
#[derive(Clone, Debug)]
pub struct Membrane {
    /// Particle indices of each side in counter-clockwise order around the sample: the right
    /// side from bottom to top, the left side from top to bottom. Each chain's ends move with
    /// the platens.
    sides: [Vec<usize>; 2],
    radius: f64,
    /// Rest length of a link (m).
    rest_length: f64,
    /// Link stiffness in tension (N/m).
    stiffness: f64,
}

impl Membrane {
    /// Replaces the side walls of a sample prepared in a box (walls in the order left, right,
    /// bottom, top) by chains of particles of `radius`, touching one another from platen to
    /// platen just outside where the walls stood. The walls left are the platens: bottom (0)
    /// and top (1). Each membrane particle has the mass of the smallest grain, so the stable
    /// step stays the grains', and its links the contact stiffness.
    pub fn wrap(discs: &mut Discs, radius: f64) -> Result<Self, SolverError> {
        let r_min = discs.radius[..discs.grains()]
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        if !(radius > 0.0 && radius < r_min) {
            return Err(SolverError::invalid(
                "membrane particle radius",
                radius,
                &format!("> 0 and below the smallest grain's radius {r_min:e} m"),
            ));
        }
        if discs.walls.len() != 4 {
            return Err(SolverError::invalid(
                "walls",
                discs.walls.len(),
                "4 (left, right, bottom, top) to wrap a prepared sample",
            ));
        }
        let (left, right) = (discs.walls[0].point[0], discs.walls[1].point[0]);
        let (bottom, top) = (discs.walls[2].point[1], discs.walls[3].point[1]);
        let span = top - bottom - 2.0 * radius;
        let links = (span / (2.0 * radius)).ceil() as usize;
        let rest_length = span / links as f64;
        let m_min = (0..discs.grains())
            .map(|k| discs.mass[k])
            .fold(f64::INFINITY, f64::min);
        let mut chain = |x: f64, upward: bool| -> Vec<usize> {
            (0..=links)
                .map(|k| {
                    let y = if upward {
                        bottom + radius + k as f64 * rest_length
                    } else {
                        top - radius - k as f64 * rest_length
                    };
                    discs.add_boundary_particle(Vector::<2>::new(x, y), radius, m_min)
                })
                .collect()
        };
        let sides = [chain(right + radius, true), chain(left - radius, false)];
        discs.walls.drain(0..2);
        discs.wall_force.drain(0..2);
        Ok(Self {
            sides,
            radius,
            rest_length,
            stiffness: 0.01 * discs.normal_stiffness(),
        })
    }

    /// The chain ends: (particle, platen) pairs, platen 0 bottom and 1 top.
    fn ends(&self) -> [(usize, usize); 4] {
        let [right, left] = &self.sides;
        [
            (right[0], 0),
            (right[right.len() - 1], 1),
            (left[0], 1),
            (left[left.len() - 1], 0),
        ]
    }

    /// Adds the link tensions and the confining pressure (force per unit length `line_load` =
    /// σ3 × layer thickness) to the membrane particles, and holds each chain end at its
    /// platen's vertical speed (its vertical force is dropped).
    pub fn add_forces(&self, discs: &mut Discs, line_load: f64) {
        for side in &self.sides {
            for link in side.windows(2) {
                let (a, b) = (link[0], link[1]);
                let d = discs.position[b] - discs.position[a];
                let stretch = d.norm() - self.rest_length;
                if stretch > 0.0 {
                    let pull = d.normalize() * (self.stiffness * stretch);
                    discs.force[a] += pull;
                    discs.force[b] -= pull;
                }
            }
            // the pressure on each particle's share of the chain, half of each adjacent link:
            // rotating the chord counter-clockwise points it into the sample
            for (k, &p) in side.iter().enumerate() {
                let previous = side[k.saturating_sub(1)];
                let next = side[(k + 1).min(side.len() - 1)];
                let chord = discs.position[next] - discs.position[previous];
                discs.force[p] += Vector::<2>::new(-chord[1], chord[0]) * (0.5 * line_load);
            }
        }
        for (p, platen) in self.ends() {
            discs.force[p][1] = 0.0;
            discs.velocity[p][1] = discs.walls[platen].velocity[1];
        }
    }

    /// The polygon through the chains' centres, counter-clockwise (the platens close it).
    pub fn outline(&self, discs: &Discs) -> Vec<Vector<2>> {
        self.corners(discs).collect()
    }

    /// The [`Self::outline`]'s corners in order, without collecting them (σ1 reads the area at
    /// every step).
    fn corners<'a>(&'a self, discs: &'a Discs) -> impl Iterator<Item = Vector<2>> + 'a {
        self.sides.iter().flatten().map(|&k| discs.position[k])
    }

    /// The sample's area: the [`Self::outline`] polygon less the strip of one particle radius
    /// between each chain's centre line and its inner edge.
    pub fn enclosed_area(&self, discs: &Discs) -> f64 {
        let mut ring = self.corners(discs);
        let first = ring.next().expect("a membrane has particles");
        let cross = |a: Vector<2>, b: Vector<2>| a[0] * b[1] - a[1] * b[0];
        let (mut shoelace, mut last) = (0.0, first);
        for next in ring {
            shoelace += cross(last, next);
            last = next;
        }
        shoelace += cross(last, first);
        let chain_length: f64 = self
            .sides
            .iter()
            .flat_map(|side| side.windows(2))
            .map(|link| (discs.position[link[1]] - discs.position[link[0]]).norm())
            .sum();
        0.5 * shoelace - self.radius * chain_length
    }
}

/// The loading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Loading {
    /// σ3 applied through the membrane (Pa).
    pub confining_stress: f64,
    /// Each platen's speed towards the other (m/s).
    pub platen_speed: f64,
    /// The servo platens' speed during isotropic consolidation at an error of half of σ3
    /// (m/s): consolidation only seeks equilibrium, so it need not be as slow as the loading.
    pub consolidation_speed: f64,
    /// Cundall's local damping α while the platens load (the contact model's holds through
    /// preparation and consolidation).
    pub local_damping: f64,
    /// Stop at this axial strain.
    pub axial_strain: f64,
    /// Steps between records.
    pub record_every: usize,
}

/// One record of the test (strains compression positive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BiaxialState {
    pub axial_strain: f64,
    pub volumetric_strain: f64,
    /// Axial stress on the platens (Pa).
    pub sigma1: f64,
    /// Lateral stress applied through the membrane (Pa).
    pub sigma3: f64,
}

/// Steps over which the platen force is averaged, both to judge consolidation and for each
/// record (a single step's force flickers with the contacts that open and close).
const WINDOW: usize = 500;

/// Windows of consolidation after which the test gives up.
const MAX_CONSOLIDATION_WINDOWS: usize = 400;

/// The axial stress: the mean platen force over the mean width (area over height) and the
/// layer thickness ([`Discs::layer_thickness`], fixed while the sample is tested).
fn axial_stress(discs: &Discs, membrane: &Membrane, layer_thickness: f64) -> f64 {
    let height = discs.walls[1].point[1] - discs.walls[0].point[1];
    let force = 0.5 * (discs.wall_force[0][1].abs() + discs.wall_force[1][1].abs());
    force * height / (membrane.enclosed_area(discs) * layer_thickness)
}

/// Runs the test on a wrapped sample. First isotropic consolidation: the platens are servo
/// controlled (speed ∝ σ3 − σ1: the consolidation speed at an error of half of σ3) until the
/// axial stress, averaged over a window, has stayed within 2 % of σ3 for five windows in a row: a packing
/// expanded between rigid walls keeps rearranging for thousands of steps, and without this it
/// creeps under the membrane while being loaded. Then the platens close at the loading speed
/// until the axial strain is reached; each record holds the window's mean σ1.
pub fn run_biaxial(
    discs: &mut Discs,
    membrane: &Membrane,
    loading: Loading,
) -> Result<Vec<BiaxialState>, SolverError> {
    let checks = [
        ("confining stress", loading.confining_stress),
        ("platen speed", loading.platen_speed),
        ("consolidation speed", loading.consolidation_speed),
        ("axial strain", loading.axial_strain),
    ];
    for (field, value) in checks {
        if !(value > 0.0 && value.is_finite()) {
            return Err(SolverError::invalid(field, value, "finite and > 0"));
        }
    }
    // checked now, not after the consolidation that precedes its use
    if !(0.0..1.0).contains(&loading.local_damping) {
        return Err(SolverError::invalid(
            "loading local damping",
            loading.local_damping,
            "0 ≤ α < 1",
        ));
    }
    if loading.record_every == 0 {
        return Err(SolverError::invalid("record every", 0, "≥ 1 step"));
    }
    let dt = discs.critical_time_step(0.2);
    let sigma3 = loading.confining_stress;
    let layer_thickness = discs.layer_thickness();
    let line_load = sigma3 * layer_thickness;
    let step_once = |discs: &mut Discs| -> Result<f64, SolverError> {
        discs.compute_forces(dt)?;
        membrane.add_forces(discs, line_load);
        let sigma1 = axial_stress(discs, membrane, layer_thickness);
        discs.advance(dt)?;
        Ok(sigma1)
    };
    let (mut steady, mut mean) = (0, 0.0);
    for window in 0.. {
        if window == MAX_CONSOLIDATION_WINDOWS {
            return Err(SolverError::invalid(
                "consolidation",
                format!(
                    "σ1 = {mean:.4e} Pa, not within 2 % of σ3 = {sigma3} Pa after {window} windows"
                ),
                "a sample closer to equilibrium",
            ));
        }
        mean = 0.0;
        for _ in 0..WINDOW {
            let sigma1 = step_once(discs)?;
            mean += sigma1 / WINDOW as f64;
            let error = (sigma3 - sigma1) / sigma3;
            let speed = loading.consolidation_speed * (2.0 * error).clamp(-1.0, 1.0);
            discs.walls[0].velocity[1] = speed;
            discs.walls[1].velocity[1] = -speed;
        }
        steady = if (mean / sigma3 - 1.0).abs() < 0.02 {
            steady + 1
        } else {
            0
        };
        if steady == 5 {
            break;
        }
    }
    discs.set_local_damping(loading.local_damping)?;
    let height = |discs: &Discs| discs.walls[1].point[1] - discs.walls[0].point[1];
    let (height0, area0) = (height(discs), membrane.enclosed_area(discs));
    discs.walls[0].velocity[1] = loading.platen_speed;
    discs.walls[1].velocity[1] = -loading.platen_speed;
    let mut records = Vec::new();
    let (mut sum, mut count) = (0.0, 0);
    loop {
        sum += step_once(discs)?;
        count += 1;
        let axial = 1.0 - height(discs) / height0;
        let done = axial >= loading.axial_strain;
        if count == loading.record_every || done {
            records.push(BiaxialState {
                axial_strain: axial,
                volumetric_strain: 1.0 - membrane.enclosed_area(discs) / area0,
                sigma1: sum / count as f64,
                sigma3,
            });
            (sum, count) = (0.0, 0);
        }
        if done {
            return Ok(records);
        }
    }
}

/// The liquid for a degree of saturation S: S times the pore volume, taken as n/(1 − n) times
/// the grains' sphere volume with n the porosity in the plane (the rule of the notes,
/// `dem-capillary-notes.md` §3: a 2D packing of spheres; a slab of the layer thickness would
/// give each bridge several times the pendular range of volumes).
pub fn liquid_for_saturation(discs: &Discs, sample_area: f64, saturation: f64) -> f64 {
    let porosity = 1.0 - discs.grain_area() / sample_area;
    saturation * porosity / (1.0 - porosity) * discs.grain_volume()
}

/// Everything that defines one biaxial test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BiaxialTest {
    pub grains: usize,
    pub seed: u64,
    /// Smallest and largest diameter drawn (m), graded as [`graded_diameters`].
    pub diameters: (f64, f64),
    /// Grain density (kg/m³).
    pub density: f64,
    pub contact: ContactModel,
    /// Degree of saturation of the pores (0 for dry).
    pub saturation: f64,
    pub surface_tension: f64,
    /// θ (rad).
    pub contact_angle: f64,
    pub law: BridgeLaw,
    pub rupture: RuptureCriterion,
    /// Membrane particle radius over the smallest grain radius (< 1).
    pub membrane_radius_ratio: f64,
    pub loading: Loading,
}

/// What the sample looked like when loading began.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedSample {
    /// Mean wall stress where the expansion stopped (Pa).
    pub wall_stress: f64,
    pub width: f64,
    pub height: f64,
    pub porosity: f64,
    pub void_ratio: f64,
    pub coordination: f64,
    pub bridges: usize,
    /// Mean bridge volume over R³ of its pair (R the harmonic mean radius).
    pub mean_bridge_volume_ratio: f64,
    /// Mean capillary force of the bridges at their prepared gaps (N).
    pub mean_bridge_force: f64,
    pub layer_thickness: f64,
    pub preparation_steps: usize,
}

/// A finished test: the sample, the records, and the steps taken.
#[derive(Clone, Debug, PartialEq)]
pub struct BiaxialRun {
    pub sample: PreparedSample,
    pub records: Vec<BiaxialState>,
    pub particles: usize,
    pub membrane_particles: usize,
    pub time_step: f64,
    /// Steps of preparation, consolidation and loading.
    pub steps: usize,
}

/// The porosity the box is sized for (the expansion then grows the grains to the stress; a
/// graded frictional packing jams near 0.2, so the diameters end within a few per cent of
/// those drawn).
const EXPECTED_POROSITY: f64 = 0.2;

impl BiaxialTest {
    /// The source paper's test (seed 003) with this project's contact constants: diameters
    /// 0.1–0.5 mm, quartz density 2650 kg/m³, water at 15 °C (γ 0.0735 N/m, θ 0), platens at
    /// 1.27 cm/s each to 10 % axial strain. k_n = 1000 N/m keeps the overlaps near 0.1 % of a
    /// diameter at kilopascal stresses (k_n/(σ t) ≈ 1000 at 4 kPa); k_t = k_n/2; μ = 0.5;
    /// ζ = 0.3; the membrane particles are 0.8 of the smallest grain. Local damping is 0.7
    /// (PFC's default for bringing a packing to rest) through preparation and consolidation,
    /// and 0.2 while the platens load: with 0.7 the dry peak at σ3 = 500 Pa fell by 16 % when
    /// the platens were slowed from 6.9 to 3.45 mm/s. Local damping opposes each grain's
    /// motion with a share of its out-of-balance force, which slows the rearrangements that
    /// shear needs, so the strength depended on the rate twice as much as with 0.2 (whose
    /// remaining rate effect the `biaxial` problem measures and bounds). None of these
    /// constants is the source paper's (its text does not give them).
    pub fn source_paper(grains: usize, seed: u64, saturation: f64, confining_stress: f64) -> Self {
        Self {
            grains,
            seed,
            diameters: (1e-4, 5e-4),
            density: 2650.0,
            contact: ContactModel {
                normal_stiffness: 1e3,
                tangential_stiffness: 5e2,
                friction: 0.5,
                damping_ratio: 0.3,
                local_damping: 0.7,
            },
            saturation,
            surface_tension: 0.0735,
            contact_angle: 0.0,
            law: BridgeLaw::WillettFitted,
            rupture: RuptureCriterion::Lian,
            membrane_radius_ratio: 0.8,
            loading: Loading {
                confining_stress,
                platen_speed: 0.0127,
                consolidation_speed: 0.0127,
                local_damping: 0.2,
                axial_strain: 0.1,
                record_every: WINDOW,
            },
        }
    }
}

/// Prepares the dry sample: graded diameters placed at 70 % size in a box twice as high as
/// wide (sized for a porosity of 0.2), then radius expansion to σ3. Returns the grains in their
/// box (walls left, right, bottom, top), their films empty; the saturation is not used (one
/// prepared sample serves every saturation).
pub fn prepare_sample(test: &BiaxialTest) -> Result<(Discs, PreparedSample), SolverError> {
    let mut rng = SplitMix64::new(test.seed);
    let (d_min, d_max) = test.diameters;
    let radii: Vec<f64> = graded_diameters(test.grains, d_min, d_max, &mut rng)?
        .iter()
        .map(|d| 0.5 * d)
        .collect();
    let solid: f64 = radii.iter().map(|r| std::f64::consts::PI * r * r).sum();
    let width = (solid / (1.0 - EXPECTED_POROSITY) / 2.0).sqrt();
    let height = 2.0 * width;
    // placed at 70 % size, loose enough for random placement to find room
    let centres = place_without_overlap(&radii, (width, height), 0.7, 5000, &mut rng)?;
    let wetting = Some(Wetting {
        law: test.law,
        rupture: test.rupture,
        liquid: Liquid {
            volume: 0.0,
            surface_tension: test.surface_tension,
            contact_angle: test.contact_angle,
        },
    });
    let small: Vec<f64> = radii.iter().map(|r| 0.7 * r).collect();
    let mut discs = Discs::new(centres, small, test.density, test.contact, wetting)?;
    for (point, normal) in [
        ((0.0, 0.0), (1.0, 0.0)),
        ((width, 0.0), (-1.0, 0.0)),
        ((0.0, 0.0), (0.0, 1.0)),
        ((0.0, height), (0.0, -1.0)),
    ] {
        discs.add_wall(Wall {
            point: Vector::<2>::new(point.0, point.1),
            normal: Vector::<2>::new(normal.0, normal.1),
            velocity: Vector::zeros(),
        });
    }
    let sigma3 = test.loading.confining_stress;
    let expansion = expand_to_stress(&mut discs, (width, height), sigma3, (0.002, 500, 2000))?;
    let sample = PreparedSample {
        wall_stress: expansion.wall_stress,
        width,
        height,
        porosity: expansion.porosity,
        void_ratio: expansion.porosity / (1.0 - expansion.porosity),
        coordination: expansion.coordination,
        bridges: 0,
        mean_bridge_volume_ratio: 0.0,
        mean_bridge_force: 0.0,
        layer_thickness: discs.layer_thickness(),
        preparation_steps: expansion.steps,
    };
    Ok((discs, sample))
}

/// Puts the pore water of `test.saturation` into bridges at the contacts of a prepared sample
/// ([`liquid_for_saturation`], shared by [`Discs::distribute_liquid`]) and notes their number,
/// mean V/R³ and mean force at the prepared gaps. Nothing to do when dry.
pub fn add_pore_water(
    discs: &mut Discs,
    sample: &mut PreparedSample,
    test: &BiaxialTest,
) -> Result<(), SolverError> {
    if !(0.0..=0.3).contains(&test.saturation) {
        return Err(SolverError::invalid(
            "saturation",
            test.saturation,
            "0 to 0.3 (the pendular regime)",
        ));
    }
    if test.saturation == 0.0 {
        return Ok(());
    }
    discs.compute_forces(0.0)?;
    let water = liquid_for_saturation(discs, sample.width * sample.height, test.saturation);
    discs.distribute_liquid(water)?;
    let liquid = |volume| Liquid {
        volume,
        surface_tension: test.surface_tension,
        contact_angle: test.contact_angle,
    };
    let (mut count, mut volume_ratio, mut force) = (0, 0.0, 0.0);
    for ((i, j), v) in discs.bridge_volumes() {
        let (ri, rj) = (discs.radius[i], discs.radius[j]);
        let radius = effective_radius(ri, rj);
        let gap = (discs.position[j] - discs.position[i]).norm() - ri - rj;
        count += 1;
        volume_ratio += v / radius.powi(3);
        force += capillary_force(test.law, &liquid(v), radius, gap)?;
    }
    sample.bridges = count;
    sample.mean_bridge_volume_ratio = volume_ratio / count.max(1) as f64;
    sample.mean_bridge_force = force / count.max(1) as f64;
    Ok(())
}

/// Wets a prepared sample ([`add_pore_water`]), puts the membrane in place of its side walls
/// and runs the test ([`run_biaxial`]).
pub fn shear_prepared(
    mut discs: Discs,
    mut sample: PreparedSample,
    test: &BiaxialTest,
) -> Result<BiaxialRun, SolverError> {
    add_pore_water(&mut discs, &mut sample, test)?;
    let r_min = discs.radius.iter().cloned().fold(f64::INFINITY, f64::min);
    let membrane = Membrane::wrap(&mut discs, test.membrane_radius_ratio * r_min)?;
    let start = discs.time;
    let records = run_biaxial(&mut discs, &membrane, test.loading)?;
    let time_step = discs.critical_time_step(0.2);
    Ok(BiaxialRun {
        sample,
        records,
        particles: discs.len(),
        membrane_particles: discs.len() - discs.grains(),
        time_step,
        steps: sample.preparation_steps + ((discs.time - start) / time_step).round() as usize,
    })
}

/// The whole test: [`prepare_sample`], then [`shear_prepared`].
pub fn run_biaxial_test(test: &BiaxialTest) -> Result<BiaxialRun, SolverError> {
    let (discs, sample) = prepare_sample(test)?;
    shear_prepared(discs, sample, test)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const WIDTH: f64 = 2e-3;
    const HEIGHT: f64 = 4e-3;
    /// The membrane particles' radius: below the smallest grain's 1e-4 m.
    const R_MEMBRANE: f64 = 0.5e-4;
    /// The box's lower left corner: off the origin, so that a sum and a difference of its
    /// sides' coordinates differ.
    const CORNER: (f64, f64) = (1e-3, 5e-4);

    fn contact() -> ContactModel {
        ContactModel {
            normal_stiffness: 1e3,
            tangential_stiffness: 5e2,
            friction: 0.5,
            damping_ratio: 0.3,
            local_damping: 0.0,
        }
    }

    /// Two grains (radii 0.1 and 0.2 mm) in a WIDTH × HEIGHT box from CORNER whose walls are,
    /// in order, left, right, bottom and top.
    fn boxed() -> Discs {
        let (x0, y0) = CORNER;
        let centres = vec![
            Vector::<2>::new(x0 + 0.3 * WIDTH, y0 + 0.3 * HEIGHT),
            Vector::<2>::new(x0 + 0.7 * WIDTH, y0 + 0.6 * HEIGHT),
        ];
        let mut discs = Discs::new(centres, vec![1e-4, 2e-4], 2650.0, contact(), None).unwrap();
        for (point, normal) in [
            ((0.0, 0.0), (1.0, 0.0)),
            ((WIDTH, 0.0), (-1.0, 0.0)),
            ((0.0, 0.0), (0.0, 1.0)),
            ((0.0, HEIGHT), (0.0, -1.0)),
        ] {
            discs.add_wall(Wall {
                point: Vector::<2>::new(x0 + point.0, y0 + point.1),
                normal: Vector::<2>::new(normal.0, normal.1),
                velocity: Vector::zeros(),
            });
        }
        discs
    }

    /// Each side is a chain of touching (or overlapping) particles from one platen to the
    /// other, just outside where its wall stood, each as heavy as the smallest grain; the side
    /// walls are gone and the platens remain; the sample between the chains' inner edges is
    /// WIDTH wide and spans the chains' centres, HEIGHT − 2r.
    #[test]
    fn the_membrane_lines_the_box_with_touching_chains() {
        let mut discs = boxed();
        let light = discs.mass[0];
        let membrane = Membrane::wrap(&mut discs, R_MEMBRANE).unwrap();
        assert_eq!(discs.walls.len(), 2);
        assert_eq!(discs.wall_force.len(), 2);
        assert_eq!(discs.walls[0].normal, Vector::<2>::new(0.0, 1.0));
        assert_eq!(discs.walls[1].normal, Vector::<2>::new(0.0, -1.0));
        let span = HEIGHT - 2.0 * R_MEMBRANE;
        let links = (span / (2.0 * R_MEMBRANE)).ceil() as usize;
        assert_eq!(discs.len(), 2 + 2 * (links + 1));
        assert_eq!(membrane.stiffness, 0.01 * contact().normal_stiffness);
        for (side, x) in membrane
            .sides
            .iter()
            .zip([CORNER.0 + WIDTH + R_MEMBRANE, CORNER.0 - R_MEMBRANE])
        {
            assert_eq!(side.len(), links + 1);
            let ys: Vec<f64> = side.iter().map(|&k| discs.position[k][1]).collect();
            let (low, high) = (
                ys.iter().cloned().fold(f64::INFINITY, f64::min),
                ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            );
            assert!((low - (CORNER.1 + R_MEMBRANE)).abs() < 1e-15, "{low}");
            assert!(
                (high - (CORNER.1 + HEIGHT - R_MEMBRANE)).abs() < 1e-15,
                "{high}"
            );
            for link in side.windows(2) {
                let d = (discs.position[link[1]] - discs.position[link[0]]).norm();
                // at most touching (to round-off: here the span is a whole number of diameters)
                assert!((d / membrane.rest_length - 1.0).abs() < 1e-12, "{d}");
                assert!(d <= 2.0 * R_MEMBRANE * (1.0 + 1e-12), "{d}");
            }
            for &k in side {
                assert_eq!(discs.position[k][0], x);
                assert_eq!((discs.radius[k], discs.mass[k]), (R_MEMBRANE, light));
            }
        }
        // counter-clockwise: the right side upwards, the left side downwards
        let [right, left] = &membrane.sides;
        assert!(discs.position[right[1]][1] > discs.position[right[0]][1]);
        assert!(discs.position[left[1]][1] < discs.position[left[0]][1]);
        let area = membrane.enclosed_area(&discs);
        assert!((area / (WIDTH * span) - 1.0).abs() < 1e-12, "{area}");
    }

    #[test]
    fn a_membrane_it_cannot_wrap_is_refused_by_name() {
        for radius in [0.0, 1e-4, f64::NAN] {
            let err = Membrane::wrap(&mut boxed(), radius).unwrap_err();
            assert!(
                err.to_string().contains("membrane particle radius"),
                "{err}"
            );
        }
        let mut discs = boxed();
        discs.walls.pop();
        let err = Membrane::wrap(&mut discs, R_MEMBRANE).unwrap_err();
        assert!(err.to_string().contains("walls"), "{err}");
    }

    /// A straight chain of height H under the line load q = σ3 t is pushed inwards by q H in
    /// all (each particle by the pressure on half of each of its links), and nothing along
    /// it; its links at rest length pull nothing; its ends move with their platens.
    #[test]
    fn the_confining_pressure_pushes_each_side_inwards_with_its_line_load_times_its_height() {
        let mut discs = boxed();
        let membrane = Membrane::wrap(&mut discs, R_MEMBRANE).unwrap();
        discs.walls[0].velocity = Vector::<2>::new(0.0, 0.01);
        discs.walls[1].velocity = Vector::<2>::new(0.0, -0.02);
        let line_load = 2000.0 * discs.layer_thickness();
        membrane.add_forces(&mut discs, line_load);
        let span = HEIGHT - 2.0 * R_MEMBRANE;
        for (side, inwards) in membrane.sides.iter().zip([-1.0, 1.0]) {
            let total: Vector<2> = side.iter().map(|&k| discs.force[k]).sum();
            assert!(
                (total[0] / (inwards * line_load * span) - 1.0).abs() < 1e-12,
                "{total}"
            );
            assert!(total[1].abs() < 1e-12 * line_load * span, "{total}");
        }
        for (p, platen) in membrane.ends() {
            assert_eq!(discs.force[p][1], 0.0);
            assert_eq!(discs.velocity[p][1], discs.walls[platen].velocity[1]);
        }
        let [right, left] = &membrane.sides;
        assert_eq!(discs.velocity[right[0]][1], 0.01);
        assert_eq!(discs.velocity[left[0]][1], -0.02);
        assert_eq!(discs.force[0], Vector::<2>::zeros());
    }

    /// A link stretched by δ pulls both its ends together with the link stiffness times δ; a
    /// link shortened by as much stays slack.
    #[test]
    fn a_stretched_link_pulls_with_its_stiffness_and_a_shortened_one_is_slack() {
        let mut discs = boxed();
        let membrane = Membrane::wrap(&mut discs, R_MEMBRANE).unwrap();
        let chain = &membrane.sides[0];
        let (a, b, c) = (chain[1], chain[2], chain[3]);
        let delta = 1e-6;
        discs.position[b][1] += delta;
        membrane.add_forces(&mut discs, 0.0);
        let pull = membrane.stiffness * delta;
        // a's link to b stretched: a pulled up, b down; b's link to c shortened: nothing (c's
        // link beyond, at rest length, pulls by round-off alone)
        assert!(
            (discs.force[a][1] / pull - 1.0).abs() < 1e-9,
            "{}",
            discs.force[a]
        );
        assert!(
            (discs.force[b][1] / -pull - 1.0).abs() < 1e-9,
            "{}",
            discs.force[b]
        );
        assert!(discs.force[c].norm() < 1e-9 * pull, "{}", discs.force[c]);
    }

    /// σ1: the platens' mean force over the mean width (enclosed area over height) and the
    /// layer thickness.
    #[test]
    fn the_axial_stress_is_the_mean_platen_force_over_the_mean_width_and_the_layer() {
        let mut discs = boxed();
        let membrane = Membrane::wrap(&mut discs, R_MEMBRANE).unwrap();
        discs.wall_force[0] = Vector::<2>::new(0.3, 2.0);
        discs.wall_force[1] = Vector::<2>::new(-0.1, -4.0);
        let width = WIDTH * (HEIGHT - 2.0 * R_MEMBRANE) / HEIGHT;
        let thickness = 2.0 * (1e-4 + 2e-4) / 2.0;
        let want = 3.0 / (width * thickness);
        let got = axial_stress(&discs, &membrane, discs.layer_thickness());
        assert!((got / want - 1.0).abs() < 1e-12, "{got} against {want}");
    }

    /// Water for saturation S: S times the pores' volume, n/(1 − n) times the grains' sphere
    /// volume with n the porosity in the plane. Grains of half the sample's area: n = ½.
    #[test]
    fn the_water_for_a_saturation_fills_that_share_of_the_pores() {
        let discs = boxed();
        let area = 2.0 * PI * (1e-8 + 4e-8);
        let spheres = 4.0 / 3.0 * PI * (1e-12 + 8e-12);
        let got = liquid_for_saturation(&discs, area, 0.1);
        assert!((got / (0.1 * spheres) - 1.0).abs() < 1e-12, "{got}");
        let denser = liquid_for_saturation(&discs, 1.25 * PI * 5e-8, 0.1);
        assert!(
            (denser / (0.1 * 0.25 * spheres) - 1.0).abs() < 1e-12,
            "{denser}"
        );
    }

    /// The pendular range is 0–30 % saturation, both ends included; a dry sample gets no
    /// bridge.
    #[test]
    fn pore_water_outside_the_pendular_range_is_refused_by_name() {
        let prepared = PreparedSample {
            wall_stress: 1000.0,
            width: WIDTH,
            height: HEIGHT,
            porosity: 0.2,
            void_ratio: 0.25,
            coordination: 3.0,
            bridges: 0,
            mean_bridge_volume_ratio: 0.0,
            mean_bridge_force: 0.0,
            layer_thickness: 3e-4,
            preparation_steps: 0,
        };
        for saturation in [-0.01, 0.31, f64::NAN] {
            let test = BiaxialTest::source_paper(2, 1, saturation, 1000.0);
            let mut sample = prepared;
            let err = add_pore_water(&mut boxed(), &mut sample, &test).unwrap_err();
            assert!(err.to_string().contains("saturation"), "{err}");
        }
        let mut sample = prepared;
        let mut discs = boxed();
        add_pore_water(
            &mut discs,
            &mut sample,
            &BiaxialTest::source_paper(2, 1, 0.0, 1000.0),
        )
        .unwrap();
        assert_eq!(sample, prepared);
        assert_eq!(discs.bridge_volumes().count(), 0);
    }
}
