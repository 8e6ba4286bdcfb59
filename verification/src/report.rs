//! Writes a problem's outputs: `<problem>.json`, `<problem>.csv`, `<problem>.svg`. Each file is
//! written under a temporary name and renamed into place, so a file with the final name is
//! always complete.

use crate::record::{ProblemOutput, Record, Table};
use crate::svg::{Figure, Panel, Scale, Series, Style};
use crate::VerifyError;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` atomically (temporary file in the same folder, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), VerifyError> {
    let io = |source| VerifyError::Io {
        path: path.display().to_string(),
        source,
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&temporary, bytes).map_err(io)?;
    std::fs::rename(&temporary, path).map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        io(e)
    })
}

pub fn table_to_csv(table: &Table) -> Vec<u8> {
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer
        .write_record(&table.columns)
        .expect("writing to memory");
    for row in &table.rows {
        writer
            .write_record(row.iter().map(|v| format!("{v:e}")))
            .expect("writing to memory");
    }
    writer.into_inner().expect("writing to memory")
}

/// Creates `dir` if missing and proves it writable by writing and removing a probe file, so that
/// a run whose outputs could not be saved is refused before it starts.
pub fn ensure_writable(dir: &Path) -> Result<(), VerifyError> {
    let io = |source| VerifyError::Io {
        path: dir.display().to_string(),
        source,
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    let probe = dir.join(format!(".write-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(io)?;
    std::fs::remove_file(&probe).map_err(io)
}

/// Writes each (name, bytes) into `dir` atomically, in order; returns the paths.
fn write_files<N: AsRef<str>>(
    dir: &Path,
    files: impl IntoIterator<Item = (N, Vec<u8>)>,
) -> Result<Vec<PathBuf>, VerifyError> {
    files
        .into_iter()
        .map(|(name, bytes)| {
            let path = dir.join(name.as_ref());
            write_atomic(&path, &bytes).map(|_| path)
        })
        .collect()
}

/// Writes JSON, CSV and SVG of one problem into `dir` (created if missing); returns the paths.
pub fn write_outputs(dir: &Path, output: &ProblemOutput) -> Result<Vec<PathBuf>, VerifyError> {
    std::fs::create_dir_all(dir).map_err(|source| VerifyError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let stem = &output.record.problem;
    let json = serde_json::to_vec_pretty(&output.record).expect("records serialise");
    let files = [
        (format!("{stem}.csv"), table_to_csv(&output.profile)),
        (format!("{stem}.svg"), output.figure.to_svg().into_bytes()),
        // the JSON last: its presence says the others are there too
        (format!("{stem}.json"), json),
    ];
    write_files(dir, files)
}

/// `<problem>.vtu`: the particles at the end of the finest run (for ParaView), where the
/// problem ran a simulation. Written atomically like the other outputs.
pub fn write_snapshot(dir: &Path, output: &ProblemOutput) -> Result<Option<PathBuf>, VerifyError> {
    let Some(snapshot) = &output.snapshot else {
        return Ok(None);
    };
    std::fs::create_dir_all(dir).map_err(|source| VerifyError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let name = format!("{}.vtu", output.record.problem);
    let mut written = write_files(dir, [(name, snapshot.to_vtu().into_bytes())])?;
    Ok(written.pop())
}

/// A series' label and its (wall time, error) points.
type LabelledPoints = (String, Vec<(f64, f64)>);

/// A peer code's measured point on one of this suite's problems.
#[derive(Debug, serde::Deserialize)]
struct PeerPoint {
    peer: String,
    problem: String,
    error_name: String,
    error: f64,
    wall_s: f64,
}

/// The peer points of `reference_data/peer_work_precision.csv` (source in its first line).
fn peer_points() -> Vec<PeerPoint> {
    const TABLE: &str = include_str!("../../reference_data/peer_work_precision.csv");
    crate::reference_table(TABLE)
        .deserialize()
        .collect::<Result<_, _>>()
        .expect("the peer table parses")
}

/// The panel of the work–precision figure a problem's runs go to.
fn problem_family(problem: &str) -> &'static str {
    if problem == "sod" || problem.starts_with("toro") {
        "shock tubes"
    } else if problem.starts_with("sedov") {
        "Sedov blasts"
    } else if problem.starts_with("airblast") || problem == "hopkinson-cranz" {
        "air blast against Kingery–Bulmash"
    } else if problem.starts_with("ground-shock") || problem == "transmitting-boundary" {
        "ground shock and its boundaries"
    } else if problem.starts_with("taylor-bar")
        || problem == "elastic-wave"
        || problem == "colliding-rings"
    {
        "solids"
    } else {
        "interfaces and detonation"
    }
}

/// Adds `point` to the series `label` of `family`, each made on first use (so in order of
/// first appearance).
fn add_point(
    families: &mut Vec<(&'static str, Vec<LabelledPoints>)>,
    family: &'static str,
    label: String,
    point: (f64, f64),
) {
    let series = match families.iter().position(|(f, _)| *f == family) {
        Some(k) => &mut families[k].1,
        None => {
            families.push((family, Vec::new()));
            &mut families.last_mut().expect("just pushed").1
        }
    };
    match series.iter_mut().find(|(l, _)| *l == label) {
        Some((_, points)) => points.push(point),
        None => series.push((label, vec![point])),
    }
}

/// Work against precision over several problems: the headline error of every completed run
/// against its wall time (logarithmic axes), one panel per problem family and one series per
/// problem and formulation, as SVG and CSV. Where a peer code was measured on a problem
/// (`reference_data/peer_work_precision.csv`), its point joins the panel, and the problem's
/// runs are also plotted in the peer's error if that is not their headline. Returns the paths
/// and the SVG.
pub fn write_work_precision(
    dir: &Path,
    records: &[Record],
) -> Result<(Vec<PathBuf>, String), VerifyError> {
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record([
        "problem",
        "formulation",
        "run",
        "n_particles",
        "steps",
        "wall_s",
        "error_name",
        "error",
    ])
    .expect("writing to memory");
    let peers = peer_points();
    // per family, one series per problem, formulation and error, in order of first appearance
    let mut families: Vec<(&'static str, Vec<LabelledPoints>)> = Vec::new();
    for record in records {
        let family = problem_family(&record.problem);
        let peer_errors = peers
            .iter()
            .filter(|peer| peer.problem == record.problem)
            .map(|peer| peer.error_name.as_str());
        for run in record
            .runs
            .iter()
            .filter(|r| r.failure.is_none() && r.sensitivity.is_none())
        {
            let Some((headline, _)) = run.headline_error() else {
                continue;
            };
            let mut names = vec![headline];
            for name in peer_errors.clone() {
                if !names.contains(&name) {
                    names.push(name);
                }
            }
            for name in names {
                let Some(&error) = run.errors.get(name) else {
                    continue;
                };
                csv.write_record([
                    record.problem.clone(),
                    run.formulation.clone(),
                    run.label.clone(),
                    run.n_particles.to_string(),
                    run.steps.to_string(),
                    format!("{:e}", run.wall_s),
                    name.to_string(),
                    format!("{error:e}"),
                ])
                .expect("writing to memory");
                if run.wall_s > 0.0 && error > 0.0 {
                    let label = if run.formulation.is_empty() {
                        format!("{}: {name}", record.problem)
                    } else {
                        format!("{} ({}): {name}", record.problem, run.formulation)
                    };
                    add_point(&mut families, family, label, (run.wall_s, error));
                }
            }
        }
    }
    let mut peer_labels = Vec::new();
    for peer in &peers {
        if records.iter().any(|r| r.problem == peer.problem) {
            let label = format!("{} {}: {}", peer.peer, peer.problem, peer.error_name);
            let family = problem_family(&peer.problem);
            add_point(
                &mut families,
                family,
                label.clone(),
                (peer.wall_s, peer.error),
            );
            peer_labels.push(label);
        }
    }
    let panels = families
        .into_iter()
        .map(|(family, series)| Panel {
            title: family.to_string(),
            x_label: "wall time (s)".into(),
            y_label: "error (named in the legend)".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            series: series
                .into_iter()
                .map(|(label, mut points)| {
                    points.sort_by(|a, b| a.0.total_cmp(&b.0));
                    // a peer's measured point stands alone
                    let style = if peer_labels.contains(&label) {
                        Style::Markers
                    } else {
                        Style::LineMarkers
                    };
                    Series {
                        label,
                        points,
                        style,
                    }
                })
                .collect(),
        })
        .collect();
    let figure = Figure {
        title: format!(
            "work–precision: headline error against wall time ({} cores)",
            rayon::current_num_threads()
        ),
        panels,
    };
    let svg = figure.to_svg();
    let files = [
        (
            "work-precision.csv",
            csv.into_inner().expect("writing to memory"),
        ),
        ("work-precision.svg", svg.clone().into_bytes()),
    ];
    Ok((write_files(dir, files)?, svg))
}

/// `index.html`: the whole suite on one page (see [`crate::index`]), written atomically.
pub fn write_index(
    dir: &Path,
    heading: &str,
    entries: &[crate::index::Entry],
    work_precision_svg: &str,
) -> Result<PathBuf, VerifyError> {
    let html = crate::index::page(heading, entries, work_precision_svg);
    let mut written = write_files(dir, [("index.html", html.into_bytes())])?;
    Ok(written.pop().expect("one file"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::Run;
    use crate::Level;

    /// A measured peer point joins its problem's panel as a lone marker, and the problem's runs
    /// are plotted in the peer's error beside their headline error.
    #[test]
    fn peer_points_join_their_problem_in_the_peers_error() {
        let peer = peer_points()
            .into_iter()
            .find(|p| p.problem == "sedov-2d")
            .expect("a Sedov 2D peer point");
        let run = |n: usize, wall_s: f64| {
            let mut run = Run::new(format!("n = {n}"), "grad-h", n, 1.0 / n as f64);
            run.wall_s = wall_s;
            run.errors = [("l1_rho".into(), 0.1), (peer.error_name.clone(), 0.02)].into();
            run
        };
        let record = Record::new(
            "sedov-2d",
            Level::Quick,
            vec![run(900, 0.5), run(3600, 2.0)],
            Default::default(),
            Vec::new(),
            1,
        );
        let dir = std::env::temp_dir().join(format!("blastsph-peers-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (_, svg) = write_work_precision(&dir, &[record]).unwrap();
        let csv = std::fs::read_to_string(dir.join("work-precision.csv")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(svg.contains(&format!("{} sedov-2d: {}", peer.peer, peer.error_name)));
        assert!(svg.contains(&format!("sedov-2d (grad-h): {}", peer.error_name)));
        assert!(svg.contains("sedov-2d (grad-h): l1_rho"));
        // two runs, each in two errors
        assert_eq!(
            csv.lines().filter(|l| l.starts_with("sedov-2d,")).count(),
            4
        );
    }
}
