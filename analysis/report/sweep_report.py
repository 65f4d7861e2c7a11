#!/usr/bin/env python3
"""nearcap's sweep report: one HTML page with plots and tables from the CSV
rows of `nearcap sweep` (one or more files).  Run through `nearcap report`,
or directly:

    sweep_report.py RESULTS.csv [MORE.csv ...] --out DIR

DIR/index.html is the page; beside it, the plots (PNG, matplotlib), the
tables as CSV (summary.csv, by_kind.csv, case_d.csv) and report.json (what
was plotted: the files and how many data points each holds).  Nothing is
written to DIR unless the whole report was built (it is assembled in a
temporary folder next to DIR first).  Errors are one line on stderr,
"nearcap: error (KIND): FILE: ...", exit code 2.

Sections:
  1. speed against error: mean emulated frame time per configuration against
     wrong pixels and against cracks, per method; the Pareto front;
  2. each camera path: time per frame relative to Z-pass (the paper's
     Figure 9 style), cracks per frame, the exact case counts per frame;
  3. cracks against each conditioning feature (conditioning.hpp);
  4. crack-distance histograms per method;
  5. the paper's case-D claim: frames where ZP+ (corrected) cracks without a
     case-D quad, and case-D switches that were not needed;
  6. the hard-case sampler by kind.
"""
import csv
import html
import json
import math
import os
import shutil
import sys
import tempfile
from collections import OrderedDict, defaultdict
from pathlib import Path

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402
except ImportError:
    print(f"nearcap: error (io): {sys.executable} has no matplotlib (Debian: python3-matplotlib, which "
          "scripts/install-deps.sh installs; or set NEARCAP_PYTHON to a Python that has it)", file=sys.stderr)
    sys.exit(2)

POLICY_ORDER = ["doom3", "doom3-bfg", "ogre", "always-zfail"]  # engine rules (sweep --policies)
METHOD_ORDER = ["zpass", "zfail", "zpplus", "zpplus-corrected", "preload", "policy"] + POLICY_ORDER
# Per-occluder decision columns (nearcap sweep since the engine baselines); a
# CSV without them gets no baseline section.
DECISION_COLUMNS = ["occluders", "zpass_wrong_occluders", "false_negatives", "false_positives"]
BUCKETS = ["lt_1_512", "1_512", "1_64", "1_8", "1_2", "2", "8"]
BUCKET_LABELS = ["<1/512", "1/512", "1/64", "1/8", "1/2", "2", "8"]
CASES = ["A", "B", "C1", "C2", "D"]
FEATURES = [
    ("light_near_distance", "light to near plane / near (signed)"),
    ("l_far_over_width", "l_far / near width"),
    ("delta_over_width", "|Delta_xy - centre| / near width"),
    ("skew", "light pyramid skew"),
    ("l_near_over_l_far", "l_near / l_far"),
    ("cond_projection", "cond(P_l)"),
    ("cond_light_transform", "cond(P_l M_l)"),
    ("coordinate_over_size", "largest coordinate / scene size"),
    ("depth_step_over_size", "24-bit depth step at the farthest point / scene size"),
    ("cap_window_error_px", "near-cap window error (px)"),
    ("cap_window_error_ulp", "near-cap window error (ulp)"),
]
INTEGER_COLUMNS = ["light", "refused", "pixels_seen", "wrong", "cracks", "wrong_lit", "wrong_shadowed", "count_mismatch",
                   "zfail_objects", "case_disagreements"] + ["wrong_r_" + b for b in BUCKETS] + \
                  ["exact_" + c for c in CASES] + ["float_" + c for c in CASES]
FLOAT_COLUMNS = ["frame_ms", "setup_ms", "depth_ms", "near_cap_ms", "volume_ms", "reference_ms"] + \
                [f for f, _ in FEATURES]
REQUIRED = ["configuration", "source", "kind", "detail", "method", "variant", "fallback", "cap_mismatch"] + INTEGER_COLUMNS + \
           FLOAT_COLUMNS + [p + "_" + c for p in ("depth", "near_cap", "volume")
                            for c in ("fragments", "depth_pass", "depth_fail")]


class ReportError(Exception):
    def __init__(self, kind, message):
        super().__init__(message)
        self.kind = kind


def read_rows(files):
    rows, rejected, seen, refused = [], 0, {}, []
    for name in files:
        try:
            handle = open(name, newline="")
        except OSError as e:
            raise ReportError("io", f"{name}: cannot read: {e.strerror}")
        with handle:
            reader = csv.DictReader(handle)
            if reader.fieldnames is None:
                raise ReportError("parse", f"{name}: empty file, not a nearcap sweep CSV")
            missing = [c for c in REQUIRED if c not in reader.fieldnames]
            if missing:
                raise ReportError("schema", f"{name}: line 1: missing column '{missing[0]}' "
                                           f"(not a nearcap sweep CSV, or one from an older nearcap)")
            for line, r in enumerate(reader, start=2):
                if r["method"] == "rejected":
                    rejected += 1
                    continue
                if None in r or any(r[c] is None for c in REQUIRED):
                    raise ReportError("parse", f"{name}: line {line}: wrong number of fields")
                for c in INTEGER_COLUMNS:
                    try:
                        r[c] = int(r[c])
                    except ValueError:
                        raise ReportError("parse", f"{name}: line {line}: column '{c}': '{r[c]}' is not an integer")
                for c in FLOAT_COLUMNS:
                    try:
                        r[c] = float(r[c])
                    except ValueError:
                        raise ReportError("parse", f"{name}: line {line}: column '{c}': '{r[c]}' is not a number")
                for p in ("depth", "near_cap", "volume"):
                    for c in ("fragments", "depth_pass", "depth_fail"):
                        r[p + "_" + c] = int(r[p + "_" + c])
                r["cap_mismatch"] = int(r["cap_mismatch"]) if r["cap_mismatch"] else None
                for c in DECISION_COLUMNS:
                    value = r.get(c)
                    try:
                        r[c] = int(value) if value not in (None, "") else None
                    except ValueError:
                        raise ReportError("parse", f"{name}: line {line}: column '{c}': '{value}' is not an integer")
                if r["refused"]:
                    refused.append(r)
                    continue
                # A method under a non-default variant is its own series: "zpplus [light-projection=glfrustum]".
                if r["variant"] != "default":
                    r["method"] = f'{r["method"]} [{r["variant"]}]'
                key = (r["configuration"], r["light"], r["method"])
                if key in seen:
                    raise ReportError("parse", f"{name}: line {line}: a second row for configuration "
                                               f"'{key[0]}' light {key[1]} method {key[2]} (first: {seen[key]})")
                seen[key] = f"{name} line {line}"
                rows.append(r)
    if not rows:
        raise ReportError("parse", f"{files[0]}: no rows to report on")
    return rows, rejected, refused


def methods_of(rows):
    present = {r["method"] for r in rows}
    order = {m: k for k, m in enumerate(METHOD_ORDER)}
    return sorted(present, key=lambda m: (order.get(m.split(" [")[0], len(order)), m))


def legend(ax, **options):
    """A legend when the axes have labelled series (matplotlib warns otherwise)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**options)


def colour(method):
    palette = {"zpass": "#d62728", "zfail": "#1f77b4", "zpplus": "#ff7f0e", "zpplus-corrected": "#2ca02c",
               "preload": "#9467bd", "doom3": "#8c564b", "doom3-bfg": "#e377c2", "ogre": "#bcbd22",
               "always-zfail": "#17becf", "policy": "#000000"}
    if method in palette:
        return palette[method]
    # A variant: its method's hue, darker.
    base = palette.get(method.split(" [")[0], "#7f7f7f")
    r, g, b = (int(base[k:k + 2], 16) for k in (1, 3, 5))
    return f"#{r * 3 // 5:02x}{g * 3 // 5:02x}{b * 3 // 5:02x}"


class Report:
    def __init__(self, rows, rejected, out):
        self.rows, self.rejected, self.out = rows, rejected, out
        self.methods = methods_of(rows)
        self.refused = []
        self.plots, self.sections = [], []
        self.policy, self.policy_source = None, None

    def save(self, fig, name, points):
        fig.savefig(self.out / name, dpi=110, bbox_inches="tight")
        plt.close(fig)
        self.plots.append({"file": name, "points": points})
        return name

    def table(self, header, body, csv_name=None):
        if csv_name:
            with open(self.out / csv_name, "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(header)
                w.writerows(body)
        cells = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
        lines = [f"<tr>{cells}</tr>"]
        for row in body:
            lines.append("<tr>" + "".join(f"<td>{html.escape(fmt(v))}</td>" for v in row) + "</tr>")
        return "<table>" + "".join(lines) + "</table>"

    # ---- 1. speed against error ---------------------------------------------
    def pareto(self):
        per = defaultdict(lambda: {"ms": 0.0, "wrong": 0, "cracks": 0, "rows": 0, "with_cracks": 0,
                                   "frag_pass": 0, "frag_fail": 0, "ref_ms": 0.0})
        configs = {r["configuration"] for r in self.rows}
        for r in self.rows:
            p = per[r["method"]]
            p["ms"] += r["frame_ms"]
            p["wrong"] += r["wrong"]
            p["cracks"] += r["cracks"]
            p["rows"] += 1
            p["with_cracks"] += r["cracks"] > 0
            p["frag_pass"] += r["volume_depth_pass"]
            p["frag_fail"] += r["volume_depth_fail"]
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
        points = 0
        for ax, metric, label in ((axes[0], "wrong", "wrong pixels (all rows)"), (axes[1], "cracks", "cracks (all rows)")):
            xs = {m: per[m]["ms"] / max(1, per[m]["rows"]) for m in self.methods}
            ys = {m: per[m][metric] for m in self.methods}
            for m in self.methods:
                ax.scatter([xs[m]], [ys[m]], s=60, color=colour(m), label=m, zorder=3)
                ax.annotate(m, (xs[m], ys[m]), textcoords="offset points", xytext=(5, 5), fontsize=8)
                points += 1
            front = pareto_front([(xs[m], ys[m]) for m in self.methods])
            ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=1, label="Pareto front", zorder=2)
            ax.set_yscale("symlog", linthresh=1)
            ax.set_ylim(bottom=-0.3)
            ax.set_xlabel("mean emulated frame time per row (ms)")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        legend(axes[0], fontsize=8)
        fig.suptitle("speed against error, per method")
        img = self.save(fig, "pareto.png", points)
        header = ["method", "rows", "wrong", "cracks", "rows with cracks", "mean frame ms", "volume frags depth-pass",
                  "volume frags depth-fail"]
        body = [[m, per[m]["rows"], per[m]["wrong"], per[m]["cracks"], per[m]["with_cracks"],
                 per[m]["ms"] / max(1, per[m]["rows"]), per[m]["frag_pass"], per[m]["frag_fail"]] for m in self.methods]
        ref_ms = {}
        for r in self.rows:
            ref_ms[(r["configuration"], r["light"])] = r["reference_ms"]
        refused = defaultdict(int)
        for r in self.refused:
            refused[r["method"]] += 1
        refusals = ", ".join(f"{m} {n}" for m, n in sorted(refused.items()))
        text = (f"<p>{len(configs)} configurations, {len(self.rows)} rows"
                f"{f', {self.rejected} configurations rejected (the scene did not load)' if self.rejected else ''}"
                f"{f'; frames the float pipeline refused (float32 transforms degenerate): {refusals}' if refusals else ''}. "
                f"Exact reference: {sum(ref_ms.values()) / max(1, len(ref_ms)):.1f} ms per (configuration, light) "
                f"on average. Z-pass counts on depth-passing fragments and Z-fail on failing ones: the volume "
                f"pass's split says which of the two had more to do.</p>")
        self.sections.append(("Speed against error", text + f'<img src="{img}">' +
                              self.table(header, body, "summary.csv")))

    # ---- 2. paths --------------------------------------------------------------
    def paths(self):
        by_path = defaultdict(list)
        for r in self.rows:
            if r["configuration"].startswith("path:"):
                by_path[r["kind"]].append(r)
        if not by_path:
            return
        parts = []
        for name in sorted(by_path):
            rows = by_path[name]
            frame_of = lambda r: int(r["configuration"].rsplit(":", 1)[1])  # noqa: E731
            frames = sorted({frame_of(r) for r in rows})
            table = {(frame_of(r), r["light"], r["method"]): r for r in rows}
            lights = sorted({r["light"] for r in rows})
            fig, axes = plt.subplots(3, 1, figsize=(9, 8.5), sharex=True)
            points = 0
            for m in self.methods:
                rel, cr = [], []
                for f in frames:
                    ms = sum(table[(f, l, m)]["frame_ms"] for l in lights if (f, l, m) in table)
                    base = sum(table[(f, l, "zpass")]["frame_ms"] for l in lights if (f, l, "zpass") in table)
                    rel.append(ms / base if base > 0 else math.nan)
                    cr.append(sum(table[(f, l, m)]["cracks"] for l in lights if (f, l, m) in table))
                axes[0].plot(frames, rel, color=colour(m), label=m)
                axes[1].plot(frames, cr, color=colour(m), label=m)
                points += 2 * len(frames)
            axes[0].axhline(1.0, color="k", lw=0.5)
            axes[0].set_ylabel("frame time / Z-pass")
            legend(axes[0], fontsize=7, ncol=3)
            axes[1].set_yscale("symlog", linthresh=1)
            axes[1].set_ylim(bottom=-0.3)
            axes[1].set_ylabel("cracks")
            bottom = [0] * len(frames)
            first_method = self.methods[0]
            for c, col in zip(CASES, ["#c7e9c0", "#9ecae1", "#fdd0a2", "#fdae6b", "#e6550d"]):
                vals = [sum(table[(f, l, first_method)]["exact_" + c] for l in lights if (f, l, first_method) in table)
                        for f in frames]
                axes[2].bar(frames, vals, bottom=bottom, color=col, label=c, width=1.0)
                bottom = [b + v for b, v in zip(bottom, vals)]
                points += len(frames)
            axes[2].set_ylabel("exact quad cases")
            axes[2].set_xlabel("frame")
            legend(axes[2], fontsize=7, ncol=5)
            fig.suptitle(f"path {name}")
            img = self.save(fig, f"path_{safe(name)}.png", points)
            totals = [[m, sum(r["wrong"] for r in rows if r["method"] == m),
                       sum(r["cracks"] for r in rows if r["method"] == m),
                       sum(r["frame_ms"] for r in rows if r["method"] == m) / len(frames)] for m in self.methods]
            parts.append(f"<h3>{html.escape(name)} ({len(frames)} frames)</h3><img src=\"{img}\">" +
                         self.table(["method", "wrong", "cracks", "mean frame ms"], totals))
        self.sections.append(("Camera paths", "<p>Per frame: time relative to Z-pass (the paper's Figure 9 "
                                              "style), cracks, and the exact classification of the silhouette "
                                              "quads against the near plane.</p>" + "".join(parts)))

    # ---- 3. features -----------------------------------------------------------
    def features(self):
        shown = [m for m in ("zpplus", "zpplus-corrected", "zfail", "zpass") if m in self.methods]
        fig, axes = plt.subplots(4, 3, figsize=(13, 13))
        points = 0
        for ax, (feature, label) in zip(axes.flat, FEATURES):
            for m in shown:
                xs, ys = [], []
                for r in self.rows:
                    v = r[feature]
                    if r["method"] == m and math.isfinite(v):
                        xs.append(abs(v) if feature == "light_near_distance" else v)
                        ys.append(r["cracks"])
                ax.scatter(xs, ys, s=8, alpha=0.5, color=colour(m), label=m)
                points += len(xs)
            values = [abs(r[feature]) for r in self.rows if math.isfinite(r[feature])]
            positive = [v for v in values if v > 0]
            if positive and max(positive) / min(positive) > 100:
                if len(positive) < len(values):  # zeros too (the light in the near plane)
                    ax.set_xscale("symlog", linthresh=min(positive))
                else:
                    ax.set_xscale("log")
            ax.set_yscale("symlog", linthresh=1)
            ax.set_ylim(bottom=-0.3)
            ax.set_xlabel(("|" + label + "|") if feature == "light_near_distance" else label, fontsize=8)
            ax.set_ylabel("cracks", fontsize=8)
            ax.grid(alpha=0.3)
        legend(axes.flat[0], fontsize=7)
        for ax in list(axes.flat)[len(FEATURES):]:
            ax.axis("off")
        fig.suptitle("cracks against the conditioning features, one point per (configuration, light, method)")
        img = self.save(fig, "features.png", points)
        self.sections.append(("Cracks against conditioning", f'<img src="{img}">'))

    # ---- 4. crack distance -----------------------------------------------------
    def distances(self):
        fig, ax = plt.subplots(figsize=(9, 4))
        width = 0.8 / max(1, len(self.methods))
        points = 0
        body = []
        for k, m in enumerate(self.methods):
            totals = [sum(r["wrong_r_" + b] for r in self.rows if r["method"] == m) for b in BUCKETS]
            ax.bar([i + k * width for i in range(len(BUCKETS))], totals, width=width, color=colour(m), label=m)
            points += len(BUCKETS)
            body.append([m] + totals)
        ax.set_xticks([i + 0.4 - width / 2 for i in range(len(BUCKETS))])
        ax.set_xticklabels(BUCKET_LABELS)
        ax.set_yscale("symlog", linthresh=1)
        ax.set_xlabel("crack distance: largest proven-constant square half-width (pixels); >= 1/2 is a crack")
        ax.set_ylabel("wrong pixels")
        legend(ax, fontsize=8)
        img = self.save(fig, "crack_distance.png", points)
        self.sections.append(("Crack distance", "<p>Wrong pixels by how far the exact status is proven constant "
                                                "around them: below 1/2 pixel is rasterization noise at a shadow "
                                                "boundary, 1/2 and above a crack.</p>" + f'<img src="{img}">' +
                              self.table(["method"] + BUCKET_LABELS, body, "crack_distance.csv")))

    # ---- 5. the case-D claim ---------------------------------------------------
    def case_d(self):
        rows = {(r["configuration"], r["light"], r["method"]): r for r in self.rows}
        keys = sorted({(c, l) for (c, l, m) in rows})
        if "zpplus-corrected" not in self.methods:
            return
        cracked_without_d, switches, unnecessary, cracked_with_d, after_fallback = 0, 0, 0, 0, 0
        examples = []
        for c, l in keys:
            zc = rows.get((c, l, "zpplus-corrected"))
            zp = rows.get((c, l, "zpplus"))
            if zc is None:
                continue
            if zc["fallback"] and not zc["zfail_objects"]:
                after_fallback += zc["cracks"] > 0
                continue
            zf = rows.get((c, l, "zfail"))
            baseline = zf["cracks"] if zf is not None else 0  # cracks every method has (depth precision)
            if zc["cracks"] > baseline and zc["float_D"] == 0:
                cracked_without_d += 1
                if len(examples) < 8:
                    examples.append([c, l, zc["cracks"], zc["float_D"], zc["fallback"]])
            if zc["cracks"] > baseline and zc["float_D"] > 0:
                cracked_with_d += 1
            if zc["zfail_objects"] > 0:
                switches += 1
                if zp is not None and zp["cracks"] == 0:
                    unnecessary += 1
        body = [["(configuration, light) pairs", len(keys)],
                ["ZP+ corrected cracks more than Z-fail, no case-D quad", cracked_without_d],
                ["ZP+ corrected cracks more than Z-fail despite case D", cracked_with_d],
                ["ZP+ corrected has cracks after falling back to Z-fail (no light frustum)", after_fallback],
                ["case-D switches to Z-fail", switches],
                ["  of which ZP+ without the switch had no crack", unnecessary if "zpplus" in self.methods else "-"]]
        text = ("<p>The paper switches an occluder to Z-fail when one of its silhouette quads is in case D, "
                "assuming that case D flags the ill-conditioned configurations. Measured here, counting only "
                "the cracks Z-fail does not have in the same frame (those come from depth precision, not the "
                "near-cap):</p>" +
                self.table(["", "count"], body, "case_d.csv"))
        if examples:
            text += "<p>Examples of cracks without case D (replay them with the sweep's replay column):</p>" + \
                    self.table(["configuration", "light", "cracks", "float D", "fallback"], examples)
        self.sections.append(("Does case D flag the bad configurations?", text))

    # ---- 5b. Z-pass or Z-fail per occluder: the engines' rules ------------------
    def baselines(self):
        rows = [r for r in self.rows if r.get("false_negatives") is not None]
        if not rows:
            return
        header = ["method", "occluder decisions", "Z-pass wrong (exact)", "Z-fail where needed",
                  "false negatives", "false positives", "Z-pass where right", "frames with cracks", "cracks",
                  "wrong", "mean frame ms", "volume fragments"]
        body = []
        for m in self.methods:
            rs = [r for r in rows if r["method"] == m]
            if not rs:
                continue
            occluders = sum(r["occluders"] for r in rs)
            truth = sum(r["zpass_wrong_occluders"] for r in rs)
            fn = sum(r["false_negatives"] for r in rs)
            fp = sum(r["false_positives"] for r in rs)
            body.append([m, occluders, truth, truth - fn, fn, fp, occluders - truth - fp,
                         sum(1 for r in rs if r["cracks"] > 0), sum(r["cracks"] for r in rs),
                         sum(r["wrong"] for r in rs), fmt(sum(r["frame_ms"] for r in rs) / len(rs)),
                         sum(r["volume_fragments"] for r in rs)])
        text = ("<p>Each occluder of each (configuration, light) drawn with Z-pass or Z-fail: by the methods "
                "themselves (all one or the other) and by the rules shipped engines use "
                "(<code>nearcap sweep --policies</code>; README, \"Engine baselines\"). The exact truth: Z-pass is "
                "wrong for an occluder when its own near-cap covers a pixel centre. A false negative is Z-pass "
                "where it is wrong (a crack an engine ships), a false positive Z-fail where Z-pass is right "
                "(cost paid for nothing).</p>" + self.table(header, body, "baselines.csv"))
        self.sections.append(("Z-pass or Z-fail per occluder: engine rules", text))

    # ---- 5c. the switch policy's fitted models ---------------------------------
    def policy_models(self):
        p = self.policy
        if p is None:
            return
        prov = p.get("provenance", {})
        m = p.get("crack_model", {})
        capped = html.escape(str(p.get('capped_method')))
        projection = p.get("light_projection", "paper")
        if projection != "paper":
            capped += f" (near-cap: <code>{html.escape(str(projection))}</code>)"
        if m.get("features"):
            rule = (f"unless the crack model predicts a crack (P &ge; {m.get('threshold', 0):.3g}), then "
                    f"{html.escape(str(p.get('fallback_method')))}")
        else:
            rule = ("always: no crack model (the capped method never cracked more than "
                    f"{html.escape(str(p.get('fallback_method')))} in training, so there was nothing to fit)")
        if p.get("exact_zpass", True):
            who = "occluders that meet no point of the light pyramid get Z-pass (exact); the others"
        else:
            who = "every occluder (no exact Z-pass test) gets"
        text = (f"<p>From <code>{html.escape(self.policy_source)}</code>: {who} {capped} {rule}. Fitted by <code>"
                f"{html.escape(str(prov.get('command', '?')))}</code>; split: "
                f"{html.escape(str(prov.get('split', '?')))}.</p>")
        body = []
        for side, label in (("train", "train"), ("held_out", "held out")):
            c = prov.get(side)
            if c:
                body.append([label, c.get("samples"), c.get("cracks"), c.get("cracks_predicted"), c.get("false_alarms")])
        if body:
            text += self.table(["split", "(configuration, light) pairs", "capped cracks more than fallback",
                                "predicted", "false alarms"], body, "policy_crack_model.csv")
        weights = [[f, fmt(w), fmt(mu), fmt(sd)] for f, w, mu, sd in
                   zip(m.get("features", []), m.get("weights", []), m.get("mean", []), m.get("scale", []))]
        if weights:
            text += "<p>The logistic model on standardized features (bias " + fmt(float(m.get("bias", 0))) + "):</p>"
        else:
            text += "<p>No logistic model: no feature, no weight.</p>"
        text += self.table(["feature", "weight", "mean", "scale"], weights, "policy_weights.csv")
        costs = []
        for method, cm in p.get("cost_models", {}).items():
            errors = prov.get("cost", {}).get(method, {})
            costs.append([method, fmt(float(cm["intercept_ms"])), fmt(float(cm["ms_per_mtriangle"])),
                          fmt(float(cm["ms_per_mfragment"])),
                          fmt(100 * float(errors.get("train_median_relative_error", float("nan")))),
                          fmt(100 * float(errors.get("held_out_median_relative_error", float("nan"))))])
        if costs:
            text += "<p>Cost models (frame time from the work drawn; median relative error in %):</p>"
            text += self.table(["method", "ms", "ms per M triangles", "ms per M fragments", "train error %",
                                "held-out error %"], costs, "policy_costs.csv")
        self.sections.append(("The switch policy's fitted models", text))

    # ---- 5d. the policy's cost against its targets ---------------------------
    def policy_cost(self):
        """Issue 12's cost targets: where Z-pass is right (every occluder's exact near-cap empty), the policy's
        frame time and fragments against Z-pass's; elsewhere against ZP+ corrected's.  Pairs are the
        (configuration, light) where all three rows are present."""
        table = {}
        for r in self.rows:
            table[(r["configuration"], r["light"], r["method"])] = r
        pairs = {(c, l) for (c, l, m) in table if m == "policy"}
        sums = {}
        for c, l in pairs:
            z, p, zp = (table.get((c, l, m)) for m in ("zpass", "policy", "zpplus-corrected"))
            if z is None or p is None or z.get("zpass_wrong_occluders") is None:
                continue
            where, base = ("Z-pass right", z) if z["zpass_wrong_occluders"] == 0 else ("elsewhere", zp)
            if base is None:
                continue
            s_ = sums.setdefault(where, [0, 0.0, 0.0, 0, 0, 0.0])
            s_[0] += 1
            s_[1] += p["frame_ms"]
            s_[2] += base["frame_ms"]
            s_[3] += p["volume_fragments"] + p["near_cap_fragments"]
            s_[4] += base["volume_fragments"] + base["near_cap_fragments"]
            s_[5] += p["near_cap_ms"]
        if not sums:
            return
        body = []
        for where, against, target in (("Z-pass right", "zpass", "within 5 %"),
                                       ("elsewhere", "zpplus-corrected", "no more")):
            if where not in sums:
                continue
            n, ms, base_ms, frags, base_frags, cap_ms = sums[where]
            body.append([where, n, against, fmt(ms), fmt(base_ms), fmt(100 * (ms / base_ms - 1)) if base_ms else "",
                         frags, base_frags, fmt(100 * (frags / base_frags - 1)) if base_frags else "", fmt(cap_ms),
                         target])
        text = ("<p>The switch policy's cost where Z-pass is right (every occluder's exact near-cap empty: the "
                "target is within 5 % of Z-pass) and elsewhere (no more than ZP+ corrected), summed over the "
                "(configuration, light) pairs with all three rows. Frame times are the emulation's, measured "
                "row by row while other configurations run; fragments are the volume and near-cap passes' "
                "(deterministic).</p>")
        self.sections.append(("The policy's cost", text + self.table(
            ["pairs", "count", "against", "policy ms", "their ms", "ms +%", "policy fragments", "their fragments",
             "fragments +%", "policy near-cap ms", "target"], body, "policy_cost.csv")))

    # ---- 6. sampler by kind ----------------------------------------------------
    def kinds(self):
        sampled = [r for r in self.rows if r["configuration"].startswith("sample:")]
        if not sampled:
            return
        kinds = sorted({r["kind"] for r in sampled})
        header = ["kind", "configurations"] + [f"{m} cracks" for m in self.methods]
        body = []
        for k in kinds:
            rows = [r for r in sampled if r["kind"] == k]
            body.append([k, len({r["configuration"] for r in rows})] +
                        [sum(r["cracks"] for r in rows if r["method"] == m) for m in self.methods])
        self.sections.append(("Hard cases by kind", self.table(header, body, "by_kind.csv")))

    def write(self):
        self.pareto()
        self.paths()
        self.features()
        self.distances()
        self.case_d()
        self.baselines()
        self.policy_models()
        self.policy_cost()
        self.kinds()
        toc = "".join(f'<li><a href="#s{k}">{html.escape(t)}</a></li>' for k, (t, _) in enumerate(self.sections))
        body = "".join(f'<h2 id="s{k}">{html.escape(t)}</h2>{c}' for k, (t, c) in enumerate(self.sections))
        page = f"""<!doctype html><html><head><meta charset="utf-8"><title>nearcap sweep report</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}} img{{max-width:100%}}
table{{border-collapse:collapse;margin:0.5em 0 1.5em}} td,th{{border:1px solid #ccc;padding:2px 8px;text-align:right}}
th{{background:#eee}} td:first-child{{text-align:left}}</style></head><body>
<h1>nearcap sweep report</h1><p>From {html.escape(', '.join(self.sources))}. Each row of a sweep is one
(configuration, light, method); "wrong" counts pixels whose shadow status differs from the exact reference,
"cracks" those among them whose exact status is proven constant over the whole pixel (README, "Crack distance").
Times are the float pipeline's emulation on the CPU, not a GPU's.</p><ul>{toc}</ul>{body}</body></html>"""
        (self.out / "index.html").write_text(page)
        (self.out / "report.json").write_text(json.dumps(
            {"rows": len(self.rows), "rejected": self.rejected, "refused": len(self.refused), "methods": self.methods,
             "configurations": len({r["configuration"] for r in self.rows}), "plots": self.plots}, indent=1) + "\n")


def pareto_front(points):
    front = []
    for x, y in sorted(points):
        if not front or y < front[-1][1]:
            front.append((x, y))
    return front


def safe(name):
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in name)


def fmt(v):
    if isinstance(v, float):
        return f"{v:.3g}" if abs(v) < 1000 else f"{v:.0f}"
    return str(v)


def main(argv):
    args, out, policy = [], None, None
    k = 0
    while k < len(argv):
        if argv[k] == "--out" and k + 1 < len(argv):
            out = argv[k + 1]
            k += 2
        elif argv[k] == "--policy" and k + 1 < len(argv):
            policy = argv[k + 1]
            k += 2
        else:
            args.append(argv[k])
            k += 1
    if not args or out is None:
        raise ReportError("usage", "usage: sweep_report.py RESULTS.csv [MORE.csv ...] --out DIR [--policy FILE]")
    rows, rejected, refused = read_rows(args)
    policy_json = None
    if policy is not None:
        try:
            with open(policy) as handle:
                policy_json = json.load(handle)
        except OSError as e:
            raise ReportError("io", f"{policy}: cannot read the policy: {e.strerror}")
        except ValueError as e:
            raise ReportError("parse", f"{policy}: not JSON: {e}")
        if not isinstance(policy_json, dict) or policy_json.get("format") != "nearcap-policy":
            raise ReportError("parse", f"{policy}: format: not a nearcap policy")
    target = Path(out)
    if target.exists() and not target.is_dir():
        raise ReportError("io", f"{out}: exists and is not a directory")
    parent = target.resolve().parent
    parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".nearcap-report-", dir=parent))
    try:
        report = Report(rows, rejected, staging)
        report.refused = refused
        report.sources = args
        report.policy, report.policy_source = policy_json, policy
        report.write()
        target.mkdir(exist_ok=True)
        for f in sorted(staging.iterdir()):
            os.replace(f, target / f.name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    print(f"report: {len(rows)} rows, {len(report.plots)} plots, {target / 'index.html'}")


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except ReportError as e:
        print(f"nearcap: error ({e.kind}): {e}", file=sys.stderr)
        sys.exit(2)
