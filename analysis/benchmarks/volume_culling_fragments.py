#!/usr/bin/env python3
"""Volume culling's fragments and wrong pixels, from the sweeps of
`./scripts/findings.sh volume-culling`: DIR/paths-C.csv and DIR/hard-C.csv
for C in none, scissor, depth-bounds, both (the same rows but the culling).

Usage: volume_culling_fragments.py DIR

Prints, per set and culling, each method's volume and near-cap fragments
relative to no culling (over the rows both sweeps hold), as the rows of
docs/findings/volume-culling.md's table; then each method's wrong pixels
and cracks summed, without culling and with both.  Exit status 2 on
unusable input.
"""
import csv
import os
import sys

from script_errors import fail, reading, run  # the same directory

METHODS = ["zpass", "zfail", "zpplus-corrected", "preload", "policy"]
SETS = [("paths", "seven bundled paths (`--path` each, 160×120)"), ("hard", "3,000 hard cases (seed 7, 48×36)")]
CULLINGS = ["scissor", "depth-bounds", "both"]


def load(path):
    with reading(path, "a sweep CSV"), open(path, newline="", encoding="utf-8") as f:
        return {(r["configuration"], r["light"], r["method"]): r for r in csv.DictReader(f)}


def fragments(r):
    return int(r["volume_fragments"]) + int(r["near_cap_fragments"])


def main():
    if len(sys.argv) != 2:
        fail("usage", "usage: volume_culling_fragments.py DIR")
    top = sys.argv[1]
    for name, label in SETS:
        rows = {c: load(os.path.join(top, f"{name}-{c}.csv")) for c in ["none"] + CULLINGS}
        base = rows["none"]
        for c in CULLINGS:
            ratios = []
            for m in METHODS:
                keys = [k for k in base if k[2] == m and k in rows[c]]
                before = sum(fragments(base[k]) for k in keys)
                after = sum(fragments(rows[c][k]) for k in keys)
                ratios.append(f"{after / before:.3f}" if before else "—")
            print(f"| {label}: {c} | " + " | ".join(ratios) + " |")
        for c in ["none", "both"]:
            wrong, cracks = {}, {}
            for (_, _, m), r in rows[c].items():
                wrong[m] = wrong.get(m, 0) + int(r["wrong"])
                cracks[m] = cracks.get(m, 0) + int(r["cracks"])
            print(f"{name} {c}: wrong " + ", ".join(f"{m} {wrong[m]:,}" for m in sorted(wrong))
                  + "; cracks " + ", ".join(f"{m} {cracks[m]:,}" for m in sorted(cracks)))


if __name__ == "__main__":
    run(main, sys.argv[1] if len(sys.argv) > 1 else "")
