#!/usr/bin/env bash
# Mutation testing of the solver library: every mutant cargo-mutants makes in solver/src,
# judged by the solver package's own tests. Not part of CI: a full run takes hours on two
# cores. Mutants listed as equivalent (they change nothing observable) are in
# scripts/mutants-equivalent.md with the reason; every other survivor wants a test.
#
#   scripts/mutants.sh                          # all of solver/src
#   scripts/mutants.sh --file solver/src/strength/mod.rs
#
# Two passes make a file several times cheaper: the library's unit tests first (a second or
# less per mutant beside the rebuild), then every test of the package on what they missed.
# `-C --lib` builds only the library's tests for each mutant (`-- --lib` still builds every
# integration test, a minute per mutant); --exclude-re leaves out functions by name.
#
#   scripts/mutants.sh --file solver/src/eos/jwl.rs -C --lib
#   scripts/mutants.sh --file solver/src/eos/jwl.rs --iterate
#
# A mutant's tests time out at three times the unmutated run's; with two jobs, or beside
# other work, a test run takes longer than the baseline measured alone, so set a fixed limit:
#
#   MUTANTS_TIMEOUT="--timeout 60" scripts/mutants.sh --file F
#
# Results land in mutants.out/ (caught.txt, missed.txt, timeout.txt, unviable.txt).
#
# A large file in parts: `--shard 0/3 --sharding round-robin`, and so on. `--iterate` drops the
# caught before it shards (so it picks another part); rerun a part's missed by name instead:
#
#   scripts/mutants.sh --file F -F "$(python3 -c 'import re,sys; print("|".join("^"+re.escape(l.strip())+"$" for l in open(sys.argv[1]) if l.strip()))' mutants.out/missed.txt)" -C --lib -C --test=integration
#
# A file's rate holds for the code that was run. After a change to it, run the mutants of the
# changed lines (REV: the commit its row in mutants-equivalent.md was measured at):
#
#   git diff -U0 REV -- solver/src > /tmp/change.diff
#   scripts/mutants.sh --in-diff /tmp/change.diff -C --lib -C --test=integration
#
# The package's integration tests are one binary, `integration`, a module per subject. The first
# `--` ends cargo-mutants' options and passes the rest to `cargo test`, whose own `--` passes
# filters to every test binary: `-- -- step:: individual_steps::` runs only those modules (and
# the library's tests whose names hold them), `-- -- --skip dem::` leaves one out.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v cargo-mutants >/dev/null 2>&1 || cargo install cargo-mutants --locked
# the `mutants` profile: optimised (the tests run real simulations) but incremental and
# without LTO or debug info, so that rebuilding one mutated file takes seconds
exec cargo mutants \
  --package blastsph-solver \
  --profile mutants \
  --jobs "${MUTANTS_JOBS:-2}" \
  ${MUTANTS_TIMEOUT:---timeout-multiplier 3} \
  "$@"
