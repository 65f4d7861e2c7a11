#!/usr/bin/env python3
"""How far a work-based price can follow a whole frame's GL time, from a
`nearcap calibrate` CSV (its `frame` and `pass` rows) and a policy file
with a device profile.

Usage: frame_price_residuals.py CALIBRATION.csv POLICY.json [AGAIN.csv ...]

Per method, over the frames drawn with it (not those with a pass the six
kinds below leave out, AtomicZP's eye count):
  - price: the profile's price of the work the frame really drew (each
    pass's intercept, triangles, triangles in view and fragments, and the
    profile's `frame` row), and the median relative error of that price
    once scaled by the method's median measured/priced (the best single
    scale, in hindsight);
  - refit: the median relative error of a linear model refitted on these
    very frames by least squares on relative error (per pass kind its
    count, triangles, in-view triangles and fragments, and a constant): a
    price linear in the profile's inputs, fitted in sample;
  - the correlation, between two methods, of the log residuals
    log(measured / scaled price) of the same configuration, and between
    one configuration and the next for the first method.
Then the error left when each configuration's frame of the first method
is priced with the scale its frame of the second method shows: a
predictor told that configuration's speed.  With AGAIN.csv (the same
configurations calibrated again), the correlation of the first method's
residuals of the same configuration in the two runs: what of a
configuration's residual comes back, beside what moves with the moment.  A pass row belongs to
the frame row whose frame it names without its ":lightK"
(docs/calibration.md).  Exit status 2 on unusable input.
"""
import collections
import csv
import math
import statistics
import sys

from frame_against_passes import frame_of_pass  # the same directory
from in_view_fit import solve
from script_errors import fail, read_json, reading, run

KINDS = ["depth", "sides", "lit", "light_cap", "dark_cap", "near_cap"]


def price(profile, passes):
    t = 0.0
    for r in passes:
        c = profile["passes"][r["kind"]]
        t += (c["intercept_ms"] + c["ms_per_mtriangle"] * r["triangles"] * 1e-6 +
              c["ms_per_mfragment"] * r["fragments"] * 1e-6 + c["ms_per_mtriangle_in_view"] * r["in_view"] * 1e-6)
    frame = profile.get("frame")
    if frame and passes:
        t += frame["intercept_ms"] - frame["ms_saved_per_pass"] * len(passes)
    return t


def inputs(passes):
    x = [1.0]
    for k in KINDS:
        q = [r for r in passes if r["kind"] == k]
        x += [len(q), sum(r["triangles"] for r in q) * 1e-3, sum(r["in_view"] for r in q) * 1e-3,
              sum(r["fragments"] for r in q) * 1e-4]
    return x


def refit_error(samples):
    """Median |fit - ms| / ms of least squares on relative error, in sample."""
    n = len(samples[0][0])
    a = [[0.0] * n for _ in range(n)]
    b = [0.0] * n
    for x, ms in samples:
        w = 1.0 / (ms * ms)
        for i in range(n):
            b[i] += w * x[i] * ms
            for j in range(n):
                a[i][j] += w * x[i] * x[j]
    for i in range(n):
        a[i][i] += 1e-9  # a pass kind the method never draws: its columns are zero
    w = solve(a, b)
    return statistics.median(abs(sum(p * q for p, q in zip(w, x)) - ms) / ms for x, ms in samples)


def correlation(a, b):
    ma, mb = statistics.mean(a), statistics.mean(b)
    num = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    den = math.sqrt(sum((x - ma) ** 2 for x in a) * sum((y - mb) ** 2 for y in b))
    return num / den if den > 0 else float("nan")


def frame_rows(csv_path, profile, policy_path):
    """Per method, per configuration: (measured ms, price, refit inputs)."""
    passes, frames, unpriced = collections.defaultdict(list), {}, set()
    with reading(csv_path, "a calibration CSV"):
        with open(csv_path, newline="", encoding="utf-8") as f:
            for r in csv.DictReader(f):
                if r["record"] == "pass" and r["kind"] not in KINDS:
                    unpriced.add(frame_of_pass(r["frame"]))
                elif r["record"] == "pass":
                    passes[frame_of_pass(r["frame"])].append({
                        "kind": r["kind"], "triangles": float(r["triangles"]), "fragments": float(r["fragments"]),
                        "in_view": float(r["in_view"] or 0)})
                elif r["record"] == "frame":
                    frames[r["frame"]] = float(r["ms"])
    by_method = collections.defaultdict(dict)
    try:
        for name, ms in frames.items():
            config, _, method = name.rpartition(":")
            if ms > 0 and passes.get(name) and name not in unpriced:
                by_method[method][config] = (ms, price(profile, passes[name]), inputs(passes[name]))
    except (KeyError, TypeError) as e:
        fail("schema", f"{policy_path}: its device profile lacks a pass kind's costs ({e})")
    by_method = {m: rows for m, rows in by_method.items() if len(rows) >= 3}
    if len(by_method) < 2 or any(p <= 0 for rows in by_method.values() for _, p, _ in rows.values()):
        fail("schema", f"{csv_path}: frame rows of two methods in three configurations or more, "
             "with their passes and a positive price, needed (run nearcap calibrate)")
    return by_method


def centred_residuals(rows):
    """log(measured / price) per configuration, less the method's median, and that median."""
    logs = {c: math.log(ms / p) for c, (ms, p, _) in rows.items()}
    centre = statistics.median(logs.values())
    return {c: v - centre for c, v in logs.items()}, centre


def main(csv_path, policy_path, again_paths):
    policy = read_json(policy_path, "a policy file")
    if not isinstance(policy, dict) or not isinstance(policy.get("device_profile"), dict):
        fail("schema", f"{policy_path}: a policy without a device profile (nearcap calibrate --write-policy)")
    profile = policy["device_profile"]
    by_method = frame_rows(csv_path, profile, policy_path)
    residual = {}
    print("method                 frames  measured/priced  price, best scale  refit in sample")
    for method, rows in sorted(by_method.items()):
        residual[method], centre = centred_residuals(rows)
        scaled = statistics.median(abs(math.exp(v) - 1) for v in residual[method].values())
        refit = refit_error([(x, ms) for ms, _, x in rows.values()])
        print(f"{method:<22} {len(rows):>6}  {math.exp(centre):15.3f}  {100 * scaled:16.1f}%  {100 * refit:14.1f}%")
    methods = sorted(by_method)
    first, second = ("zfail", "zpass") if {"zfail", "zpass"} <= set(methods) else methods[:2]
    for a, b in [(first, m) for m in methods if m != first]:
        common = sorted(set(residual[a]) & set(residual[b]))
        if len(common) < 3:
            continue
        print(f"residuals of {a} and {b} in the same configuration: correlation "
              f"{correlation([residual[a][c] for c in common], [residual[b][c] for c in common]):.2f}")
    order = sorted(residual[first], key=lambda c: [int(t) if t.isdigit() else t for t in c.split(":")])
    print(f"residuals of {first} in one configuration and the next: correlation "
          f"{correlation([residual[first][c] for c in order[:-1]], [residual[first][c] for c in order[1:]]):.2f}")
    common = set(residual[first]) & set(residual[second])
    if len(common) >= 3:
        told = statistics.median(abs(math.exp(residual[first][c] - residual[second][c]) - 1) for c in common)
        print(f"{first}'s price scaled by its configuration's {second} residual: median error {100 * told:.1f}%")
    for again_path in again_paths:
        again = frame_rows(again_path, profile, policy_path).get(first, {})
        again_residual, _ = centred_residuals(again) if len(again) >= 3 else ({}, 0)
        common = sorted(set(residual[first]) & set(again_residual))
        if len(common) < 3:
            fail("schema", f"{again_path}: not three of {csv_path}'s configurations drawn with {first}")
        print(f"residuals of {first} in the same configuration in {again_path}: correlation "
              f"{correlation([residual[first][c] for c in common], [again_residual[c] for c in common]):.2f}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 3:
        fail("usage", "usage: frame_price_residuals.py CALIBRATION.csv POLICY.json [AGAIN.csv ...]")
    run(lambda: main(sys.argv[1], sys.argv[2], sys.argv[3:]), " or ".join(sys.argv[1:]))
