#!/usr/bin/env python3
"""Per (configuration, light, variant) of a `nearcap sweep` CSV, each row's
cracks and wrong pixels against Z-fail's in the same frame, over the frames
where Z-fail cracks.

Usage: cracks_against_zfail.py SWEEP.csv

For each method: in how many of those frames it has fewer cracks than
Z-fail, none, more; its cracks there in all; and fewer / more wrong pixels.
Refused rows are left out.  Exit status 2 on unusable input.
"""
import collections
import csv
import sys

from script_errors import fail, reading, run  # the same directory


def main(path):
    with reading(path, "a sweep CSV"), open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    needed = {"configuration", "light", "variant", "method", "cracks", "wrong", "refused"}
    if not rows or not needed <= set(rows[0]):
        fail("schema", f"{path}: not a sweep CSV with rows")
    for line, r in enumerate(rows, start=2):
        for c in ("cracks", "wrong"):
            if not (r[c] or "").isdigit():
                fail("parse", f"{path}: line {line}: column '{c}': '{r[c]}' is not a count")
    frames = collections.defaultdict(dict)
    for r in rows:
        frames[(r["configuration"], r["light"], r["variant"])][r["method"]] = r
    cracking = [k for k, f in frames.items() if "zfail" in f and int(f["zfail"]["cracks"]) > 0]
    total = sum(int(frames[k]["zfail"]["cracks"]) for k in cracking)
    print(f"{len(frames)} frames; Z-fail cracks in {len(cracking)} ({total} cracks)")
    methods = sorted({m for k in cracking for m in frames[k]} - {"zfail"})
    print("method             fewer  none  more  cracks  fewer-wrong  more-wrong")
    for m in methods:
        there = [frames[k] for k in cracking if m in frames[k] and frames[k][m]["refused"] == "0"]
        c = [(int(f[m]["cracks"]), int(f["zfail"]["cracks"])) for f in there]
        w = [(int(f[m]["wrong"]), int(f["zfail"]["wrong"])) for f in there]
        print(f"{m:18s} {sum(a < b for a, b in c):5d} {sum(a == 0 for a, b in c):5d} {sum(a > b for a, b in c):5d} "
              f"{sum(a for a, b in c):7d} {sum(a < b for a, b in w):12d} {sum(a > b for a, b in w):11d}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        fail("usage", "usage: cracks_against_zfail.py SWEEP.csv")
    run(lambda: main(sys.argv[1]), sys.argv[1])
