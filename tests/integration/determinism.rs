//! The same input gives bitwise the same output with one, two and three threads: every particle
//! field of the final state, the profile, the errors, the metrics and the step count.

use blastsph_verification::record::ProblemOutput;
use blastsph_verification::{problems, Level};

/// `problem` with the `overrides`, run on `threads` threads.
fn run(problem: &str, overrides: &[(&str, &str)], threads: usize) -> ProblemOutput {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let overrides: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    pool.install(|| problems::run(problem, Level::Quick, &overrides, &|_| {}).unwrap())
}

/// Everything a run produced as bit patterns (so that even a NaN would have to match), the
/// wall times left out.
fn fingerprint(out: &ProblemOutput) -> Vec<u64> {
    let mut bits: Vec<u64> = out
        .profile
        .rows
        .iter()
        .flatten()
        .map(|v| v.to_bits())
        .collect();
    let snapshot = out.snapshot.as_ref().expect("a simulated problem");
    assert!(!snapshot.positions.is_empty());
    bits.extend(snapshot.positions.iter().flatten().map(|v| v.to_bits()));
    for (_, field) in &snapshot.vectors {
        bits.extend(field.iter().flatten().map(|v| v.to_bits()));
    }
    for (_, field) in &snapshot.scalars {
        bits.extend(field.iter().map(|v| v.to_bits()));
    }
    for run in &out.record.runs {
        bits.push(run.steps);
        bits.extend(run.errors.values().map(|v| v.to_bits()));
        bits.extend(run.metrics.values().map(|v| v.to_bits()));
    }
    bits
}

fn assert_thread_count_independent(problem: &str, overrides: &[(&str, &str)]) {
    let one = fingerprint(&run(problem, overrides, 1));
    for threads in [2, 3] {
        let other = fingerprint(&run(problem, overrides, threads));
        assert_eq!(one.len(), other.len(), "{problem}: {threads} threads");
        let first_difference = one.iter().zip(&other).position(|(a, b)| a != b);
        assert_eq!(
            first_difference, None,
            "{problem}: {threads} threads differ from one"
        );
    }
}

/// 1D shock tube with a jittered start.
#[test]
fn jittered_shock_tube_is_thread_count_independent() {
    assert_thread_count_independent("toro-1", &[("n_left", "200"), ("jitter", "0.05")]);
}

/// 2D and 3D cell lists with Morton reordering, and grad-h's repeated searches.
#[test]
fn sedov_2d_and_3d_with_grad_h_are_thread_count_independent() {
    for (problem, n, t_end) in [("sedov-2d", "24", "0.02"), ("sedov-3d", "10", "0.01")] {
        assert_thread_count_independent(
            problem,
            &[("n", n), ("t_end", t_end), ("smoothing", "grad-h")],
        );
    }
}

/// Grad-h with individual time steps: each active particle's h solved among partners at
/// different points of their steps, the limiter and the wake-ups.
#[test]
fn sedov_2d_and_3d_with_grad_h_and_individual_steps_are_thread_count_independent() {
    for (problem, n, t_end) in [("sedov-2d", "24", "0.02"), ("sedov-3d", "10", "0.01")] {
        assert_thread_count_independent(
            problem,
            &[
                ("n", n),
                ("t_end", t_end),
                ("smoothing", "grad-h"),
                ("step_ratio", "64"),
            ],
        );
    }
}

/// Radial (spherical shells) geometry.
#[test]
fn radial_blast_is_thread_count_independent() {
    assert_thread_count_independent("sedov-spherical-1d", &[("n", "100"), ("t_end", "0.2")]);
}

/// Solids: the axisymmetric rings (updated form) and the total-Lagrangian quarter, whose bond
/// loops gather per particle too, a few µs into the impact.
#[test]
fn taylor_bars_are_thread_count_independent() {
    assert_thread_count_independent(
        "taylor-bar-axisymmetric",
        &[("n_radius", "4"), ("t_end", "5e-6")],
    );
    assert_thread_count_independent("taylor-bar-3d", &[("n_radius", "4"), ("t_end", "5e-6")]);
}
