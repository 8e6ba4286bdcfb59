//! The solver package's integration tests, in one binary: cargo runs test binaries one after
//! another, and within one binary libtest keeps every core busy (and the generic solver is
//! compiled for the tests once, not once per file).

mod axisymmetric;
mod compaction;
mod conservation;
mod dem;
mod individual_steps;
mod operators;
mod outflow;
mod radial;
mod solids;

/// Runs `work` on a pool of its own with one thread. libtest already runs one test per core;
/// a small scene that also spread its particle loops over every core would leave each loop
/// waiting for a worker the other test's threads have preempted, at every step.
fn on_one_thread<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool of one thread")
        .install(work)
}
