#!/usr/bin/env python3
"""The float ray tracer (Embree) on the hard-case sampler, per kind.

For configurations 0..N-1 of one seed (`nearcap sample`, 48x36 by default),
runs `nearcap cracks --method raytrace,zfail` with each shadow epsilon and
prints, per sampler kind, the configurations where raytrace is wrong and its
wrong pixels / cracks, beside Z-fail's: the hard-case table
of docs/findings/raytrace.md.

usage: raytrace_hard_cases.py [--samples N] [--seed S]   (from the repository root, after a build)
"""
import argparse
import collections
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from script_errors import fail, run  # the same directory

EPSILONS = ["fixed", "relative", "primitive-id"]


class Arguments(argparse.ArgumentParser):
    def error(self, message):
        fail("usage", f"{message} (usage: raytrace_hard_cases.py [--samples N] [--seed S] [--nearcap PATH])")


def main():
    ap = Arguments(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--nearcap", default="./build/nearcap")
    args = ap.parse_args()
    rows = collections.defaultdict(lambda: collections.Counter())
    rejected = []
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "s.json"
        for i in range(args.samples):
            sampled = subprocess.run([args.nearcap, "sample", "--seed", str(args.seed), "--index", str(i), "--out",
                                      str(scene)], capture_output=True, text=True)
            if sampled.returncode != 0:
                if i > 0:
                    print(file=sys.stderr)  # after the progress count
                fail("io", f"{args.nearcap} sample --seed {args.seed} --index {i} failed (exit status {sampled.returncode}): "
                     f"{sampled.stderr.strip()}")
            kind = json.loads(scene.read_text())["description"].split(": ", 1)[1].split(",")[0]
            row = rows[kind]
            for e in EPSILONS:
                out = subprocess.run([args.nearcap, "cracks", str(scene), "--light", "0", "--method", "raytrace,zfail",
                                      "--shadow-epsilon", e], capture_output=True, text=True)
                if out.returncode != 0:  # the scene reader refuses it (a light inside an occluder, ...)
                    rejected.append(f"configuration {i} ({kind}): {out.stderr.strip()}")
                    break
                if e == EPSILONS[0]:
                    row["configurations"] += 1
                records = {r["method"]: r for r in json.loads(out.stdout)["methods"]}
                r = records["raytrace"]
                if "refused" in r:
                    row["refused " + e] += 1
                    print(f"\nconfiguration {i} ({kind}), {e}: raytrace refused: {r['refused']}", file=sys.stderr)
                    continue
                row[e + " configs wrong"] += r["wrong"] > 0
                row[e + " wrong"] += r["wrong"]
                row[e + " cracks"] += r["cracks"]
                if e == EPSILONS[0] and "refused" not in records["zfail"]:
                    z = records["zfail"]
                    row["zfail configs wrong"] += z["wrong"] > 0
                    row["zfail wrong"] += z["wrong"]
                    row["zfail cracks"] += z["cracks"]
            print(f"\r{i + 1}/{args.samples}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    head = "| kind | configurations | " + " | ".join(EPSILONS) + " | Z-fail |"
    print(head)
    print("|---|---:|" + "---:|" * (len(EPSILONS) + 1))
    total = collections.Counter()
    for kind in sorted(rows):
        total.update(rows[kind])
    for kind, row in sorted(rows.items()) + [("all", total)]:
        cells = []
        for e in EPSILONS + ["zfail"]:
            cell = "%d: %d / %d" % (row[e + " configs wrong"], row[e + " wrong"], row[e + " cracks"])
            if row["refused " + e]:
                cell += " (%d refused)" % row["refused " + e]
            cells.append(cell)
        print(f"| {kind} | {row['configurations']} | " + " | ".join(cells) + " |")
    if rejected:
        print(f"\n{len(rejected)} configurations the scene reader refuses, left out:")
        for r in rejected:
            print(f"- {r}")


if __name__ == "__main__":
    run(main, "the output of nearcap sample and nearcap cracks")
