//! `blastsph`: the command line. It parses, shows progress, prints tables and writes files; the
//! work is done by `blastsph-verification` and `blastsph-solver`.

use blastsph_verification::gate::{self, GateRequest};
use blastsph_verification::impedance::{self, Drive};
use blastsph_verification::materials::Library;
use blastsph_verification::params::parse_assignment;
use blastsph_verification::record::Outcome;
use blastsph_verification::riemann::{self, GasState};
use blastsph_verification::scene::{self, Checkpoints, Scene};
use blastsph_verification::sedov::{geometry_named, SedovBlast};
use blastsph_verification::{index, problems, report, tunnel, Level, VerifyError};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "blastsph",
    version,
    about = "SPH for blast and impact, verified on problems with known answers"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum LevelArg {
    Quick,
    Full,
}

#[derive(Subcommand)]
enum Command {
    /// Run canonical problems against their exact answers (all of them if none is named).
    /// Exit 0 PASS, 4 QUALIFIED, 1 FAIL, 2 bad input.
    Verify {
        /// Problems to run; `blastsph verify --list` shows them.
        problems: Vec<String>,
        /// quick: the levels `cargo test` runs; full: convergence studies.
        #[arg(long, value_enum, default_value = "quick")]
        level: LevelArg,
        /// Folder for <problem>.json, .csv and .svg.
        #[arg(long, default_value = "results/verify")]
        out: PathBuf,
        /// Worker threads (default: all cores). Results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Override a problem parameter, e.g. --set t_end=0.15 --set n_left=640.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// List the problems and their parameters, then exit.
        #[arg(long)]
        list: bool,
        /// Also write <problem>.vtu: the particles at the end of the finest run (position,
        /// velocity, density, pressure, energy, material; for solids von Mises stress, plastic
        /// strain, plastic work and status 0 elastic / 1 plastic / 2 failed), for ParaView.
        #[arg(long)]
        vtk: bool,
    },
    /// The tunnel study: the free-field gate for each charge, then a lined tunnel at each
    /// crown depth under each surface charge: gauges at crown and invert, peak stress against
    /// depth, the safe depth per charge. Exit 0 PASS, 4 QUALIFIED (a gate or a check at a
    /// qualified limit), 1 a study check failed, 3 a gate failed (nothing else is run unless
    /// --accept-unvalidated, which stamps NOT VALIDATED on every output), 2 bad input.
    Tunnel {
        /// Crown depths below the ground (m), comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "10,15,20")]
        depths: Vec<f64>,
        /// TNT charges on the ground (kg), comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "500,1000,5000")]
        charges: Vec<f64>,
        /// The TM 5-855-1 soil (the gate's; its library model is simulated).
        #[arg(long, default_value = "dry-sand-backfill")]
        soil: String,
        /// Internal diameter of the tunnel (m).
        #[arg(long, default_value_t = 6.0)]
        diameter: f64,
        /// Thickness of the concrete lining (m).
        #[arg(long, default_value_t = 0.35)]
        lining: f64,
        /// quick: the reduced model (axisymmetric free field driving plane-strain sections);
        /// full: also a 3D quarter model of every case, compared with it (about 20 minutes
        /// for 10 m under 500 kg on 2 cores), and the gate's full level.
        #[arg(long, value_enum, default_value = "quick")]
        level: LevelArg,
        #[arg(long, default_value = "results/tunnel")]
        out: PathBuf,
        /// Run the cases even where a gate failed, every output stamped NOT VALIDATED.
        #[arg(long)]
        accept_unvalidated: bool,
        /// Go on with the study in DIR (instead of --out): finished cases are kept, a run that
        /// was stopped resumes from its last checkpoint, bitwise as if never stopped.
        #[arg(long, value_name = "DIR", conflicts_with = "out")]
        restart: Option<PathBuf>,
        #[command(flatten)]
        checkpoints: CheckpointArgs,
    },
    /// Run a scene file (TOML; see `scenes/` and the README): gauge histories (CSV), per
    /// material momentum and energy, particle snapshots (VTU with a .pvd index) and
    /// scene.json, the summary written last.
    Run {
        /// The scene file.
        scene: PathBuf,
        /// Output folder (default: results/<scene file name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads (default: all cores). Results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Resume the run in DIR (instead of --out) from its last checkpoint: its outputs are
        /// bitwise those of a run that was never stopped.
        #[arg(long, value_name = "DIR", conflicts_with = "out")]
        restart: Option<PathBuf>,
        #[command(flatten)]
        checkpoints: CheckpointArgs,
    },
    /// The exact Sedov–Taylor blast: shock radius, post-shock state, similarity constant.
    Sedov {
        /// planar, cylindrical or spherical.
        #[arg(long, default_value = "spherical")]
        geometry: String,
        #[arg(long, default_value_t = 1.4, allow_negative_numbers = true)]
        gamma: f64,
        /// Blast energy E (J; per unit length in cylindrical, per unit area on one side of the
        /// plane in planar geometry).
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        energy: f64,
        /// Background density (kg/m³, or the matching per-length/area unit).
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        rho0: f64,
        /// Time after the release (s).
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        time: f64,
        #[arg(long)]
        json: bool,
    },
    /// List the material library: models, parameters, their sources and status.
    Materials {
        #[arg(long)]
        json: bool,
    },
    /// The exact state where material A meets material B: interface particle velocity and
    /// pressure, transmitted shock speed, reflected wave type (all SI).
    Impedance {
        /// Material A (the flyer, or the one the incident shock runs in); see `materials`.
        #[arg(long)]
        a: String,
        /// Material B, at rest.
        #[arg(long)]
        b: String,
        /// Velocity of A hitting B at rest (m/s).
        #[arg(
            long,
            conflicts_with = "pressure",
            required_unless_present = "pressure",
            allow_negative_numbers = true
        )]
        impact: Option<f64>,
        /// Pressure of the incident shock in A (Pa).
        #[arg(long, allow_negative_numbers = true)]
        pressure: Option<f64>,
        #[arg(long)]
        json: bool,
    },
    /// Scaled-distance relations for a charge at a range: Kingery–Bulmash air blast and, with
    /// --soil, TM 5-855-1 free-field ground shock (SI; Z = R/W^(1/3) with W in kg TNT).
    Scaled {
        /// Charge mass (kg of the explosive).
        #[arg(long, allow_negative_numbers = true)]
        charge: f64,
        /// Range from the charge (m).
        #[arg(long, allow_negative_numbers = true)]
        range: f64,
        /// surface (hemispherical on the ground), free-air or buried.
        #[arg(long, default_value = "surface")]
        burst: String,
        /// Depth of the charge's centre below the ground (m; negative above it): sets the
        /// ground-shock coupling factor. Needed for a buried charge; 0 for a surface burst.
        #[arg(long, allow_negative_numbers = true)]
        depth_of_burst: Option<f64>,
        /// tnt or c4.
        #[arg(long, default_value = "tnt")]
        explosive: String,
        /// A soil of the TM 5-855-1 table for the ground shock: loose-dry-sand,
        /// dry-sand-backfill, dense-sand, wet-sandy-clay, saturated-sandy-clay, saturated-clay.
        #[arg(long)]
        soil: Option<String>,
        #[arg(long)]
        json: bool,
    },
    /// Check a table of first-arrival times (CSV: depth_m,charge_kg,gauge,arrival_ms) against
    /// the earliest arrival physics allows, depth / c_max (c_max: the fastest wave the soil
    /// and the concrete lining carry). Exit 1 if any entry is impossible.
    CheckArrivals {
        file: PathBuf,
        /// A compaction soil of the material library.
        #[arg(long, default_value = "dry-sand")]
        soil: String,
        #[arg(long)]
        json: bool,
    },
    /// The free-field gate a study of this charge in this soil rests on: the study's free
    /// field at its resolution and the next coarser one, against the ground-shock relations
    /// at the study's depths, and converged between the two. A result is reused while the
    /// request and the program are the same (keyed by a hash of both). Exit 0 PASS,
    /// 4 QUALIFIED, 3 FAIL, 2 bad input.
    Gate {
        /// TNT mass (kg).
        #[arg(long, allow_negative_numbers = true)]
        charge: f64,
        /// A TM 5-855-1 soil with a material model: dry-sand-backfill.
        #[arg(long)]
        soil: String,
        /// The study's crown depths below the charge (m), comma-separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "10,15,20",
            allow_negative_numbers = true
        )]
        depths: Vec<f64>,
        /// The study's tunnel: internal diameter (m), which places the gauges (crowns,
        /// inverts, the sections' half-width) and sizes the free field's domain.
        #[arg(long, default_value_t = 6.0)]
        diameter: f64,
        /// The study's tunnel: lining thickness (m).
        #[arg(long, default_value_t = 0.35)]
        lining: f64,
        /// quick: 3 and 4 particles across the charge (the quick study's); full: 4 and 6.
        #[arg(long, value_enum, default_value = "quick")]
        level: LevelArg,
        /// Folder for gate-<hash>.json.
        #[arg(long, default_value = "results/gate")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Moist soil at grain scale: liquid bridges between grains.
    Soil {
        #[command(subcommand)]
        command: SoilCommand,
    },
    /// Solve a Riemann problem of the ideal gas exactly and print the star state.
    Riemann {
        /// Left state ρ,u,p (SI).
        #[arg(long, allow_hyphen_values = true)]
        left: String,
        /// Right state ρ,u,p (SI).
        #[arg(long, allow_hyphen_values = true)]
        right: String,
        #[arg(long, default_value_t = 1.4)]
        gamma: f64,
        #[arg(long)]
        json: bool,
    },
}

#[derive(Subcommand)]
enum SoilCommand {
    /// The force of one pendular liquid bridge between two spheres (SI; θ in degrees).
    Bridge(BridgeArgs),
    /// DEM biaxial tests of moist sand: Mohr–Coulomb c and φ per saturation (the `biaxial`
    /// problem at full size, one seed). Writes the record, curves (CSV, SVG) and
    /// soil-strength.json, whose cohesion_pa and friction_angle_degrees are the SPH
    /// Drucker–Prager model's c and φ.
    Biaxial {
        /// Degrees of saturation in per cent, comma-separated (0 = dry).
        #[arg(long, default_value = "0,10,15,20")]
        saturation: String,
        /// Confining stresses σ3 in Pa, comma-separated (at least two).
        #[arg(long, default_value = "500,1000,2000")]
        confining: String,
        /// Sample seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Grains per sample.
        #[arg(long, default_value_t = 1700)]
        grains: usize,
        /// Axial strain at the end of loading.
        #[arg(long, default_value_t = 0.1)]
        axial_strain: f64,
        /// Output directory.
        #[arg(long, default_value = "results/soil-biaxial")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
}

#[derive(clap::Args)]
struct BridgeArgs {
    /// Sphere radius R1, or R1,R2 for unequal spheres (m).
    #[arg(long, allow_hyphen_values = true)]
    radius: String,
    /// Liquid volume of the bridge (m³).
    #[arg(long)]
    volume: f64,
    /// Surface gap between the spheres (m); an overlap (< 0) counts as contact.
    #[arg(long, allow_negative_numbers = true)]
    gap: f64,
    /// Contact angle (degrees).
    #[arg(long, default_value_t = 0.0)]
    theta: f64,
    /// willett (fitted, the default), simple, rabinovich or toroidal.
    #[arg(long, default_value = "willett")]
    law: String,
    /// Surface tension (N/m); water at 20 °C by default.
    #[arg(long, default_value_t = 0.0728)]
    surface_tension: f64,
    /// Where the bridge breaks: lian ((1 + θ/2) V^(1/3)) or willett.
    #[arg(long, default_value = "lian")]
    rupture: String,
    #[arg(long)]
    json: bool,
}

impl From<LevelArg> for Level {
    fn from(level: LevelArg) -> Self {
        match level {
            LevelArg::Quick => Level::Quick,
            LevelArg::Full => Level::Full,
        }
    }
}

/// How often a long run keeps a checkpoint of itself.
#[derive(clap::Args, Debug)]
struct CheckpointArgs {
    /// Wall-clock minutes between two checkpoints of a run (kept in its folder as
    /// checkpoint.bin, removed when the run finishes).
    #[arg(long, value_name = "MINUTES", default_value_t = 5.0)]
    checkpoint_minutes: f64,
}

impl CheckpointArgs {
    /// The policy: checkpoints at the interval, resumed from where `resume`.
    fn policy(&self, resume: bool) -> Result<Checkpoints, VerifyError> {
        let minutes = self.checkpoint_minutes;
        if !(minutes > 0.0 && minutes.is_finite()) {
            return Err(VerifyError::bad_value(
                "--checkpoint-minutes",
                minutes,
                "finite and > 0",
            ));
        }
        Ok(Checkpoints {
            every_s: Some(60.0 * minutes),
            resume,
            context: String::new(),
        })
    }
}

/// Exit codes: 0 PASS; 4 QUALIFIED (every failed check at a qualified limit of the modelled
/// physics); 1 FAIL (a problem's or the study's own check, or a scene run that stopped);
/// 3 a gate FAIL (`gate`; `tunnel` then writes no tunnel result); 2 bad input or an error.
const EXIT_FAILED: u8 = 1;
const EXIT_BAD_INPUT: u8 = 2;
const EXIT_GATE_FAILED: u8 = 3;
const EXIT_QUALIFIED: u8 = 4;

/// The exit code of `outcome`, with `fail` the code of a FAIL.
fn exit_code(outcome: Outcome, fail: u8) -> ExitCode {
    match outcome {
        Outcome::Pass => ExitCode::SUCCESS,
        Outcome::Qualified => ExitCode::from(EXIT_QUALIFIED),
        Outcome::Fail => ExitCode::from(fail),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Verify {
            problems,
            level,
            out,
            threads,
            set,
            list,
            vtk,
        } => {
            if list {
                print_problem_list();
                return ExitCode::SUCCESS;
            }
            return match verify(problems, level, out, threads, set, vtk) {
                Ok(outcome) => exit_code(outcome, EXIT_FAILED),
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(EXIT_BAD_INPUT)
                }
            };
        }
        Command::Run {
            scene,
            out,
            threads,
            restart,
            checkpoints,
        } => checkpoints
            .policy(restart.is_some())
            .and_then(|policy| run_scene(&scene, restart.or(out), threads, &policy)),
        Command::Tunnel {
            depths,
            charges,
            soil,
            diameter,
            lining,
            level,
            out,
            accept_unvalidated,
            restart,
            checkpoints,
        } => {
            let policy = match checkpoints.policy(restart.is_some()) {
                Ok(policy) => policy,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(EXIT_BAD_INPUT);
                }
            };
            let out = restart.unwrap_or(out);
            let request = tunnel::StudyRequest {
                depths_m: depths,
                charges_kg: charges,
                soil,
                tunnel: tunnel::Tunnel {
                    inner_diameter_m: diameter,
                    lining_m: lining,
                    ..tunnel::Tunnel::default()
                },
                level: level.into(),
            };
            return match tunnel_command(&request, accept_unvalidated, &out, &policy) {
                Ok(Some(outcome)) => exit_code(outcome, EXIT_FAILED),
                Ok(None) => ExitCode::from(EXIT_GATE_FAILED),
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(EXIT_BAD_INPUT)
                }
            };
        }
        Command::Sedov {
            geometry,
            gamma,
            energy,
            rho0,
            time,
            json,
        } => sedov_command(&geometry, gamma, energy, rho0, time, json).map(|_| true),
        Command::Materials { json } => {
            materials_command(json);
            Ok(true)
        }
        Command::Impedance {
            a,
            b,
            impact,
            pressure,
            json,
        } => impedance_command(&a, &b, impact, pressure, json).map(|_| true),
        Command::Riemann {
            left,
            right,
            gamma,
            json,
        } => riemann_command(&left, &right, gamma, json).map(|_| true),
        Command::Soil { command } => soil_command(command).map(|_| true),
        Command::CheckArrivals { file, soil, json } => check_arrivals_command(&file, &soil, json),
        Command::Gate {
            charge,
            soil,
            depths,
            diameter,
            lining,
            level,
            out,
            json,
        } => {
            let request = GateRequest {
                charge_kg: charge,
                soil,
                depths_m: depths,
                tunnel: tunnel::Tunnel {
                    inner_diameter_m: diameter,
                    lining_m: lining,
                    ..tunnel::Tunnel::default()
                },
                level: level.into(),
            };
            return match gate_command(&request, &out, json) {
                Ok(outcome) => exit_code(outcome, EXIT_GATE_FAILED),
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(EXIT_BAD_INPUT)
                }
            };
        }
        Command::Scaled {
            charge,
            range,
            burst,
            depth_of_burst,
            explosive,
            soil,
            json,
        } => scaled_command(
            charge,
            range,
            &burst,
            depth_of_burst,
            &explosive,
            soil.as_deref(),
            json,
        )
        .map(|_| true),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(EXIT_FAILED),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

/// Prints the problems and their parameters.
fn print_problem_list() {
    use std::fmt::Write;
    let mut text = String::new();
    for p in problems::all() {
        let _ = writeln!(text, "{:22} {}", p.name, p.summary);
        for spec in &p.params {
            let _ = writeln!(
                text,
                "    {:10} quick={:16} full={:16} {}",
                spec.key, spec.quick, spec.full, spec.help
            );
        }
    }
    emit(&text);
}

/// Runs the tunnel study and writes its outputs; Some(its outcome), or None when a gate failed
/// and the study stopped there.
fn tunnel_command(
    request: &tunnel::StudyRequest,
    accept_unvalidated: bool,
    out: &Path,
    checkpoints: &Checkpoints,
) -> Result<Option<Outcome>, VerifyError> {
    tunnel::validate(request)?;
    report::ensure_writable(out)?;
    // a study.json left by an earlier run must not stand beside this run's outputs
    let study_path = out.join("study.json");
    if study_path.exists() {
        std::fs::remove_file(&study_path).map_err(|source| VerifyError::Io {
            path: study_path.display().to_string(),
            source,
        })?;
    }
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("[{bar:40}] {percent:>3}% {msg}").expect("valid template"),
    );
    // several runs go at once: the bar shows the least advanced, the message all of them
    let running = std::sync::Mutex::new(std::collections::BTreeMap::<String, f64>::new());
    let outcome = tunnel::run_study(
        request,
        accept_unvalidated,
        out,
        &|name, f| {
            let mut running = running.lock().expect("no progress update panicked");
            if f < 1.0 {
                running.insert(name.to_string(), f);
            } else {
                running.remove(name);
            }
            let least = running.values().copied().fold(1.0, f64::min);
            let names: Vec<&str> = running.keys().map(String::as_str).collect();
            bar.set_message(names.join(" | "));
            bar.set_position((least * 1000.0) as u64);
        },
        checkpoints,
    )?;
    bar.finish_and_clear();
    let study = match outcome {
        tunnel::StudyOutcome::GateFailed(gate) => {
            for g in &gate {
                println!(
                    "gate {} kg: {} (report {}/gate/gate-{}.json)",
                    g.charge_kg,
                    g.outcome.name(),
                    out.display(),
                    g.inputs_hash
                );
                for failure in &g.failures {
                    println!("    FAIL {failure}");
                }
            }
            println!(
                "the free-field gate failed: no tunnel results (--accept-unvalidated runs them \
                 stamped NOT VALIDATED)"
            );
            return Ok(None);
        }
        tunnel::StudyOutcome::Done(study) => study,
    };
    let figures = tunnel::figures(&study, out)?;
    for (name, figure) in &figures {
        report::write_atomic(&out.join(format!("{name}.svg")), figure.to_svg().as_bytes())?;
    }
    let markdown = tunnel::report_markdown(&study);
    report::write_atomic(&out.join("report.md"), markdown.as_bytes())?;
    let html = tunnel::report_html(&study, &figures);
    report::write_atomic(&out.join("report.html"), html.as_bytes())?;
    let json = serde_json::to_vec_pretty(&study).expect("the study serialises");
    report::write_atomic(&study_path, &json)?;
    print!("{markdown}");
    println!("study: {}", study.outcome.name());
    Ok(Some(study.outcome))
}

/// Starts the worker pool with `threads` threads (default: one per core).
fn set_threads(threads: Option<usize>) -> Result<(), VerifyError> {
    let Some(n) = threads else {
        return Ok(());
    };
    if n == 0 {
        return Err(VerifyError::bad_value("--threads", n, "≥ 1"));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| {
            VerifyError::bad_value(
                "--threads",
                format!("{n} ({e})"),
                "a thread count the system can start",
            )
        })
}

/// Reads, checks and runs a scene file; Ok(false) when the run stopped early.
fn run_scene(
    path: &Path,
    out: Option<PathBuf>,
    threads: Option<usize>,
    checkpoints: &Checkpoints,
) -> Result<bool, VerifyError> {
    let text = std::fs::read_to_string(path).map_err(|source| VerifyError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let scene = Scene::parse(&text)?;
    scene.check_memory()?;
    let out = out.unwrap_or_else(|| {
        let stem = path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        Path::new("results").join(stem)
    });
    report::ensure_writable(&out)?;
    let checkpoint = out.join(scene::CHECKPOINT_FILE);
    if checkpoints.resume && !checkpoint.exists() {
        return Err(VerifyError::bad_value(
            "--restart",
            out.display(),
            &format!(
                "a folder holding a stopped run's {} (a finished run removes its own)",
                scene::CHECKPOINT_FILE
            ),
        ));
    }
    set_threads(threads)?;
    let bar = ProgressBar::new(1000).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {percent}% ({elapsed} elapsed, ETA {eta})")
            .expect("a valid template"),
    );
    bar.set_message(scene.name.clone());
    let summary = scene::run_checkpointed(
        &scene,
        &out,
        &mut |fraction| bar.set_position((fraction * 1000.0) as u64),
        checkpoints,
    )?;
    bar.finish_and_clear();
    let energy = match summary.energy_relative_change {
        Some(relative) => format!("{relative:.2e} of the initial energy"),
        None => format!("{:.3e} J", summary.energy_change_j),
    };
    println!(
        "{}: {} particles, {} steps, {:.1} s wall, energy change {energy}; outputs in {}",
        summary.scene,
        summary.particles,
        summary.steps,
        summary.wall_s,
        out.display()
    );
    if summary.departed.particles > 0 {
        println!(
            "  {} particles ({:.4e} kg) left through outflow sides",
            summary.departed.particles, summary.departed.mass
        );
    }
    if let Some(balance) = &summary.gravity_balance {
        println!(
            "  geostatic state held by external accelerations within {:.2} % (mean) of g inside the bodies",
            100.0 * balance.interior_mean_departure
        );
    }
    for g in &summary.gauges {
        println!(
            "  gauge {:<16} ({}) peak pressure {:.4e} Pa, peak velocity {:.4e} m/s, peak von Mises {:.4e} Pa",
            g.name, g.body, g.peak_pressure_pa, g.peak_velocity_m_s, g.peak_von_mises_pa
        );
    }
    if let Some(diagnosis) = &summary.stopped {
        println!(
            "STOPPED at t = {:.4e} s: {diagnosis}",
            summary.time_reached_s
        );
    }
    Ok(summary.stopped.is_none())
}

/// Runs the problems; Ok(true) when every check passed.
fn verify(
    names: Vec<String>,
    level: LevelArg,
    out: PathBuf,
    threads: Option<usize>,
    set: Vec<String>,
    vtk: bool,
) -> Result<Outcome, VerifyError> {
    let level = Level::from(level);
    let names: Vec<String> = if names.is_empty() {
        problems::names().iter().map(|s| s.to_string()).collect()
    } else {
        names
    };
    // check every name and override before running anything
    let overrides = set
        .iter()
        .map(|s| parse_assignment(s))
        .collect::<Result<Vec<_>, _>>()?;
    for name in &names {
        problems::preflight(name, level, &overrides)?;
    }
    report::ensure_writable(&out)?;
    set_threads(threads)?;
    println!(
        "{:<22} {:>9} {:>7} {:>9}  {:<44} {:<20} result",
        "problem", "particles", "steps", "wall s", "main errors", "observed order"
    );
    let jobs: Vec<problems::Job> = names
        .iter()
        .map(|name| problems::Job {
            name: name.clone(),
            overrides: overrides.clone(),
        })
        .collect();
    let bars = indicatif::MultiProgress::new();
    let style = ProgressStyle::with_template("{msg:22} [{bar:40}] {percent:>3}% eta {eta}")
        .expect("valid template");
    let running: Vec<std::sync::OnceLock<ProgressBar>> =
        names.iter().map(|_| std::sync::OnceLock::new()).collect();
    let progress = |k: usize, fraction: f64| {
        let bar = running[k].get_or_init(|| {
            bars.add(
                ProgressBar::new(1000)
                    .with_style(style.clone())
                    .with_message(names[k].clone()),
            )
        });
        bar.set_position((fraction * 1000.0) as u64);
    };
    let mut outcome = Outcome::Pass;
    let mut records = Vec::new();
    let mut figures = Vec::new();
    problems::run_many(level, &jobs, &progress, &mut |k, output| {
        if let Some(bar) = running[k].get() {
            bar.finish_and_clear();
            bars.remove(bar);
        }
        report::write_outputs(&out, &output)?;
        if vtk {
            report::write_snapshot(&out, &output)?;
        }
        bars.suspend(|| println!("{}", result_lines(&output.record)));
        outcome = outcome.max(output.record.outcome);
        figures.push(output.figure.to_svg());
        records.push(output.record);
        Ok(())
    })?;
    let (_, work_precision) = report::write_work_precision(&out, &records)?;
    let entries: Vec<index::Entry> = records
        .iter()
        .zip(&figures)
        .map(|(record, figure_svg)| index::Entry { record, figure_svg })
        .collect();
    let heading = format!(
        "{} level, {} worker threads",
        level.name(),
        rayon::current_num_threads()
    );
    report::write_index(&out, &heading, &entries, &work_precision)?;
    println!(
        "outputs in {} (index.html shows them all; work-precision.svg, .csv)",
        out.display()
    );
    Ok(outcome)
}

/// A problem's line of the table, then its failed checks and stopped runs.
fn result_lines(r: &blastsph_verification::record::Record) -> String {
    use std::fmt::Write;
    let finest = r.headline();
    let errors = r
        .headline_errors()
        .map(|(k, v)| format!("{k}={v:.2e}"))
        .collect::<Vec<_>>()
        .join(" ");
    let orders = r
        .order
        .iter()
        .take(2)
        .map(|(k, v)| format!("{}={v:.2}", k.trim_start_matches("l1_")))
        .collect::<Vec<_>>()
        .join(" ");
    let mut text = format!(
        "{:<22} {:>9} {:>7} {:>9.3}  {:<44} {:<20} {}",
        r.problem,
        finest.map_or(0, |run| run.n_particles),
        finest.map_or(0, |run| run.steps),
        r.wall_s,
        errors,
        orders,
        r.outcome.name()
    );
    for check in r.checks.iter().filter(|c| !c.pass) {
        let _ = write!(
            text,
            "\n    {} {}: {:.4e} (must be {} {:.4e})",
            check.outcome().name(),
            check.name,
            check.value,
            check.relation,
            check.limit
        );
        if let Some(q) = &check.qualification {
            let _ = write!(text, "\n        {}", q.describe());
        }
    }
    for run in &r.runs {
        if let Some(failure) = &run.failure {
            let _ = write!(text, "\n    {}: stopped: {failure}", run.label);
        }
    }
    text
}

fn materials_command(json: bool) {
    use std::fmt::Write;
    let library = Library::standard();
    let mut text = String::new();
    if json {
        text = serde_json::to_string_pretty(&library).expect("json") + "\n";
    } else {
        for (name, entry) in &library.materials {
            let _ = writeln!(text, "{name:12} {:15} {}", entry.model, entry.description);
            for (key, p) in &entry.parameters {
                let _ = writeln!(
                    text,
                    "    {key:8} {:>12e} {:8} {:20} {}",
                    p.value, p.unit, p.status, p.source
                );
            }
            for (key, t) in &entry.tables {
                let _ = writeln!(
                    text,
                    "    {key:8} table of {} points vs density, {:8} {:20} {}",
                    t.density.len(),
                    t.unit,
                    t.status,
                    t.source
                );
            }
        }
    }
    emit(&text);
}

/// Writes to stdout, stopping quietly if the reader has gone (`| head`).
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

fn sedov_command(
    geometry: &str,
    gamma: f64,
    energy: f64,
    rho0: f64,
    time: f64,
    json: bool,
) -> Result<(), VerifyError> {
    let geometry = geometry_named(geometry).ok_or_else(|| {
        VerifyError::bad_value("--geometry", geometry, "planar, cylindrical or spherical")
    })?;
    let blast = SedovBlast::new(geometry, gamma, energy, rho0, time)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&blast).expect("json"));
    } else {
        println!("xi0            = {:.6}", blast.xi0);
        println!("energy integral= {:.6}", blast.energy_integral);
        println!("r_shock        = {:.6e}", blast.r_shock);
        println!("rho2           = {:.6e}", blast.rho2);
        println!("u2             = {:.6e}", blast.u2);
        println!("p2             = {:.6e}", blast.p2);
        println!("e2             = {:.6e}", blast.e2);
    }
    Ok(())
}

fn impedance_command(
    a: &str,
    b: &str,
    impact: Option<f64>,
    pressure: Option<f64>,
    json: bool,
) -> Result<(), VerifyError> {
    let drive = match (impact, pressure) {
        (Some(v), _) => Drive::Impact(v),
        (None, Some(p)) => Drive::Pressure(p),
        (None, None) => unreachable!("clap requires --impact or --pressure"),
    };
    let case = impedance::library_case(&Library::standard(), a, b, drive)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&case).expect("json"));
        return Ok(());
    }
    let s = &case.solution;
    println!("{} onto {} ({:?})", case.a, case.b, case.drive);
    println!(
        "incident in A  u = {:.6e} m/s, p = {:.6e} Pa, rho = {:.6e} kg/m3",
        case.incident.velocity, case.incident.pressure, case.incident.density
    );
    println!(
        "interface      up = {:.6e} m/s, p = {:.6e} Pa",
        case.up, case.p
    );
    println!(
        "transmitted    shock in B, us_b = {:.6e} m/s, rho = {:.6e} kg/m3",
        case.us_b, s.into_b.behind.density
    );
    println!(
        "reflected      {} in A, head {:.6e} m/s, tail {:.6e} m/s, rho = {:.6e} kg/m3",
        case.reflected, s.into_a.head_speed, s.into_a.tail_speed, s.into_a.behind.density
    );
    if let Some((u, p)) = case.eq_2_16 {
        println!(
            "eq. 2-16       up = {u:.6e} m/s ({:+.2} %), p = {p:.6e} Pa ({:+.2} %) (mirrored Hugoniot)",
            100.0 * (u / case.up - 1.0),
            100.0 * (p / case.p - 1.0)
        );
    }
    Ok(())
}

/// Runs (or reuses) the gate and prints its verdict.
fn gate_command(request: &GateRequest, out: &Path, json: bool) -> Result<Outcome, VerifyError> {
    gate::validate(request)?;
    report::ensure_writable(out)?;
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{msg:22} [{bar:40}] {percent:>3}% eta {eta}")
            .expect("valid template"),
    );
    let (report, reused) = gate::run_gate(request, out, &|name, f| {
        bar.set_message(name.to_string());
        bar.set_position((f * 1000.0) as u64);
    })?;
    bar.finish_and_clear();
    if json {
        println!("{}", serde_json::to_string_pretty(&report).expect("json"));
        return Ok(report.outcome);
    }
    println!(
        "gate for {} kg TNT in {}, depths {:?} m, level {}{}",
        request.charge_kg,
        request.soil,
        request.depths_m,
        request.level.name(),
        if reused {
            " (reused: same request, same program)"
        } else {
            ""
        }
    );
    for p in &report.problems {
        println!(
            "  {:24} {:>8.1} s  {}",
            p.problem,
            p.wall_s,
            p.outcome.name()
        );
    }
    for failure in report.failures() {
        println!("    FAIL {failure}");
    }
    for qualification in report.qualifications() {
        println!("    QUALIFIED {qualification}");
    }
    for missing in &report.not_covered {
        println!("  not covered: {missing}");
    }
    println!(
        "gate {}: {}",
        report.outcome.name(),
        gate::report_path(out, &report.inputs_hash).display()
    );
    Ok(report.outcome)
}

fn check_arrivals_command(file: &Path, soil: &str, json: bool) -> Result<bool, VerifyError> {
    use blastsph_verification::scaled::arrivals;
    let text = std::fs::read_to_string(file).map_err(|error| {
        VerifyError::bad_value(
            "arrivals file",
            format!("{} ({error})", file.display()),
            "a readable CSV file",
        )
    })?;
    let table = arrivals::read_arrivals(&text, &file.display().to_string())?;
    let report = arrivals::check_arrivals(&Library::standard(), soil, &table)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report).expect("json"));
    } else {
        println!(
            "c_max = {:.0} m/s (the fastest of {} and {}): no arrival at depth d before d / c_max",
            report.c_max_m_s, report.soil, report.lining
        );
        println!(
            "{:>8} {:>10} {:>8} {:>12} {:>14} {:>14}  verdict",
            "depth m", "charge kg", "gauge", "arrival s", "implied m/s", "earliest s"
        );
        for e in &report.entries {
            println!(
                "{:>8} {:>10} {:>8} {:>12.4e} {:>14.4e} {:>14.4e}  {}",
                e.depth_m,
                e.charge_kg,
                e.gauge,
                e.arrival_s,
                e.implied_speed_m_s,
                e.min_possible_arrival_s,
                if e.possible { "possible" } else { "IMPOSSIBLE" }
            );
        }
    }
    Ok(report.all_possible())
}

fn scaled_command(
    charge: f64,
    range: f64,
    burst: &str,
    depth_of_burst: Option<f64>,
    explosive: &str,
    soil: Option<&str>,
    json: bool,
) -> Result<(), VerifyError> {
    use blastsph_verification::scaled::{explosives, ground_shock, query};
    let placement = query::Placement::ALL
        .into_iter()
        .find(|p| p.name() == burst)
        .ok_or_else(|| VerifyError::bad_value("--burst", burst, "surface, free-air or buried"))?;
    let soil = soil.map(ground_shock::soil).transpose()?;
    let report = query::scaled_report(
        charge,
        explosives::explosive(explosive)?,
        range,
        placement,
        depth_of_burst,
        soil,
    )?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report).expect("json"));
        return Ok(());
    }
    println!(
        "{} kg {} {} burst at {} m: Z = {:.4} m/kg^(1/3)",
        report.charge_kg, report.explosive, report.burst, report.range_m, report.z
    );
    let line = |what: &str, value: Option<f64>, unit: &str| match value {
        Some(v) => println!("  {what:<28} {v:.4e} {unit}"),
        None => println!("  {what:<28} —"),
    };
    if placement != query::Placement::Buried {
        println!("air blast (Kingery–Bulmash)");
        line(
            "incident overpressure",
            report.incident_overpressure_pa,
            "Pa",
        );
        line(
            "reflected overpressure",
            report.reflected_overpressure_pa,
            "Pa",
        );
        line("arrival", report.arrival_s, "s");
        line("positive duration", report.duration_s, "s");
        line("incident impulse", report.incident_impulse_pa_s, "Pa s");
        line("reflected impulse", report.reflected_impulse_pa_s, "Pa s");
    }
    if let (Some(shock), Some(soil)) = (&report.ground_shock, report.soil) {
        println!(
            "ground shock in {soil} (TM 5-855-1, f = {:.3})",
            shock.coupling_factor
        );
        line(
            "peak particle velocity",
            Some(shock.peak_velocity_m_s),
            "m/s",
        );
        line("peak stress", Some(shock.peak_stress_pa), "Pa");
        line("impulse", Some(shock.impulse_pa_s), "Pa s");
        line("arrival", Some(shock.arrival_s), "s");
        line("rise time", Some(shock.rise_s), "s");
    }
    Ok(())
}

fn parse_state(side: &str, text: &str) -> Result<GasState, VerifyError> {
    let parts: Vec<&str> = text.split(',').collect();
    let bad = || VerifyError::bad_value(&format!("--{side}"), text, "three numbers RHO,U,P");
    if parts.len() != 3 {
        return Err(bad());
    }
    let v: Vec<f64> = parts
        .iter()
        .map(|s| s.trim().parse::<f64>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    Ok(GasState::new(v[0], v[1], v[2]))
}

fn riemann_command(left: &str, right: &str, gamma: f64, json: bool) -> Result<(), VerifyError> {
    let solution = riemann::solve(
        parse_state("left", left)?,
        parse_state("right", right)?,
        gamma,
    )?;
    // with a vacuum there is no star region: zero pressure and density, no velocity
    let (p_star, u_star, rho_l, rho_r) = solution.star().map_or((0.0, f64::NAN, 0.0, 0.0), |s| {
        (s.p, s.u, s.rho_left, s.rho_right)
    });
    let waves = solution.describe();
    if json {
        let value = serde_json::json!({
            "p_star": p_star, "u_star": if u_star.is_finite() { Some(u_star) } else { None },
            "rho_star_l": rho_l, "rho_star_r": rho_r, "waves": waves, "gamma": gamma,
        });
        println!("{}", serde_json::to_string_pretty(&value).expect("json"));
    } else {
        println!("waves:      {waves}");
        println!("p*        = {p_star:.6e}");
        println!("u*        = {u_star:.6e}");
        println!("rho*_left = {rho_l:.6e}");
        println!("rho*_right= {rho_r:.6e}");
    }
    Ok(())
}

fn soil_command(command: SoilCommand) -> Result<(), VerifyError> {
    match command {
        SoilCommand::Bridge(args) => bridge_command(args),
        SoilCommand::Biaxial {
            saturation,
            confining,
            seed,
            grains,
            axial_strain,
            out,
            json,
        } => {
            let overrides = [
                ("saturation", saturation),
                ("confining", confining),
                ("seeds", seed.to_string()),
                ("grains", grains.to_string()),
                ("axial_strain", axial_strain.to_string()),
            ]
            .map(|(k, v)| (k.to_string(), v));
            report::ensure_writable(&out)?;
            let output = problems::run("biaxial", Level::Full, &overrides, &|_| {})?;
            report::write_outputs(&out, &output)?;
            let strength = biaxial_strength(&output.record, seed, grains);
            let text = serde_json::to_string_pretty(&strength).expect("json");
            report::write_atomic(&out.join("soil-strength.json"), text.as_bytes())?;
            if json {
                println!("{text}");
            } else {
                println!(
                    "saturation  cohesion (Pa)  friction angle (°)  critical-state c (Pa), φ (°)"
                );
                for s in strength["saturations"].as_array().expect("list") {
                    println!(
                        "{:>8.0} %  {:>13.1}  {:>18.2}  {:>10.1}, {:.2}",
                        100.0 * s["saturation"].as_f64().unwrap_or(f64::NAN),
                        s["cohesion_pa"].as_f64().unwrap_or(f64::NAN),
                        s["friction_angle_degrees"].as_f64().unwrap_or(f64::NAN),
                        s["critical_cohesion_pa"].as_f64().unwrap_or(f64::NAN),
                        s["critical_friction_angle_degrees"]
                            .as_f64()
                            .unwrap_or(f64::NAN),
                    );
                }
                println!("outputs in {}", out.display());
            }
            Ok(())
        }
    }
}

/// The envelopes of a `biaxial` record as the SPH soil model's inputs, per saturation.
fn biaxial_strength(
    record: &blastsph_verification::record::Record,
    seed: u64,
    grains: usize,
) -> serde_json::Value {
    let saturations: Vec<serde_json::Value> = record
        .runs
        .iter()
        .filter(|run| run.metrics.contains_key("cohesion_peak_pa"))
        .map(|run| {
            let m = &run.metrics;
            serde_json::json!({
                "saturation": m["saturation"],
                "cohesion_pa": m["cohesion_peak_pa"],
                "friction_angle_degrees": m["friction_angle_peak_deg"],
                "critical_cohesion_pa": m["cohesion_critical_pa"],
                "critical_friction_angle_degrees": m["friction_angle_critical_deg"],
                "rumpf_cohesion_pa": m.get("rumpf_cohesion_pa"),
            })
        })
        .collect();
    serde_json::json!({
        "source": "blastsph soil biaxial (DEM, 2D spheres with Willett liquid bridges)",
        "seed": seed,
        "grains": grains,
        "checks_pass": record.outcome == Outcome::Pass,
        "saturations": saturations,
    })
}

fn bridge_command(args: BridgeArgs) -> Result<(), VerifyError> {
    use blastsph_solver::dem::capillary::{
        bridge_force, effective_radius, rupture_gap, BridgeLaw, Liquid, RuptureCriterion,
    };
    let BridgeArgs {
        radius,
        volume,
        gap,
        theta,
        law,
        surface_tension,
        rupture,
        json,
    } = args;
    let radii: Vec<f64> = radius
        .split(',')
        .map(|r| r.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .ok()
        .filter(|r: &Vec<f64>| {
            (1..=2).contains(&r.len()) && r.iter().all(|&x| x > 0.0 && x.is_finite())
        })
        .ok_or_else(|| VerifyError::bad_value("--radius", &radius, "R1 or R1,R2 in m, each > 0"))?;
    let r = effective_radius(radii[0], *radii.last().expect("one radius"));
    let named = BridgeLaw::named(&law).ok_or_else(|| {
        VerifyError::bad_value("--law", &law, "willett, simple, rabinovich or toroidal")
    })?;
    let criterion = match rupture.as_str() {
        "lian" => RuptureCriterion::Lian,
        "willett" => RuptureCriterion::Willett,
        _ => {
            return Err(VerifyError::bad_value(
                "--rupture",
                &rupture,
                "lian or willett",
            ))
        }
    };
    if !gap.is_finite() {
        return Err(VerifyError::bad_value("--gap", gap, "a finite gap in m"));
    }
    let liquid = Liquid {
        volume,
        surface_tension,
        contact_angle: theta.to_radians(),
    };
    liquid.validate()?;
    named.admits(&liquid, r)?;
    let rupture_gap_m = rupture_gap(criterion, &liquid, r);
    // beyond the rupture distance the bridge has broken and pulls no more
    let force_n = if gap < rupture_gap_m {
        bridge_force(named, &liquid, r, gap)?
    } else {
        0.0
    };
    if json {
        let value = serde_json::json!({
            "force_n": force_n, "rupture_gap_m": rupture_gap_m, "effective_radius_m": r,
            "law": named.name(), "bridged": gap < rupture_gap_m,
        });
        println!("{}", serde_json::to_string_pretty(&value).expect("json"));
    } else {
        println!("law            = {}", named.name());
        println!("effective R    = {r:.6e} m");
        println!("force          = {force_n:.6e} N");
        println!("rupture gap    = {rupture_gap_m:.6e} m");
    }
    Ok(())
}
