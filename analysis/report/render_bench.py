#!/usr/bin/env python3
"""nearcap render --bench's plot: each frame's GL time relative to Z-pass's,
one line per method, along a camera path (the ZP+ paper's Figures 9-11).

Usage: render_bench.py BENCH.csv OUT.png [TITLE] --settings TABLE.json
BENCH.csv is what `nearcap render --path PATH --bench --out DIR` writes:
frame,method,stencil,vertex_stage,layout,culling,ms,depth_ms,stencil_ms,lit_ms,
gpu_depth_ms,gpu_stencil_ms,gpu_lit_ms,cpu_ms,end_to_end_ms (rows of method
M#again: the first method drawn twice per frame, the noise floor, a line near
1 when M is Z-pass).  TABLE.json is the settings table (`nearcap settings`;
nearcap render passes it): the lines follow its order and colours, and the
times are relative to the method whose role is the timing baseline (Z-pass).
`render_bench.py --check` only imports what it needs (nearcap render runs it
before drawing the path).  Errors are one line on stderr, "nearcap: error
(KIND): render_bench.py: ...", exit code 2, KIND as nearcap's own: usage,
unavailable (no matplotlib), io, parse (not a CSV of numbers, or the table
not JSON), schema (a column or the table's field missing).
"""
import csv
import os
import sys


def fail(kind, message):
    print(f"nearcap: error ({kind}): render_bench.py: {message}", file=sys.stderr)
    sys.exit(2)


def main(argv):
    args, settings = [], None
    k = 1
    while k < len(argv):
        if argv[k] == "--settings" and k + 1 < len(argv):
            settings = argv[k + 1]
            k += 2
        else:
            args.append(argv[k])
            k += 1
    check = argv[1:] == ["--check"]
    if not check and (len(args) < 2 or settings is None):
        fail("usage", "usage: render_bench.py BENCH.csv OUT.png [TITLE] --settings TABLE.json, or render_bench.py --check")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import settings_table
    except ImportError as e:
        fail("unavailable", f"{sys.executable}: {e.name} is missing (matplotlib: scripts/install-deps.sh installs "
             "python3-matplotlib; settings_table.py lies beside this script)")
    if check:
        return
    try:
        table = settings_table.read(settings)
    except settings_table.InputError as e:
        fail(e.kind, str(e))
    baseline = table.role("timing-baseline")
    times = {}  # method -> {frame: ms}
    name = os.path.basename(args[1])
    if not name.lower().endswith(".png") or name.lower() == ".png":
        fail("usage", f"{args[1]}: the plot is a PNG file: name it NAME.png")
    try:
        with open(args[0], newline="") as f:
            for row in csv.DictReader(f):
                times.setdefault(row["method"], {})[int(row["frame"])] = float(row["ms"])
    except OSError as e:
        fail("io", f"{args[0]}: cannot read it ({e.strerror})")
    except KeyError as e:
        fail("schema", f"{args[0]}: not a bench CSV (no column {e})")
    except (ValueError, TypeError, UnicodeDecodeError, csv.Error) as e:
        fail("parse", f"{args[0]}: not a bench CSV ({e})")
    if baseline not in times:
        fail("usage", f"{args[0]}: no {baseline} rows (the times are relative to {baseline}'s: render with --method "
             f"including {baseline})")
    reference = times[baseline]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    # A method's second drawing (M#again) right after it, dotted, in its colour.
    for method in table.sorted({m.split("#")[0] for m in times}):
        for name, style in ((method, "-"), (method + "#again", ":")):
            if name not in times:
                continue
            by_frame = times[name]
            frames = sorted(f for f in by_frame if f in reference and reference[f] > 0)
            ax.plot(frames, [by_frame[f] / reference[f] for f in frames], label=name, linewidth=1.2,
                    linestyle=style, color=table.colour(method))
    ax.axhline(1.0, color="grey", linewidth=0.8, linestyle=":")
    ax.set_xlabel("frame")
    ax.set_ylabel(f"GL frame time / {baseline}'s")
    ax.set_title(args[2] if len(args) > 2 else f"frame time relative to {baseline}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    try:
        fig.savefig(args[1], dpi=100)
    except (OSError, ValueError) as e:
        fail("io", f"{args[1]}: {e}")


if __name__ == "__main__":
    main(sys.argv)
