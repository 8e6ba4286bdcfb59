//! The same input gives bitwise the same output with one thread and with two.

use blastsph_verification::{problems, Level};

fn sod_profile(threads: usize) -> blastsph_verification::record::Table {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let overrides = vec![
        ("n_left".to_string(), "200".to_string()),
        ("jitter".to_string(), "0.05".to_string()),
    ];
    pool.install(|| {
        problems::run("toro-1", Level::Quick, &overrides, &|_| {})
            .unwrap()
            .profile
    })
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
}
