#!/usr/bin/env python3
"""How close a prediction made before drawing can come to a frame's measured
time, from two or more `nearcap evaluate` runs that drew the same frames
(their evaluation.csv files, in the order they ran; a set, a path or a
sampler seed, is compared across the runs that hold it).

Usage: prediction_floor.py FIRST.csv AGAIN.csv [MORE.csv ...]

Per set and run:
  - the policy's predicted frame time: the median of |predicted_ms -
    end_to_end_ms| / end_to_end_ms over its rows with a prediction, as
    evaluate's table reports it;
  - Z-fail's frame timed twice in the same rounds (rules zfail and
    zfail#again): the median of |again / first - 1|, evaluate's noise floor.
    The two timings are moments apart and share the machine's speed of
    that moment.
Per set and pair of consecutive runs holding it (A, then B):
  - the same frame in the other run: the median of |B / A - 1| of Z-fail's
    end-to-end time, frame by frame;
  - A's Z-fail times scaled by the median of B / A over the set's last W
    frames before each (W = 1 along a path, 8 across sampled
    configurations: the windows of the policy's own prediction,
    analysis::FrameTimeDrift), judged against B's, and the same from B to A.
    Both runs' timings are noisy, so this error holds the noise of two runs.
Per set held by three runs or more, per run:
  - the same with the geometric mean of every other run's Z-fail times in
    place of A's: an estimate of how far one run's timing of a frame strays
    from the frame's typical time, which a prediction made before drawing
    cannot know.  It runs high: the mean carries the other runs' noise.
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


def predicted_from(known, measured, order, window):
    """Median relative error of `known` times scaled by the median
    measured/known of the last `window` frames before each, against `measured`."""
    logs, errors = [], []
    for key in order:
        scale = math.exp(statistics.median(logs[-window:])) if logs else 1.0
        errors.append(abs(known[key] * scale - measured[key]) / measured[key])
        logs.append(math.log(measured[key] / known[key]))
    return statistics.median(errors)


def percent(x):
    return f"{100 * x:.1f}%"


def main(paths):
    runs = [read_run(p) for p in paths]
    names = list(dict.fromkeys(name for sets in runs for name in sets))
    compared = 0
    for name in names:
        holding = [(path, sets[name]) for path, sets in zip(paths, runs) if name in sets]
        if len(holding) < 2:
            continue
        compared += 1
        first_path, first = holding[0]
        for path, s in holding[1:]:
            if s["order"] != first["order"]:
                fail("schema", f"{path}: set {name} holds other frames than {first_path}'s, or in another order "
                     "(give runs of the same evaluate command)")
        order = [k for k in first["order"] if all(k in s["zfail"] for _, s in holding)]
        if len(order) < 2:
            fail("schema", f"set {name}: fewer than two frames with Z-fail's time in every run that holds it")
        window = PATH_WINDOW if first["path"] else SAMPLED_WINDOW
        print(f"{name} ({len(order)} frames, window {window}):")
        for path, s in holding:
            twice = [abs(s["again"][k] / s["zfail"][k] - 1) for k in order if k in s["again"]]
            print(f"  {path}: the policy's prediction, median error "
                  f"{percent(statistics.median(s['predicted'])) if s['predicted'] else '-'}; "
                  f"Z-fail timed twice in its rounds, median |again/first - 1| "
                  f"{percent(statistics.median(twice)) if twice else '-'}")
        for (path_a, a), (path_b, b) in zip(holding, holding[1:]):
            raw = statistics.median(abs(b["zfail"][k] / a["zfail"][k] - 1) for k in order)
            forward = predicted_from(a["zfail"], b["zfail"], order, window)
            backward = predicted_from(b["zfail"], a["zfail"], order, window)
            print(f"  {path_a} then {path_b}: Z-fail's frame in the other run, median |B/A - 1| {percent(raw)}; "
                  f"from the other run's time, median error {percent(forward)} (A to B), {percent(backward)} (B to A)")
        if len(holding) >= 3:
            for i, (path, s) in enumerate(holding):
                others = [o for j, (_, o) in enumerate(holding) if j != i]
                mean = {k: math.exp(sum(math.log(o["zfail"][k]) for o in others) / len(others)) for k in order}
                print(f"  {path}: from the mean of the other {len(others)} runs' times, median error "
                      f"{percent(predicted_from(mean, s['zfail'], order, window))}")
    if compared == 0:
        fail("schema", f"{' and '.join(paths)}: no set is in two of the runs (give runs of the same evaluate command)")
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 3:
        fail("usage", "usage: prediction_floor.py FIRST.csv AGAIN.csv [MORE.csv ...]")
    run(lambda: main(sys.argv[1:]), " or ".join(sys.argv[1:]))
