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
