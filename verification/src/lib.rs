//! blastsph-verification: exact solutions, error norms and the canonical problem suite.
//!
//! Each problem (one file in [`problems`]) declares its parameters with defaults per level, sets
//! up a scene, runs the solver at one or more resolutions, compares with its exact answer and
//! returns a [`record::Record`] with profiles and a plot. `blastsph verify` and `cargo test`
//! both call [`problems::run`], so the tests exercise exactly what the CLI runs.

pub mod cache;
pub mod gate;
pub mod gauges;
pub mod impedance;
pub mod index;
pub mod laplace_young;
pub mod materials;
pub mod memory;
pub mod norms;
pub mod params;
pub mod problems;
pub mod record;
pub mod report;
pub mod riemann;
pub mod scaled;
pub mod scene;
pub mod sedov;
pub mod surface_burst;
pub mod svg;
pub mod tunnel;
pub mod vtk;

use thiserror::Error;

/// Runs `work` on a pool of its own with one thread. libtest already runs one test per core;
/// a test whose small scene also spread its particle loops over every core would leave each
/// loop waiting for a worker the other test's threads have preempted, at every step.
#[cfg(test)]
pub(crate) fn on_one_thread<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool of one thread")
        .install(work)
}

/// A reader of a table from `reference_data/`: CSV with a header row, whose `#` lines are
/// comments (the first names the table's source).
pub(crate) fn reference_table(table: &'static str) -> csv::Reader<&'static [u8]> {
    csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(table.as_bytes())
}

/// How much work a problem does: `quick` for `cargo test`, `full` for convergence studies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    Quick,
    Full,
}

impl Level {
    pub fn name(self) -> &'static str {
        match self {
            Level::Quick => "quick",
            Level::Full => "full",
        }
    }
}

#[derive(Debug, Error)]
pub enum VerifyError {
    #[error("unknown problem '{name}'; available: {available}")]
    UnknownProblem { name: String, available: String },
    #[error("unknown parameter '{key}' for problem {problem}; its parameters: {available}")]
    UnknownParameter {
        problem: String,
        key: String,
        available: String,
    },
    #[error("unknown material '{name}'; available: {available}")]
    UnknownMaterial { name: String, available: String },
    #[error("material {material} ({model}) lacks parameter {parameter}")]
    MissingParameter {
        material: String,
        model: String,
        parameter: String,
    },
    #[error("invalid {field} = {value}: allowed {allowed}")]
    BadValue {
        field: String,
        value: String,
        allowed: String,
    },
    #[error(
        "{field} = {value} needs about {estimate_gib:.1} GiB of memory ({particles:.3e} particles); \
         {available_gib:.1} GiB are available: the largest {field} that fits is {largest}"
    )]
    TooLarge {
        field: String,
        value: usize,
        particles: f64,
        estimate_gib: f64,
        available_gib: f64,
        largest: usize,
    },
    #[error("scene file, line {line}: {key}: {message}")]
    Scene {
        line: usize,
        key: String,
        message: String,
    },
    #[error(transparent)]
    Solver(#[from] blastsph_solver::SolverError),
    #[error("writing {path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

impl VerifyError {
    /// Sorts what `Simulation::new` refused: a parameter out of range is the caller's bad input
    /// (returned as the error), anything else is the run's diagnosis (returned as text for the
    /// record: the problem reports the failed run and goes on).
    pub fn from_scene(error: blastsph_solver::SolverError) -> Result<String, VerifyError> {
        match error {
            blastsph_solver::SolverError::InvalidParameter {
                field,
                value,
                allowed,
            } => Err(VerifyError::BadValue {
                field,
                value,
                allowed,
            }),
            diagnosis => Ok(diagnosis.to_string()),
        }
    }

    pub fn bad_value(field: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        VerifyError::BadValue {
            field: field.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
}
