use super::*;
use blastsph_solver::Simulation;
use proptest::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// A small valid plane-strain scene: sand with a lined hole, a charge on the surface, gauges.
const VALID: &str = r#"
[scene]
name = "small"
geometry = "plane-strain"
end_time = 1e-4

[domain]
min = [-4.0, -4.0]
max = [4.0, 1.0]
sides = { x_min = "transmitting", x_max = "transmitting", y_min = "wall", y_max = "open" }

[[material]]
name = "sand"
library = "dry-sand"
drucker_prager = { cohesion = 0.0, friction_angle = 30.0 }

[[material]]
name = "lining"
library = "concrete"
von_mises = { yield = 30e6 }

[[body]]
name = "soil"
material = "sand"
spacing = 0.25
shape = { kind = "layer", bottom = -4.0, top = 0.0 }
subtract = ["lining", { kind = "sphere", centre = [0.0, -2.0], radius = 0.5 }]

[[body]]
name = "lining"
material = "lining"
spacing = 0.125
shape = { kind = "annulus", centre = [0.0, -2.0], inner_radius = 0.5, outer_radius = 0.75 }

[[body]]
name = "charge"
material = "tnt"
spacing = 0.125
shape = { kind = "hemisphere", centre = [0.0, 0.0], radius = 0.375 }
detonation_points = [[0.0, 0.0]]

[[gauge]]
name = "crown"
position = [0.0, -1.3]
"#;

fn error_of(text: &str) -> (usize, String, String) {
    match Scene::parse(text) {
        Err(VerifyError::Scene { line, key, message }) => (line, key, message),
        other => panic!("expected a scene error, got {other:?}"),
    }
}

/// The line of `VALID` (1-based) that starts with `start`.
fn line_starting(start: &str) -> usize {
    VALID
        .lines()
        .position(|l| l.starts_with(start))
        .expect("the line exists")
        + 1
}

#[test]
fn a_valid_scene_reads_with_its_materials_bodies_and_holes() {
    let scene = Scene::parse(VALID).expect("the scene is valid");
    assert_eq!(scene.geometry, Geometry::PlaneStrain);
    assert_eq!(scene.bodies.len(), 3);
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["sand", "lining", "tnt"]);
    assert!(scene.materials[0].strength.is_some() && scene.materials[2].strength.is_none());
    assert_eq!(scene.materials[2].detonation_speed, Some(6930.0));
    // the soil leaves out the lining (by name) and the tunnel's inside (by shape)
    assert_eq!(scene.bodies[0].subtract.len(), 2);
    assert!(!in_any_hole(&scene.bodies[0], &[0.0, -2.8]));
    assert!(in_any_hole(&scene.bodies[0], &[0.0, -2.7]));
    assert!(in_any_hole(&scene.bodies[0], &[0.0, -2.0]));
}

fn in_any_hole(body: &Body, x: &[f64]) -> bool {
    body.subtract.iter().any(|hole| contains(hole, x))
}

#[test]
fn a_charge_given_by_mass_gets_the_radius_of_that_mass() {
    let text = VALID
        .replace("plane-strain", "3d")
        .replace("[-4.0, -4.0]", "[-4.0, -4.0, -4.0]")
        .replace("max = [4.0, 1.0]", "max = [4.0, 4.0, 1.0]")
        .replace(
            "y_max = \"open\"",
            "y_max = \"wall\", z_min = \"wall\", z_max = \"open\"",
        )
        .replace("[0.0, -2.0]", "[0.0, 0.0, -2.0]")
        .replace("[0.0, -1.3]", "[0.0, 0.0, -1.3]")
        .replace(
            "centre = [0.0, 0.0], radius = 0.375",
            "centre = [0.0, 0.0, 0.0], mass = 100.0",
        )
        .replace("[[0.0, 0.0]]", "[[0.0, 0.0, 0.0]]");
    let scene = Scene::parse(&text).expect("the 3D scene is valid");
    let Shape::Hemisphere {
        radius: Some(r), ..
    } = scene.bodies[2].shape
    else {
        panic!("a hemisphere")
    };
    // half a sphere of 2W at TNT's 1630 kg/m³: (3·200/(4π·1630))^(1/3)
    let expected = (3.0 * 200.0 / (4.0 * std::f64::consts::PI * 1630.0)).cbrt();
    approx::assert_relative_eq!(r, expected, max_relative = 1e-12);
}

#[test]
fn an_unknown_material_is_named_with_its_line_and_the_choices() {
    let (line, key, message) =
        error_of(&VALID.replace("material = \"sand\"", "material = \"sandd\""));
    assert_eq!(line, line_starting("material = \"sand"));
    assert_eq!(key, "body.material");
    assert!(
        message.contains("sandd") && message.contains("dry-sand"),
        "{message}"
    );
}

#[test]
fn an_unknown_key_is_named_with_its_line() {
    let text = VALID.replace("spacing = 0.25", "spacing = 0.25\ndensity = 3.0");
    let (line, _, message) = error_of(&text);
    assert_eq!(line, line_starting("spacing = 0.25") + 1);
    assert!(message.contains("unknown field `density`"), "{message}");
}

#[test]
fn a_body_outside_the_domain_is_refused() {
    // above the open top (across the bottom, a wall, a body may reach: its mirror stands in)
    let text = VALID.replace("bottom = -4.0, top = 0.0", "bottom = -6.0, top = 2.0");
    let (line, key, message) = error_of(&text);
    assert_eq!(
        (line, key.as_str()),
        (line_starting("name = \"soil\"") - 1, "body.shape")
    );
    assert!(message.contains("beyond the domain"), "{message}");
}

#[test]
fn a_non_positive_spacing_is_refused_with_the_allowed_range() {
    let (line, key, message) = error_of(&VALID.replace("spacing = 0.25", "spacing = 0.0"));
    assert_eq!(
        (line, key.as_str()),
        (line_starting("spacing = 0.25"), "body.spacing")
    );
    assert!(message.contains("≤ body.spacing ≤"), "{message}");
}

/// A lining given a tensile strength cracks by Rankine's criterion; a non-positive one is
/// refused on its material's line, by name.
#[test]
fn a_brittle_lining_takes_a_positive_tensile_strength() {
    let brittle = VALID.replace(
        "von_mises = { yield = 30e6 }",
        "von_mises = { yield = 30e6, tensile_strength = 3e6 }",
    );
    let scene = Scene::parse(&brittle).expect("a brittle lining reads");
    let lining = scene.materials.iter().find(|m| m.name == "lining").unwrap();
    assert_eq!(
        lining.strength.as_ref().unwrap().tensile_strength,
        Some(3e6)
    );
    let (line, _, message) =
        error_of(&brittle.replace("tensile_strength = 3e6", "tensile_strength = -3e6"));
    let material_line = brittle
        .lines()
        .position(|l| l.starts_with("von_mises"))
        .unwrap();
    assert!(line.abs_diff(material_line + 1) <= 3, "line {line}");
    assert!(message.contains("tensile strength"), "{message}");
}

#[test]
fn a_truncated_file_is_refused() {
    let cut = VALID.find("[[body]]").expect("a body") + 12;
    let (line, key, _) = error_of(&VALID[..cut]);
    assert_eq!(key, "file");
    assert!(line > 0);
}

#[test]
fn an_explosive_needs_detonation_points_and_only_an_explosive_has_them() {
    let (_, key, _) = error_of(&VALID.replace("detonation_points = [[0.0, 0.0]]", ""));
    assert_eq!(key, "body.detonation_points");
    let text = VALID.replace(
        "shape = { kind = \"layer\"",
        "detonation_points = [[0.0, 0.0]]\nshape = { kind = \"layer\"",
    );
    let (_, key, message) = error_of(&text);
    assert_eq!(key, "body.detonation_points");
    assert!(message.contains("not one"), "{message}");
}

#[test]
fn an_axisymmetric_scene_needs_its_axis_and_spheres_on_it() {
    let text = VALID.replace("plane-strain", "axisymmetric");
    let (_, key, _) = error_of(&text);
    assert_eq!(key, "domain.sides.x_min");
    let text = r#"
[scene]
name = "off-axis"
geometry = "axisymmetric"
end_time = 1e-4
[domain]
min = [0.0, 0.0]
max = [2.0, 2.0]
sides = { x_min = "wall", x_max = "open", y_min = "open", y_max = "open" }
[[body]]
name = "ball"
material = "air"
spacing = 0.1
shape = { kind = "sphere", centre = [1.0, 1.0], radius = 0.5 }
"#;
    let (_, _, message) = error_of(text);
    assert!(
        message.contains("torus") || message.contains("on the axis"),
        "{message}"
    );
}

/// Builds and runs a scene for a few steps; `Err` as the CLI would report it (exit 2).
fn run_briefly(text: &str) -> Result<RunSummary, VerifyError> {
    let mut scene = Scene::parse(text)?;
    scene.check_memory()?;
    if scene.particle_estimate() > 2e4 {
        // a valid scene too large for a unit test: it would run
        return Ok(RunSummary::default());
    }
    scene.end_time = scene.end_time.min(2e-6);
    scene.output_interval = None;
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let out = std::env::temp_dir().join(format!("blastsph-scene-{}-{k}", std::process::id()));
    let result = crate::on_one_thread(|| run(&scene, &out, &mut |_| {}));
    let _ = std::fs::remove_dir_all(&out);
    result
}

#[test]
fn overlapping_bodies_and_a_gauge_in_no_body_are_refused_before_the_run() {
    // the soil without its holes overlaps the lining
    let text = VALID.replace(
        "subtract = [\"lining\", { kind = \"sphere\", centre = [0.0, -2.0], radius = 0.5 }]",
        "",
    );
    let Err(VerifyError::Scene { key, message, .. }) = run_briefly(&text) else {
        panic!("overlap accepted")
    };
    assert_eq!(key, "body.shape");
    assert!(message.contains("overlaps"), "{message}");
    // in the tunnel
    let text = VALID.replace("position = [0.0, -1.3]", "position = [0.0, -2.0]");
    let Err(VerifyError::Scene { key, message, .. }) = run_briefly(&text) else {
        panic!("a gauge in the void accepted")
    };
    assert_eq!(key, "gauge.position");
    assert!(message.contains("no body"), "{message}");
}

#[test]
fn the_valid_scene_runs_and_its_gauge_reads_the_lining() {
    let summary = run_briefly(VALID).expect("the scene runs");
    assert!(summary.stopped.is_none(), "{:?}", summary.stopped);
    assert_eq!(summary.gauges[0].body, "lining");
    assert!(summary.steps > 0);
}

/// With the top an outflow side just above the charge, the products leave the run: the summary
/// counts them and the energy that left, and a gauge on a particle that left reads NaN from
/// then on (its earlier rows stay).
#[test]
fn products_leave_through_an_outflow_top_and_their_gauge_stops_reading() {
    let text = VALID
        .replace("y_max = \"open\"", "y_max = \"outflow\"")
        .replace("max = [4.0, 1.0]", "max = [4.0, 0.4]")
        .replace("position = [0.0, -1.3]", "position = [0.0, 0.3]")
        .replace("end_time = 1e-4", "end_time = 4e-4");
    let scene = Scene::parse(&text).expect("the scene is valid");
    let out = std::env::temp_dir().join(format!("blastsph-outflow-{}", std::process::id()));
    let summary = run(&scene, &out, &mut |_| {}).expect("the scene runs");
    let table = std::fs::read_to_string(out.join("gauges").join("crown.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    assert!(summary.stopped.is_none(), "{:?}", summary.stopped);
    assert_eq!(summary.gauges[0].body, "charge");
    assert!(summary.departed.particles > 0 && summary.departed.mass > 0.0);
    assert!(summary.energy_exchanged_j > 0.0);
    let rows: Vec<&str> = table.lines().skip(1).collect();
    let gone = rows
        .iter()
        .position(|row| row.contains("NaN"))
        .expect("the gauge's particle left");
    assert!(gone > 0 && rows[gone..].iter().all(|row| row.contains("NaN")));
}

/// Small edits of a valid scene: a number replaced, a line dropped or doubled, the file cut.
fn mutated(seed: (usize, usize, u8)) -> String {
    let (at, pick, kind) = seed;
    let lines: Vec<&str> = VALID.lines().collect();
    let k = at % lines.len();
    let numbers = [
        "0", "-1", "1e30", "-0.0", "nan", "inf", "3", "1e-9", "\"x\"", "[]",
    ];
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    match kind % 4 {
        0 => {
            // the first number on line k replaced
            if let Some(start) = out[k].find(|c: char| c.is_ascii_digit()) {
                let end = out[k][start..]
                    .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
                    .map_or(out[k].len(), |e| start + e);
                out[k].replace_range(start..end, numbers[pick % numbers.len()]);
            }
        }
        1 => {
            out.remove(k);
        }
        2 => {
            let copy = out[k].clone();
            out.insert(k, copy);
        }
        _ => {
            let text = out.join("\n");
            let cut = pick % text.len();
            let cut = (0..=cut)
                .rev()
                .find(|&c| text.is_char_boundary(c))
                .unwrap_or(0);
            return text[..cut].to_string();
        }
    }
    out.join("\n")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// A mutated scene either runs or is refused with a scene or value error; never a panic.
    #[test]
    fn a_mutated_scene_runs_or_is_refused_by_name(
        at in 0usize..100, pick in 0usize..10_000, kind in 0u8..4
    ) {
        let text = mutated((at, pick, kind));
        match run_briefly(&text) {
            Ok(_) => {}
            Err(VerifyError::Scene { .. } | VerifyError::BadValue { .. } | VerifyError::Solver(_)) => {}
            Err(other) => prop_assert!(false, "unexpected error kind: {other}"),
        }
    }
}

#[test]
fn bodies_in_contact_may_not_jump_in_spacing_by_more_than_two() {
    let text = VALID.replace("spacing = 0.25", "spacing = 0.3");
    let Err(VerifyError::Scene { key, message, .. }) = run_briefly(&text) else {
        panic!("a spacing jump of 2.4 accepted")
    };
    assert_eq!(key, "body.spacing");
    assert!(
        message.contains("'soil'") && message.contains("touch"),
        "{message}"
    );
}

/// The valid scene without its charge, with gravity.
fn ground_at_rest() -> String {
    let charge = VALID
        .find("[[body]]\nname = \"charge\"")
        .expect("the charge");
    let gauges = VALID.find("[[gauge]]").expect("the gauges");
    let mut text = VALID[..charge].to_string() + &VALID[gauges..];
    text = text.replace("end_time = 1e-4", "end_time = 0.05");
    text.replace(
        "[[material]]\nname = \"sand\"",
        "[gravity]\nacceleration = 9.81\nsurface = 0.0\n\n[[material]]\nname = \"sand\"",
    )
}

/// Ground under gravity, a lined tunnel in it and no charge, started in its geostatic state
/// and held there, stays at rest over the study's 0.05 s (displacements below 1e-6 m, with
/// global and with individual time steps), and
/// the external accelerations that hold it are gravity inside the bodies: within 5 % of g.
/// The gradient of a linear stress on this lattice at h = 1.3 Δ is off by about 1 % (measured
/// 1.0 %: the discrete kernel moment); the wrong density in the overburden, or K0 where σ_v
/// belongs, would be off by tens of per cent.
#[test]
fn ground_in_its_geostatic_state_stays_at_rest_held_by_gravity() {
    // global and individual steps, run side by side (a small scene leaves a core idle)
    let run_held = |text: &str, folder: &str| {
        let mut scene = Scene::parse(text).expect("the scene is valid");
        scene.output_interval = None;
        let out = std::env::temp_dir().join(format!("{folder}-{}", std::process::id()));
        let summary = run(&scene, &out, &mut |_| {}).expect("the scene runs");
        let _ = std::fs::remove_dir_all(&out);
        (scene, summary)
    };
    // the same with individual time steps: the lining's and the soil's steps then differ,
    // and each particle's external acceleration still holds it
    let individual = ground_at_rest().replace(
        "[gravity]",
        "[numerics]\ntime_steps = \"individual\"\n\n[gravity]",
    );
    let ((_, summary), (scene, held)) = rayon::join(
        || run_held(&ground_at_rest(), "blastsph-geostatic"),
        || run_held(&individual, "blastsph-geostatic-individual"),
    );
    assert_eq!(scene.time_steps, StepChoice::Individual);
    assert!(summary.stopped.is_none(), "{:?}", summary.stopped);
    assert_eq!(summary.time_reached_s, 0.05);
    assert!(
        summary.max_displacement_m < 1e-6,
        "{}",
        summary.max_displacement_m
    );
    assert!(held.stopped.is_none(), "{:?}", held.stopped);
    assert!(
        held.max_displacement_m < 1e-6,
        "{}",
        held.max_displacement_m
    );
    let balance = summary.gravity_balance.expect("gravity");
    assert!(balance.interior_particles > 50, "{balance:?}");
    assert!(balance.interior_max_departure < 0.05, "{balance:?}");
    // the lining's crown carries the free field's stress: σ_v = −ρ_sand g d at d ≈ 1.3 m, so
    // about (1 + 2 K0)/3 of that as pressure with K0 = ν/(1 − ν) of the concrete
    let crown = &summary.gauges[0];
    assert_eq!(crown.body, "lining");
    let sigma_v = 1674.0 * 9.81 * 1.3;
    let k0 =
        crate::problems::ground_shock::POISSON / (1.0 - crate::problems::ground_shock::POISSON);
    let expected = sigma_v * (1.0 + 2.0 * k0) / 3.0;
    assert!(
        (crown.peak_pressure_pa / expected - 1.0).abs() < 0.1,
        "crown pressure {} against {expected}",
        crown.peak_pressure_pa
    );
}

/// The times of the steps a run has taken; it stops the run (a panic, as a crash would) once
/// it has seen `stop_after` steps. The stop is not part of its state.
#[derive(Default, Serialize, Deserialize)]
struct StepTimes {
    times: Vec<f64>,
    #[serde(skip)]
    stop_after: Option<usize>,
}

impl Observer<2> for StepTimes {
    fn observe(&mut self, sim: &Simulation<2>) {
        self.times.push(sim.time());
        assert_ne!(Some(self.times.len()), self.stop_after, "stopped");
    }
}

/// Every file under `dir`, by its path there, with its bytes (`scene.json` without its wall
/// time, the one output that may differ).
fn outputs(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
                continue;
            }
            let mut bytes = std::fs::read(&path).unwrap();
            if path.ends_with("scene.json") {
                let mut summary: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                summary["wall_s"] = serde_json::Value::Null;
                bytes = summary.to_string().into_bytes();
            }
            let name = path.strip_prefix(dir).unwrap().display().to_string();
            files.insert(name, bytes);
        }
    }
    files
}

/// A run that stops after a checkpoint (a checkpoint after every step here) and is resumed
/// from it writes bitwise the outputs of a run that never stopped, and its observer ends with
/// the same state (restored from the checkpoint, then fed the remaining steps); the finished
/// run removes its checkpoint. A checkpoint of another context is refused by name.
#[test]
fn a_stopped_run_resumed_from_its_checkpoint_writes_the_same_outputs() {
    let mut scene = Scene::parse(VALID).expect("the scene is valid");
    scene.end_time = 3e-4;
    scene.output_interval = Some(1e-4);
    let dir = std::env::temp_dir().join(format!("blastsph-resume-{}", std::process::id()));
    let (straight_dir, stopped_dir) = (dir.join("straight"), dir.join("stopped"));
    let every_step = Checkpoints {
        every_s: Some(0.0),
        ..Checkpoints::default()
    };
    let run_into = |out: &Path, observer: &mut StepTimes, checkpoints: &Checkpoints| {
        run_with::<2, StepTimes>(
            &scene,
            out,
            &mut |_| {},
            &|_, _| None,
            observer,
            checkpoints,
        )
    };
    let mut straight = StepTimes::default();
    let summary = run_into(&straight_dir, &mut straight, &every_step).unwrap();
    assert!(summary.stopped.is_none(), "{:?}", summary.stopped);
    let steps = straight.times.len();
    assert!(steps > 20, "{steps} steps");

    let mut stopping = StepTimes {
        stop_after: Some(steps / 2),
        ..StepTimes::default()
    };
    let crashed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run_into(&stopped_dir, &mut stopping, &every_step)
    }));
    assert!(crashed.is_err());
    let checkpoint = stopped_dir.join(CHECKPOINT_FILE);
    assert!(checkpoint.exists() && !stopped_dir.join("scene.json").exists());

    let other_context = Checkpoints {
        resume: true,
        context: "another free field".into(),
        ..every_step.clone()
    };
    let refused = run_into(&stopped_dir, &mut StepTimes::default(), &other_context);
    assert!(
        matches!(&refused, Err(VerifyError::BadValue { field, .. }) if field == "checkpoint"),
        "{:?}",
        refused.map(|s| s.steps)
    );

    let resume = Checkpoints {
        resume: true,
        ..every_step
    };
    let mut resumed = StepTimes::default();
    let summary = run_into(&stopped_dir, &mut resumed, &resume).unwrap();
    assert_eq!(summary.steps as usize, steps);
    assert!(!checkpoint.exists());
    let same_times = resumed.times.len() == steps
        && resumed
            .times
            .iter()
            .zip(&straight.times)
            .all(|(a, b)| a.to_bits() == b.to_bits());
    let (a, b) = (outputs(&straight_dir), outputs(&stopped_dir));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(same_times, "the observer's state was not restored");
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, bytes) in &a {
        assert!(*bytes == b[name], "{name} differs");
    }
}

/// A small surface burst: 1 kg of TNT on the dry sand, gauges in the top layer of the soil
/// and above the ground, both 2 m from the axis.
fn small_surface_burst(air_blast: bool) -> String {
    let gauges = [
        ("top".to_string(), [2.0, -0.05]),
        ("air".to_string(), [2.0, 0.0]),
    ];
    crate::surface_burst::SurfaceBurst {
        charge_kg: 1.0,
        soil: &crate::surface_burst::Soil::default(),
        across_charge: 2,
        radius_m: 3.0,
        depth_m: 2.0,
        far_spacing_m: 0.25,
        gauges: if air_blast { &gauges } else { &gauges[..1] },
        end_time_s: 6e-3,
        air_blast,
    }
    .text()
}

/// An air blast loads the ground of an axisymmetric scene with gravity only, and its charge
/// and shells are refused outside their ranges by name.
#[test]
fn an_air_blast_needs_an_axisymmetric_ground_and_numbers_in_range() {
    let (_, key, message) = error_of(&format!("{VALID}\n[air_blast]\ncharge = 1.0\n"));
    assert_eq!(key, "air_blast");
    assert!(message.contains("axisymmetric"), "{message}");
    let text = small_surface_burst(true);
    let scene = Scene::parse(&text).expect("the surface burst reads");
    assert_eq!(
        scene.air_blast,
        Some(AirBlast {
            charge_kg: 1.0,
            shells: AIR_BLAST_SHELLS
        })
    );
    let section = "[air_blast]\ncharge = 1\n";
    assert!(text.contains(section));
    for (bad, key) in [
        ("[air_blast]\ncharge = -1\n", "air_blast.charge"),
        ("[air_blast]\ncharge = 1\nshells = 2\n", "air_blast.shells"),
    ] {
        let (_, found, message) = error_of(&text.replace(section, bad));
        assert_eq!(found, key);
        assert!(message.contains('≤'), "{message}");
    }
}

/// The air blast of 1 kg reaches the gauges 2 m out (Z = 2 m/kg^(1/3)) after about 2.4 ms
/// (Kingery–Bulmash hemispherical), beyond the fireball: the gauge above the ground reads
/// Kingery–Bulmash's peak overpressure within 30 % (the band of `ground-shock-surface`), and
/// the top layer of soil below it, which without the air blast the ground wave alone moves,
/// is pressed down far harder (the peak speed at least doubles; measured 7.6 times).
#[test]
fn an_air_blast_presses_on_the_top_layer_beyond_the_fireball() {
    let run_scene = |text: &str| {
        let scene = Scene::parse(text).expect("the scene reads");
        static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let k = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let out = std::env::temp_dir().join(format!("blastsph-air-{}-{k}", std::process::id()));
        let summary = crate::on_one_thread(|| run(&scene, &out, &mut |_| {}));
        let _ = std::fs::remove_dir_all(&out);
        summary.expect("the scene runs")
    };
    let with_air = run_scene(&small_surface_burst(true));
    let without = run_scene(&small_surface_burst(false));
    assert!(with_air.stopped.is_none() && without.stopped.is_none());
    let air = &with_air.air_gauges[0];
    let kb = crate::scaled::air_blast::air_blast(
        crate::scaled::air_blast::Burst::Hemispherical,
        1.0,
        2.0,
    )
    .unwrap();
    let ratio = air.peak_pressure_pa / kb.incident_overpressure_pa;
    assert!((ratio - 1.0).abs() < 0.3, "peak/KB {ratio}");
    let (loaded, alone) = (
        with_air.gauges[0].peak_velocity_m_s,
        without.gauges[0].peak_velocity_m_s,
    );
    assert!(loaded > 2.0 * alone, "{loaded} against {alone}");
}
