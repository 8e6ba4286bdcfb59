//! `capillary-pair`: the force of one pendular water bridge between two equal spheres against
//! the gap, for the volumes V* = V/R³ = 0.001, 0.01, 0.05, 0.1 and contact angles 0° and 20°:
//! the closed-form laws of solver::dem::capillary against the exact Laplace–Young bridge
//! (laplace_young.rs). Forces as F* = F/(2πγR), gaps as S* = S/R.
//!
//! Measured per volume and angle: each law's largest relative error against the exact force
//! over the gaps up to half the rupture distance (Lian et al.: S_c = (1 + θ/2) V^{1/3}), the
//! largest gap at which an exact bridge of that volume exists (its own rupture) beside S_c.

use crate::laplace_young;
use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Figure, Panel, Series, Style};
use crate::VerifyError;
use blastsph_solver::dem::capillary::{
    bridge_force, rupture_gap, BridgeLaw, Liquid, RuptureCriterion,
};
use rayon::prelude::*;
use std::f64::consts::PI;

pub const NAME: &str = "capillary-pair";
const VOLUMES: [f64; 4] = [0.001, 0.01, 0.05, 0.1];
const ANGLES_DEGREES: [f64; 2] = [0.0, 20.0];

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "one liquid bridge: closed-form force laws against the exact Laplace–Young shape",
        params: vec![ParamSpec::per_level(
            "gaps",
            11,
            21,
            "gaps per curve, evenly from contact to the rupture distance",
        )],
    }
}

/// F* of `law` for volume V*, angle θ (rad), gap S* (unit radius and 2πγ = 1).
fn law_force(law: BridgeLaw, volume: f64, theta: f64, gap: f64) -> Result<f64, VerifyError> {
    let liquid = Liquid {
        volume,
        surface_tension: 1.0 / (2.0 * PI),
        contact_angle: theta,
    };
    Ok(bridge_force(law, &liquid, 1.0, gap)?)
}

/// One curve: (S*, exact F*, each law's F*) where the exact bridge exists.
type Curve = Vec<(f64, f64, [f64; 4])>;

pub fn run(params: &Params) -> Result<ProblemOutput, VerifyError> {
    let gaps = params.number("gaps", 3.0, 200.0)?.round() as usize;
    let mut runs = Vec::new();
    let mut checks = Vec::new();
    let mut table = Table::new(&[
        "volume",
        "theta_deg",
        "gap",
        "laplace_young",
        "willett",
        "simple",
        "rabinovich",
        "toroidal",
    ]);
    let mut panels = Vec::new();
    let mut spans: Vec<(f64, f64, f64)> = Vec::new(); // (θ, V*, exact span)
    let mut mid_forces: Vec<(f64, f64, f64, f64)> = Vec::new(); // (θ, V*, S*, F*)
    for &degrees in &ANGLES_DEGREES {
        let theta = degrees.to_radians();
        let mut series = Vec::new();
        for &volume in &VOLUMES {
            let start = std::time::Instant::now();
            let liquid = Liquid {
                volume,
                surface_tension: 1.0,
                contact_angle: theta,
            };
            let rupture = rupture_gap(RuptureCriterion::Lian, &liquid, 1.0);
            let curve: Curve = (0..gaps)
                .into_par_iter()
                .map(|k| {
                    let gap = rupture * k as f64 / (gaps - 1) as f64;
                    let Some(exact) = laplace_young::solve(volume, theta, gap) else {
                        return Ok(None);
                    };
                    let mut laws = [0.0; 4];
                    for (force, law) in laws.iter_mut().zip(BridgeLaw::ALL) {
                        *force = law_force(law, volume, theta, gap)?;
                    }
                    Ok(Some((gap, exact.force, laws)))
                })
                .collect::<Result<Vec<_>, VerifyError>>()?
                .into_iter()
                .flatten()
                .collect();
            let label = format!("V* = {volume}, θ = {degrees}°");
            let mut run = Run::new(label.clone(), "", 2, volume);
            run.wall_s = start.elapsed().as_secs_f64();
            for (k, law) in BridgeLaw::ALL.iter().enumerate() {
                let error = curve
                    .iter()
                    .filter(|q| q.0 <= 0.5 * rupture + 1e-12)
                    .map(|q| (q.2[k] / q.1 - 1.0).abs())
                    .fold(0.0, f64::max);
                run.errors
                    .insert(format!("{}_max_relative_error", law.name()), error);
            }
            let span = curve.last().map_or(0.0, |q| q.0);
            run.metrics.insert("lian_rupture_gap".into(), rupture);
            run.metrics
                .insert("laplace_young_largest_gap_solved".into(), span);
            run.metrics
                .insert("laplace_young_contact_force".into(), curve[0].1);
            spans.push((degrees, volume, span));
            // the force at the middle of the smallest volume's half-rupture range
            let probe = 0.5
                * rupture_gap(
                    RuptureCriterion::Lian,
                    &Liquid {
                        volume: VOLUMES[0],
                        ..liquid
                    },
                    1.0,
                );
            if let Some(b) = laplace_young::solve(volume, theta, probe) {
                mid_forces.push((degrees, volume, probe, b.force));
            }
            let monotone = curve.windows(2).all(|w| w[1].1 < w[0].1);
            checks.push(Check::at_least(
                format!("exact_force_falls_with_gap_{label}"),
                f64::from(u8::from(monotone)),
                1.0,
            ));
            // Willett's fit within 3 %, the toroidal gorge form within 8 %
            checks.push(Check::at_most(
                format!("willett_max_relative_error_{label}"),
                run.errors["willett_max_relative_error"],
                0.03,
            ));
            checks.push(Check::at_most(
                format!("toroidal_max_relative_error_{label}"),
                run.errors["toroidal_max_relative_error"],
                0.08,
            ));
            for q in &curve {
                let mut row = vec![volume, degrees, q.0, q.1];
                row.extend_from_slice(&q.2);
                table.rows.push(row);
            }
            series.push(Series {
                label: format!("V* = {volume}, Laplace–Young"),
                points: curve.iter().map(|q| (q.0, q.1)).collect(),
                style: Style::Line,
            });
            series.push(Series {
                label: format!("V* = {volume}, Willett fit"),
                points: curve.iter().map(|q| (q.0, q.2[0])).collect(),
                style: Style::Markers,
            });
            runs.push(run);
        }
        panels.push(Panel {
            title: format!("θ = {degrees}°"),
            x_label: "gap S/R".into(),
            y_label: "F/(2πγR)".into(),
            series,
            ..Panel::default()
        });
    }
    // the source paper's figure 5 trend: a larger bridge reaches farther and, once the
    // spheres are apart, pulls harder
    for &degrees in &ANGLES_DEGREES {
        let of_angle = |v: &[(f64, f64, f64)]| {
            v.iter()
                .filter(|q| q.0 == degrees)
                .map(|q| q.2)
                .collect::<Vec<f64>>()
        };
        let reach = of_angle(&spans);
        checks.push(Check::at_least(
            format!("larger_volume_reaches_farther_theta_{degrees}"),
            f64::from(u8::from(reach.windows(2).all(|w| w[1] > w[0]))),
            1.0,
        ));
        let pulls: Vec<f64> = mid_forces
            .iter()
            .filter(|q| q.0 == degrees)
            .map(|q| q.3)
            .collect();
        checks.push(Check::at_least(
            format!("larger_volume_pulls_harder_apart_theta_{degrees}"),
            f64::from(u8::from(
                pulls.len() == VOLUMES.len() && pulls.windows(2).all(|w| w[1] > w[0]),
            )),
            1.0,
        ));
    }
    let figure = Figure {
        title: format!(
            "{NAME}: bridge force against gap, exact (lines) and Willett's fit (markers), V* = {VOLUMES:?}"
        ),
        panels,
    };
    Ok(ProblemOutput {
        record: Record::new(
            NAME,
            crate::Level::Quick,
            runs,
            Default::default(),
            checks,
            0,
        ),
        profile: table,
        figure,
        snapshot: None,
    })
}
