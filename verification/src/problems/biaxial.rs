//! `biaxial`: the source paper's biaxial test on moist sand (seed 003) with the DEM of
//! solver::dem: for each saturation and confining stress, a graded sample of grains joined by
//! pendular water bridges is sheared to 10 % axial strain; Mohr–Coulomb c and φ are fitted at
//! the peak (σ1 averaged over 1 % axial strain) and at the critical state (the mean of the
//! last fifth of the strain).
//!
//! References and checks:
//! - dry sand has no cohesion: c(dry) below a tenth of c(10 %). At the quick level one
//!   300-grain sample's peaks scatter by about ±10 %, which puts about ±150 Pa on a c fitted
//!   over σ3 = 0.5–2 kPa (seed 1's c(10 %) measured 237, 236 and 96 Pa under three loading
//!   speeds), so there only c(10 %) > c(dry) is checked, and the Rumpf factor below is 10;
//! - the wet cohesion is positive and within a factor of 3 of Rumpf's estimate, the bridges'
//!   tensile stress σ_t = φ_s Z F̄/(π d̄ t) (2D Love–Weber average with the measured solid
//!   fraction φ_s, coordination Z and mean bridge force F̄; d̄ the mean diameter, t the layer
//!   thickness) shifted onto the envelope as c = σ_t tan φ_dry (Pierrat & Caram 1997);
//! - moisture changes φ by less than 3° (10° at the quick level: one 300-grain sample per
//!   point scatters; seeds 1, 2, 3 measured changes of 7.6°, 2.6° and 8.3°);
//! - quasi-static loading: the mean σ1 from 1 % strain to the end of the slow run
//!   (`rate_share` of the loading: all of it, half at the quick level) of the first seed and
//!   saturation at the highest σ3 moves by less than 4 % (10 % at the quick level) when the
//!   platens run at half the speed (the platens are slowed, in proportion to σ3, until the
//!   damping number is below 4e-3: see `DAMPING_NUMBER_LIMIT`). The inertial number
//!   ε̇ d̄ √(ρ/σ3) is recorded, not checked: the speeds are chosen to hold it at or below 5e-4
//!   ([`platen_speeds`]), inside the quasi-static regime below 1e-3 (GDR MiDi 2004);
//! - the friction study: more friction between grains prepares a sample with a larger void
//!   ratio and a lower coordination number.

use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Figure, Panel, Series, Style};
use crate::{Level, VerifyError};
use blastsph_solver::dem::biaxial::{
    prepare_sample, shear_prepared, BiaxialRun, BiaxialTest, PreparedSample,
};
use blastsph_solver::dem::discs::{sphere_mass, Discs};
use blastsph_solver::dem::strength_fit::{fit_mohr_coulomb, MohrCoulomb};
use rayon::prelude::*;
use std::f64::consts::PI;

pub const NAME: &str = "biaxial";

/// The loading speed of the source paper, each platen (m/s).
const PAPER_PLATEN_SPEED: f64 = 0.0127;

/// Inter-particle friction coefficients of the friction study.
const FRICTION_STUDY: [f64; 3] = [0.1, 0.5, 1.0];

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "DEM biaxial test of moist sand: Mohr–Coulomb c and φ against saturation",
        params: vec![
            ParamSpec::per_level("grains", 300, 1700, "grains in each sample"),
            ParamSpec::per_level("seeds", "1", "1,2", "sample seeds (comma-separated)"),
            ParamSpec::per_level(
                "saturation",
                "0,10",
                "0,10,15,20",
                "degrees of saturation in per cent (comma-separated, 0 = dry)",
            ),
            // the quick level drops σ3 = 0.5 kPa, whose platens run slowest (speed ∝ σ3): half
            // the level's work. Two points fix c and φ exactly. Measured at 300 grains, seed 1,
            // c and φ dry and at 10 %: 59 and 375 Pa, 18.4° and 13.0° (Rumpf ratio 1.52); with
            // all three σ3, 52 and 267 Pa, 18.6° and 15.3° (ratio 1.08)
            ParamSpec::per_level(
                "confining",
                "1000,2000",
                "500,1000,2000",
                "confining stresses σ3 in Pa (comma-separated, at least two)",
            ),
            ParamSpec::new("axial_strain", 0.1, "axial strain at the end of loading"),
            // the rate check's slow run is the longest: at the quick level it stops at half
            // the strain, and both runs' mean σ1 is taken from 1 % to there
            ParamSpec::per_level(
                "rate_share",
                0.5,
                1.0,
                "share of axial_strain the rate check's slow run loads to",
            ),
        ],
    }
}

/// One sheared sample.
struct Shear {
    seed: u64,
    saturation: f64,
    /// The loading speed's factor on the problem's (½ in the rate check).
    slowing: f64,
    confining: f64,
    run: BiaxialRun,
    platen_speed: f64,
    inertial_number: f64,
    damping_number: f64,
    wall_s: f64,
}

/// The axial strain over which σ1 is averaged before its peak is taken.
const PEAK_WINDOW: f64 = 0.01;

impl Shear {
    /// The peak: the largest mean σ1 over a span of [`PEAK_WINDOW`] axial strain. A single
    /// record's σ1 rises and drops by several per cent as force chains build and buckle, and
    /// the largest record would measure the largest of those swings rather than the sample's
    /// strength.
    fn peak(&self) -> f64 {
        let records = &self.run.records;
        let mut start = 0;
        let mut peak: f64 = 0.0;
        for (end, r) in records.iter().enumerate() {
            while r.axial_strain - records[start].axial_strain > PEAK_WINDOW {
                start += 1;
            }
            if r.axial_strain >= PEAK_WINDOW {
                let span = &records[start..=end];
                let mean = span.iter().map(|x| x.sigma1).sum::<f64>() / span.len() as f64;
                peak = peak.max(mean);
            }
        }
        peak
    }

    /// The mean σ1 of the records at axial strains from `from` to `to`.
    fn mean_between(&self, from: f64, to: f64) -> f64 {
        let span: Vec<f64> = self
            .run
            .records
            .iter()
            .filter(|r| (from..=to).contains(&r.axial_strain))
            .map(|r| r.sigma1)
            .collect();
        span.iter().sum::<f64>() / span.len().max(1) as f64
    }

    /// The critical state: the mean σ1 over the last fifth of the axial strain.
    fn critical(&self, axial_strain: f64) -> f64 {
        self.mean_between(0.8 * axial_strain, f64::INFINITY)
    }
}

/// The envelope of one saturation, over all seeds, and per seed.
struct Envelope {
    saturation: f64,
    peak: MohrCoulomb,
    critical: MohrCoulomb,
    per_seed: Vec<(u64, MohrCoulomb)>,
    /// Means over the samples at this saturation.
    coordination: f64,
    solid_fraction: f64,
    bridge_force: f64,
    bridge_volume_ratio: f64,
}

/// The inertial number ε̇ d̄ √(ρ/σ3) of platens closing at `speed` each (ε̇ = 2 speed / H).
fn inertial_number(test: &BiaxialTest, sample: &PreparedSample, speed: f64, sigma3: f64) -> f64 {
    2.0 * speed / sample.height * sample.layer_thickness * (test.density / sigma3).sqrt()
}

/// The damping number c_n ε̇/(σ3 t): the normal dashpot c_n = 2ζ√(m̄ k_n/2) of two grains of
/// the mean diameter t, at the affine approach speed ε̇ t, over the contact force σ3 t² of the
/// confining stress. Dashpots and local damping resist the grains' rearrangements in proportion
/// to their speed, so the loading adds a viscous stress to the quasi-static one.
fn damping_number(test: &BiaxialTest, sample: &PreparedSample, speed: f64, sigma3: f64) -> f64 {
    let t = sample.layer_thickness;
    let (mass, _) = sphere_mass(0.5 * t, test.density);
    let c = &test.contact;
    let dashpot = 2.0 * c.damping_ratio * (0.5 * mass * c.normal_stiffness).sqrt();
    dashpot * (2.0 * speed / sample.height) / (sigma3 * t)
}

/// The largest damping number the loading may run at. Measured on the 1700-grain sample
/// (seed 1, dry, σ3 = 500 Pa, damping as now): the mean σ1 beyond 1 % axial strain was 1025,
/// 950 and 911 Pa at damping numbers 1.4e-2, 7.6e-3 and 3.8e-3 (seed 2: 960 and 920 Pa at the
/// last two), a viscous excess of about 10 D. At 4e-3 it is about 4 %, the same share at every
/// σ3 ([`platen_speeds`]): φ rises by under 1° and c not at all.
const DAMPING_NUMBER_LIMIT: f64 = 4e-3;

/// The platens' speeds at confining stress σ3, (consolidation, loading). Consolidation runs
/// at the paper's speed, or slower where the inertial number would pass half of 1e-3 (on a
/// small sample a fast servo overshoots and never settles). Loading runs at that speed, or
/// slower where the damping number would pass [`DAMPING_NUMBER_LIMIT`]; wherever the damping
/// number sets it the speed is proportional to σ3, so the viscous excess is the same share of
/// the strength at every σ3: it moves φ a little and adds no cohesion.
fn platen_speeds(test: &BiaxialTest, sample: &PreparedSample, sigma3: f64) -> (f64, f64) {
    let inertial = inertial_number(test, sample, PAPER_PLATEN_SPEED, sigma3);
    let consolidation = PAPER_PLATEN_SPEED * (5e-4 / inertial).min(1.0);
    let damping = damping_number(test, sample, consolidation, sigma3);
    (
        consolidation,
        consolidation * (DAMPING_NUMBER_LIMIT / damping).min(1.0),
    )
}

/// One loading of a prepared sample: the saturation it is wetted to, the factor on the
/// problem's loading speed (1, or ½ for the rate check) and the axial strain it ends at.
#[derive(Clone, Copy)]
struct Loading {
    saturation: f64,
    slowing: f64,
    axial_strain: f64,
}

/// Runs every sample in one pool: one dry preparation per seed and σ3, each sheared at each of
/// its loadings; returns the shears and the preparation of each (seed, σ3) in `cases`' order.
fn shear_all(
    grains: usize,
    cases: &[(u64, f64)],
    loadings: &(dyn Fn(u64, f64) -> Vec<Loading> + Sync),
    progress: &(dyn Fn(f64) + Sync),
) -> Result<(Vec<Shear>, Vec<PreparedSample>), VerifyError> {
    let done = std::sync::atomic::AtomicUsize::new(0);
    let total: usize = cases.iter().map(|&(s, p)| loadings(s, p).len()).sum();
    let prepared: Vec<(Vec<Shear>, PreparedSample)> = cases
        .par_iter()
        .map(|&(seed, sigma3)| -> Result<_, VerifyError> {
            let base = BiaxialTest::source_paper(grains, seed, 0.0, sigma3);
            let start = std::time::Instant::now();
            let (discs, sample) = prepare_sample(&base)?;
            let preparation_s = start.elapsed().as_secs_f64();
            let (consolidation, speed) = platen_speeds(&base, &sample, sigma3);
            let shears = loadings(seed, sigma3)
                .par_iter()
                .map(|loading| {
                    let speeds = (consolidation, loading.slowing * speed);
                    let shear = shear(&base, (&discs, sample), *loading, speeds)?;
                    let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                    progress(n as f64 / total as f64);
                    Ok(Shear {
                        wall_s: preparation_s + shear.wall_s,
                        ..shear
                    })
                })
                .collect::<Result<Vec<_>, blastsph_solver::SolverError>>()?;
            Ok((shears, sample))
        })
        .collect::<Result<_, _>>()?;
    let (shears, samples): (Vec<Vec<Shear>>, Vec<PreparedSample>) = prepared.into_iter().unzip();
    Ok((shears.into_iter().flatten().collect(), samples))
}

/// Shears a prepared sample (a copy) as `loading` says, at platen speeds (consolidation,
/// loading); the wall time is the shearing's.
fn shear(
    base: &BiaxialTest,
    (discs, sample): (&Discs, PreparedSample),
    loading: Loading,
    (consolidation, speed): (f64, f64),
) -> Result<Shear, blastsph_solver::SolverError> {
    let mut test = *base;
    test.saturation = loading.saturation;
    test.loading.consolidation_speed = consolidation;
    test.loading.platen_speed = speed;
    test.loading.axial_strain = loading.axial_strain;
    let start = std::time::Instant::now();
    let run = shear_prepared(discs.clone(), sample, &test)?;
    Ok(Shear {
        seed: test.seed,
        saturation: loading.saturation,
        slowing: loading.slowing,
        confining: test.loading.confining_stress,
        run,
        platen_speed: speed,
        inertial_number: inertial_number(&test, &sample, speed, test.loading.confining_stress),
        damping_number: damping_number(&test, &sample, speed, test.loading.confining_stress),
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// One test as the problem runs it: the sample prepared dry, wetted to `saturation` and
/// sheared at the problem's platen speeds for σ3 to `axial_strain` (what the benchmark times).
pub fn biaxial_run(
    grains: usize,
    seed: u64,
    saturation: f64,
    sigma3: f64,
    axial_strain: f64,
) -> Result<BiaxialRun, VerifyError> {
    let loading = Loading {
        saturation,
        slowing: 1.0,
        axial_strain,
    };
    let (mut shears, _) = shear_all(grains, &[(seed, sigma3)], &|_, _| vec![loading], &|_| {})?;
    Ok(shears.remove(0).run)
}

/// The Mohr–Coulomb fit, or NaN for c and φ where the points admit none (σ1 growing slower than
/// σ3: a sample too small for its scatter); the checks on a NaN fail.
fn fit(points: &[(f64, f64)]) -> MohrCoulomb {
    fit_mohr_coulomb(points).unwrap_or(MohrCoulomb {
        cohesion: f64::NAN,
        friction_angle_degrees: f64::NAN,
    })
}

/// Fits the envelopes of one saturation (peak and critical state over every seed, peak per
/// seed).
fn envelope(shears: &[&Shear], axial_strain: f64) -> Envelope {
    let points = |of: &dyn Fn(&Shear) -> f64, seed: Option<u64>| -> Vec<(f64, f64)> {
        shears
            .iter()
            .filter(|s| seed.is_none_or(|k| s.seed == k))
            .map(|s| (s.confining, of(s)))
            .collect()
    };
    let mut seeds: Vec<u64> = shears.iter().map(|s| s.seed).collect();
    seeds.dedup();
    let per_seed = seeds
        .iter()
        .map(|&k| (k, fit(&points(&|s| s.peak(), Some(k)))))
        .collect();
    let mean = |of: &dyn Fn(&PreparedSample) -> f64| {
        shears.iter().map(|s| of(&s.run.sample)).sum::<f64>() / shears.len() as f64
    };
    Envelope {
        saturation: shears[0].saturation,
        peak: fit(&points(&|s| s.peak(), None)),
        critical: fit(&points(&|s| s.critical(axial_strain), None)),
        per_seed,
        coordination: mean(&|p| p.coordination),
        solid_fraction: mean(&|p| 1.0 - p.porosity),
        bridge_force: mean(&|p| p.mean_bridge_force),
        bridge_volume_ratio: mean(&|p| p.mean_bridge_volume_ratio),
    }
}

/// Rumpf's tensile stress of the bridges shifted onto the dry envelope (Pierrat & Caram 1997):
/// c = φ_s Z F̄/(π d̄ t) tan φ_dry, with t = d̄ (the layer is one mean diameter thick).
fn rumpf_cohesion(wet: &Envelope, layer_thickness: f64, dry_friction_degrees: f64) -> f64 {
    let tensile = wet.solid_fraction * wet.coordination * wet.bridge_force
        / (PI * layer_thickness * layer_thickness);
    tensile * dry_friction_degrees.to_radians().tan()
}

/// The friction study's samples (dry, first seed, lowest σ3), prepared with each friction
/// coefficient but the source paper's, whose sample the shears prepare.
fn friction_study(
    grains: usize,
    seed: u64,
    sigma3: f64,
) -> Result<Vec<(f64, PreparedSample)>, VerifyError> {
    let paper = BiaxialTest::source_paper(grains, seed, 0.0, sigma3)
        .contact
        .friction;
    FRICTION_STUDY
        .par_iter()
        .filter(|&&mu| mu != paper)
        .map(|&mu| {
            let mut test = BiaxialTest::source_paper(grains, seed, 0.0, sigma3);
            test.contact.friction = mu;
            Ok((mu, prepare_sample(&test)?.1))
        })
        .collect()
}

pub fn run(
    params: &Params,
    level: Level,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let grains = params.number("grains", 20.0, 20_000.0)?.round() as usize;
    let seeds: Vec<u64> = params
        .integers("seeds", 0, u32::MAX as usize)?
        .into_iter()
        .map(|s| s as u64)
        .collect();
    let mut saturations: Vec<f64> = params
        .numbers("saturation", 0.0, 30.0)?
        .iter()
        .map(|s| s / 100.0)
        .collect();
    saturations.sort_by(f64::total_cmp);
    saturations.dedup();
    let mut confining = params.numbers("confining", 1.0, 1e7)?;
    confining.sort_by(f64::total_cmp);
    confining.dedup();
    if confining.len() < 2 {
        return Err(VerifyError::bad_value(
            "confining",
            params.text("confining"),
            "at least two distinct confining stresses (to fit c and φ)",
        ));
    }
    let axial_strain = params.number("axial_strain", 0.01, 0.3)?;
    let rate_strain = params.number("rate_share", 0.0, 1.0)? * axial_strain;
    if rate_strain <= PEAK_WINDOW {
        return Err(VerifyError::bad_value(
            "rate_share",
            params.text("rate_share"),
            "a share of axial_strain beyond 1 % strain (the rate check's mean starts there)",
        ));
    }
    let cases: Vec<(u64, f64)> = seeds
        .iter()
        .flat_map(|&s| confining.iter().map(move |&p| (s, p)))
        .collect();
    // the rate check: the first seed's sample at the highest σ3 and the first saturation (dry
    // when run) sheared again at half the speed. Wherever the damping number sets the loading
    // speed it is proportional to σ3 (`platen_speeds`), so the viscous excess is the same share
    // of the strength at every σ3, and the highest σ3 tests it in the fewest steps.
    let rate_case = (seeds[0], confining[confining.len() - 1]);
    let loadings = |seed: u64, sigma3: f64| {
        let mut loadings: Vec<Loading> = saturations
            .iter()
            .map(|&saturation| Loading {
                saturation,
                slowing: 1.0,
                axial_strain,
            })
            .collect();
        if (seed, sigma3) == rate_case {
            loadings.push(Loading {
                saturation: saturations[0],
                slowing: 0.5,
                axial_strain: rate_strain,
            });
        }
        loadings
    };
    let (sheared, study) = rayon::join(
        || shear_all(grains, &cases, &loadings, progress),
        || friction_study(grains, seeds[0], confining[0]),
    );
    let ((mut shears, samples), mut study) = (sheared?, study?);
    let paper_friction = BiaxialTest::source_paper(grains, seeds[0], 0.0, confining[0])
        .contact
        .friction;
    study.push((paper_friction, samples[0]));
    study.sort_by(|a, b| a.0.total_cmp(&b.0));
    let slow = shears.remove(
        shears
            .iter()
            .position(|s| s.slowing != 1.0)
            .expect("the rate check's shear"),
    );
    let envelopes = saturations
        .iter()
        .map(|&s| {
            let of: Vec<&Shear> = shears.iter().filter(|x| x.saturation == s).collect();
            envelope(&of, axial_strain)
        })
        .collect::<Vec<_>>();
    let layer = shears
        .iter()
        .map(|s| s.run.sample.layer_thickness)
        .sum::<f64>()
        / shears.len() as f64;

    let mut runs = Vec::new();
    let mut checks = Vec::new();
    let mut table = Table::new(&[
        "saturation",
        "confining_pa",
        "seed",
        "axial_strain",
        "volumetric_strain",
        "sigma1_pa",
        "sigma3_pa",
    ]);
    for s in &shears {
        let label = format!(
            "S = {:.0} %, σ3 = {} Pa, seed {}",
            100.0 * s.saturation,
            s.confining,
            s.seed
        );
        let mut run = Run::new(
            label.clone(),
            "dem",
            s.run.particles,
            s.run.sample.layer_thickness,
        );
        run.wall_s = s.wall_s;
        run.steps = s.run.steps as u64;
        let sample = &s.run.sample;
        for (key, value) in [
            ("peak_sigma1_pa", s.peak()),
            ("critical_sigma1_pa", s.critical(axial_strain)),
            ("porosity", sample.porosity),
            ("void_ratio", sample.void_ratio),
            ("coordination", sample.coordination),
            ("bridges", sample.bridges as f64),
            (
                "mean_bridge_volume_over_r3",
                sample.mean_bridge_volume_ratio,
            ),
            ("mean_bridge_force_n", sample.mean_bridge_force),
            ("membrane_particles", s.run.membrane_particles as f64),
            ("time_step_s", s.run.time_step),
            ("platen_speed_m_s", s.platen_speed),
            ("inertial_number", s.inertial_number),
            ("damping_number", s.damping_number),
            ("sample_width_m", sample.width),
            ("sample_height_m", sample.height),
        ] {
            run.metrics.insert(key.into(), value);
        }
        for r in &s.run.records {
            table.rows.push(vec![
                s.saturation,
                s.confining,
                s.seed as f64,
                r.axial_strain,
                r.volumetric_strain,
                r.sigma1,
                r.sigma3,
            ]);
        }
        runs.push(run);
    }
    let dry = envelopes.iter().find(|e| e.saturation == 0.0);
    for e in &envelopes {
        let percent = 100.0 * e.saturation;
        let mut run = Run::new(format!("envelope S = {percent:.0} %"), "", grains, layer);
        for (key, value) in [
            ("saturation", e.saturation),
            ("cohesion_peak_pa", e.peak.cohesion),
            ("friction_angle_peak_deg", e.peak.friction_angle_degrees),
            ("cohesion_critical_pa", e.critical.cohesion),
            (
                "friction_angle_critical_deg",
                e.critical.friction_angle_degrees,
            ),
            ("coordination", e.coordination),
            ("solid_fraction", e.solid_fraction),
            ("mean_bridge_force_n", e.bridge_force),
            ("mean_bridge_volume_over_r3", e.bridge_volume_ratio),
        ] {
            run.metrics.insert(key.into(), value);
        }
        for (seed, fit) in &e.per_seed {
            run.metrics
                .insert(format!("cohesion_peak_pa_seed_{seed}"), fit.cohesion);
            run.metrics.insert(
                format!("friction_angle_peak_deg_seed_{seed}"),
                fit.friction_angle_degrees,
            );
        }
        if let (Some(dry), true) = (dry, e.saturation > 0.0) {
            let estimate = rumpf_cohesion(e, layer, dry.peak.friction_angle_degrees);
            run.metrics.insert("rumpf_cohesion_pa".into(), estimate);
            let ratio = e.peak.cohesion / estimate;
            // a factor of 3 either way; 10 at the quick level, where one 300-grain
            // sample's c scatters by ±150 Pa (see the module notes) about a c near 250 Pa
            let factor = if level == Level::Full { 3.0 } else { 10.0 };
            checks.push(Check::at_least(
                format!("cohesion_over_rumpf_at_least_1_over_{factor}_s{percent:.0}"),
                ratio,
                1.0 / factor,
            ));
            checks.push(Check::at_most(
                format!("cohesion_over_rumpf_at_most_{factor}_s{percent:.0}"),
                ratio,
                factor,
            ));
            let limit = if level == Level::Full { 3.0 } else { 10.0 };
            checks.push(Check::at_most(
                format!("friction_angle_change_deg_s{percent:.0}"),
                (e.peak.friction_angle_degrees - dry.peak.friction_angle_degrees).abs(),
                limit,
            ));
        }
        runs.push(run);
    }
    if let (Some(dry), Some(ten)) = (
        dry,
        envelopes.iter().find(|e| (e.saturation - 0.1).abs() < 1e-9),
    ) {
        // at the quick level both c scatter by ±150 Pa, and only their order is checked
        checks.push(if level == Level::Full {
            Check::at_most(
                "dry_cohesion_over_cohesion_at_10_percent",
                dry.peak.cohesion.abs() / ten.peak.cohesion,
                0.1,
            )
        } else {
            Check::at_least(
                "cohesion_at_10_percent_minus_dry_pa",
                ten.peak.cohesion - dry.peak.cohesion,
                0.0,
            )
        });
    }
    let first = shears
        .iter()
        .find(|s| (s.seed, s.confining) == rate_case && s.saturation == saturations[0])
        .expect("a shear of the first seed and saturation");
    // quasi-static: halving the platen speed moves the mean σ1 from 1 % strain on by the
    // viscous excess's half, about 2 % (DAMPING_NUMBER_LIMIT), plus the scatter between loading
    // histories: 1 % between seeds 1 and 2 at 1700 grains, hence 4 %; a 300-grain sample's
    // mean moved by 4.6 % at damping numbers 2e-3 and 1e-3, where the rate accounts for 1 %,
    // hence 10 % at the quick level (the rate effect that the check exists for, local damping
    // 0.7, moved the 1700-grain mean by 16 %)
    let rate_limit = if level == Level::Full { 0.04 } else { 0.1 };
    let mean = |s: &Shear| s.mean_between(PEAK_WINDOW, rate_strain);
    checks.push(Check::at_most(
        "mean_sigma1_change_at_half_platen_speed",
        (mean(&slow) / mean(first) - 1.0).abs(),
        rate_limit,
    ));
    let mut rate_run = Run::new(
        format!(
            "rate check: S = {:.0} %, σ3 = {} Pa, seed {} at half speed",
            100.0 * first.saturation,
            first.confining,
            first.seed
        ),
        "dem",
        slow.run.particles,
        slow.run.sample.layer_thickness,
    );
    rate_run.wall_s = slow.wall_s;
    rate_run.steps = slow.run.steps as u64;
    for (key, value) in [
        ("mean_sigma1_from_1_percent_to_rate_strain_pa", mean(&slow)),
        (
            "mean_sigma1_from_1_percent_to_rate_strain_pa_at_full_speed",
            mean(first),
        ),
        ("rate_strain", rate_strain),
        ("platen_speed_m_s", slow.platen_speed),
        ("damping_number", slow.damping_number),
    ] {
        rate_run.metrics.insert(key.into(), value);
    }
    runs.push(rate_run);
    let mut friction_run = Run::new("friction study (dry)", "", grains, layer);
    for (mu, sample) in &study {
        friction_run
            .metrics
            .insert(format!("void_ratio_mu_{mu}"), sample.void_ratio);
        friction_run
            .metrics
            .insert(format!("coordination_mu_{mu}"), sample.coordination);
    }
    let (smooth, rough) = (&study[0].1, &study[study.len() - 1].1);
    checks.push(Check::at_least(
        "void_ratio_rough_minus_smooth",
        rough.void_ratio - smooth.void_ratio,
        0.0,
    ));
    checks.push(Check::at_least(
        "coordination_smooth_minus_rough",
        smooth.coordination - rough.coordination,
        0.0,
    ));
    runs.push(friction_run);

    let figure = figure(&shears, &envelopes, seeds[0]);
    // the first envelope's run, after the samples'
    let headline = shears.len();
    let mut record = Record::new(NAME, level, runs, Default::default(), checks, 0);
    record.headline_run = headline;
    Ok(ProblemOutput {
        record,
        profile: table,
        figure,
        snapshot: None,
    })
}

/// Deviator and volumetric strain against axial strain (first seed), and the envelopes'
/// c and φ against saturation.
fn figure(shears: &[Shear], envelopes: &[Envelope], seed: u64) -> Figure {
    let curves = |of: &dyn Fn(&blastsph_solver::dem::biaxial::BiaxialState) -> f64| {
        shears
            .iter()
            .filter(|s| s.seed == seed)
            .map(|s| Series {
                label: format!("S {:.0} %, σ3 {} Pa", 100.0 * s.saturation, s.confining),
                points: s
                    .run
                    .records
                    .iter()
                    .map(|r| (r.axial_strain, of(r)))
                    .collect(),
                style: Style::Line,
            })
            .collect()
    };
    let by_saturation = |of: &dyn Fn(&Envelope) -> f64, label: &str| Series {
        label: label.into(),
        points: envelopes
            .iter()
            .map(|e| (100.0 * e.saturation, of(e)))
            .collect(),
        style: Style::LineMarkers,
    };
    Figure {
        title: format!("{NAME}: DEM biaxial tests of moist sand (seed {seed})"),
        panels: vec![
            Panel {
                title: "deviator stress".into(),
                x_label: "axial strain".into(),
                y_label: "σ1 − σ3 (Pa)".into(),
                series: curves(&|r| r.sigma1 - r.sigma3),
                ..Panel::default()
            },
            Panel {
                title: "volumetric strain (compression positive)".into(),
                x_label: "axial strain".into(),
                y_label: "volumetric strain".into(),
                series: curves(&|r| r.volumetric_strain),
                ..Panel::default()
            },
            Panel {
                title: "cohesion".into(),
                x_label: "saturation (%)".into(),
                y_label: "c (Pa)".into(),
                series: vec![
                    by_saturation(&|e| e.peak.cohesion, "peak"),
                    by_saturation(&|e| e.critical.cohesion, "critical state"),
                ],
                ..Panel::default()
            },
            Panel {
                title: "friction angle".into(),
                x_label: "saturation (%)".into(),
                y_label: "φ (degrees)".into(),
                series: vec![
                    by_saturation(&|e| e.peak.friction_angle_degrees, "peak"),
                    by_saturation(&|e| e.critical.friction_angle_degrees, "critical state"),
                ],
                ..Panel::default()
            },
        ],
    }
}
