#!/usr/bin/env python3
"""The code a callgrind profile ran: distinct 64-byte instruction lines, per function.

What a call costs when its caches are cold is mostly its code: each distinct
line it runs is a miss.  Give a profile written with --dump-instr=yes, e.g.

    NEARCAP_BENCH_POLICY_SEED=4242 NEARCAP_BENCH_POLICY_SAMPLES=40 NEARCAP_BENCH_POLICY_SIZE=160x120 \
    valgrind --tool=callgrind --dump-instr=yes \
        --toggle-collect='nearcap::analysis::decide(*' --callgrind-out-file=F \
        ./build/analysis/benchmarks/nearcap_benchmarks --benchmark_filter='PolicyDecision/0/1' \
        --benchmark_min_time=0.01

Usage: analysis/benchmarks/code_footprint.py F [TOP]   (TOP functions listed, default 12)
"""
import collections
import re
import sys

from script_errors import fail, run  # the same directory


def footprint(path):
    names, lines, current, address = {}, collections.defaultdict(set), None, 0
    for text in open(path, encoding="utf-8", errors="replace"):
        if text.startswith(("fn=", "cfn=")):
            m = re.match(r"c?fn=\((\d+)\)(?: (.*))?", text.rstrip("\n"))
            if m and m.group(2):
                names[m.group(1)] = m.group(2)
            if m and text.startswith("fn="):
                current = names.get(m.group(1))
            continue
        # Cost lines: an address (absolute, +/- relative or * for the same),
        # then the costs.  Call lines' costs name the call site's address.
        m = re.match(r"^(0x[0-9a-f]+|[+-]\d+|\*)\s+\d", text)
        if not m:
            continue
        a = m.group(1)
        if a.startswith("0x"):
            address = int(a, 16)
        elif a[0] in "+-":
            address += int(a)
        lines[current].add(address >> 6)
    return lines


def main():
    if len(sys.argv) not in (2, 3):
        fail("usage", "usage: code_footprint.py CALLGRIND_FILE [TOP]")
    try:
        top = int(sys.argv[2]) if len(sys.argv) > 2 else 12
    except ValueError:
        fail("usage", f"TOP: '{sys.argv[2]}' is not a whole number")
    try:
        lines = footprint(sys.argv[1])
    except OSError as e:
        fail("io", f"{sys.argv[1]}: cannot read it ({e.strerror})")
    if not lines:
        fail("parse", f"{sys.argv[1]}: no cost line (a callgrind profile written with --dump-instr=yes)")
    total = set()
    for s in lines.values():
        total |= s
    pages = {line >> 6 for line in total}
    print(f"{len(total)} distinct 64-byte lines of code ({len(total) * 64 / 1024:.0f} KiB) on {len(pages)} 4 KiB pages")
    for name, s in sorted(lines.items(), key=lambda kv: -len(kv[1]))[:top]:
        print(f"{len(s):6d}  {name[:110] if name else '?'}")


if __name__ == "__main__":
    run(main, sys.argv[1] if len(sys.argv) > 1 else "")
