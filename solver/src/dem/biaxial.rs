//! The biaxial test on a prepared disc sample: rigid platens (the bottom and top walls) close at
//! a constant speed while the side walls are servo-controlled to hold the confining stress σ3
//! (rigid servo walls stand in here for the flexible membrane of the source paper). Records
//! axial strain, volumetric strain, σ1 and σ3 along the way.

use super::discs::Discs;
use crate::error::SolverError;

/// The loading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Loading {
    /// σ3 held on the side walls (Pa, unit thickness).
    pub confining_stress: f64,
    /// Each platen's speed towards the other (m/s).
    pub platen_speed: f64,
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
    /// Lateral stress on the side walls (Pa).
    pub sigma3: f64,
}

/// The sample's stresses from the wall forces (walls in the order left, right, bottom, top):
/// σ3 on the side walls over the height, σ1 on the platens over the width.
fn wall_stresses(discs: &Discs) -> (f64, f64, f64, f64) {
    let w = &discs.walls;
    let width = w[1].point[0] - w[0].point[0];
    let height = w[3].point[1] - w[2].point[1];
    let f = &discs.wall_force;
    let sigma3 = 0.5 * (f[0][0].abs() + f[1][0].abs()) / height;
    let sigma1 = 0.5 * (f[2][1].abs() + f[3][1].abs()) / width;
    (sigma1, sigma3, width, height)
}

/// Runs the test from the current state (the sample already confined at about σ3). Each side
/// wall is servo-controlled (the PFC rule): it moves inward at v = G (σ3_target − σ3) with
/// G = α h/(k_n N_c Δt), N_c the discs touching it, so that one step's move changes its stress
/// by α = 0.5 of the error; the speed is capped at twice the platen speed. Uncapped, the wall
/// chattered, and the dashpot (repulsive only) pushed the mean σ3 to twice the target
/// (measured 183 Pa for 100 Pa); capped, 102 Pa.
pub fn run_biaxial(discs: &mut Discs, loading: Loading) -> Result<Vec<BiaxialState>, SolverError> {
    if discs.walls.len() != 4 {
        return Err(SolverError::invalid(
            "walls",
            discs.walls.len(),
            "4 (left, right, bottom, top)",
        ));
    }
    if !(loading.confining_stress > 0.0 && loading.platen_speed > 0.0 && loading.axial_strain > 0.0)
    {
        return Err(SolverError::invalid(
            "biaxial loading",
            format!("{loading:?}"),
            "positive confining stress, platen speed and axial strain",
        ));
    }
    let dt = discs.critical_time_step(0.2);
    let stiffness = discs.normal_stiffness();
    discs.compute_forces(0.0);
    let (_, _, width0, height0) = wall_stresses(discs);
    let area0 = width0 * height0;
    discs.walls[2].velocity[1] = loading.platen_speed;
    discs.walls[3].velocity[1] = -loading.platen_speed;
    let mut records = Vec::new();
    let mut step = 0usize;
    loop {
        let (sigma1, sigma3, width, height) = wall_stresses(discs);
        let axial = 1.0 - height / height0;
        if step.is_multiple_of(loading.record_every) {
            records.push(BiaxialState {
                axial_strain: axial,
                volumetric_strain: 1.0 - width * height / area0,
                sigma1,
                sigma3,
            });
        }
        if axial >= loading.axial_strain {
            return Ok(records);
        }
        for (w, inward) in [(0usize, 1.0), (1, -1.0)] {
            let wall = discs.walls[w];
            let touching = (0..discs.len())
                .filter(|&k| (discs.position[k] - wall.point).dot(&wall.normal) < discs.radius[k])
                .count()
                .max(1);
            let gain = 0.5 * height / (stiffness * touching as f64 * dt);
            let sigma = discs.wall_force[w][0].abs() / height;
            let speed = (gain * (loading.confining_stress - sigma))
                .clamp(-2.0 * loading.platen_speed, 2.0 * loading.platen_speed);
            discs.walls[w].velocity[0] = inward * speed;
        }
        discs.step(dt)?;
        step += 1;
    }
}
