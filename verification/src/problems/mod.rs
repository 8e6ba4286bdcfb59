//! The canonical problem suite. Each problem: parameters with per-level defaults, a setup, an
//! exact answer, checks with justified limits.

pub(crate) mod airblast;
mod biaxial;
mod capillary_pair;
mod colliding_rings;
mod density_ratio_tube;
mod elastic_wave;
pub mod ground_shock;
pub mod ground_shock_surface;
mod impedance_mismatch;
mod kernel_interpolation;
mod sedov_blast;
mod shock_tube;
mod taylor_bar;
mod thesis_arrivals;
mod tnt_slab;
mod transmitting_boundary;

pub(crate) use airblast::viscosity_switched_down_to;
pub use biaxial::biaxial_run;

use crate::params::{ParamSpec, Params};
use crate::record::ProblemOutput;
use crate::{Level, VerifyError};

/// What the suite knows about a problem before running it.
#[derive(Clone, Debug)]
pub struct ProblemInfo {
    pub name: &'static str,
    pub summary: &'static str,
    pub params: Vec<ParamSpec>,
}

/// Every problem, in the order `blastsph verify` runs them.
pub fn all() -> Vec<ProblemInfo> {
    let mut list = vec![kernel_interpolation::info()];
    list.extend(shock_tube::infos());
    list.extend(sedov_blast::infos());
    list.extend(impedance_mismatch::infos());
    list.push(density_ratio_tube::info());
    list.push(tnt_slab::info());
    list.push(elastic_wave::info());
    list.push(colliding_rings::info());
    list.push(capillary_pair::info());
    list.push(biaxial::info());
    list.extend(taylor_bar::infos());
    list.push(thesis_arrivals::info());
    list.extend(airblast::infos());
    list.push(ground_shock::info());
    list.push(ground_shock_surface::info());
    list.push(transmitting_boundary::info());
    list
}

pub fn names() -> Vec<&'static str> {
    all().iter().map(|p| p.name).collect()
}

/// Looks a problem up by name, with the list of names in the error.
pub fn find(name: &str) -> Result<ProblemInfo, VerifyError> {
    all()
        .into_iter()
        .find(|p| p.name == name)
        .ok_or_else(|| VerifyError::UnknownProblem {
            name: name.to_string(),
            available: names().join(", "),
        })
}

/// Checks a problem's name and `--set` overrides, and that its runs fit in memory, without
/// running it: the command line calls this for every problem before it starts the first.
pub fn preflight(
    name: &str,
    level: Level,
    overrides: &[(String, String)],
) -> Result<(), VerifyError> {
    let info = find(name)?;
    let params = Params::new(name, &info.params, level, overrides)?;
    if sedov_blast::is_sedov(name) {
        sedov_blast::resolutions(name, &params)?;
    }
    if name == ground_shock::SPHERICAL {
        ground_shock::check_gauges(&params)?;
    }
    if name == ground_shock_surface::NAME {
        ground_shock_surface::check(&params)?;
    }
    Ok(())
}

/// Runs one problem at `level` with `--set` overrides; `progress` receives the fraction done.
/// The problem runs on a worker of the thread pool, so that the solver's parallel passes start
/// there rather than being handed over from an outside thread, which sleeps and wakes for each
/// one (for Sod's 720 particles that handover took a third of the run).
pub fn run(
    name: &str,
    level: Level,
    overrides: &[(String, String)],
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    rayon::scope(|_| run_here(name, level, overrides, progress))
}

/// One problem of [`run_many`]: its name and `--set` overrides.
pub struct Job {
    pub name: String,
    pub overrides: Vec<(String, String)>,
}

/// The problems whose quick level takes longest, longest first (wall seconds in the suite on
/// two cores, measured: 55, 20, 19, 12, 10, 10, 9, 8, 8, 7, 6; the rest take under 4).
/// [`run_many`] starts them before the others: with longest processing time first the pool's
/// workers run out of work at about the same time, while a long problem started last runs alone
/// at the end (the first 21 problems of the table took 65 s in table order on two cores, 60–62 s
/// so).
const LONGEST_FIRST: [&str; 11] = [
    "biaxial",
    "ground-shock-spherical",
    "ground-shock-surface",
    "colliding-rings",
    "taylor-bar-axisymmetric",
    "airblast-free-air",
    "taylor-bar-3d",
    "toro-5",
    "transmitting-boundary",
    "airblast-surface",
    "sedov-3d",
];

/// The order in which [`run_many`] starts `jobs` (indices): those of [`LONGEST_FIRST`] in its
/// order, then the rest in the jobs' order.
fn start_order(jobs: &[Job]) -> Vec<usize> {
    let rank = |job: &Job| {
        LONGEST_FIRST
            .iter()
            .position(|&name| name == job.name)
            .unwrap_or(LONGEST_FIRST.len())
    };
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&k| rank(&jobs[k]));
    order
}

/// Runs several problems at `level` at once, each on one worker of the thread pool, started in
/// [`start_order`]; a problem's own parallel passes go to workers that are free (a small
/// problem gains little from them: on two cores the quick suite takes 0.7 of the time it takes
/// one problem after another, each on both). `progress` receives
/// the job's index and its fraction done (0 when it starts). Each output goes to `done` in the
/// jobs' order as soon as it and those before it have finished. At the first error, whether a
/// problem's or `done`'s, no further problem starts, and that error is returned once the
/// running ones end. Every output is the same as [`run`]'s: results do not depend on which
/// worker runs them. Call it from outside the pool: it waits for the outputs, and a worker
/// waiting there could not run the problems.
pub fn run_many(
    level: Level,
    jobs: &[Job],
    progress: &(dyn Fn(usize, f64) + Sync),
    done: &mut dyn FnMut(usize, ProblemOutput) -> Result<(), VerifyError>,
) -> Result<(), VerifyError> {
    let stop = std::sync::atomic::AtomicBool::new(false);
    let (sender, finished) = std::sync::mpsc::channel();
    std::thread::scope(|threads| {
        let stop = &stop;
        threads.spawn(move || {
            rayon::scope_fifo(|scope| {
                for k in start_order(jobs) {
                    let (job, sender) = (&jobs[k], sender.clone());
                    scope.spawn_fifo(move |_| {
                        if stop.load(std::sync::atomic::Ordering::Relaxed) {
                            return;
                        }
                        progress(k, 0.0);
                        let output =
                            run_here(&job.name, level, &job.overrides, &|f| progress(k, f));
                        if output.is_err() {
                            stop.store(true, std::sync::atomic::Ordering::Relaxed);
                        }
                        // the receiver outlives the scope
                        let _ = sender.send((k, output));
                    });
                }
            });
        });
        let mut waiting: Vec<Option<Result<ProblemOutput, VerifyError>>> =
            jobs.iter().map(|_| None).collect();
        let (mut next, mut first_error) = (0, None);
        for (k, output) in finished {
            waiting[k] = Some(output);
            while let Some(output) = waiting.get_mut(next).and_then(Option::take) {
                let handed = output.and_then(|output| done(next, output));
                if let Err(error) = handed {
                    stop.store(true, std::sync::atomic::Ordering::Relaxed);
                    first_error.get_or_insert(error);
                }
                next += 1;
            }
        }
        first_error.map_or(Ok(()), Err)
    })
}

fn run_here(
    name: &str,
    level: Level,
    overrides: &[(String, String)],
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ProblemOutput, VerifyError> {
    let info = find(name)?;
    let params = Params::new(name, &info.params, level, overrides)?;
    let start = std::time::Instant::now();
    let mut output = if name == kernel_interpolation::NAME {
        kernel_interpolation::run(&params)?
    } else if name == thesis_arrivals::NAME {
        thesis_arrivals::run(&params)?
    } else if name == capillary_pair::NAME {
        capillary_pair::run(&params)?
    } else if name == biaxial::NAME {
        biaxial::run(&params, level, progress)?
    } else if name == colliding_rings::NAME {
        colliding_rings::run(&params, progress)?
    } else if taylor_bar::NAMES.contains(&name) {
        taylor_bar::run(name, &params, level, progress)?
    } else if name == elastic_wave::NAME {
        elastic_wave::run(&params, progress)?
    } else if airblast::NAMES.contains(&name) {
        airblast::run(name, &params, progress)?
    } else if name == transmitting_boundary::NAME {
        transmitting_boundary::run(&params, progress)?
    } else if name == ground_shock::SPHERICAL {
        ground_shock::run(&params, level, progress)?
    } else if name == ground_shock_surface::NAME {
        ground_shock_surface::run(&params, level, progress)?
    } else if name == tnt_slab::NAME {
        tnt_slab::run(&params, progress)?
    } else if name == density_ratio_tube::NAME {
        density_ratio_tube::run(&params, progress)?
    } else if impedance_mismatch::NAMES.contains(&name) {
        impedance_mismatch::run(name, &params, progress)?
    } else if sedov_blast::is_sedov(name) {
        sedov_blast::run(name, &params, level, progress)?
    } else {
        shock_tube::run(name, &params, level, progress)?
    };
    let record = &mut output.record;
    record.problem = name.to_string();
    record.level = level;
    record.parameters = params.values();
    record.overrides = params.overrides();
    record.wall_s = start.elapsed().as_secs_f64();
    record.settle();
    Ok(output)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job(name: &str, overrides: &[(&str, &str)]) -> Job {
        Job {
            name: name.into(),
            overrides: overrides
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
        }
    }

    /// The outputs come in the jobs' order, each the record one problem run alone gives.
    #[test]
    fn several_problems_at_once_come_back_in_order_as_run_alone() {
        let jobs = [
            job("sedov-spherical-1d", &[]),
            job(kernel_interpolation::NAME, &[]),
            job(thesis_arrivals::NAME, &[]),
        ];
        let mut seen = Vec::new();
        run_many(Level::Quick, &jobs, &|_, _| {}, &mut |k, output| {
            seen.push((k, output.record));
            Ok(())
        })
        .unwrap();
        assert_eq!(seen.iter().map(|(k, _)| *k).collect::<Vec<_>>(), [0, 1, 2]);
        for (k, record) in &seen {
            let alone = run(&jobs[*k].name, Level::Quick, &jobs[*k].overrides, &|_| {}).unwrap();
            let strip = |r: &crate::record::Record| {
                let mut v = serde_json::to_value(r).unwrap();
                v["wall_s"] = serde_json::Value::Null;
                for run in v["runs"].as_array_mut().unwrap() {
                    run["wall_s"] = serde_json::Value::Null;
                    run["phase_s"] = serde_json::Value::Null;
                }
                v
            };
            assert_eq!(strip(record), strip(&alone.record), "{}", jobs[*k].name);
        }
    }

    /// The long problems start first, longest first; the rest keep the jobs' order. Every
    /// name in the list is a problem's.
    #[test]
    fn the_longest_problems_start_first() {
        for name in LONGEST_FIRST {
            assert!(find(name).is_ok(), "{name}");
        }
        let jobs = [
            job("sod", &[]),
            job("colliding-rings", &[]),
            job("toro-1", &[]),
            job("biaxial", &[]),
        ];
        assert_eq!(start_order(&jobs), [3, 1, 0, 2]);
    }

    /// A problem's error comes back as the run's, and nothing is handed over for it (the one
    /// before it, started first, may have finished and been handed over).
    #[test]
    fn an_error_stops_the_run_and_is_returned() {
        let jobs = [
            job(kernel_interpolation::NAME, &[]),
            job(thesis_arrivals::NAME, &[("no_such_key", "1")]),
        ];
        let mut seen = Vec::new();
        let error = run_many(Level::Quick, &jobs, &|_, _| {}, &mut |k, _| {
            seen.push(k);
            Ok(())
        })
        .unwrap_err();
        assert!(
            matches!(error, VerifyError::UnknownParameter { .. }),
            "{error}"
        );
        assert!(seen.iter().all(|&k| k == 0), "{seen:?}");
    }
}
