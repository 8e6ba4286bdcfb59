#!/usr/bin/env bash
# Runs every quick-level problem with the working tree and with REV (default HEAD), then
# compares the records number by number (scripts/record_diff.py; wall times ignored).
# A refactor is accepted when nothing differs, or when what differs is round-off below
# the tolerance and explained.
#
# usage: scripts/record-diff.sh [REV] [--tolerance 1e-12]
# REV is built in a git worktree under target/record-diff/ with its own target folder,
# kept between calls so that a second comparison against the same REV only rebuilds.
set -euo pipefail
cd "$(dirname "$0")/.."
rev=HEAD
tolerance=()
while [ $# -gt 0 ]; do
    case "$1" in
        --tolerance) tolerance=(--tolerance "$2"); shift 2 ;;
        *) rev="$1"; shift ;;
    esac
done
root=target/record-diff
tree="$root/tree"
mkdir -p "$root"
git worktree remove --force "$tree" 2>/dev/null || rm -rf "$tree"
git worktree prune
git worktree add --detach "$tree" "$rev" >/dev/null
run() { # $1 source tree, $2 target folder, $3 output folder
    (cd "$1" && CARGO_TARGET_DIR="$2" cargo build --release --quiet --bin blastsph)
    rm -rf "$3"
    "$2/release/blastsph" verify --level quick --out "$3" > "$3.log" 2>&1 \
        || echo "  some checks failed or runs stopped: see $3.log"
}
echo "before: $(git rev-parse --short "$rev")"
run "$tree" "$PWD/$root/target" "$PWD/$root/before"
echo "after: working tree"
run . "$PWD/target" "$PWD/$root/after"
git worktree remove --force "$tree"
python3 scripts/record_diff.py "$root/before" "$root/after" "${tolerance[@]}"
