#!/usr/bin/env python3
"""Table and fitted scaling exponents from criterion's results of `benches/linear.rs`.

Usage: python3 crates/solver/benches/fit_scaling.py [target/criterion]
Fits log(time) = a + p·log(n) by least squares over n >= 200 (the asymptotic range) and over
all sizes; p is the scaling exponent (about 1 expected for the sparse LU on these patterns,
about 3 for the dense LU).
"""
import json
import math
import os
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "target/criterion"
rows = {}
for group in ("chain", "ladder"):
    for solver in ("dense", "sparse", "faer-default"):
        d = os.path.join(root, group, solver)
        if not os.path.isdir(d):
            continue
        for n in os.listdir(d):
            est = os.path.join(d, n, "new", "estimates.json")
            if n.isdigit() and os.path.exists(est):
                with open(est) as f:
                    t = json.load(f)["mean"]["point_estimate"] * 1e-9
                rows.setdefault((group, solver), []).append((int(n), t))


def fit(points):
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    k = len(xs)
    mx, my = sum(xs) / k, sum(ys) / k
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def fmt(t):
    return f"{t * 1e6:.1f} µs" if t < 1e-3 else f"{t * 1e3:.2f} ms"


sizes = sorted({n for pts in rows.values() for n, _ in pts})
keys = sorted(rows)
print("| n | " + " | ".join(f"{g} {s}" for g, s in keys) + " |")
print("|---:|" + "---:|" * len(keys))
for n in sizes:
    cells = []
    for key in keys:
        t = dict(rows[key]).get(n)
        cells.append(fmt(t) if t is not None else "—")
    print(f"| {n} | " + " | ".join(cells) + " |")
print()
for key in keys:
    pts = sorted(rows[key])
    big = [p for p in pts if p[0] >= 200]
    print(f"{key[0]:6} {key[1]:12} exponent (n ≥ 200): {fit(big):.2f}   (all sizes: {fit(pts):.2f})")
