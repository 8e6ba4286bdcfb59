#!/usr/bin/env python3
"""How much a particle map would change if its particles were placed on whole pixels.

Reads the particle dots (filled circles) of an SVG that `blastsph verify` wrote and compares
each particle's nearest-neighbour distance before and after rounding its position to a whole
pixel, which is what a plotting library with integer backend coordinates does (plotters:
`BackendCoord = (i32, i32)`).

    python3 scripts/pixel-rounding.py results/verify/taylor-bar-axisymmetric.svg
"""
import math
import re
import sys


def nearest_distances(points):
    return [
        min(math.hypot(a[0] - b[0], a[1] - b[1]) for j, b in enumerate(points) if j != i)
        for i, a in enumerate(points)
    ]


def main(path):
    svg = open(path, encoding="utf-8").read()
    dots = [
        (float(x), float(y))
        for x, y in re.findall(r'<circle cx="([-\d.]+)" cy="([-\d.]+)" r="2.5" fill="#', svg)
    ]
    if len(dots) < 2:
        sys.exit(f"{path}: no particle map")
    exact = nearest_distances(dots)
    rounded = nearest_distances([(round(x), round(y)) for x, y in dots])
    change = sorted(abs(b - a) / a for a, b in zip(exact, rounded) if a > 0)
    quantile = lambda q: 100 * change[min(len(change) - 1, int(q * len(change)))]
    print(f"{path}: {len(dots)} dots, median spacing {sorted(exact)[len(exact) // 2]:.2f} px")
    print(
        f"nearest-neighbour distance changed by rounding to whole pixels: "
        f"median {quantile(0.5):.1f} %, 95th percentile {quantile(0.95):.1f} %, "
        f"max {quantile(1.0):.1f} %"
    )


if __name__ == "__main__":
    main(sys.argv[1])
