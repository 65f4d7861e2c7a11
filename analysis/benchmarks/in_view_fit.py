#!/usr/bin/env python3
"""What a pass's triangles in view add to its cost model, from a `nearcap
calibrate` CSV (its `pass` rows).

Usage: in_view_fit.py CALIBRATION.csv

Per pass kind, two linear models of the pass's time are fitted by least
squares on the relative error (each row weighted by 1 / ms^2): one on the
triangles submitted and the fragments (ms ~ c + a t + b f), one with the
triangles in view too (ms ~ c + a t + v i + b f), the device profile's
(include/nearcap/analysis/device_profile.hpp).  A fifth of the
configurations is held out (FNV-1a of the configuration's name, mod 5), and
the median |predicted - measured| / measured is printed on both sides.  A
check beside `nearcap calibrate`'s own Ceres fit (robust, non-negative),
which prints the second model's errors only.  Exit status 2 on unusable
input.
"""
import collections
import csv
import statistics
import sys

from script_errors import fail, reading, run  # the same directory

KINDS = ["depth", "sides", "light_cap", "dark_cap", "near_cap", "lit"]


def fnv1a(text):
    h = 0xCBF29CE484222325
    for b in text.encode("utf-8"):
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def configuration(frame):
    # "path:NAME:F:..." or "sample:SEED:I:...": the first three fields.
    return ":".join(frame.split(":")[:3])


def solve(a, b):
    """Gaussian elimination with partial pivoting; None if singular."""
    n = len(a)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        if abs(m[c][c]) < 1e-300:
            return None
        for r in range(n):
            if r != c:
                f = m[r][c] / m[c][c]
                for k in range(c, n + 1):
                    m[r][k] -= f * m[c][k]
    return [m[i][n] / m[i][i] for i in range(n)]


def fit(rows, columns):
    n = len(columns) + 1
    a = [[0.0] * n for _ in range(n)]
    b = [0.0] * n
    for r in rows:
        x = [1.0] + [r[c] * 1e-3 for c in columns]
        w = 1.0 / max(r["ms"], 1e-3) ** 2
        for i in range(n):
            b[i] += w * x[i] * r["ms"]
            for j in range(n):
                a[i][j] += w * x[i] * x[j]
    return solve(a, b)


def median_error(coefficients, rows, columns):
    if coefficients is None or not rows:
        return float("nan")
    return statistics.median(
        abs(coefficients[0] + sum(k * r[c] * 1e-3 for k, c in zip(coefficients[1:], columns)) - r["ms"]) / r["ms"]
        for r in rows)


def main(path):
    with reading(path, "a calibration CSV"):
        with open(path, newline="", encoding="utf-8") as f:
            by_kind = collections.defaultdict(list)
            for r in csv.DictReader(f):
                if r["record"] != "pass" or r["kind"] not in KINDS or float(r["ms"]) <= 0:
                    continue
                by_kind[r["kind"]].append({"frame": r["frame"], "ms": float(r["ms"]),
                                           "triangles": float(r["triangles"]), "fragments": float(r["fragments"]),
                                           "in_view": float(r["in_view"])})
    if not by_kind:
        fail("schema", f"{path}: no pass row (run nearcap calibrate)")
    two, three = ["triangles", "fragments"], ["triangles", "in_view", "fragments"]
    print("pass kind   train / held out   median error, triangles + fragments   with triangles in view")
    print("                                      train    held out                train    held out")
    for kind in KINDS:
        rows = by_kind.get(kind, [])
        train = [r for r in rows if fnv1a(configuration(r["frame"])) % 5 != 0]
        held = [r for r in rows if fnv1a(configuration(r["frame"])) % 5 == 0]
        if not train:
            continue
        without, with_in_view = fit(train, two), fit(train, three)
        print(f"{kind:<10} {len(train):>6} / {len(held):<6}  "
              f"{100 * median_error(without, train, two):13.1f} % {100 * median_error(without, held, two):8.1f} %"
              f"  {100 * median_error(with_in_view, train, three):17.1f} % {100 * median_error(with_in_view, held, three):8.1f} %")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        fail("usage", "usage: in_view_fit.py CALIBRATION.csv")
    run(lambda: main(sys.argv[1]), sys.argv[1])
