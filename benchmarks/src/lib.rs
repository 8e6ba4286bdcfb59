//! Scenes for the benchmarks: jittered lattices and a gas box ready to step.

use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    Density, Domain, Formulation, IdealGas, Material, Simulation, SimulationConfig,
    SmoothingLength, Vector,
};

/// A hash-based number in [−1, 1) for index k (reproducible, no generator state).
pub fn noise(k: usize, salt: u64) -> f64 {
    let mut z =
        (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt.wrapping_mul(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    2.0 * ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 1.0
}

/// About `n` points on a cubic lattice of spacing `dx`, each moved by up to 10 % of dx.
pub fn jittered_lattice<const D: usize>(n: usize, dx: f64) -> Vec<Vector<D>> {
    let side = (n as f64).powf(1.0 / D as f64).round() as usize;
    (0..side.pow(D as u32))
        .map(|k| {
            Vector::<D>::from_fn(|a, _| {
                ((k / side.pow(a as u32)) % side) as f64 * dx + 0.1 * dx * noise(k, a as u64)
            })
        })
        .collect()
}

/// A box of ideal gas in D dimensions (ρ = 1, p = 1, random velocities at Mach ~0.1, about
/// `n` particles) with h = 1.2 Δx, fixed, and free surfaces, ready to step.
pub fn gas_box<const D: usize>(n: usize) -> Simulation<D> {
    let dx = 0.01;
    let gas = IdealGas::new(1.4).unwrap();
    let init: Vec<ParticleInit<D>> = jittered_lattice::<D>(n, dx)
        .into_iter()
        .enumerate()
        .map(|(k, position)| ParticleInit {
            position,
            velocity: Vector::<D>::from_fn(|a, _| 0.1 * noise(k, 7 + a as u64)),
            mass: dx.powi(D as i32),
            smoothing_length: 1.2 * dx,
            density: 1.0,
            internal_energy: gas.internal_energy(1.0, 1.0),
            material: 0,
        })
        .collect();
    let config = SimulationConfig {
        formulation: Formulation::Cartesian(Density::Summation(SmoothingLength::Fixed)),
        ..SimulationConfig::default()
    };
    Simulation::new(
        &init,
        vec![Material::new("air", gas)],
        Domain::open(),
        config,
    )
    .unwrap()
}
