//! Stability stress tests. Random Riemann problems (states, resolution, Courant number across
//! its allowed range, a jittered start) must all run to the end without a diagnosis, positive,
//! and within the energy and momentum limits of the shock-tube problem; the lowest Courant
//! number of the range is stable too. (That an unstable step stops with a diagnosis naming
//! the particle is `courant_number_2_stops_with_a_diagnosis_naming_the_particle` in the
//! solver's conservation tests.)

use blastsph_solver::step::CFL_RANGE;
use blastsph_verification::record::ProblemOutput;
use blastsph_verification::{problems, Level};
use proptest::prelude::*;

fn run(overrides: &[(&str, String)]) -> ProblemOutput {
    let overrides: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    problems::run("toro-1", Level::Quick, &overrides, &|_| {}).unwrap()
}

/// Every run finished, and every conservation and positivity check passed.
fn assert_stable(out: &ProblemOutput) -> Result<(), TestCaseError> {
    for run in &out.record.runs {
        prop_assert!(run.failure.is_none(), "{}: {:?}", run.label, run.failure);
    }
    let guarded = [
        "energy",
        "momentum",
        "min_density",
        "min_pressure",
        "runs_completed",
    ];
    let mut seen = 0;
    for check in &out.record.checks {
        if guarded.iter().any(|g| check.name.starts_with(g)) {
            seen += 1;
            prop_assert!(
                check.pass,
                "{} = {:e}, must be {} {:e}",
                check.name,
                check.value,
                check.relation,
                check.limit
            );
        }
    }
    prop_assert!(seen >= 5, "only {seen} guarded checks");
    for column in ["rho", "u", "p", "e"] {
        let values = out.profile.column(column).unwrap();
        prop_assert!(!values.is_empty());
        prop_assert!(values.iter().all(|v| v.is_finite()));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Densities 0.2–5, sound speeds √(γ p/ρ) of 0.37–2.4 and velocities within ±1, so that
    /// no state pair opens a vacuum (2(c_L + c_R)/(γ − 1) > 3.7 > u_R − u_L).
    #[test]
    fn random_riemann_problems_run_stably(
        rho in prop::array::uniform2(0.2f64..5.0),
        temperature in prop::array::uniform2(0.1f64..4.0),
        u in prop::array::uniform2(-1.0f64..1.0),
        n_left in 50usize..150,
        cfl in CFL_RANGE.0.max(0.05)..=CFL_RANGE.1,
        jitter in 0.0f64..=0.1,
        seed in 0u64..1000,
    ) {
        let state = |k: usize| format!("{},{},{}", rho[k], u[k], rho[k] * temperature[k]);
        let out = run(&[
            ("left", state(0)),
            ("right", state(1)),
            ("t_end", "0.1".to_string()),
            ("n_left", n_left.to_string()),
            ("cfl", cfl.to_string()),
            ("jitter", jitter.to_string()),
            ("seed", seed.to_string()),
        ]);
        assert_stable(&out)?;
    }
}

/// The smallest Courant number of the range (one deterministic case: it costs many steps).
#[test]
fn lowest_courant_number_is_stable() {
    let out = run(&[
        ("n_left", "50".to_string()),
        ("jitter", "0.1".to_string()),
        ("cfl", CFL_RANGE.0.to_string()),
    ]);
    assert_stable(&out).unwrap();
}
