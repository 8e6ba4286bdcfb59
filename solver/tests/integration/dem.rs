//! 2D discrete elements: binary collisions against the exact linear spring–dashpot solution,
//! momentum conservation of a jostled assembly, and the life cycle of a liquid bridge.

use blastsph_solver::dem::biaxial::{prepare_sample, BiaxialTest, PreparedSample};
use blastsph_solver::dem::capillary::{
    bridge_force, effective_radius, rupture_gap, BridgeLaw, Liquid, RuptureCriterion,
};
use blastsph_solver::dem::discs::{ContactModel, Discs, Wetting};
use blastsph_solver::Vector;

const RADIUS: f64 = 1e-4;
const DENSITY: f64 = 2650.0;

fn model(damping_ratio: f64) -> ContactModel {
    ContactModel {
        normal_stiffness: 1e5,
        tangential_stiffness: 5e4,
        friction: 0.5,
        damping_ratio,
        local_damping: 0.0,
    }
}

/// Two equal discs approaching head on at ±v; returns the restitution coefficient (their
/// separation speed over the approach speed) once they have parted.
fn collide(damping_ratio: f64, dt_fraction: f64) -> f64 {
    let v = 0.1;
    let positions = vec![
        Vector::<2>::new(-RADIUS - 1e-7, 0.0),
        Vector::<2>::new(RADIUS + 1e-7, 0.0),
    ];
    let mut discs = Discs::new(
        positions,
        vec![RADIUS; 2],
        DENSITY,
        model(damping_ratio),
        None,
    )
    .unwrap();
    discs.velocity[0] = Vector::<2>::new(v, 0.0);
    discs.velocity[1] = Vector::<2>::new(-v, 0.0);
    let dt = discs.critical_time_step(dt_fraction);
    let period = (discs.mass[0] * 0.5 / 1e5).sqrt() * std::f64::consts::PI;
    while discs.time < 4.0 * period {
        discs.step(dt).unwrap();
    }
    assert_eq!(discs.counts().0, 0, "still touching");
    (discs.velocity[1][0] - discs.velocity[0][0]) / (2.0 * v)
}

/// The exact restitution of the linear spring and a dashpot that cannot pull: the overlap
/// x(t) = (v0/ω_d) e^{−ζωt} sin ω_d t ends as a contact when the force k x + c ẋ reaches zero,
/// at tan(ω_d t*) = −2ζ√(1 − ζ²)/(1 − 2ζ²) (t* in the second quarter period), and
/// e = e^{−ζωt*} |cos ω_d t* − ζ/√(1 − ζ²) sin ω_d t*| (Schwager & Pöschel 2007 discuss this
/// model); ζ = 0 gives 1.
fn exact_restitution(zeta: f64) -> f64 {
    let root = (1.0 - zeta * zeta).sqrt();
    // ω_d t* in (π/2, π]
    let phase = std::f64::consts::PI + (-2.0 * zeta * root / (1.0 - 2.0 * zeta * zeta)).atan();
    (-zeta / root * phase).exp() * (phase.cos() - zeta / root * phase.sin()).abs()
}

/// Elastic (ζ = 0): e = 1 within (ωΔt)²: the spring switches on and off inside a step, an
/// impulse error of up to k (v0 Δt) Δt against m_eff v0 (measured 1.5e-3 where the bound is
/// 2e-2; with disc masses of unit thickness it was 1e-4, so the error depends on where in a
/// step the touch falls). Damped (ζ = 0.1, 0.3): e within 2ζωΔt of the exact
/// solution at a tenth, a twentieth and a fortieth of the critical step, ω = √(k/m_eff): the
/// dashpot's force jumps to c·v0 at first touch, and the touch falls anywhere inside a step, an
/// impulse error of up to c v0 Δt against the pair's momentum m_eff v0 (measured at ζ = 0.3:
/// 0.01 %, 1.5 %, 0.13 % where the bound is 8.5 %, 4.2 %, 2.1 %).
#[test]
fn binary_collisions_match_the_spring_dashpot_solution() {
    let elastic = collide(0.0, 0.1);
    let omega_dt = std::f64::consts::SQRT_2 * 0.1;
    assert!((elastic - 1.0).abs() < omega_dt * omega_dt, "e = {elastic}");
    for zeta in [0.1, 0.3] {
        let exact = exact_restitution(zeta);
        for fraction in [0.1, 0.05, 0.025] {
            // ωΔt = √2 × fraction for two equal discs (m_eff = m/2, Δt = fraction √(m/k))
            let bound = 2.0 * zeta * std::f64::consts::SQRT_2 * fraction;
            let error = (collide(zeta, fraction) / exact - 1.0).abs();
            assert!(
                error < bound,
                "ζ = {zeta}, Δt fraction {fraction}: {error} ≥ {bound}"
            );
        }
    }
}

/// A jostled, overlapping assembly of discs with friction and damping (it flies apart): the
/// pair forces are equal and opposite, so total momentum stays at its start to round-off.
#[test]
fn jostled_assembly_conserves_momentum() {
    let n = 8;
    let mut positions = Vec::new();
    for k in 0..n * n {
        let (i, j) = ((k % n) as f64, (k / n) as f64);
        positions.push(Vector::<2>::new(i * 1.9 * RADIUS, j * 1.9 * RADIUS));
    }
    let mut discs = Discs::new(positions, vec![RADIUS; n * n], DENSITY, model(0.2), None).unwrap();
    for k in 0..n * n {
        let s = ((k * 7919) % 101) as f64 / 101.0 - 0.5;
        let c = ((k * 104729) % 97) as f64 / 97.0 - 0.5;
        discs.velocity[k] = Vector::<2>::new(0.2 * s, 0.2 * c);
        discs.angular_velocity[k] = 100.0 * s;
    }
    let momentum =
        |d: &Discs| -> Vector<2> { (0..d.len()).map(|k| d.velocity[k] * d.mass[k]).sum() };
    let scale: f64 = (0..discs.len())
        .map(|k| discs.mass[k] * discs.velocity[k].norm())
        .sum();
    let start = momentum(&discs);
    let dt = discs.critical_time_step(0.1);
    let mut touching = 0;
    for _ in 0..2000 {
        discs.step(dt).unwrap();
        touching = touching.max(discs.counts().0);
    }
    assert!(touching > n * n, "{touching} contacts at most");
    assert!((momentum(&discs) - start).norm() < 1e-12 * scale);
}

/// A bridge forms only at contact, from half of each grain's film; pulls with its law's force
/// at the gap; breaks beyond the rupture gap, giving half its liquid back to each grain; does
/// not form again until the grains touch. The liquid in films and bridges stays the same
/// throughout.
#[test]
fn liquid_bridge_forms_at_contact_and_breaks_at_rupture() {
    let film = 1e-14;
    let liquid = Liquid::water(film, 0.0).unwrap();
    let wetting = Wetting {
        law: BridgeLaw::WillettFitted,
        rupture: RuptureCriterion::Lian,
        liquid,
    };
    let r = effective_radius(RADIUS, RADIUS);
    let s_c = rupture_gap(RuptureCriterion::Lian, &liquid, r);
    let at_gap = |discs: &mut Discs, gap: f64| {
        discs.position[1] = Vector::<2>::new(2.0 * RADIUS + gap, 0.0);
        discs.compute_forces(0.0).unwrap();
        assert!((discs.total_liquid() / (2.0 * film) - 1.0).abs() < 1e-12);
        discs.force[0][0]
    };
    let mut discs = Discs::new(
        vec![
            Vector::zeros(),
            Vector::<2>::new(2.0 * RADIUS + 0.5 * s_c, 0.0),
        ],
        vec![RADIUS; 2],
        DENSITY,
        model(0.0),
        Some(wetting),
    )
    .unwrap();
    // apart and never touched: dry
    assert_eq!(at_gap(&mut discs, 0.5 * s_c), 0.0);
    // touch: the bridge forms with half of each film, V = film
    at_gap(&mut discs, -1e-7);
    let volumes: Vec<f64> = discs.bridge_volumes().map(|(_, v)| v).collect();
    assert_eq!(volumes, vec![film]);
    assert_eq!(discs.film, vec![0.5 * film; 2]);
    // pulled apart: the law's force for that volume, towards the other disc
    let pull = at_gap(&mut discs, 0.5 * s_c);
    let expected = bridge_force(BridgeLaw::WillettFitted, &liquid, r, 0.5 * s_c).unwrap();
    assert!((pull / expected - 1.0).abs() < 1e-12, "{pull} {expected}");
    // beyond rupture: broken, the liquid back in the films, and no bridge short of contact
    assert_eq!(at_gap(&mut discs, 1.01 * s_c), 0.0);
    assert_eq!(discs.counts().1, 0);
    assert_eq!(discs.film, vec![film; 2]);
    assert_eq!(at_gap(&mut discs, 0.5 * s_c), 0.0);
}

/// The pore water of a prepared sample goes to the contacts in proportion to their centre
/// distances and adds up to the volume given; the films are left empty.
#[test]
fn liquid_is_distributed_in_proportion_to_centre_distance() {
    let wetting = Wetting {
        law: BridgeLaw::WillettFitted,
        rupture: RuptureCriterion::Lian,
        liquid: Liquid::water(1e-15, 0.0).unwrap(),
    };
    // a row of three touching discs of different sizes: two contacts at different distances
    let radii = vec![RADIUS, 2.0 * RADIUS, 1.5 * RADIUS];
    let positions = vec![
        Vector::<2>::zeros(),
        Vector::<2>::new(3.0 * RADIUS - 1e-7, 0.0),
        Vector::<2>::new(6.5 * RADIUS - 2e-7, 0.0),
    ];
    let mut discs = Discs::new(positions, radii, DENSITY, model(0.0), Some(wetting)).unwrap();
    discs.compute_forces(0.0).unwrap();
    discs.distribute_liquid(6e-14).unwrap();
    let volumes: Vec<((usize, usize), f64)> = discs.bridge_volumes().collect();
    assert_eq!(volumes.len(), 2);
    let d01 = 3.0 * RADIUS - 1e-7;
    let d12 = 3.5 * RADIUS - 1e-7;
    assert!((volumes[0].1 / (6e-14 * d01 / (d01 + d12)) - 1.0).abs() < 1e-12);
    assert!((volumes[1].1 / (6e-14 * d12 / (d01 + d12)) - 1.0).abs() < 1e-12);
    assert!((discs.total_liquid() / 6e-14 - 1.0).abs() < 1e-12);
    assert!(discs.film.iter().all(|&f| f == 0.0));
}

/// Bad contact data is named.
#[test]
fn bad_contact_model_is_named() {
    let bad = ContactModel {
        damping_ratio: 1.5,
        ..model(0.0)
    };
    let err = Discs::new(vec![Vector::zeros()], vec![RADIUS], DENSITY, bad, None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("damping ratio"), "{err}");
    let err = Discs::new(vec![Vector::zeros()], vec![-1.0], DENSITY, model(0.0), None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("radius"), "{err}");
}

/// The tangential spring under a steady sliding velocity u (positions frozen): its force grows
/// as k_t u t until it reaches the Coulomb limit μ k_n δ and stays there; the torques are the
/// contact radius times it, equal for equal discs.
#[test]
fn tangential_spring_grows_to_the_coulomb_limit() {
    let overlap = 1e-6;
    let mut discs = Discs::new(
        vec![
            Vector::zeros(),
            Vector::<2>::new(2.0 * RADIUS - overlap, 0.0),
        ],
        vec![RADIUS; 2],
        DENSITY,
        model(0.0),
        None,
    )
    .unwrap();
    let u = 0.05; // the limit is reached at step 20
    discs.velocity[1] = Vector::<2>::new(0.0, u);
    let dt = 1e-6;
    let m = model(0.0);
    let limit = m.friction * m.normal_stiffness * overlap;
    let mut slipped = false;
    for k in 1..=200 {
        discs.compute_forces(dt).unwrap();
        slipped |= m.tangential_stiffness * u * dt * k as f64 > limit;
        let expected = (m.tangential_stiffness * u * dt * k as f64).min(limit);
        // j drags i along +y
        let tangential = discs.force[0][1];
        assert!(
            (tangential / expected - 1.0).abs() < 1e-9,
            "step {k}: {tangential} vs {expected}"
        );
        assert!((discs.force[0][0] + m.normal_stiffness * overlap).abs() < 1e-12);
        assert!((discs.torque[0] - RADIUS * tangential).abs() < 1e-15);
        assert!((discs.torque[1] - discs.torque[0]).abs() < 1e-15);
    }
    assert!(slipped);
}

/// The biaxial problem's dry sample preparation (blastsph_solver::dem::biaxial) at 200 grains,
/// expanded to `stress` with inter-particle friction μ.
fn expanded_sample(friction: f64, stress: f64) -> (Discs, PreparedSample) {
    let mut test = BiaxialTest::source_paper(200, 11, 0.0, stress);
    test.contact.friction = friction;
    prepare_sample(&test).unwrap()
}

/// Radius expansion with μ = 0.5 reaches the target wall stress within 2 % and leaves a jammed
/// packing: porosity between 0.1 and 0.3 (random packings of polydisperse discs lie near
/// 0.15–0.2, looser with friction) and a mean coordination of the load-carrying discs (wall
/// contacts counted) between the isostatic bounds of 2D jamming, 3 (frictional, μ → ∞) and 4
/// (frictionless), allowing 0.5 above 4 for the springs' finite overlap. Measured: porosity
/// 0.213, coordination 3.10, 182 000 steps. The wall stress is checked as the walls feel it:
/// the mean of the four walls' normal forces over their areas (length × layer thickness),
/// ½(σ_xx + σ_yy); the steps as whole cycles of 500.
#[test]
fn radius_expansion_jams_a_graded_sample_at_the_target_stress() {
    let (discs, done) = expanded_sample(0.5, 1000.0);
    let thickness = discs.layer_thickness();
    let pressure = |wall: usize, length: f64| discs.wall_force[wall].norm() / (length * thickness);
    let sigma_xx = 0.5 * (pressure(0, done.height) + pressure(1, done.height));
    let sigma_yy = 0.5 * (pressure(2, done.width) + pressure(3, done.width));
    let felt = 0.5 * (sigma_xx + sigma_yy);
    assert!(
        (felt / done.wall_stress - 1.0).abs() < 1e-12,
        "{felt} {done:?}"
    );
    assert!((felt / 1000.0 - 1.0).abs() < 0.02, "{felt} {done:?}");
    assert!(
        done.preparation_steps > 0 && done.preparation_steps % 500 == 0,
        "{done:?}"
    );
    assert!((0.1..0.3).contains(&done.porosity), "{done:?}");
    assert!((3.0..4.5).contains(&done.coordination), "{done:?}");
}

/// The friction study's expected trend (a standard DEM result): the same sample
/// prepared with more friction between grains is looser and less coordinated. Measured:
/// μ = 0.1: porosity 0.188, coordination 3.53; μ = 1: 0.232, 3.08.
#[test]
fn more_friction_prepares_a_looser_less_coordinated_sample() {
    let (smooth, rough) = (
        expanded_sample(0.1, 1000.0).1,
        expanded_sample(1.0, 1000.0).1,
    );
    assert!(rough.porosity > smooth.porosity, "{smooth:?} {rough:?}");
    assert!(
        rough.coordination < smooth.coordination,
        "{smooth:?} {rough:?}"
    );
}

/// A jostled wet assembly, where bridges keep forming and breaking: the liquid in films and
/// bridges together stays the same to round-off.
#[test]
fn jostled_wet_assembly_conserves_its_liquid() {
    let n = 6;
    let positions: Vec<Vector<2>> = (0..n * n)
        .map(|k| {
            Vector::<2>::new(
                (k % n) as f64 * 2.02 * RADIUS,
                (k / n) as f64 * 2.02 * RADIUS,
            )
        })
        .collect();
    let wetting = Wetting {
        law: BridgeLaw::WillettFitted,
        rupture: RuptureCriterion::Lian,
        liquid: Liquid::water(1e-14, 0.0).unwrap(),
    };
    let mut discs = Discs::new(
        positions,
        vec![RADIUS; n * n],
        DENSITY,
        model(0.1),
        Some(wetting),
    )
    .unwrap();
    for k in 0..n * n {
        let s = ((k * 7919) % 101) as f64 / 101.0 - 0.5;
        let c = ((k * 104729) % 97) as f64 / 97.0 - 0.5;
        discs.velocity[k] = Vector::<2>::new(0.5 * s, 0.5 * c);
    }
    let start = discs.total_liquid();
    let dt = discs.critical_time_step(0.1);
    let (mut most, mut fewest) = (0, usize::MAX);
    for _ in 0..3000 {
        discs.step(dt).unwrap();
        let bridges = discs.counts().1;
        most = most.max(bridges);
        fewest = fewest.min(bridges);
    }
    assert!(
        most > fewest,
        "bridges {fewest}..{most}: none formed or broke"
    );
    assert!((discs.total_liquid() / start - 1.0).abs() < 1e-12);
}

/// A wet biaxial test of 200 grains at 10 % saturation and σ3 = 1 kPa, through the membrane:
/// - every grain stays inside the membrane and between the platens (none slips through);
/// - the liquid in bridges and films stays the saturation's volume, to round-off;
/// - the sample shows a shear strength: its peak mobilised friction angle
///   asin((σ1 − σ3)/(σ1 + σ3)) lies between 15° and 45° (a plausibility band for frictional
///   discs that roll freely, cohesion included, not a calibration).
#[test]
fn wet_biaxial_keeps_its_grains_and_its_water_and_shows_strength() {
    use blastsph_solver::dem::biaxial::{add_pore_water, run_biaxial, Membrane};
    let mut test = BiaxialTest::source_paper(200, 5, 0.1, 1000.0);
    test.loading.axial_strain = 0.05;
    let (mut discs, mut sample) = prepare_sample(&test).unwrap();
    add_pore_water(&mut discs, &mut sample, &test).unwrap();
    let water = discs.total_liquid();
    assert!(water > 0.0 && sample.bridges > 0, "{sample:?}");
    let r_min = discs.radius.iter().cloned().fold(f64::INFINITY, f64::min);
    let membrane = Membrane::wrap(&mut discs, 0.8 * r_min).unwrap();
    let records = run_biaxial(&mut discs, &membrane, test.loading).unwrap();
    assert!((discs.total_liquid() / water - 1.0).abs() < 1e-12);
    // inside: the winding number of the outline around each grain centre is 1
    let outline = membrane.outline(&discs);
    let (bottom, top) = (discs.walls[0].point[1], discs.walls[1].point[1]);
    for k in 0..discs.grains() {
        let x = discs.position[k];
        let winding: f64 = (0..outline.len())
            .map(|e| {
                let (a, b) = (outline[e] - x, outline[(e + 1) % outline.len()] - x);
                (a[0] * b[1] - a[1] * b[0]).atan2(a.dot(&b))
            })
            .sum::<f64>()
            / std::f64::consts::TAU;
        assert!(
            (winding - 1.0).abs() < 1e-6,
            "grain {k} outside the membrane"
        );
        assert!(x[1] > bottom && x[1] < top, "grain {k} beyond a platen");
    }
    let peak = records.iter().map(|r| r.sigma1).fold(0.0, f64::max);
    let phi = ((peak - 1000.0) / (peak + 1000.0)).asin().to_degrees();
    assert!((15.0..45.0).contains(&phi), "peak friction angle {phi}°");
}

/// The same seed gives the same test to the last bit, with one thread or with several (the
/// pair list is sorted, the force loop runs in its order).
#[test]
fn biaxial_is_deterministic_across_thread_counts() {
    use blastsph_solver::dem::biaxial::run_biaxial_test;
    let mut test = BiaxialTest::source_paper(100, 3, 0.1, 1000.0);
    test.loading.axial_strain = 0.01;
    let run_with = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run_biaxial_test(&test).unwrap())
    };
    assert_eq!(run_with(1), run_with(2));
}

/// Bad loading data is refused, named, before the consolidation runs.
#[test]
fn bad_loading_is_named_before_consolidation() {
    use blastsph_solver::dem::biaxial::shear_prepared;
    let test = BiaxialTest::source_paper(40, 2, 0.0, 1000.0);
    let (discs, sample) = prepare_sample(&test).unwrap();
    let refusal = |bad: BiaxialTest| {
        shear_prepared(discs.clone(), sample, &bad)
            .unwrap_err()
            .to_string()
    };
    // Cundall's α in [0, 1): 1 would stop every grain
    for alpha in [1.2, 1.0, -0.1, f64::NAN] {
        let mut bad = test;
        bad.loading.local_damping = alpha;
        let err = refusal(bad);
        assert!(err.contains("local damping"), "{alpha}: {err}");
    }
    type Field = fn(&mut BiaxialTest) -> &mut f64;
    let positive: [(&str, Field); 4] = [
        ("confining stress", |t| &mut t.loading.confining_stress),
        ("platen speed", |t| &mut t.loading.platen_speed),
        ("consolidation speed", |t| {
            &mut t.loading.consolidation_speed
        }),
        ("axial strain", |t| &mut t.loading.axial_strain),
    ];
    for (name, field) in positive {
        for value in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let mut bad = test;
            *field(&mut bad) = value;
            let err = refusal(bad);
            assert!(err.contains(name), "{name} = {value}: {err}");
        }
    }
    let mut bad = test;
    bad.loading.record_every = 0;
    let err = refusal(bad);
    assert!(err.contains("record every"), "{err}");
}

/// A whole test of 40 dry grains to 1 % axial strain, checked from what defines it:
/// - the box is sized for the drawn grains at a porosity of 0.2 (Σπr²/(0.8 · 2W²) = 1) and is
///   twice as high as wide; the void ratio is n/(1 − n);
/// - a record every 500 steps while the platens close at a constant speed, so that the k-th
///   record's axial strain is k times the first's; the last record, when the strain is
///   reached, ends within one step's closing of it; σ3 as applied;
/// - the sample's area changes by at most three times the axial strain: compression alone
///   makes ε_v = ε_a, and dilatancy at angles up to 30° widens it by at most 2 ε_a more;
/// - the time step is 0.2 √(m_min/k_n); the steps counted are the preparation's, whole
///   consolidation windows of 500 (at least the five in a row that end it) and the loading's;
/// - the run counts the grains and the membrane's particles.
#[test]
fn a_short_biaxial_test_records_what_it_runs() {
    use blastsph_solver::dem::biaxial::run_biaxial_test;
    use blastsph_solver::dem::sample::graded_diameters;
    use blastsph_solver::random::SplitMix64;
    let mut test = BiaxialTest::source_paper(40, 2, 0.0, 1000.0);
    test.loading.axial_strain = 0.01;
    let (discs, sample) = prepare_sample(&test).unwrap();
    let (d_min, d_max) = test.diameters;
    let drawn: f64 = graded_diameters(40, d_min, d_max, &mut SplitMix64::new(2))
        .unwrap()
        .iter()
        .map(|d| std::f64::consts::PI * 0.25 * d * d)
        .sum();
    let box_area = sample.width * sample.height;
    assert!((drawn / (0.8 * box_area) - 1.0).abs() < 1e-12, "{sample:?}");
    assert!(
        (sample.height / sample.width - 2.0).abs() < 1e-12,
        "{sample:?}"
    );
    assert!(
        (sample.void_ratio - sample.porosity / (1.0 - sample.porosity)).abs() < 1e-15,
        "{sample:?}"
    );
    assert_eq!(sample.layer_thickness, discs.layer_thickness());
    let run = run_biaxial_test(&test).unwrap();
    assert_eq!(run.sample, sample);
    let m_min = discs.mass[..discs.grains()]
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let dt = 0.2 * (m_min / test.contact.normal_stiffness).sqrt();
    assert!(
        (run.time_step / dt - 1.0).abs() < 1e-12,
        "{}",
        run.time_step
    );
    let records = &run.records;
    let (first, last) = (records[0], records[records.len() - 1]);
    assert!(records.len() >= 3, "{}", records.len());
    for (k, r) in records[..records.len() - 1].iter().enumerate() {
        let want = (k + 1) as f64 * first.axial_strain;
        assert!(
            (r.axial_strain / want - 1.0).abs() < 1e-9,
            "record {k}: {r:?}"
        );
        assert!(r.sigma3 == 1000.0 && r.sigma1 > 0.0, "record {k}: {r:?}");
    }
    for r in records {
        assert!(r.volumetric_strain.abs() <= 3.0 * r.axial_strain, "{r:?}");
    }
    let per_step = first.axial_strain / 500.0;
    assert!(
        last.axial_strain >= 0.01 && last.axial_strain - 0.01 < per_step,
        "{last:?}"
    );
    let loading = (last.axial_strain / per_step).round() as usize;
    let consolidation = run.steps - sample.preparation_steps - loading;
    assert!(
        consolidation.is_multiple_of(500) && consolidation >= 2500,
        "{} steps: {} preparing, {loading} loading",
        run.steps,
        sample.preparation_steps
    );
    assert_eq!(run.particles, discs.grains() + run.membrane_particles);
    assert!(run.membrane_particles >= 4, "{run:?}");
}

/// The pore water of a prepared sample: the bridges hold S times the pores' volume (the
/// notes' rule, `liquid_for_saturation`, over the prepared box), and the sample records
/// their number, their mean V/R³ and their mean force at the gaps they formed at (a wiring
/// check: the same means taken again from the bridges one by one).
#[test]
fn pore_water_goes_into_bridges_and_is_summarised() {
    use blastsph_solver::dem::biaxial::{add_pore_water, liquid_for_saturation};
    let test = BiaxialTest::source_paper(40, 2, 0.1, 1000.0);
    let (mut discs, mut sample) = prepare_sample(&test).unwrap();
    let water = liquid_for_saturation(&discs, sample.width * sample.height, 0.1);
    add_pore_water(&mut discs, &mut sample, &test).unwrap();
    assert!((discs.total_liquid() / water - 1.0).abs() < 1e-12);
    let liquid = |volume| Liquid {
        volume,
        surface_tension: test.surface_tension,
        contact_angle: test.contact_angle,
    };
    let (mut count, mut ratio, mut force) = (0, 0.0, 0.0);
    for ((i, j), v) in discs.bridge_volumes() {
        let radius = effective_radius(discs.radius[i], discs.radius[j]);
        let gap =
            (discs.position[j] - discs.position[i]).norm() - discs.radius[i] - discs.radius[j];
        count += 1;
        ratio += v / radius.powi(3);
        force += bridge_force(test.law, &liquid(v), radius, gap).unwrap();
    }
    assert!(count > 10, "{count} bridges");
    assert_eq!(sample.bridges, count);
    let mean_ratio = ratio / count as f64;
    let mean_force = force / count as f64;
    assert!(
        (sample.mean_bridge_volume_ratio / mean_ratio - 1.0).abs() < 1e-12,
        "{sample:?}"
    );
    assert!(
        (sample.mean_bridge_force / mean_force - 1.0).abs() < 1e-12,
        "{sample:?}"
    );
}
