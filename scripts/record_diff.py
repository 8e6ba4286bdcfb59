#!/usr/bin/env python3
"""Compares two folders of verification records (`blastsph verify --out DIR`).

Every number of every `<problem>.json` (parameters, errors, metrics, steps, particle counts,
observed orders, check values and limits) and of every `<problem>.csv` profile is compared;
wall and phase times are ignored, as are the work-precision files, which hold nothing but
times and errors already in the records. A number differs when
|a − b| > tolerance · max(|a|, |b|); the default tolerance 0 asks for bitwise equality.

Prints one line per differing number (problem, field, before, after, relative difference)
and a summary; exits 1 if anything differs or a record is missing on one side.

usage: record_diff.py BEFORE AFTER [--tolerance 1e-12]
"""

import argparse
import csv
import json
import math
import sys
from pathlib import Path

# Keys whose values are clock readings, not results.
TIMING_KEYS = {"wall_s", "phase_s"}
# Outputs that are made of times (work-precision) or drawn from the records (figures).
SKIPPED_FILES = {"work-precision.json", "work-precision.csv"}


def numbers(value, path):
    """Yields (path, value) for every leaf of a JSON value, skipping the timing keys."""
    if isinstance(value, dict):
        for key in sorted(value):
            if key not in TIMING_KEYS:
                yield from numbers(value[key], f"{path}.{key}")
    elif isinstance(value, list):
        for k, item in enumerate(value):
            # a list of named items (runs, checks) is indexed by name where it has one
            name = item.get("label") or item.get("name") if isinstance(item, dict) else None
            yield from numbers(item, f"{path}[{name if name else k}]")
    else:
        yield path, value


def csv_numbers(path):
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], rows[1:]
    for r, row in enumerate(body):
        for column, cell in zip(header, row):
            yield f"row {r}.{column}", cell
    yield "rows", len(body)


def as_float(value):
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, (int, float)):
        return float(value)
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def relative_difference(a, b):
    if a == b or (math.isnan(a) and math.isnan(b)):
        return 0.0
    scale = max(abs(a), abs(b))
    return math.inf if scale == 0.0 or math.isinf(scale) else abs(a - b) / scale


def compare(before, after, tolerance):
    """Returns the differing (field, before, after, relative difference) of two leaf lists."""
    left, right = dict(before), dict(after)
    differences = []
    for field in sorted(set(left) | set(right)):
        if field not in left or field not in right:
            differences.append((field, left.get(field, "—"), right.get(field, "—"), math.inf))
            continue
        a, b = left[field], right[field]
        fa, fb = as_float(a), as_float(b)
        if fa is None or fb is None:
            if a != b:
                differences.append((field, a, b, math.inf))
            continue
        rel = relative_difference(fa, fb)
        if rel > tolerance:
            differences.append((field, a, b, rel))
    return differences


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--tolerance", type=float, default=0.0)
    args = parser.parse_args()
    files = lambda folder: {
        f.name for f in folder.iterdir() if f.suffix in (".json", ".csv")
    } - SKIPPED_FILES
    names = sorted(files(args.before) | files(args.after))
    failures, largest, compared = 0, 0.0, 0
    for name in names:
        sides = [args.before / name, args.after / name]
        missing = [str(s) for s in sides if not s.exists()]
        if missing:
            print(f"{name}: missing in {', '.join(missing)}")
            failures += 1
            continue
        if name.endswith(".json"):
            before, after = (list(numbers(json.loads(s.read_text()), "")) for s in sides)
        else:
            before, after = (list(csv_numbers(s)) for s in sides)
        compared += len(before)
        for field, a, b, rel in compare(before, after, args.tolerance):
            failures += 1
            if math.isfinite(rel):
                largest = max(largest, rel)
            print(f"{name} {field}: {a} → {b} (relative {rel:.3g})")
    verdict = "same" if failures == 0 else f"{failures} differences"
    print(
        f"{len(names)} files, {compared} values compared at tolerance {args.tolerance:g}: "
        f"{verdict}; largest finite relative difference {largest:.3g}"
    )
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
