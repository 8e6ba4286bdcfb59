//! Axisymmetric (r, z) SPH: a column in uniform stress stays at rest (the ring fluxes' planar
//! gradient cancels the hoop force, right up to the axis), a homologous radial expansion gets
//! the cylindrical rates, and the scheme conserves energy and axial momentum.

use blastsph_solver::particles::ParticleInit;
use blastsph_solver::{
    ArtificialViscosity, Boundary, Domain, Formulation, Material, MieGruneisen, Simulation,
    SimulationConfig, SmoothingLength, Strength, Vector,
};
use std::f64::consts::PI;

const RHO0: f64 = 8930.0;

/// Copper with a linear bulk response and the benchmark's elastic moduli.
fn copper(yield_stress: f64) -> Material {
    let (g, k) = Strength::elastic_moduli(117e9, 0.35).unwrap();
    let eos = MieGruneisen::linear(RHO0, (k / RHO0).sqrt(), 0.0, 0.0, f64::NEG_INFINITY).unwrap();
    Material::new("copper", eos).with_strength(Strength::new(g, yield_stress, 0.0).unwrap())
}

fn config() -> SimulationConfig {
    SimulationConfig {
        formulation: Formulation::Axisymmetric(SmoothingLength::Fixed),
        viscosity: ArtificialViscosity::default(),
        ..SimulationConfig::default()
    }
}

/// Rings on an n_r × n_z lattice of spacing dx filling r < n_r dx, periodic in z, with a wall
/// at the axis and at the outer radius; density ρ, velocity from `velocity(r, z)`.
fn column(
    n_r: usize,
    n_z: usize,
    density: f64,
    velocity: impl Fn(f64, f64) -> Vector<2>,
) -> (Vec<ParticleInit<2>>, Domain<2>) {
    let dx = 1e-3;
    let mut init = Vec::new();
    for k in 0..n_z {
        for i in 0..n_r {
            let (r, z) = ((i as f64 + 0.5) * dx, (k as f64 + 0.5) * dx);
            init.push(ParticleInit {
                position: Vector::<2>::new(r, z),
                velocity: velocity(r, z),
                mass: density * 2.0 * PI * r * dx * dx,
                smoothing_length: 1.2 * dx,
                density,
                internal_energy: 0.0,
                material: 0,
            });
        }
    }
    let domain = Domain::with_sides(
        Vector::<2>::zeros(),
        Vector::<2>::new(n_r as f64 * dx, n_z as f64 * dx),
        [Boundary::Wall, Boundary::Periodic],
        [Boundary::Wall, Boundary::Periodic],
    )
    .unwrap();
    (init, domain)
}

/// Copper compressed by 1 % (p ≈ 1.4 GPa) at rest: every ring's acceleration, the first rows
/// at the axis and the last at the outer wall included, is below 1.2 % of the hoop term
/// p/(ρ r) it must cancel. The hoop force is the exact p/(ρr) away from the axis, while the
/// planar gradient of the ring flux 2πr p is a kernel sum of a linear field, which the cubic
/// spline at η = 1.2 gets short by δ ≈ 1 % (the 2D elastic wave's speed bias):
/// the residual is δ of the hoop term (measured 0.92 %, 0.43 % at the first ring, where the
/// axis factor carries part of it).
#[test]
fn uniform_pressure_stays_at_rest() {
    let (init, domain) = column(12, 8, 1.01 * RHO0, |_, _| Vector::zeros());
    let sim = Simulation::new(&init, vec![copper(400e6)], domain, config()).unwrap();
    let p = sim.particles();
    for i in 0..p.n_real() {
        let hoop = p.pressure[i] / (p.density[i] * p.position[i][0]);
        let a = p.acceleration[i].norm();
        assert!(
            a < 1.2e-2 * hoop,
            "ring at r = {}: |a| = {a:e}, hoop term {hoop:e}",
            p.position[i][0]
        );
    }
}

/// v_r = a r, v_z = 0: ε̇_rr = ε̇_θθ = a, so Dρ/Dt = −2aρ and the deviatoric stress rate is
/// 2G(a/3, −2a/3) on (rr, zz). From the third ring off the axis out to the interior (away from
/// the outer wall, whose mirror cannot follow the expansion) within 2.5 %: ε̇_rr is a planar
/// kernel-gradient sum of a linear field, which the cubic spline at η = 1.2 gets short by
/// δ ≈ 1 % (the same bias as the 2D elastic wave's speed), while the hoop rate
/// v_r/r is exact, so Dρ/Dt and ṡ_zz are short by δ/2 and ṡ_rr = 2G(ε̇_rr − tr ε̇/3) by 2δ
/// (measured 0.46 %, 0.46 %, 1.84 %). The first two rings
/// carry the even axis images' kink in their hoop rate (see solver::axisymmetric), measured:
/// 1.9 % at the second ring (limit 3 %), 27 % at the first (its density rate between 0.6 and
/// 0.9 of the exact).
#[test]
fn homologous_expansion_has_the_cylindrical_rates() {
    let a = 100.0;
    let dx = 1e-3;
    let (init, domain) = column(16, 8, RHO0, |r, _| Vector::<2>::new(a * r, 0.0));
    let sim = Simulation::new(&init, vec![copper(400e9)], domain, config()).unwrap();
    let p = sim.particles();
    let g = copper(400e9).strength.unwrap().shear_modulus;
    for i in 0..p.n_real() {
        let r = p.position[i][0];
        let rho_rate = p.density_rate[i] / (-2.0 * a * p.density[i]);
        if r < dx {
            assert!(
                (0.6..0.9).contains(&rho_rate),
                "first ring density rate {rho_rate} of the exact"
            );
            continue;
        }
        if r > 12.0 * dx {
            continue;
        }
        let limit = if r < 2.0 * dx { 3e-2 } else { 2.5e-2 };
        let s_rate = p.stress_rate[i];
        let rr = s_rate[(0, 0)] / (2.0 * g * a / 3.0);
        let zz = s_rate[(1, 1)] / (-4.0 * g * a / 3.0);
        for (what, ratio) in [
            ("density rate", rho_rate),
            ("s_rr rate", rr),
            ("s_zz rate", zz),
        ] {
            assert!(
                (ratio - 1.0).abs() < limit,
                "{what} at r = {r}: {ratio} of the exact"
            );
        }
    }
}

fn noise(k: usize, salt: u64) -> f64 {
    let mut z = (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    2.0 * ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 1.0
}

fn energy_and_axial_momentum(sim: &Simulation<2>) -> (f64, f64) {
    let p = sim.particles();
    let (mut energy, mut momentum) = (0.0, 0.0);
    for i in 0..p.n_real() {
        energy += p.mass[i] * (0.5 * p.velocity[i].norm_squared() + p.internal_energy[i]);
        momentum += p.mass[i] * p.velocity[i][1];
    }
    (energy, momentum)
}

/// A jostled copper column (random 20 m/s velocities; elastic, and plastic at a 20 MPa yield)
/// with a free outer surface: axial momentum to round-off (the axis images are even, so their
/// pair forces cancel in z like a wall's), and a total-energy error that is the time
/// integration's: it falls at second order as Δt halves (ratio ≥ 3.5 of the ideal 4).
#[test]
fn jostled_column_conserves_energy_and_axial_momentum() {
    for yield_stress in [10e9, 20e6] {
        let mut errors = Vec::new();
        for refinement in [1usize, 2] {
            let (init, mut domain) = column(12, 12, RHO0, |r, z| {
                let k = (r * 1e7) as usize * 7919 + (z * 1e7) as usize;
                Vector::<2>::new(20.0 * noise(k, 3), 20.0 * noise(k, 4))
            });
            domain.upper[0] = Boundary::Open;
            let mut sim =
                Simulation::new(&init, vec![copper(yield_stress)], domain, config()).unwrap();
            let (e0, m0) = energy_and_axial_momentum(&sim);
            let scale: f64 = init.iter().map(|p| p.mass * p.velocity.norm()).sum();
            let kinetic0: f64 = init
                .iter()
                .map(|p| 0.5 * p.mass * p.velocity.norm_squared())
                .sum();
            let dt = 2e-8 / refinement as f64;
            for _ in 0..(100 * refinement) {
                sim.step(dt).unwrap();
            }
            let (e1, m1) = energy_and_axial_momentum(&sim);
            assert!(
                (m1 - m0).abs() < 1e-12 * scale,
                "axial momentum {m0} → {m1}"
            );
            errors.push((e1 - e0).abs() / kinetic0);
        }
        assert!(errors[0] / errors[1] > 3.5, "energy errors {errors:?}");
    }
}

/// Kept neighbour lists change no result in rings either: the jostled column, plastic at a
/// 20 MPa yield (stress, hoop terms, radius gradients, the axis and outer walls, periodic ends),
/// ends 60 steps in the same state, bit for bit, with lists kept across steps as with a search
/// at every step, and searches at most half as often.
#[test]
fn kept_neighbour_lists_change_no_result_in_rings() {
    let run = |neighbour_skin: f64| {
        let (init, domain) = column(12, 12, RHO0, |r, z| {
            let k = (r * 1e7) as usize * 7919 + (z * 1e7) as usize;
            Vector::<2>::new(20.0 * noise(k, 3), 20.0 * noise(k, 4))
        });
        let config = SimulationConfig {
            neighbour_skin,
            ..config()
        };
        let mut sim = Simulation::new(&init, vec![copper(20e6)], domain, config).unwrap();
        for _ in 0..60 {
            sim.step(2e-8).unwrap();
        }
        sim
    };
    let (kept, fresh) = (run(0.2), run(0.0));
    let (a, b) = (kept.particles(), fresh.particles());
    let n = a.n_real();
    assert_eq!(a.position[..n], b.position[..n]);
    assert_eq!(a.velocity[..n], b.velocity[..n]);
    assert_eq!(a.deviatoric_stress[..n], b.deviatoric_stress[..n]);
    assert_eq!(a.internal_energy[..n], b.internal_energy[..n]);
    assert!(2 * kept.neighbour_searches() <= fresh.neighbour_searches());
}

/// A ring with no partner (a particle left alone where a blast's products thinned out) feels
/// the exact hoop force p/(ρr) of its own pressure, not the 0/0 of the axis factor that the
/// pair sums cannot define without partners.
#[test]
fn a_ring_without_partners_feels_its_own_hoop_force() {
    let (dx, r) = (1e-3, 0.01);
    let compressed = 1.01 * RHO0;
    let init = [ParticleInit {
        position: Vector::<2>::new(r, 0.0),
        velocity: Vector::zeros(),
        mass: compressed * 2.0 * PI * r * dx * dx,
        smoothing_length: 1.2 * dx,
        density: compressed,
        internal_energy: 0.0,
        material: 0,
    }];
    let domain = Domain::with_sides(
        Vector::<2>::new(0.0, -1.0),
        Vector::<2>::new(1.0, 1.0),
        [Boundary::Wall, Boundary::Open],
        [Boundary::Open, Boundary::Open],
    )
    .unwrap();
    let sim = Simulation::new(&init, vec![copper(400e6)], domain, config()).unwrap();
    let p = sim.particles();
    let pressure = p.pressure[0];
    assert!(pressure > 1e9, "{pressure}");
    let hoop = pressure / (compressed * r);
    assert!(
        (p.acceleration[0][0] - hoop).abs() <= 1e-12 * hoop,
        "{} against {hoop}",
        p.acceleration[0][0]
    );
}

/// An axisymmetric scene needs 2D, a wall on the axis and r > 0: each refused by name (its
/// continuity density is in its type).
#[test]
fn bad_axisymmetric_scenes_are_refused_by_name() {
    let refuse = |init: &[ParticleInit<2>], domain: Domain<2>, config: SimulationConfig| {
        Simulation::new(init, vec![copper(400e6)], domain, config)
            .unwrap_err()
            .to_string()
    };
    let (init, domain) = column(4, 4, RHO0, |_, _| Vector::zeros());
    let mut open_axis = domain;
    open_axis.lower[0] = Boundary::Open;
    assert!(refuse(&init, open_axis, config()).contains("axis"));
    let mut on_axis = init.clone();
    on_axis[0].position[0] = 0.0;
    assert!(refuse(&on_axis, domain, config()).contains("radius"));
    let init_3d = vec![ParticleInit::<3> {
        position: Vector::<3>::new(1e-3, 1e-3, 1e-3),
        velocity: Vector::zeros(),
        mass: 1e-6,
        smoothing_length: 1e-3,
        density: RHO0,
        internal_energy: 0.0,
        material: 0,
    }];
    let err = Simulation::new(&init_3d, vec![copper(400e6)], Domain::open(), config())
        .unwrap_err()
        .to_string();
    assert!(err.contains("formulation") && err.contains("2D"), "{err}");
}

/// A plane compression running along the axis of a copper column of rings (walls at the axis
/// and the outer radius) leaves through a transmitting end: the mean axial velocity of the
/// rings 0.05 m (50 spacings) inside it departs from that of a column twice as long, whose ends
/// send nothing back in time, by at most 10 % of the incident peak (the limit `transmitting-boundary` puts
/// on Cartesian columns; measured 1.2 % here at 10 rings per pulse width), while walls in its
/// place send back more than half (measured 85 %). The column's other end is a wall, whose
/// echo of the half running that way reaches the gauge only after the record ends: the one
/// transmitting side is found by the particles within a kernel's reach of it alone.
#[test]
fn a_plane_wave_leaves_an_axisymmetric_column_through_a_transmitting_end() {
    let dx = 1e-3;
    let (n_r, width, centre, gauge) = (4, 0.01, 0.1, 0.15);
    // the history of the mean v_z of the row of rings nearest the gauge
    let column_history = |z_lo: f64, n_z: usize, end: Boundary| -> Vec<(f64, f64)> {
        let mut init = Vec::new();
        for k in 0..n_z {
            for i in 0..n_r {
                let (r, z) = ((i as f64 + 0.5) * dx, z_lo + (k as f64 + 0.5) * dx);
                let density = RHO0 * (1.0 + 4e-4 * (-((z - centre) / width).powi(2)).exp());
                init.push(ParticleInit {
                    position: Vector::<2>::new(r, z),
                    velocity: Vector::<2>::zeros(),
                    mass: density * 2.0 * PI * r * dx * dx,
                    smoothing_length: 1.2 * dx,
                    density,
                    internal_energy: 0.0,
                    material: 0,
                });
            }
        }
        let domain = Domain::with_sides(
            Vector::<2>::new(0.0, z_lo),
            Vector::<2>::new(n_r as f64 * dx, z_lo + n_z as f64 * dx),
            [Boundary::Wall, Boundary::Wall],
            [Boundary::Wall, end],
        )
        .unwrap();
        let mut sim = Simulation::new(&init, vec![copper(1e12)], domain, config()).unwrap();
        let speed = sim.particles().sound_speed[0];
        // the reflection's centre back at the gauge, plus four widths
        let t_end = (0.1 + 0.05 + 4.0 * width) / speed;
        let mut samples = Vec::new();
        while sim.time() < t_end {
            sim.step_toward(t_end).unwrap();
            let p = sim.particles();
            let row: Vec<f64> = (0..p.n_real())
                .filter(|&i| (p.position[i][1] - gauge).abs() < 0.5 * dx)
                .map(|i| p.velocity[i][1])
                .collect();
            samples.push((sim.time(), row.iter().sum::<f64>() / row.len() as f64));
        }
        samples
    };
    let history = |z_lo: f64, n_z: usize, end: Boundary| {
        crate::on_one_thread(|| column_history(z_lo, n_z, end))
    };
    let transmitted = history(0.0, 200, Boundary::Transmitting);
    let far = history(-0.1, 400, Boundary::Open);
    let incident = far.iter().map(|s| s.1.abs()).fold(0.0, f64::max);
    // the reference at the same time, linearly interpolated
    let at = |t: f64| {
        let k = far.partition_point(|s| s.0 < t).clamp(1, far.len() - 1);
        let ((t0, v0), (t1, v1)) = (far[k - 1], far[k]);
        v0 + (v1 - v0) * (t - t0) / (t1 - t0)
    };
    let departure = |history: &[(f64, f64)]| {
        history
            .iter()
            .map(|&(t, v)| (v - at(t)).abs())
            .fold(0.0, f64::max)
            / incident
    };
    assert!(incident > 0.0);
    let reflected = departure(&transmitted);
    assert!(reflected < 0.1, "{reflected:e}");
    // walls in its place send the pulse back: the measurement sees a reflection
    let walled = departure(&history(0.0, 200, Boundary::Wall));
    assert!(walled > 0.5, "{walled:e}");
}
