//! The command line: outputs, exit codes and bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;

/// Runs the binary with `args` on one worker thread (the harness runs one test per core; see
/// `common::on_one_thread`), unless `args` name a thread count.
fn blastsph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .env("RAYON_NUM_THREADS", "1")
        .args(args)
        .output()
        .expect("binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Runs `verify` with `args` into `dir`; the run must end with 0 (pass) or 1 (a check failed),
/// not with a crash or bad input.
fn verify_into(dir: &Path, args: &[&str]) {
    let mut all = vec!["verify"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", dir.to_str().unwrap()]);
    let out = blastsph(&all);
    assert!(
        out.status.code().is_some_and(|c| c == 0 || c == 1),
        "{}",
        stderr(&out)
    );
}

/// A fresh empty folder under the target directory (no temp-dir crate needed).
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn verify_writes_json_csv_and_svg_with_the_promised_fields() {
    let dir = scratch("verify-kernel");
    let out = blastsph(&[
        "verify",
        "kernel-interpolation",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("kernel-interpolation") && stdout.contains("PASS"));
    // the record carries its outcome, PASS, QUALIFIED or FAIL
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("kernel-interpolation.json")).unwrap())
            .unwrap();
    for field in [
        "problem",
        "level",
        "runs",
        "order",
        "checks",
        "outcome",
        "parameters",
        "wall_s",
    ] {
        assert!(json.get(field).is_some(), "missing {field}");
    }
    assert_eq!(json["outcome"], "PASS");
    let run = &json["runs"][0];
    for field in ["n_particles", "steps", "wall_s", "errors"] {
        assert!(run.get(field).is_some(), "run misses {field}");
    }
    for check in json["checks"].as_array().unwrap() {
        for field in ["name", "value", "limit", "pass"] {
            assert!(check.get(field).is_some(), "check misses {field}");
        }
    }
    let csv = std::fs::read_to_string(dir.join("kernel-interpolation.csv")).unwrap();
    assert_eq!(csv.lines().count(), 21, "header and 20 evaluation points");
    let svg = std::fs::read_to_string(dir.join("kernel-interpolation.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    // nothing half-written is left behind
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty());
}

/// Every verify run also writes the work–precision table and plot of the problems it ran.
#[test]
fn verify_writes_the_work_precision_table() {
    let dir = scratch("verify-work-precision");
    verify_into(&dir, &["toro-1", "--set", "n_left=50,100"]);
    let csv = std::fs::read_to_string(dir.join("work-precision.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("problem,formulation,run,n_particles,steps,wall_s,error_name,error")
    );
    assert_eq!(
        lines.filter(|l| l.starts_with("toro-1,")).count(),
        2,
        "one row per resolution"
    );
    let svg = std::fs::read_to_string(dir.join("work-precision.svg")).unwrap();
    common::assert_renders(&svg, "work-precision.svg");
}

/// Every verify run writes `index.html`: one page with the summary table, the work–precision
/// figure and each problem's checks and figure inline, and nothing fetched from a network.
#[test]
fn verify_writes_a_self_contained_index_page() {
    let dir = scratch("verify-index");
    verify_into(&dir, &["kernel-interpolation", "thesis-arrivals"]);
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    for name in ["kernel-interpolation", "thesis-arrivals"] {
        assert!(html.contains(&format!("<h2 id=\"{name}\">")), "{name}");
        assert!(html.contains(&format!("<a href=\"#{name}\">")), "{name}");
    }
    // two problem figures and the work–precision figure, inline
    assert_eq!(html.matches("<svg").count(), 3);
    // the only URLs are the SVG namespace declarations
    assert_eq!(
        html.matches("http").count(),
        html.matches("xmlns=\"http://www.w3.org/2000/svg\"").count()
    );
}

#[test]
fn set_overrides_are_recorded() {
    let dir = scratch("verify-set");
    verify_into(
        &dir,
        &["toro-1", "--set", "n_left=60", "--set", "t_end=0.1"],
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("toro-1.json")).unwrap()).unwrap();
    assert_eq!(json["overrides"]["n_left"], "60");
    assert_eq!(json["parameters"]["t_end"], "0.1");
    assert_eq!(json["runs"].as_array().unwrap().len(), 1);
}

#[test]
fn unknown_problem_is_exit_2_and_lists_the_problems() {
    let dir = scratch("verify-unknown");
    let out = blastsph(&["verify", "sedov-9d", "--out", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("sedov-9d") && err.contains("sod") && err.contains("kernel-interpolation"),
        "{err}"
    );
    assert!(!dir.exists(), "nothing is written for bad input");
}

#[test]
fn unknown_parameter_is_exit_2_and_lists_the_keys() {
    let out = blastsph(&["verify", "sod", "--set", "n_rigth=10"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("n_rigth") && err.contains("n_left") && err.contains("t_end"),
        "{err}"
    );
}

#[test]
fn non_physical_parameters_are_exit_2_with_the_range() {
    for (set, field) in [
        ("gamma=1.0", "gamma"),
        ("cfl=3", "cfl"),
        ("n_left=-5", "n_left"),
        ("t_end=abc", "t_end"),
        ("density=magic", "density"),
        ("left=1,0", "left"),
        ("right=1,0,-0.1", "right"),
    ] {
        let out = blastsph(&["verify", "sod", "--set", set]);
        assert_eq!(out.status.code(), Some(2), "{set}");
        let err = stderr(&out);
        assert!(
            err.contains(field) && err.contains("allowed"),
            "{set}: {err}"
        );
    }
}

/// A run that could not save its outputs, or would not fit in memory, is refused before it
/// starts (nothing printed on stdout, not even the table header).
#[test]
fn unwritable_output_and_oversized_runs_are_refused_before_running() {
    let out = blastsph(&["verify", "sod", "--out", "/proc/forbidden"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("/proc/forbidden"), "{}", stderr(&out));
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );

    let dir = std::env::temp_dir().join(format!("blastsph-cli-large-{}", std::process::id()));
    let out = blastsph(&[
        "verify",
        "sedov-3d",
        "--set",
        "n=1500",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("n = 1500") && err.contains("GiB") && err.contains("largest n that fits"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn riemann_prints_the_sod_star_state_as_json() {
    let out = blastsph(&[
        "riemann",
        "--left",
        "1,0,1",
        "--right",
        "0.125,0,0.1",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // Toro (2009) Table 4.2: p* = 0.30313, u* = 0.92745
    assert!((json["p_star"].as_f64().unwrap() - 0.30313).abs() < 1e-5);
    assert!((json["u_star"].as_f64().unwrap() - 0.92745).abs() < 1e-5);
    assert!(json["rho_star_l"].is_number() && json["rho_star_r"].is_number());
    assert_eq!(json["waves"], "left rarefaction, contact, right shock");
}

#[test]
fn riemann_rejects_non_physical_states_by_name() {
    for (left, right, gamma, field) in [
        ("0,0,1", "-1,0,1", "1.4", "right density"),
        ("1,0,-1", "1,0,1", "1.4", "left pressure"),
        ("1,0,1", "1,0,1", "1", "gamma"),
        ("1,0", "1,0,1", "1.4", "--left"),
    ] {
        let out = blastsph(&[
            "riemann", "--left", left, "--right", right, "--gamma", gamma,
        ]);
        assert_eq!(out.status.code(), Some(2), "{left} {right} {gamma}");
        assert!(stderr(&out).contains(field), "{}", stderr(&out));
    }
}

#[test]
fn sedov_prints_the_classic_spherical_constant() {
    let out = blastsph(&[
        "sedov",
        "--geometry",
        "spherical",
        "--gamma",
        "1.4",
        "--energy",
        "1",
        "--rho0",
        "1",
        "--time",
        "1",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for field in ["xi0", "r_shock", "rho2", "u2", "p2"] {
        assert!(json[field].is_number(), "missing {field}");
    }
    // Sedov (1959) and Taylor (1950): ξ0 = 1.033 for γ = 1.4, printed to three decimals
    assert!((json["xi0"].as_f64().unwrap() - 1.033).abs() < 5e-4);
    // strong-shock jump: ρ2 = (γ + 1)/(γ − 1) ρ0
    assert!((json["rho2"].as_f64().unwrap() - 6.0).abs() < 1e-12);
}

#[test]
fn sedov_rejects_bad_input_by_name() {
    for (args, field) in [
        (vec!["sedov", "--geometry", "conical"], "--geometry"),
        (vec!["sedov", "--energy", "-1"], "energy"),
        (vec!["sedov", "--gamma", "1"], "gamma"),
    ] {
        let out = blastsph(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(field), "{}", stderr(&out));
    }
}

#[test]
fn materials_lists_the_library_with_sources() {
    let out = blastsph(&["materials", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let materials = json["materials"].as_object().unwrap();
    // the CLI shows the whole library (which names it must hold is the library's own test)
    let library = blastsph_verification::materials::Library::standard();
    assert_eq!(materials.len(), library.materials.len());
    for name in library.names() {
        let m = &materials[name];
        assert!(m["model"].is_string(), "{name}");
        for (key, p) in m["parameters"].as_object().unwrap() {
            assert!(
                p["value"].is_number() && p["source"].is_string() && p["status"].is_string(),
                "{name}.{key}"
            );
        }
    }
}

#[test]
fn impedance_prints_the_interface_state_as_json() {
    // symmetric impact Cu onto Cu at 1000 m/s: up = 500 m/s exactly,
    // p = ρ0 (C0 + S up) up = 8930 (3940 + 1.489·500) 500 Pa (Steinberg's Cu Hugoniot)
    let out = blastsph(&[
        "impedance",
        "--a",
        "cu-ofhc",
        "--b",
        "cu-ofhc",
        "--impact",
        "1000",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!((json["up"].as_f64().unwrap() - 500.0).abs() < 1e-6);
    let p = 8930.0 * (3940.0 + 1.489 * 500.0) * 500.0;
    assert!((json["p"].as_f64().unwrap() / p - 1.0).abs() < 1e-9);
    assert!((json["us_b"].as_f64().unwrap() - (3940.0 + 1.489 * 500.0)).abs() < 1e-6);
    assert_eq!(json["reflected"], "shock");
    // a shock from copper into aluminium (lower impedance) reflects a rarefaction
    let out = blastsph(&[
        "impedance",
        "--a",
        "cu-ofhc",
        "--b",
        "al-6061",
        "--pressure",
        "2e10",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["reflected"], "rarefaction");
    assert!(json["p"].as_f64().unwrap() < 2e10);
}

#[test]
fn impedance_rejects_bad_input_by_name() {
    let out = blastsph(&[
        "impedance",
        "--a",
        "kryptonite",
        "--b",
        "cu-ofhc",
        "--impact",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("kryptonite") && stderr(&out).contains("al-6061"));
    let out = blastsph(&[
        "impedance",
        "--a",
        "cu-ofhc",
        "--b",
        "al-6061",
        "--impact",
        "-5",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--impact"), "{}", stderr(&out));
    let out = blastsph(&["impedance", "--a", "cu-ofhc", "--b", "al-6061"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--impact") || stderr(&out).contains("--pressure"));
}

/// `--vtk` writes the final particles as a VTK unstructured grid that an independent reader
/// (the vtkio crate) parses: one point per particle, the promised point arrays with one value
/// (or vector) per point, and for a solid the stress, status and temperature-rise fields.
#[test]
fn verify_vtk_writes_a_readable_unstructured_grid() {
    use vtkio::model::{Attribute, DataSet, VertexNumbers};
    let dir = scratch("verify-vtk");
    verify_into(&dir, &["elastic-wave", "--set", "n=100", "--vtk"]);
    let vtk = vtkio::Vtk::import(dir.join("elastic-wave.vtu")).expect("vtkio reads the file");
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("elastic-wave.json")).unwrap()).unwrap();
    // the snapshot is the finest 2D run's particles
    let particles = record["runs"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["formulation"] == "2D")
        .map(|r| r["n_particles"].as_u64().unwrap())
        .max()
        .unwrap() as usize;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid");
    };
    let piece = pieces[0].load_piece_data(None).expect("inline piece data");
    assert_eq!(piece.num_points(), particles);
    match &piece.cells.cell_verts {
        VertexNumbers::XML { offsets, .. } => assert_eq!(offsets.len(), particles),
        other => panic!("unexpected cell layout {other:?}"),
    }
    let names: Vec<String> = piece
        .data
        .point
        .iter()
        .map(|a| match a {
            Attribute::DataArray(d) => {
                let components = d.elem.num_comp() as usize;
                assert_eq!(d.data.len(), particles * components, "{}", d.name);
                d.name.clone()
            }
            Attribute::Field { name, .. } => name.clone(),
        })
        .collect();
    for expected in [
        "density",
        "pressure",
        "velocity",
        "von_mises",
        "plastic_strain",
        "status",
        "temperature_rise",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} missing: {names:?}"
        );
    }
}

/// `soil bridge --json` prints the force and the rupture gap in SI: Willett's simple law at
/// contact is exactly 2πγR cos θ; beyond the rupture gap the force is zero; a bad radius or
/// law is refused with exit code 2, naming the flag.
#[test]
fn soil_bridge_prints_force_and_rupture_gap() {
    let out = blastsph(&[
        "soil", "bridge", "--radius", "1e-4", "--volume", "1e-14", "--gap", "0", "--law", "simple",
        "--theta", "20", "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let expected = 2.0 * std::f64::consts::PI * 0.0728 * 1e-4 * 20f64.to_radians().cos();
    assert!((value["force_n"].as_f64().unwrap() / expected - 1.0).abs() < 1e-12);
    let rupture = value["rupture_gap_m"].as_f64().unwrap();
    assert!((rupture / ((1.0 + 0.5 * 20f64.to_radians()) * 1e-14f64.cbrt()) - 1.0).abs() < 1e-12);
    let beyond = format!("{}", 1.01 * rupture);
    let out = blastsph(&[
        "soil",
        "bridge",
        "--radius",
        "1e-4,2e-4",
        "--volume",
        "1e-14",
        "--gap",
        &beyond,
        "--theta",
        "20",
        "--json",
    ]);
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(value["force_n"].as_f64(), Some(0.0));
    for (flag, args) in [
        ("--radius", &["--radius", "-1", "--law", "willett"][..]),
        ("--law", &["--radius", "1e-4", "--law", "hooke"]),
        // V* = 0.01 at θ = 80°: more than a concave toroidal meridian holds (1.4e-3 R³)
        (
            "bridge volume",
            &["--radius", "1e-4", "--law", "toroidal", "--theta", "80"],
        ),
    ] {
        let mut all = vec!["soil", "bridge", "--volume", "1e-14", "--gap", "0"];
        all.extend(args);
        let out = blastsph(&all);
        assert_eq!(out.status.code(), Some(2));
        assert!(stderr(&out).contains(flag), "{}", stderr(&out));
    }
}

/// `soil biaxial` on a tiny sample writes the record, the curves and soil-strength.json, and
/// prints the same JSON: one entry per saturation whose cohesion_pa and friction_angle_degrees
/// the SPH soil model (Strength::drucker_prager) accepts as its c and φ. A bad saturation is
/// refused with exit code 2, naming the parameter.
#[test]
fn soil_biaxial_writes_strength_the_sph_soil_model_accepts() {
    let dir = std::env::temp_dir().join(format!("blastsph-soil-biaxial-{}", std::process::id()));
    let out = blastsph(&[
        "soil",
        "biaxial",
        "--grains",
        "60",
        "--saturation",
        "0,10",
        // the platens run in proportion to σ3: 1 and 2 kPa load in about two thirds of the time
        // that 0.5 and 1 kPa take
        "--confining",
        "1000,2000",
        "--axial-strain",
        "0.02",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("soil-strength.json")).unwrap()).unwrap();
    assert_eq!(printed, written);
    for file in ["biaxial.json", "biaxial.csv", "biaxial.svg"] {
        assert!(dir.join(file).exists(), "{file}");
    }
    let entries = printed["saturations"].as_array().unwrap();
    assert_eq!(entries.len(), 2);
    // this seed's 60-grain samples admit an envelope at both saturations (a fit of a small
    // sample can put the dry c below zero, which the soil model reads as cohesionless)
    for entry in entries {
        let c = entry["cohesion_pa"].as_f64().expect("a fitted cohesion");
        let phi = entry["friction_angle_degrees"]
            .as_f64()
            .expect("a fitted friction angle");
        assert!(c.is_finite() && (0.0..60.0).contains(&phi), "{entry}");
        blastsph_solver::Strength::drucker_prager(1e7, c.max(0.0), phi, 0.0).unwrap();
    }
    let out = blastsph(&[
        "soil",
        "biaxial",
        "--saturation",
        "50",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("saturation"), "{}", stderr(&out));
    std::fs::remove_dir_all(&dir).ok();
}

/// The JSON answers of the calculators, to three significant digits, against their reviewed
/// snapshots: a changed number shows as a diff to review. Their correctness is checked above
/// and in the library's tests; the snapshots verify nothing.
#[test]
fn calculator_json_matches_the_reviewed_snapshots() {
    let cases: [(&str, &[&str]); 6] = [
        (
            "riemann_sod",
            &[
                "riemann",
                "--left",
                "1,0,1",
                "--right",
                "0.125,0,0.1",
                "--json",
            ],
        ),
        (
            "sedov_spherical",
            &[
                "sedov",
                "--geometry",
                "spherical",
                "--gamma",
                "1.4",
                "--energy",
                "0.851072",
                "--rho0",
                "1",
                "--time",
                "1",
                "--json",
            ],
        ),
        (
            "impedance_al_onto_cu",
            &[
                "impedance",
                "--a",
                "al-6061",
                "--b",
                "cu-ofhc",
                "--impact",
                "1000",
                "--json",
            ],
        ),
        (
            "impedance_tnt_into_concrete",
            &[
                "impedance",
                "--a",
                "tnt",
                "--b",
                "concrete",
                "--pressure",
                "2e10",
                "--json",
            ],
        ),
        ("materials", &["materials", "--json"]),
        (
            "soil_bridge",
            &[
                "soil", "bridge", "--radius", "1e-4", "--volume", "1e-13", "--gap", "1e-6",
                "--json",
            ],
        ),
    ];
    for (name, args) in cases {
        let out = blastsph(args);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        insta::assert_json_snapshot!(name, common::reviewable(json, &[]));
    }
}

/// `scaled` on the MSB worked example (125 kg C-4 buried at 4 m, 5 m away in dry sand and
/// backfill: u0 3.84 m/s, P0 1907 kPa, I0 31.0 kPa·s, t_a 16.4 ms) and the JSON fields of a
/// surface burst.
#[test]
fn scaled_prints_air_blast_and_ground_shock_as_json() {
    let out = blastsph(&[
        "scaled",
        "--charge",
        "125",
        "--range",
        "5",
        "--burst",
        "buried",
        "--depth-of-burst",
        "4",
        "--explosive",
        "c4",
        "--soil",
        "dry-sand-backfill",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let shock = &json["ground_shock"];
    assert!((shock["peak_velocity_m_s"].as_f64().unwrap() - 3.84).abs() <= 0.005);
    assert!((shock["peak_stress_pa"].as_f64().unwrap() - 1907e3).abs() <= 0.5e3);
    assert!((shock["impulse_pa_s"].as_f64().unwrap() - 31.0e3).abs() <= 0.05e3);
    assert!((shock["arrival_s"].as_f64().unwrap() - 16.4e-3).abs() <= 0.05e-3);
    assert_eq!(shock["coupling_factor"].as_f64(), Some(1.0));
    assert!(json["incident_overpressure_pa"].is_null());
    let out = blastsph(&["scaled", "--charge", "500", "--range", "20", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for field in [
        "z",
        "incident_overpressure_pa",
        "reflected_overpressure_pa",
        "arrival_s",
        "duration_s",
        "incident_impulse_pa_s",
        "reflected_impulse_pa_s",
    ] {
        assert!(json[field].as_f64().is_some_and(|v| v > 0.0), "{field}");
    }
}

/// Bad input exits 2 naming the value and its allowed range.
#[test]
fn scaled_refuses_bad_input_by_name() {
    for (args, named) in [
        (vec!["--charge", "-5", "--range", "20"], "charge mass"),
        (vec!["--charge", "5", "--range", "2000"], "0.0674 ≤ Z ≤ 40"),
        (
            vec!["--charge", "5", "--range", "20", "--soil", "peat"],
            "dense-sand",
        ),
        (
            vec!["--charge", "5", "--range", "20", "--explosive", "semtex"],
            "tnt, c4",
        ),
        (
            vec!["--charge", "5", "--range", "20", "--burst", "underwater"],
            "buried",
        ),
        (
            vec!["--charge", "5", "--range", "20", "--burst", "buried"],
            "depth of burst",
        ),
    ] {
        let out = blastsph(&[&["scaled"], args.as_slice()].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(named), "{args:?}: {}", stderr(&out));
    }
}

/// `gate` refuses bad input before running anything: exit 2 naming the value and what is
/// allowed.
#[test]
fn gate_refuses_bad_input_by_name() {
    for (args, named) in [
        (
            vec!["--charge", "-5", "--soil", "dry-sand-backfill"],
            "charge",
        ),
        (vec!["--charge", "500", "--soil", "peat"], "dense-sand"),
        (
            vec!["--charge", "500", "--soil", "saturated-clay"],
            "material model: dry-sand-backfill",
        ),
        (
            vec![
                "--charge",
                "500",
                "--soil",
                "dry-sand-backfill",
                "--depths",
                "0.5",
            ],
            "depths (m) = 0.5",
        ),
    ] {
        let out = blastsph(&[&["gate", "--out", "/nonexistent/never"], args.as_slice()].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(named), "{args:?}: {}", stderr(&out));
    }
}

/// `check-arrivals` on the thesis table: every entry impossible, exit 1; a physically possible
/// table passes with exit 0; a missing file exits 2 naming it.
#[test]
fn check_arrivals_flags_the_thesis_table() {
    let thesis = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/reference_data/thesis_arrivals.csv"
    );
    let out = blastsph(&["check-arrivals", thesis, "--json"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let entries = json["entries"].as_array().unwrap();
    assert_eq!(entries.len(), 18);
    for entry in entries {
        assert_eq!(entry["possible"], false);
        for field in [
            "depth_m",
            "charge_kg",
            "arrival_s",
            "implied_speed_m_s",
            "min_possible_arrival_s",
        ] {
            assert!(entry[field].is_number(), "{field}");
        }
    }
    let dir = scratch("arrivals");
    std::fs::create_dir_all(&dir).unwrap();
    let possible = dir.join("possible.csv");
    // 10 m at 305 m/s (the relations' dry-sand speed): 32.8 ms
    std::fs::write(
        &possible,
        "depth_m,charge_kg,gauge,arrival_ms\n10,500,crown,32.8\n",
    )
    .unwrap();
    let out = blastsph(&["check-arrivals", possible.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = blastsph(&["check-arrivals", "/no/such/arrivals.csv"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("arrivals file"), "{}", stderr(&out));
}

/// The render check itself: a text element placed off its canvas is caught (where the machine
/// has fonts to lay it out), and an SVG that does not parse is refused.
#[test]
fn the_render_check_catches_text_off_the_canvas_and_broken_svg() {
    let on_canvas = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100"><rect width="100%" height="100%" fill="white"/><line x1="0" y1="50" x2="200" y2="50" stroke="black"/><text x="10" y="60" font-family="sans-serif" font-size="12">fits</text></svg>"#;
    common::assert_renders(on_canvas, "on canvas");
    let off_canvas = on_canvas.replace(r#"x="10" y="60""#, r#"x="190" y="60""#);
    let fonts_present = {
        let mut db = resvg::usvg::fontdb::Database::new();
        db.load_system_fonts();
        !db.is_empty()
    };
    let caught = std::panic::catch_unwind(|| common::assert_renders(&off_canvas, "off canvas"));
    assert_eq!(caught.is_err(), fonts_present);
    let broken = std::panic::catch_unwind(|| common::assert_renders("<svg", "broken"));
    assert!(broken.is_err());
}

/// The shipped Taylor-bar scene, run through `blastsph run`, is the benchmark bar: its final
/// length and footprint agree with the benchmark within the limits of the
/// `taylor-bar-axisymmetric` problem's quick level (4 % and 8 %, a handful of rings across
/// the radius); every output is there and the .pvd lists the snapshots written.
#[test]
fn the_shipped_taylor_bar_scene_reaches_the_benchmark_shape() {
    use vtkio::model::{DataSet, IOBuffer};
    let dir = scratch("scene-taylor-bar");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/taylor-bar.toml");
    let out = blastsph(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("scene.json")).unwrap()).unwrap();
    assert!(summary["stopped"].is_null());
    // the energy balance of the axisymmetric Taylor bar problem holds at ten times its measure
    assert!(summary["energy_relative_change"].as_f64().unwrap() < 5e-4);
    for gauge in ["impact-face", "rear-end"] {
        let csv = std::fs::read_to_string(dir.join("gauges").join(format!("{gauge}.csv"))).unwrap();
        assert!(csv.starts_with("time_s,pressure_pa,velocity_x_m_s"));
        assert_eq!(
            csv.lines().count() as u64,
            summary["steps"].as_u64().unwrap() + 2
        );
    }
    let pvd = std::fs::read_to_string(dir.join("snapshots.pvd")).unwrap();
    let listed: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    assert_eq!(
        listed.len(),
        9,
        "snapshots every 10 µs over 80 µs, the start included"
    );
    assert!(listed.iter().all(|f| dir.join(f).exists()));

    let vtk = vtkio::Vtk::import(dir.join(listed[8])).expect("vtkio reads the last snapshot");
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid");
    };
    let piece = pieces[0].load_piece_data(None).expect("inline piece data");
    let IOBuffer::F64(points) = piece.points else {
        panic!("f64 points")
    };
    let spacing = 0.4e-3;
    let (r, z): (Vec<f64>, Vec<f64>) = points.chunks(3).map(|p| (p[0], p[1])).unzip();
    // measured as the problem measures: the highest particle and the bottom layer's widest,
    // each plus half a spacing
    let length = z.iter().fold(0.0_f64, |a, &b| a.max(b)) + 0.5 * spacing;
    let footprint = r
        .iter()
        .zip(&z)
        .filter(|(_, &z)| z < spacing)
        .fold(0.0_f64, |a, (&r, _)| a.max(r))
        + 0.5 * spacing;
    assert!(
        (length / 21.42e-3 - 1.0).abs() < 0.04,
        "final length {length}"
    );
    assert!(
        (footprint / 7.12e-3 - 1.0).abs() < 0.08,
        "footprint radius {footprint}"
    );
}

/// A broken scene exits 2 naming its line and writes nothing; so does an unwritable output
/// folder.
#[test]
fn a_broken_scene_exits_2_by_name_and_writes_nothing() {
    let dir = scratch("scene-broken");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/taylor-bar.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, text.replace("cu-taylor-bar", "unobtainium")).unwrap();
    let out_dir = dir.join("out");
    let out = blastsph(&[
        "run",
        broken.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let message = stderr(&out);
    assert!(
        message.contains("line 19") && message.contains("unknown material 'unobtainium'"),
        "{message}"
    );
    assert!(!out_dir.exists());
    let out = blastsph(&["run", scene.to_str().unwrap(), "--out", "/proc/forbidden"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("/proc/forbidden"));
}

/// The tunnel study refuses depths, charges, soils and cases its full level cannot grade (a
/// 1 kg charge's fine soil next to the far soil), by name, before anything runs or is
/// written.
#[test]
fn the_tunnel_study_refuses_bad_requests_by_name() {
    let dir = scratch("tunnel-bad");
    for (args, named) in [
        (vec!["--depths", "0.5"], "--depths"),
        (vec!["--charges", "500,-3"], "--charges"),
        (vec!["--soil", "peat"], "soil"),
        (vec!["--level", "full", "--charges", "1"], "--level full"),
        (vec!["--lining", "0"], "--lining"),
    ] {
        let mut all = vec!["tunnel", "--out", dir.to_str().unwrap()];
        all.extend(args.iter().copied());
        let out = blastsph(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(named), "{args:?}: {}", stderr(&out));
        assert!(!dir.exists(), "{args:?} wrote its folder");
    }
}

/// A scene run killed after it kept a checkpoint and resumed with `--restart` (on one thread,
/// the killed run had two) writes bitwise the outputs of a run that was never stopped (the
/// summary's wall time aside) and removes its checkpoint; `--restart` on a folder without a
/// checkpoint exits 2 naming the option.
#[test]
fn a_killed_run_resumed_with_restart_writes_the_uninterrupted_outputs() {
    let dir = scratch("scene-restart");
    std::fs::create_dir_all(&dir).unwrap();
    // the shipped Taylor bar's first 20 µs, a snapshot every 5 µs
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/taylor-bar.toml");
    let text = std::fs::read_to_string(shipped)
        .unwrap()
        .replace("end_time = 80e-6", "end_time = 20e-6")
        .replace("output_interval = 10e-6", "output_interval = 5e-6");
    assert!(text.contains("end_time = 20e-6") && text.contains("output_interval = 5e-6"));
    let scene = dir.join("bar.toml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_str().unwrap();
    let (straight, stopped) = (dir.join("straight"), dir.join("stopped"));
    let out = blastsph(&["run", scene, "--out", straight.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));

    let mut child = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["run", scene, "--out", stopped.to_str().unwrap()])
        .args(["--threads", "2", "--checkpoint-minutes", "0.001"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("binary runs");
    let checkpoint = stopped.join("checkpoint.bin");
    let started = std::time::Instant::now();
    while !checkpoint.exists() {
        assert!(started.elapsed().as_secs() < 120, "no checkpoint written");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        !stopped.join("scene.json").exists(),
        "the run finished before it was killed"
    );
    let out = blastsph(&[
        "run",
        scene,
        "--restart",
        stopped.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(!checkpoint.exists());
    let files = |root: &Path| {
        let mut found = std::collections::BTreeMap::new();
        let mut pending = vec![root.to_path_buf()];
        while let Some(folder) = pending.pop() {
            for entry in std::fs::read_dir(folder).unwrap() {
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
                let name = path.strip_prefix(root).unwrap().display().to_string();
                found.insert(name, bytes);
            }
        }
        found
    };
    let (a, b) = (files(&straight), files(&stopped));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    assert!(a.contains_key("snapshots/4.vtu"), "{:?}", a.keys());
    for (name, bytes) in &a {
        assert!(*bytes == b[name], "{name} differs");
    }

    let out = blastsph(&["run", scene, "--restart", straight.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("--restart"), "{}", stderr(&out));
}
