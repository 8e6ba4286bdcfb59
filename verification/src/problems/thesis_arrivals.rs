//! `thesis-arrivals`: the source thesis' first-arrival table against what physics allows. A
//! wave from a surface charge cannot reach a gauge d deep before d/c_max, with c_max the
//! fastest wave the soil and the concrete lining carry (`scaled::arrivals`). The thesis
//! reports 0.004–0.014 ms at 10–20 m: implied speeds of 1.0–2.9 × 10⁶ m/s, over 200 times
//! c_max. The problem passes when the check flags every entry: it is the harness proving it
//! catches an error of units of this kind before a tunnel result rests on it.

use crate::materials::Library;
use crate::params::{ParamSpec, Params};
use crate::record::{Check, ProblemOutput, Record, Run, Table};
use crate::scaled::arrivals::{check_arrivals, read_arrivals};
use crate::svg::{Figure, Panel, Series, Style};
use crate::{Level, VerifyError};
use std::collections::BTreeMap;

pub const NAME: &str = "thesis-arrivals";

const TABLE: &str = include_str!("../../../reference_data/thesis_arrivals.csv");

pub fn info() -> super::ProblemInfo {
    super::ProblemInfo {
        name: NAME,
        summary: "the source thesis' tunnel arrival times against the earliest arrival physics allows (depth / fastest wave speed)",
        params: vec![ParamSpec::new(
            "soil",
            "dry-sand",
            "the soil of the library whose fully compacted sound speed bounds the wave speed (with the concrete lining's)",
        )],
    }
}

pub fn run(params: &Params) -> Result<ProblemOutput, VerifyError> {
    let start = std::time::Instant::now();
    let soil = params.text("soil");
    let arrivals = read_arrivals(TABLE, "reference_data/thesis_arrivals.csv")?;
    let report = check_arrivals(&Library::standard(), &soil, &arrivals)?;
    let mut checks = Vec::new();
    let mut table = Table::new(&[
        "depth_m",
        "charge_kg",
        "invert",
        "arrival_s",
        "implied_speed_m_s",
        "min_possible_arrival_s",
    ]);
    for entry in &report.entries {
        // flagged: the implied speed exceeds the fastest the ground and lining can carry
        checks.push(Check::at_least(
            format!(
                "{}_{}m_{}kg_implied_speed_over_c_max",
                entry.gauge, entry.depth_m, entry.charge_kg
            ),
            entry.implied_speed_m_s / report.c_max_m_s,
            1.0,
        ));
        table.rows.push(vec![
            entry.depth_m,
            entry.charge_kg,
            f64::from(u8::from(entry.gauge == "invert")),
            entry.arrival_s,
            entry.implied_speed_m_s,
            entry.min_possible_arrival_s,
        ]);
    }
    let slowest = report
        .entries
        .iter()
        .map(|e| e.implied_speed_m_s)
        .fold(f64::INFINITY, f64::min);
    let mut run = Run::new(
        "thesis table",
        format!("c_max of {soil} and concrete"),
        0,
        0.0,
    );
    run.wall_s = start.elapsed().as_secs_f64();
    run.metrics = BTreeMap::from([
        ("c_max_m_s".to_string(), report.c_max_m_s),
        ("slowest_implied_speed_m_s".to_string(), slowest),
        (
            "entries_flagged".to_string(),
            report.entries.iter().filter(|e| !e.possible).count() as f64,
        ),
        ("entries".to_string(), report.entries.len() as f64),
    ]);
    let series = |gauge: &str, value: fn(&crate::scaled::arrivals::ArrivalCheck) -> f64| {
        report
            .entries
            .iter()
            .filter(|e| e.gauge == gauge)
            .map(|e| (e.depth_m, 1e3 * value(e)))
            .collect::<Vec<_>>()
    };
    let figure = Figure {
        title: "Reported first arrivals against the earliest possible".into(),
        panels: vec![Panel {
            title: format!("c_max = {:.0} m/s", report.c_max_m_s),
            x_label: "depth (m)".into(),
            y_label: "arrival (ms)".into(),
            series: vec![
                Series {
                    label: "earliest possible, depth / c_max".into(),
                    points: series("crown", |e| e.min_possible_arrival_s),
                    style: Style::LineMarkers,
                },
                Series {
                    label: "thesis, crown".into(),
                    points: series("crown", |e| e.arrival_s),
                    style: Style::Markers,
                },
                Series {
                    label: "thesis, invert".into(),
                    points: series("invert", |e| e.arrival_s),
                    style: Style::Markers,
                },
            ],
            ..Panel::default()
        }],
    };
    Ok(ProblemOutput {
        record: Record::new(NAME, Level::Quick, vec![run], BTreeMap::new(), checks, 0),
        profile: table,
        figure,
        snapshot: None,
    })
}
