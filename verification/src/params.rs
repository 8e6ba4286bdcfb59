//! Problem parameters: declared per problem with a default per level, overridden by
//! `--set KEY=VALUE`, parsed with a named error for every bad value.

use crate::{Level, VerifyError};
use blastsph_solver::TimeSteps;
use std::collections::BTreeMap;

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// One declared parameter.
#[derive(Clone, Debug)]
pub struct ParamSpec {
    pub key: &'static str,
    pub quick: String,
    pub full: String,
    pub help: &'static str,
}

impl ParamSpec {
    /// A parameter with one default for both levels.
    pub fn new(key: &'static str, default: impl ToString, help: &'static str) -> Self {
        Self::per_level(key, default.to_string(), default.to_string(), help)
    }

    /// `step_ratio`, read by [`Params::time_steps`], for problems whose scenes may take
    /// individual time steps (radial ones), `default` at both levels.
    pub fn step_ratio(default: u64) -> Self {
        Self::new(
            "step_ratio",
            default,
            "individual time steps: each particle's up to this power of two times the shortest (1: one global step)",
        )
    }

    pub fn per_level(
        key: &'static str,
        quick: impl ToString,
        full: impl ToString,
        help: &'static str,
    ) -> Self {
        Self {
            key,
            quick: quick.to_string(),
            full: full.to_string(),
            help,
        }
    }
}

/// The parameter values of one problem run: defaults for the level plus overrides.
#[derive(Clone, Debug)]
pub struct Params {
    problem: String,
    values: BTreeMap<&'static str, String>,
    overridden: BTreeMap<String, String>,
}

impl Params {
    pub fn new(
        problem: &str,
        specs: &[ParamSpec],
        level: Level,
        overrides: &[(String, String)],
    ) -> Result<Self, VerifyError> {
        let mut values: BTreeMap<&'static str, String> = specs
            .iter()
            .map(|s| {
                (
                    s.key,
                    if level == Level::Quick {
                        &s.quick
                    } else {
                        &s.full
                    }
                    .clone(),
                )
            })
            .collect();
        let mut overridden = BTreeMap::new();
        for (key, value) in overrides {
            let Some(spec) = specs.iter().find(|s| s.key == key) else {
                return Err(VerifyError::UnknownParameter {
                    problem: problem.to_string(),
                    key: key.clone(),
                    available: specs.iter().map(|s| s.key).collect::<Vec<_>>().join(", "),
                });
            };
            values.insert(spec.key, value.clone());
            overridden.insert(key.clone(), value.clone());
        }
        Ok(Self {
            problem: problem.to_string(),
            values,
            overridden,
        })
    }

    /// All values, for the record.
    pub fn values(&self) -> BTreeMap<String, String> {
        self.values
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect()
    }

    /// The `--set` overrides, for the record.
    pub fn overrides(&self) -> BTreeMap<String, String> {
        self.overridden.clone()
    }

    fn raw(&self, key: &str) -> &str {
        self.values
            .get(key)
            .unwrap_or_else(|| panic!("problem {} reads undeclared parameter {key}", self.problem))
    }

    /// A free-text value (a material name, checked by whoever uses it).
    pub fn text(&self, key: &str) -> String {
        self.raw(key).to_string()
    }

    /// The Courant number `cfl`, within the solver's allowed range.
    pub fn cfl(&self) -> Result<f64, VerifyError> {
        let (lo, hi) = blastsph_solver::step::CFL_RANGE;
        self.number("cfl", lo, hi)
    }

    /// `step_ratio`: 1 for one global time step, or a power of two for individual steps, the
    /// longest at most that many times the shortest.
    pub fn time_steps(&self) -> Result<TimeSteps, VerifyError> {
        let raw = self.raw("step_ratio");
        match raw.trim().parse::<u64>() {
            Ok(1) => Ok(TimeSteps::Global),
            Ok(ratio) if ratio.is_power_of_two() && ratio <= TimeSteps::MAX_RATIO => {
                Ok(TimeSteps::Individual { max_ratio: ratio })
            }
            _ => Err(VerifyError::bad_value(
                "step_ratio",
                raw,
                &format!(
                    "1 (global steps) or a power of two up to {}",
                    TimeSteps::MAX_RATIO
                ),
            )),
        }
    }

    /// A number in [lo, hi].
    pub fn number(&self, key: &str, lo: f64, hi: f64) -> Result<f64, VerifyError> {
        let raw = self.raw(key);
        match raw.trim().parse::<f64>() {
            Ok(x) if x >= lo && x <= hi => Ok(x),
            _ => Err(VerifyError::bad_value(
                key,
                raw,
                &format!("a number in [{lo}, {hi}]"),
            )),
        }
    }

    /// A comma-separated list of integers in [lo, hi].
    pub fn integers(&self, key: &str, lo: usize, hi: usize) -> Result<Vec<usize>, VerifyError> {
        let raw = self.raw(key);
        let bad = || {
            VerifyError::bad_value(
                key,
                raw,
                &format!("comma-separated integers in [{lo}, {hi}]"),
            )
        };
        let list: Vec<usize> = raw
            .split(',')
            .map(|s| s.trim().parse::<usize>().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        if list.is_empty() || list.iter().any(|&n| n < lo || n > hi) {
            return Err(bad());
        }
        Ok(list)
    }

    /// Resolutions as [`Params::integers`], each refused where the run it sets would not fit
    /// in the memory this machine has available: `particles(n)` is the particle count at
    /// resolution n in a `dimension`-D run. The error gives the estimate and the largest
    /// resolution that fits.
    pub fn resolutions(
        &self,
        key: &str,
        lo: usize,
        hi: usize,
        dimension: usize,
        particles: impl Fn(usize) -> f64,
    ) -> Result<Vec<usize>, VerifyError> {
        let list = self.integers(key, lo, hi)?;
        let Some(available) = crate::memory::available_bytes() else {
            return Ok(list);
        };
        let need = |n: usize| particles(n) * crate::memory::bytes_per_particle(dimension);
        if let Some(&n) = list.iter().find(|&&n| need(n) > available) {
            // the particle count grows with n: bisect for the largest n that fits
            let (mut fits, mut too_large) = (lo, n);
            while too_large - fits > 1 {
                let mid = fits + (too_large - fits) / 2;
                if need(mid) > available {
                    too_large = mid;
                } else {
                    fits = mid;
                }
            }
            return Err(VerifyError::TooLarge {
                field: key.to_string(),
                value: n,
                particles: particles(n),
                estimate_gib: need(n) / GIB,
                available_gib: available / GIB,
                largest: fits,
            });
        }
        Ok(list)
    }

    /// A comma-separated list of numbers in [lo, hi].
    pub fn numbers(&self, key: &str, lo: f64, hi: f64) -> Result<Vec<f64>, VerifyError> {
        let raw = self.raw(key);
        let list: Option<Vec<f64>> = raw
            .split(',')
            .map(|s| {
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| (lo..=hi).contains(x))
            })
            .collect();
        list.filter(|l| !l.is_empty()).ok_or_else(|| {
            VerifyError::bad_value(
                key,
                raw,
                &format!("comma-separated numbers in [{lo}, {hi}]"),
            )
        })
    }

    /// One of `options`, named by `name`.
    pub fn choice<T: Copy>(
        &self,
        key: &str,
        options: &[T],
        name: impl Fn(T) -> &'static str,
    ) -> Result<T, VerifyError> {
        lookup(key, self.raw(key).trim(), options, &name)
    }

    /// A comma-separated list of `options`, each named by `name`.
    pub fn choices<T: Copy>(
        &self,
        key: &str,
        options: &[T],
        name: impl Fn(T) -> &'static str,
    ) -> Result<Vec<T>, VerifyError> {
        self.raw(key)
            .split(',')
            .map(|item| lookup(key, item.trim(), options, &name))
            .collect()
    }
}

/// The option called `raw`, or an error listing the names.
fn lookup<T: Copy>(
    key: &str,
    raw: &str,
    options: &[T],
    name: &impl Fn(T) -> &'static str,
) -> Result<T, VerifyError> {
    options
        .iter()
        .copied()
        .find(|&o| name(o) == raw)
        .ok_or_else(|| {
            let names: Vec<&str> = options.iter().map(|&o| name(o)).collect();
            VerifyError::bad_value(key, raw, &format!("one of {}", names.join(", ")))
        })
}

/// Parses `KEY=VALUE`.
pub fn parse_assignment(text: &str) -> Result<(String, String), VerifyError> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(VerifyError::bad_value("--set", text, "KEY=VALUE")),
    }
}
