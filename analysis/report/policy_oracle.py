#!/usr/bin/env python3
"""nearcap evaluate's plot: along a camera path, each frame's end-to-end time
of the policy and of the oracle (every light's summed), and Z-fail's.

Usage: policy_oracle.py EVALUATION.csv SET OUT.png [TITLE]
EVALUATION.csv is what `nearcap evaluate --path PATH --out DIR` writes:
set,configuration,frame,light,rule,refused,applies,wrong,cracks,decision_ms,
cpu_ms,end_to_end_ms,choice_ms,chosen (rows of rule "oracle": the fastest candidate as
right as Z-fail, per frame and light).  SET is the path file's stem.
`policy_oracle.py --check` only imports what it needs (nearcap evaluate runs
it before measuring).  Errors are one line on stderr, "nearcap: error
(KIND): policy_oracle.py: ...", exit code 2, KIND as nearcap's own: usage,
unavailable (no matplotlib), io, parse (not a CSV of numbers), schema (a
column missing).
"""
import csv
import os
import sys


def fail(kind, message):
    print(f"nearcap: error ({kind}): policy_oracle.py: {message}", file=sys.stderr)
    sys.exit(2)


def main(argv):
    if len(argv) != 2 or argv[1] != "--check":
        if len(argv) < 4:
            fail("usage", "usage: policy_oracle.py EVALUATION.csv SET OUT.png [TITLE], or policy_oracle.py --check")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        fail("unavailable", f"{sys.executable} has no matplotlib (scripts/install-deps.sh installs python3-matplotlib)")
    if argv[1:] == ["--check"]:
        return
    wanted = ("policy", "oracle", "zfail")
    times = {rule: {} for rule in wanted}  # rule -> {frame: ms}
    name = os.path.basename(argv[3])
    if not name.lower().endswith(".png") or name.lower() == ".png":
        fail("usage", f"{argv[3]}: the plot is a PNG file: name it NAME.png")
    try:
        with open(argv[1], newline="") as f:
            for row in csv.DictReader(f):
                if row["set"] != argv[2] or row["rule"] not in wanted or row["refused"] == "1":
                    continue
                frame = int(row["frame"])
                by_frame = times[row["rule"]]
                by_frame[frame] = by_frame.get(frame, 0.0) + float(row["end_to_end_ms"])
    except OSError as e:
        fail("io", f"{argv[1]}: cannot read it ({e.strerror})")
    except KeyError as e:
        fail("schema", f"{argv[1]}: not an evaluation CSV (no column {e})")
    except (ValueError, TypeError, UnicodeDecodeError, csv.Error) as e:
        fail("parse", f"{argv[1]}: not an evaluation CSV ({e})")
    if not times["oracle"]:
        fail("usage", f"{argv[1]}: no oracle rows of set {argv[2]}")
    fig, ax = plt.subplots(figsize=(8, 4.5))
    styles = {"policy": dict(linewidth=1.4), "oracle": dict(linewidth=1.4), "zfail": dict(linewidth=0.9, linestyle=":")}
    for rule in wanted:
        frames = sorted(f for f in times[rule] if f in times["oracle"])
        ax.plot(frames, [times[rule][f] for f in frames], label=rule, **styles[rule])
    ax.set_xlabel("frame")
    ax.set_ylabel("end-to-end ms (CPU work + GL to glFinish)")
    ax.set_title(argv[4] if len(argv) > 4 else f"{argv[2]}: policy against the oracle")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8)
    fig.tight_layout()
    try:
        fig.savefig(argv[3], dpi=100)
    except (OSError, ValueError) as e:
        fail("io", f"{argv[3]}: {e}")


if __name__ == "__main__":
    main(sys.argv)
