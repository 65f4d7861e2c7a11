#!/usr/bin/env python3
"""How close a prediction made before drawing can come to a frame's measured
time, from two or more `nearcap evaluate` runs of the same command (their
evaluation.csv files, in the order they ran).

Usage: prediction_floor.py FIRST.csv AGAIN.csv [MORE.csv ...]

Per set (a path, or a sampler seed) and run:
  - the policy's predicted frame time: the median of |predicted_ms -
    end_to_end_ms| / end_to_end_ms over its rows with a prediction, as
    evaluate's table reports it;
  - Z-fail's frame timed twice in the same rounds (rules zfail and
    zfail#again): the median of |again / first - 1|, evaluate's noise floor.
    The two timings are moments apart and share the machine's speed of
    that moment.
Per set and pair of consecutive runs (A, then B):
  - the same frame in the other run: the median of |B / A - 1| of Z-fail's
    end-to-end time, frame by frame;
  - a predictor that knows each frame's time from run A: A's time scaled by
    the median of B / A over the set's last W frames before it (W = 1 along
    a path, 8 across sampled configurations: the windows of the policy's own
    prediction, analysis::FrameTimeDrift), judged against B's time, and the
    same from B to A.  What that predictor misses is what no price of the
    frame's work can know before drawing: the speed of the moment the frame
    is drawn in.
Exit status 2 on unusable input.
"""
import csv
import math
import statistics
import sys

from script_errors import fail, reading, run

PATH_WINDOW, SAMPLED_WINDOW = 1, 8


def read_run(path):
    """Per set: its (configuration, frame, light) in the order drawn, the
    policy's relative prediction errors, and Z-fail's first and again times."""
    sets = {}
    with reading(path, "an evaluation CSV"):
        with open(path, newline="", encoding="utf-8") as f:
            for r in csv.DictReader(f):
                s = sets.setdefault(r["set"], {"order": [], "path": bool(r["frame"]), "predicted": [],
                                               "zfail": {}, "again": {}})
                key = (r["configuration"], r["frame"], r["light"])
                m = float(r["end_to_end_ms"]) if r["end_to_end_ms"] else None
                if r["rule"] == "policy":
                    s["order"].append(key)
                    if r["predicted_ms"] and m:
                        s["predicted"].append(abs(float(r["predicted_ms"]) - m) / m)
                elif r["rule"] in ("zfail", "zfail#again") and m and m > 0:
                    s["zfail" if r["rule"] == "zfail" else "again"][key] = m
    if not sets or not any(s["order"] for s in sets.values()):
        fail("schema", f"{path}: no policy row (run nearcap evaluate)")
    return sets


def predicted_from(first, again, order, window):
    """Median relative error of `first`'s time scaled by the median
    again/first of the last `window` frames before it, against `again`."""
    logs, errors = [], []
    for key in order:
        scale = math.exp(statistics.median(logs[-window:])) if logs else 1.0
        errors.append(abs(first[key] * scale - again[key]) / again[key])
        logs.append(math.log(again[key] / first[key]))
    return statistics.median(errors)


def percent(x):
    return f"{100 * x:.1f}%"


def main(paths):
    runs = [read_run(p) for p in paths]
    for name in runs[0]:
        print(f"{name}:")
        for path, sets in zip(paths, runs):
            s = sets.get(name)
            if s is None:
                fail("schema", f"{path}: no set {name} (give runs of the same evaluate command)")
            twice = [abs(s["again"][k] / s["zfail"][k] - 1) for k in s["order"] if k in s["zfail"] and k in s["again"]]
            print(f"  {path}: {len(s['order'])} frames; the policy's prediction, median error "
                  f"{percent(statistics.median(s['predicted'])) if s['predicted'] else '-'}; "
                  f"Z-fail timed twice in its rounds, median |again/first - 1| "
                  f"{percent(statistics.median(twice)) if twice else '-'}")
        for (path_a, a), (path_b, b) in zip(zip(paths, runs), zip(paths[1:], runs[1:])):
            sa, sb = a[name], b[name]
            if sa["order"] != sb["order"]:
                fail("schema", f"{path_b}: set {name} holds other frames than {path_a}'s, or in another order "
                     "(give runs of the same evaluate command)")
            order = [k for k in sa["order"] if k in sa["zfail"] and k in sb["zfail"]]
            if len(order) < 2:
                fail("schema", f"{path_a}, {path_b}: set {name} has fewer than two Z-fail frames in both")
            window = PATH_WINDOW if sa["path"] else SAMPLED_WINDOW
            raw = statistics.median(abs(sb["zfail"][k] / sa["zfail"][k] - 1) for k in order)
            forward = predicted_from(sa["zfail"], sb["zfail"], order, window)
            backward = predicted_from(sb["zfail"], sa["zfail"], order, window)
            print(f"  {path_a} then {path_b}: Z-fail's frame in the other run, median |B/A - 1| {percent(raw)}; "
                  f"predicted from the other run's time and the last {window} frame(s)' B/A, median error "
                  f"{percent(forward)} (A to B), {percent(backward)} (B to A)")
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 3:
        fail("usage", "usage: prediction_floor.py FIRST.csv AGAIN.csv [MORE.csv ...]")
    run(lambda: main(sys.argv[1:]), " or ".join(sys.argv[1:]))
