//! `kernel-interpolation`: the seed thesis' example of SPH interpolation of y = 1 on
//! X = {1, …, 8} (Δx = 1) with the cubic spline at h = 0.3, 0.75, 1.55, 2.6, by standard SPH
//! and Shepard-corrected; and the first derivative of y = 2x + 1 by standard SPH and by CSPM.
//!
//! Facts checked: the standard interpolant is within 0.01 of 1 where no neighbour is missing
//! (x = 4, 5 at h = 1.55, where the discrete sum of a cubic spline with h/Δx = 1.55 deviates
//! ~1e-3 from unity) and loses more than 0.2 at the ends, where half the kernel falls outside
//! the data. Shepard's and CSPM's errors are reported: both reproduce their fields by
//! construction (Σ W u / Σ W with u = 1; a gradient corrected by the inverse of the kernel
//! moment), which `solver/tests/integration/operators.rs` tests as wiring, not as verification.

use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::svg::{Figure, Panel, Series, Style};
use crate::{Level, VerifyError};
use blastsph_solver::operators::{
    cspm_gradient, shepard_interpolate, sph_gradient, sph_interpolate, PointSet,
};
use blastsph_solver::{Kernel, KernelShape, Vector};
use std::collections::BTreeMap;

pub const NAME: &str = "kernel-interpolation";
const SMOOTHING_LENGTHS: [f64; 4] = [0.3, 0.75, 1.55, 2.6];
const EVALUATION_POINTS: usize = 20;

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary:
            "y = 1 and y = 2x + 1 on eight points: standard SPH vs Shepard, SPH derivative vs CSPM",
        params: vec![ParamSpec::new(
            "kernel",
            "cubic-spline",
            "kernel shape (the thesis uses the cubic spline)",
        )],
    }
}

pub fn run(params: &Params) -> Result<ProblemOutput, VerifyError> {
    let kernel = Kernel::<1>::new(params.choice("kernel", &KernelShape::ALL, KernelShape::name)?);
    let data_x: Vec<Vector<1>> = (1..=8).map(|k| Vector::<1>::new(k as f64)).collect();
    let volume = vec![1.0; data_x.len()];
    let ones = vec![1.0; data_x.len()];
    let linear: Vec<f64> = data_x.iter().map(|x| 2.0 * x[0] + 1.0).collect();
    let constant = PointSet {
        position: &data_x,
        volume: &volume,
        value: &ones,
    };
    let line = PointSet {
        position: &data_x,
        volume: &volume,
        value: &linear,
    };
    let eval_x: Vec<f64> = (0..EVALUATION_POINTS)
        .map(|k| 1.0 + 7.0 * k as f64 / (EVALUATION_POINTS - 1) as f64)
        .collect();

    let mut columns = vec!["x".to_string()];
    let mut table_columns: Vec<Vec<f64>> = vec![eval_x.clone()];
    let (mut runs, mut checks) = (Vec::new(), Vec::new());
    let mut panels = vec![
        panel("standard SPH: y = 1", "u(x)"),
        panel("Shepard corrected: y = 1", "u(x)"),
        panel("dy/dx of y = 2x + 1 at the data points", "du/dx"),
    ];
    for h in SMOOTHING_LENGTHS {
        let start = std::time::Instant::now();
        // evaluation at the 20 points and at the 8 data points
        let all_x: Vec<f64> = eval_x
            .iter()
            .copied()
            .chain(data_x.iter().map(|x| x[0]))
            .collect();
        let standard: Vec<f64> = all_x
            .iter()
            .map(|&x| sph_interpolate(&kernel, h, &constant, &Vector::<1>::new(x)))
            .collect();
        let shepard: Vec<f64> = all_x
            .iter()
            .map(|&x| {
                shepard_interpolate(&kernel, h, &constant, &Vector::<1>::new(x)).unwrap_or(f64::NAN)
            })
            .collect();
        let sph_derivative: Vec<f64> = (0..data_x.len())
            .map(|i| sph_gradient(&kernel, h, &line, i)[0])
            .collect();
        let cspm_derivative: Vec<Option<f64>> = (0..data_x.len())
            .map(|i| cspm_gradient(&kernel, h, &line, i).map(|g| g[0]))
            .collect();
        let max_dev = |v: &[f64]| v.iter().map(|u| (u - 1.0).abs()).fold(0.0, f64::max);
        // NaN where an operator is undefined (no neighbour within the support)
        let worst = |v: &mut dyn Iterator<Item = f64>| {
            v.fold(
                0.0,
                |a: f64, d| if d.is_nan() { f64::NAN } else { a.max(d) },
            )
        };
        let shepard_dev = worst(&mut shepard.iter().map(|u| (u - 1.0).abs()));
        let cspm_err = worst(
            &mut cspm_derivative
                .iter()
                .map(|d| d.map_or(f64::NAN, |d| (d - 2.0).abs())),
        );
        let mut errors = BTreeMap::new();
        errors.insert("standard_max_deviation".into(), max_dev(&standard));
        errors.insert("shepard_max_deviation".into(), shepard_dev);
        errors.insert(
            "sph_derivative_max_error".into(),
            sph_derivative
                .iter()
                .map(|d| (d - 2.0).abs())
                .fold(0.0, f64::max),
        );
        errors.insert("cspm_derivative_max_error".into(), cspm_err);
        runs.push(Run {
            formulation: String::new(),
            label: format!("h = {h}"),
            n_particles: data_x.len(),
            steps: 0,
            wall_s: start.elapsed().as_secs_f64(),
            spacing: 1.0,
            errors,
            metrics: BTreeMap::new(),
            phase_s: BTreeMap::new(),
            failure: None,
            sensitivity: None,
            gauges: Vec::new(),
        });
        columns.push(format!("standard_h{h}"));
        table_columns.push(standard[..EVALUATION_POINTS].to_vec());
        columns.push(format!("shepard_h{h}"));
        table_columns.push(shepard[..EVALUATION_POINTS].to_vec());
        let curve = |v: &[f64]| {
            eval_x
                .iter()
                .copied()
                .zip(v.iter().copied())
                .collect::<Vec<_>>()
        };
        panels[0].series.push(Series {
            label: format!("h = {h}"),
            points: curve(&standard),
            style: Style::Line,
        });
        panels[1].series.push(Series {
            label: format!("h = {h}"),
            points: curve(&shepard),
            style: Style::Line,
        });
        if h == 1.55 {
            let at_data = |x: f64| standard[EVALUATION_POINTS + x as usize - 1];
            for x in [4.0, 5.0] {
                checks.push(Check::at_most(
                    format!("standard_h1.55_deviation_at_x{x}"),
                    (at_data(x) - 1.0).abs(),
                    0.01,
                ));
            }
            for x in [1.0, 8.0] {
                checks.push(Check::at_least(
                    format!("standard_h1.55_deficit_at_x{x}"),
                    1.0 - at_data(x),
                    0.2,
                ));
            }
            let points = |v: Vec<f64>| data_x.iter().map(|x| x[0]).zip(v).collect::<Vec<_>>();
            panels[2].series.push(Series {
                label: "standard SPH, h = 1.55".into(),
                points: points(sph_derivative.clone()),
                style: Style::Markers,
            });
            panels[2].series.push(Series {
                label: "CSPM, h = 1.55".into(),
                points: points(
                    cspm_derivative
                        .iter()
                        .map(|d| d.unwrap_or(f64::NAN))
                        .collect(),
                ),
                style: Style::Markers,
            });
            panels[2].series.push(Series {
                label: "exact".into(),
                points: vec![(1.0, 2.0), (8.0, 2.0)],
                style: Style::Line,
            });
        }
    }
    let rows = (0..EVALUATION_POINTS)
        .map(|k| table_columns.iter().map(|c| c[k]).collect())
        .collect();
    Ok(ProblemOutput {
        record: Record {
            problem: NAME.into(),
            level: Level::Quick,
            parameters: BTreeMap::new(),
            overrides: BTreeMap::new(),
            runs,
            order: BTreeMap::new(),
            checks,
            outcome: crate::record::Outcome::Fail,
            wall_s: 0.0,
            // h = 1.55, the case the thesis discusses
            headline_run: SMOOTHING_LENGTHS
                .iter()
                .position(|&h| h == 1.55)
                .unwrap_or(0),
        },
        profile: Table { columns, rows },
        figure: Figure {
            title: "kernel interpolation on X = {1, ..., 8}".into(),
            panels,
        },
        snapshot: None,
    })
}

fn panel(title: &str, y_label: &str) -> Panel {
    Panel {
        title: title.into(),
        x_label: "x".into(),
        y_label: y_label.into(),
        series: Vec::new(),
        ..Panel::default()
    }
}
