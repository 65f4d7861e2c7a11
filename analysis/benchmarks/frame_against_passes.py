#!/usr/bin/env python3
"""A whole frame drawn at once against the sum of its passes timed each on
its own, from a `nearcap calibrate` CSV (its `frame` and `pass` rows).

Usage: frame_against_passes.py CALIBRATION.csv

For the frames whose passes' measured sum falls in each range: how many,
the median of whole frame / passes' sum, the median sum and frame time, and
the median of (sum - whole frame) / passes drawn, the time a pass timed on
its own pays beyond the same pass in a frame drawn at once.  A pass row
belongs to the frame row whose frame it names without its ":lightK"
(docs/calibration.md).  Exit status 2 on unusable input.
"""
import collections
import csv
import re
import statistics
import sys

from script_errors import fail, reading, run  # the same directory

RANGES = [(0, 0.5), (0.5, 1), (1, 2), (2, 5), (5, 20), (20, float("inf"))]


def frame_of_pass(name):
    parts = name.split(":")
    if len(parts) >= 3 and parts[-1] and re.fullmatch(r"light[0-9]+", parts[-2]):
        return ":".join(parts[:-2] + [parts[-1]])
    return name


def main(path):
    with reading(path, "a calibration CSV"):
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        passes, drawn = collections.defaultdict(float), collections.defaultdict(int)
        for r in rows:
            if r["record"] == "pass":
                k = frame_of_pass(r["frame"])
                passes[k] += float(r["ms"])
                drawn[k] += 1
        frames = [(r["frame"], float(r["ms"])) for r in rows if r["record"] == "frame"]
    frames = [(f, ms) for f, ms in frames if passes[f] > 0 and ms > 0]
    if not frames:
        fail("schema", f"{path}: no frame row with its passes (run nearcap calibrate)")
    print("passes' sum (ms)  frames  whole/sum  median sum  median whole  (sum - whole) per pass")
    for lo, hi in RANGES:
        sel = [(f, ms) for f, ms in frames if lo <= passes[f] < hi]
        if not sel:
            continue
        ratio = statistics.median(ms / passes[f] for f, ms in sel)
        per_pass = statistics.median((passes[f] - ms) / drawn[f] for f, ms in sel)
        print(f"[{lo:g}, {hi:g}){'':<{10 - len(f'{lo:g}, {hi:g}')}} {len(sel):>6}  {ratio:9.3f}  "
              f"{statistics.median(passes[f] for f, _ in sel):10.3f}  {statistics.median(ms for _, ms in sel):12.3f}"
              f"  {per_pass:10.4f} ms")
    ratio = statistics.median(ms / passes[f] for f, ms in frames)
    print(f"all {len(frames)} frames: whole / sum median {ratio:.3f}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        fail("usage", "usage: frame_against_passes.py CALIBRATION.csv")
    run(lambda: main(sys.argv[1]), sys.argv[1])
