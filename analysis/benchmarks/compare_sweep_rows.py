#!/usr/bin/env python3
"""Compare two `nearcap sweep` CSVs row by row with the timing columns dropped.

Usage: compare_sweep_rows.py BEFORE.csv AFTER.csv

Rows are matched by (configuration, light, method, variant); every column
present in both files is compared as text except the times (names ending in
`_ms`).  Columns only one file has (a format that gained columns) are listed
and not compared.  Exit status 0 when every row matches, 1 otherwise (the
first differences printed), 2 on unusable input.
"""
import csv
import sys

from script_errors import fail, reading, run  # the same directory

KEY = ("configuration", "light", "method", "variant")


def read(path):
    with reading(path, "a sweep CSV"):
        return read_rows(path)


def read_rows(path):
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header is None:
            fail("parse", f"{path}: empty")
        if any(k not in header for k in KEY):
            fail("schema", f"{path}: not a sweep CSV (no column {next(k for k in KEY if k not in header)})")
        rows = {}
        for line, cells in enumerate(reader, start=2):
            if cells == header:
                continue  # a second group's header
            if len(cells) != len(header):
                fail("parse", f"{path}:{line}: {len(cells)} fields, the header has {len(header)}")
            row = dict(zip(header, cells))
            key = tuple(row[k] for k in KEY)
            if key in rows:
                fail("parse", f"{path}:{line}: row {key} repeated")
            rows[key] = row
        return header, rows


def main(argv):
    if len(argv) != 2:
        fail("usage", "usage: compare_sweep_rows.py BEFORE.csv AFTER.csv")
    before_header, before = read(argv[0])
    after_header, after = read(argv[1])
    common = [c for c in before_header if c in after_header and not c.endswith("_ms")]
    only = sorted(set(before_header) ^ set(after_header))
    if only:
        print("columns in one file only (not compared): " + ", ".join(only))
    differences = 0
    for key in sorted(set(before) | set(after)):
        if key not in before or key not in after:
            differences += 1
            if differences <= 10:
                print(f"row {key}: only in {'AFTER' if key not in before else 'BEFORE'}")
            continue
        for c in common:
            if before[key][c] != after[key][c]:
                differences += 1
                if differences <= 10:
                    print(f"row {key}: {c}: {before[key][c]!r} -> {after[key][c]!r}")
    print(f"{len(before)} rows before, {len(after)} after, {len(common)} columns compared, "
          f"{differences} differences")
    return 0 if differences == 0 else 1


if __name__ == "__main__":
    run(lambda: main(sys.argv[1:]), " or ".join(sys.argv[1:3]))
