#!/usr/bin/env python3
"""A large sweep CSV from a small real one, to measure `nearcap report` at
the million-configuration scale (docs/findings/report-scale.md).

    replicate_rows.py SMALL.csv ROWS OUT.csv

Copies SMALL.csv's configurations (each with all its rows, in order) again
and again under new names ("sample:R:N" for the R-th copy of sample N,
"path:NAME-R:F" for a path's) until OUT.csv holds at least ROWS data rows,
and perturbs each copy's times and conditioning features by a factor in
[0.9, 1.1] (a fixed seed) so that no two copies are equal.  Counts (pixels,
cracks, fragments) are kept: every row stays a row nearcap could write.
Errors are one line on stderr, "nearcap: error (KIND): replicate_rows.py:
...", exit code 2, KIND as nearcap's own: usage, io, parse (not a sweep CSV).
"""
import csv
import random
import sys

PERTURBED = ["frame_ms", "frame_again_ms", "setup_ms", "depth_ms", "near_cap_ms", "volume_ms", "reference_ms",
             "reference_setup_ms", "reference_trace_ms",
             "light_near_distance", "l_far_over_width", "delta_over_width", "skew", "cond_projection", "cond_light_transform",
             "coordinate_over_size", "depth_step_over_size", "cap_window_error_px", "cap_window_error_ulp"]


def fail(kind, message):
    print(f"nearcap: error ({kind}): replicate_rows.py: {message}", file=sys.stderr)
    sys.exit(2)


def main(argv):
    if len(argv) != 3:
        fail("usage", "usage: replicate_rows.py SMALL.csv ROWS OUT.csv")
    small, out = argv[0], argv[2]
    try:
        wanted = int(argv[1])
    except ValueError:
        wanted = 0
    if wanted <= 0:
        fail("usage", f"ROWS: '{argv[1]}' is not a positive whole number")
    try:
        with open(small, newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            groups, current = [], None
            for row in reader:
                if not row or ":" not in row[0]:
                    fail("parse", f"{small}: line {reader.line_num}: not a sweep row (no configuration id)")
                if row[0] != current:
                    groups.append([])
                    current = row[0]
                groups[-1].append(row)
    except OSError as e:
        fail("io", f"{small}: cannot read it ({e.strerror})")
    except (UnicodeDecodeError, csv.Error) as e:
        fail("parse", f"{small}: cannot read it as a sweep CSV ({e})")
    if header is None or not groups:
        fail("parse", f"{small}: no rows to copy (a sweep CSV with at least one configuration is needed)")
    rng = random.Random(1)
    perturbed = [header.index(c) for c in PERTURBED if c in header]
    written, copy = 0, 0
    try:
        f = open(out, "w", newline="", encoding="utf-8")
    except OSError as e:
        fail("io", f"{out}: cannot write it ({e.strerror})")
    with f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        while written < wanted:
            copy += 1
            for group in groups:
                source, _, index = group[0][0].rpartition(":")
                kind, name = source.split(":", 1)
                configuration = f"{kind}:{name}-{copy}:{index}" if kind == "path" else f"{kind}:{copy}:{name}:{index}"
                factor = rng.uniform(0.9, 1.1)
                for row in group:
                    row = list(row)
                    row[0] = configuration
                    for k in perturbed:
                        try:
                            row[k] = f"{float(row[k]) * factor:.6g}"
                        except ValueError:
                            pass
                    w.writerow(row)
                    written += 1
                if written >= wanted:
                    break
    print(f"{out}: {written} rows, {copy} copies of {len(groups)} configurations")


if __name__ == "__main__":
    main(sys.argv[1:])
