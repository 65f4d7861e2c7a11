#!/usr/bin/env python3
"""nearcap render --bench's plot: each frame's GL time relative to Z-pass's,
one line per method, along a camera path (the ZP+ paper's Figures 9-11).

Usage: render_bench.py BENCH.csv OUT.png [TITLE]
BENCH.csv is what `nearcap render --path PATH --bench --out DIR` writes:
frame,method,stencil,vertex_stage,layout,culling,ms,depth_ms,stencil_ms,lit_ms,
gpu_depth_ms,gpu_stencil_ms,gpu_lit_ms,cpu_ms,end_to_end_ms (rows of method
zpass#again: Z-pass drawn twice per frame, the noise floor, a line near 1).
Errors are one line on stderr, exit code 2.
"""
import csv
import sys


def fail(message):
    print(f"render_bench.py: error: {message}", file=sys.stderr)
    sys.exit(2)


def main(argv):
    if len(argv) < 3:
        fail("usage: render_bench.py BENCH.csv OUT.png [TITLE]")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        fail("matplotlib is missing (scripts/install-deps.sh installs python3-matplotlib)")
    times = {}  # method -> {frame: ms}
    try:
        with open(argv[1], newline="") as f:
            for row in csv.DictReader(f):
                times.setdefault(row["method"], {})[int(row["frame"])] = float(row["ms"])
    except (OSError, KeyError, ValueError) as e:
        fail(f"{argv[1]}: not a bench CSV ({e})")
    if "zpass" not in times:
        fail(f"{argv[1]}: no zpass rows (the times are relative to Z-pass: render with --method including zpass)")
    zpass = times["zpass"]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for method, by_frame in sorted(times.items()):
        frames = sorted(f for f in by_frame if f in zpass and zpass[f] > 0)
        ax.plot(frames, [by_frame[f] / zpass[f] for f in frames], label=method, linewidth=1.2)
    ax.axhline(1.0, color="grey", linewidth=0.8, linestyle=":")
    ax.set_xlabel("frame")
    ax.set_ylabel("GL frame time / Z-pass's")
    ax.set_title(argv[3] if len(argv) > 3 else "frame time relative to Z-pass")
    ax.legend(fontsize=8)
    fig.tight_layout()
    try:
        fig.savefig(argv[2], dpi=100)
    except OSError as e:
        fail(f"{argv[2]}: {e}")


if __name__ == "__main__":
    main(sys.argv)
