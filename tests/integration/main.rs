//! The command line's and the verification suite's integration tests, in one binary: cargo runs
//! test binaries one after another, and within one binary libtest keeps every core busy, so
//! the short command-line tests fill the gaps the long problems leave.

mod cli;
mod common;
mod determinism;
mod stability;
mod verification_quick;
