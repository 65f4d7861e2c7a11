#!/usr/bin/env python3
"""The clipped-sides cap's construction time per frame, from the render.json of
`nearcap render --path PATH --bench --light-projection clipped-sides`
(docs/viewer.md: each frame's "cpu" breakdown per light and occluder).

Usage: cap_cpu_table.py RENDER.json LABEL [FIRST LAST]
Prints one Markdown row per method (frames FIRST..LAST, inclusive, or all):
the median GL frame (ms), end_to_end_ms and cpu_ms; the cap's build time per
frame (every light's and occluder's cap_build_ms, summed: 0 for Z-pass and
Z-fail), median, 90th percentile and max; the cap's share of the frame's
end_to_end_ms, median and max.
Bad input is one line on stderr, exit code 2 (script_errors.py).
"""
import statistics
import sys

from script_errors import fail, read_json, run  # the same directory


def main(argv):
    if len(argv) not in (3, 5):
        fail("usage", "usage: cap_cpu_table.py RENDER.json LABEL [FIRST LAST]")
    try:
        first, last = (int(argv[3]), int(argv[4])) if len(argv) == 5 else (0, None)
    except ValueError:
        fail("usage", f"FIRST and LAST: '{argv[3]}', '{argv[4]}' are not whole numbers")
    root = read_json(argv[1], "a render.json")
    if not isinstance(root, dict) or not isinstance(root.get("methods"), list):
        fail("schema", f"{argv[1]}: not a render.json (no methods list)")
    for method in root["methods"]:
        frames = [f for f in method.get("frames", []) if f["frame"] >= first and (last is None or f["frame"] <= last)]
        if not frames or "cpu" not in frames[0]:
            fail("schema", f"{argv[1]}: {method['method']}: no frames with a CPU breakdown (render with --bench)")
        cap = [sum(o["cap_build_ms"] for l in f["cpu"]["lights"] for o in l["occluders"]) for f in frames]
        e2e = [f["end_to_end_ms"] for f in frames]
        share = [c / e for c, e in zip(cap, e2e)]
        p90 = statistics.quantiles(cap, n=10)[-1] if len(cap) > 1 else cap[0]
        print(
            "| %s | %s | %d | %.2f | %.2f | %.2f | %.3f | %.3f | %.3f | %.0f%% | %.0f%% |"
            % (argv[2], method["method"], len(frames), statistics.median(f["ms"] for f in frames),
               statistics.median(e2e), statistics.median(f["cpu_ms"] for f in frames), statistics.median(cap), p90,
               max(cap), 100 * statistics.median(share), 100 * max(share)))

if __name__ == "__main__":
    run(lambda: main(sys.argv), sys.argv[1] if len(sys.argv) > 1 else "")
