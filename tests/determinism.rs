//! The same input gives bitwise the same output with one thread and with two.

use blastsph_verification::{problems, Level};

/// The profile of `problem` with the `overrides`, run on `threads` threads.
fn profile(
    problem: &str,
    overrides: &[(&str, &str)],
    threads: usize,
) -> blastsph_verification::record::Table {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let overrides: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    pool.install(|| {
        problems::run(problem, Level::Quick, &overrides, &|_| {})
            .unwrap()
            .profile
    })
}

fn sod_profile(threads: usize) -> blastsph_verification::record::Table {
    profile("toro-1", &[("n_left", "200"), ("jitter", "0.05")], threads)
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let one = sod_profile(1);
    let two = sod_profile(2);
    assert!(!one.rows.is_empty());
    // bitwise: compare the bit patterns, so that even a NaN would have to match
    let bits = |t: &blastsph_verification::record::Table| {
        t.rows
            .iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
    // the total-Lagrangian bar (its bond loops gather per particle too), a few µs of impact
    let bar = [("n_radius", "4"), ("t_end", "5e-6")];
    let (one, two) = (
        profile("taylor-bar-3d", &bar, 1),
        profile("taylor-bar-3d", &bar, 2),
    );
    assert!(!one.rows.is_empty());
    assert_eq!(bits(&one), bits(&two));
}
