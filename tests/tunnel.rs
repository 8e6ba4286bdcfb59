//! The tunnel study's quick model on its review case: the crown 10 m below 500 kg.

use blastsph_verification::scene::Checkpoints;
use blastsph_verification::surface_burst::Soil;
use blastsph_verification::tunnel::{run_charge, Tunnel, QUICK};
use serde_json::{json, Value};
use std::path::Path;

#[path = "common/review.rs"]
mod review;

/// A gauge's history at 50 equally spaced times (the last recorded row at or before each), in
/// reviewable units: ms, MPa, m/s.
fn curves(csv: &Path) -> Value {
    let mut reader = csv::Reader::from_path(csv).expect("the gauge CSV exists");
    let headers = reader.headers().expect("a header row").clone();
    let column = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{name} in {csv:?}"))
    };
    let (t, p, vy, vm) = (
        column("time_s"),
        column("pressure_pa"),
        column("velocity_y_m_s"),
        column("von_mises_pa"),
    );
    let rows: Vec<Vec<f64>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(|x| x.parse().unwrap()).collect())
        .collect();
    let end = rows.last().expect("rows")[t];
    let mut sampled = Vec::new();
    for k in 0..50 {
        let time = end * k as f64 / 49.0;
        let row = rows
            .iter()
            .take_while(|row| row[t] <= time)
            .last()
            .expect("the first row is at t = 0");
        sampled.push(json!([
            1e3 * row[t],
            1e-6 * row[p],
            row[vy],
            1e-6 * row[vm]
        ]));
    }
    json!({ "columns": ["t_ms", "pressure_mpa", "velocity_y_m_s", "von_mises_mpa"], "rows": sampled })
}

/// The quick case at 10 m under 500 kg: the physical checks the study makes (arrival no
/// sooner than the fastest wave allows and within 30 % of the free field's at the crown,
/// energy within 1 % of what the band brought in, the section without the tunnel within 30 %
/// of the free field), then its crown and invert curves and its summary row, to three
/// significant digits, against the reviewed snapshot `tests/snapshots/tunnel__*.snap` (a
/// change of the physics shows as a diff in `cargo insta review`; the snapshot checks nothing).
#[test]
fn the_10m_500kg_quick_case_matches_its_reviewed_curves() {
    let out = std::env::temp_dir().join(format!("blastsph-tunnel-review-{}", std::process::id()));
    let case = run_charge(
        500.0,
        &[10.0],
        &Soil::default(),
        Tunnel::default(),
        QUICK,
        &out,
        &|_, _| {},
        &Checkpoints::default(),
    )
    .expect("the case runs")
    .remove(0);
    assert!(case.stopped.is_none(), "{:?}", case.stopped);
    let (crown, free) = (&case.gauges["crown"], &case.gauges["free_field_at_crown"]);
    // the fastest wave: the library's fully compacted sand, 4636 m/s
    assert!(crown.arrival_s >= 10.0 / 4636.0, "{}", crown.arrival_s);
    assert!((crown.arrival_s / free.arrival_s - 1.0).abs() <= 0.30);
    assert!(case.energy_relative_error <= 0.01);
    assert!((case.reduction_ratio - 1.0).abs() <= 0.30);
    let gauges = out.join("cases/10m-500kg/section/gauges");
    let review = json!({
        "case": review::reviewable(serde_json::to_value(&case).unwrap(), &["wall_s"]),
        "crown": review::reviewable(curves(&gauges.join("crown.csv")), &[]),
        "invert": review::reviewable(curves(&gauges.join("invert.csv")), &[]),
    });
    let _ = std::fs::remove_dir_all(&out);
    insta::assert_json_snapshot!("quick-10m-500kg", review);
}
