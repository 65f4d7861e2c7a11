#!/usr/bin/env python3
"""nearcap's sweep report: one HTML page with plots and tables from the CSV
rows of `nearcap sweep` (one or more files).  Run through `nearcap report`,
or directly:

    sweep_report.py RESULTS.csv [MORE.csv ...] --out DIR --settings TABLE.json [--policy FILE]

TABLE.json is the settings table the nearcap program prints (`nearcap settings
> TABLE.json`; `nearcap report` writes it and passes it): the methods of the
rows, in the order the report lists them, with their descriptions, kinds and
roles (docs/sweeps-and-report.md, "The settings table").  No method name is
spelled here: a method the table adds appears in every section, and the
sections about one method (the case-D claim about the corrected ZP+, times
relative to Z-pass, the switch policy's cost) find it by its role.

DIR/index.html is the page; beside it, the plots (PNG, matplotlib), the
tables as CSV (summary.csv, by_kind.csv, case_d.csv, ...) and report.json
(what was plotted: the files and how many data points each holds).  Nothing
is written to DIR unless the whole report was built (it is assembled in a
temporary folder next to DIR first), and a report whose files would replace
one of its inputs is refused.  Errors are one line on stderr,
"nearcap: error (KIND): FILE: ...", exit code 2; an unexpected failure of
this script (a bug) says so in that line and leaves its traceback in a log
file the line names.

The rows are read one at a time and folded into the totals each section
needs, never held: memory does not grow with the number of rows (the
million-configuration sweep's CSV included; docs/findings/report-scale.md).
What that needs of the input: each configuration's rows together, as
`nearcap sweep` writes them (a configuration met again after others is an
error naming both places), UTF-8 text, lines under 1 MB, every row with
the header's field count.  The one part that grows with the input is a
64-bit hash per configuration (8 bytes), to find a configuration given
twice; the feature scatter plots draw all points up to FEATURE_POINTS per
(feature, method, cracked or not) and a uniform sample beyond, and say so.

Sections:
  1. speed against error: mean emulated frame time per configuration against
     wrong pixels and against cracks, per method; the Pareto front; the
     noise floor (Z-pass's frame timed twice: the spread of the ratio);
  2. each camera path: time per frame relative to Z-pass (the paper's
     Figure 9 style) over the path's noise floor, cracks per frame, the exact
     case counts per frame;
  3. cracks against each conditioning feature (conditioning.hpp);
  4. crack-distance histograms per method;
  5. the paper's case-D claim: frames where ZP+ (corrected) cracks without a
     case-D quad, and case-D switches that were not needed;
  6. the hard-case sampler by kind;
  7. the methods: each one's kind and description from the settings table.
"""
import array
import bisect
import csv
import hashlib
import html
import json
import math
import os
import random
import re
import shutil
import signal
import stat
import sys
import tempfile
import traceback
from collections import OrderedDict, defaultdict
from pathlib import Path

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402
    import matplotlib.ticker  # noqa: E402
    import numpy  # noqa: E402  (matplotlib's own dependency)
except ImportError:
    print(f"nearcap: error (io): {sys.executable} has no matplotlib (Debian: python3-matplotlib, which "
          "scripts/install-deps.sh installs; or set NEARCAP_PYTHON to a Python that has it)", file=sys.stderr)
    sys.exit(2)

try:
    import settings_table  # noqa: E402  (beside this script)
    from settings_table import base_method  # noqa: E402
except ImportError:
    print(f"nearcap: error (io): {__file__}: settings_table.py is not beside it (copy analysis/report/ whole)",
          file=sys.stderr)
    sys.exit(2)

# The roles whose methods features.png draws, in this order (settings_table.ROLES says what each is).
FEATURE_ROLES = ("published-zpplus", "corrected-zpplus", "zfail-baseline", "timing-baseline")
# Per-occluder decision columns (nearcap sweep since the engine baselines); a
# CSV without them gets no baseline section.
DECISION_COLUMNS = ["occluders", "zpass_wrong_occluders", "false_negatives", "false_positives"]
# Z-pass's frame timed a second time (on its rows only): the noise floor.  A CSV without the column, or without
# Z-pass rows, gets a page that says no noise floor was measured.
AGAIN_COLUMN = "frame_again_ms"
NOISE_POINTS = 100000  # Z-pass timing ratios kept for the overall noise floor before sampling
NOISE_PERCENTILES = (5, 95)  # the band drawn and stated
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
TIME_COLUMNS = ["frame_ms", "setup_ms", "depth_ms", "near_cap_ms", "volume_ms", "reference_ms"]
FLOAT_COLUMNS = TIME_COLUMNS + [f for f, _ in FEATURES]
# The features that are ratios of lengths, condition numbers or errors: never negative (nan where undefined),
# as `nearcap tune` reads them.
MAGNITUDE_COLUMNS = [f for f, _ in FEATURES if f != "light_near_distance"]
MAX_COUNT = 1 << 53  # counts above are not exact as the doubles the report sums them in
# Numbers as the sweep writes them, a row's fields of one kind joined by commas: decimal integers;
# decimal numbers, nan, inf and -inf.  Python's int() and float() also take a sign '+', spaces,
# underscores and other spellings of infinity and nan, which `nearcap tune` refuses as the sweep
# never writes them.
_INTEGER = r"-?[0-9]+"
_NUMBER = r"(?:-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|nan|inf|-inf)"
INTEGERS_AS_WRITTEN = re.compile(f"{_INTEGER}(?:,{_INTEGER})*\\Z")
NUMBERS_AS_WRITTEN = re.compile(f"{_NUMBER}(?:,{_NUMBER})*\\Z")
PASS_COLUMNS = [p + "_" + c for p in ("depth", "near_cap", "volume") for c in ("fragments", "depth_pass", "depth_fail")]
REQUIRED = ["configuration", "source", "kind", "detail", "method", "variant", "fallback", "cap_mismatch"] + INTEGER_COLUMNS + \
           FLOAT_COLUMNS + PASS_COLUMNS
POLICY_VERSIONS = (1, 6)  # the nearcap-policy versions read (kPolicyVersion in switch_policy.hpp)
MAX_LINE_BYTES = 1 << 20  # a sweep row is under 1 kB; a longer line is not a sweep CSV
FEATURE_POINTS = 20000  # scatter points kept per (feature, method, cracked or not) before sampling
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "*", "h", "p"]
FORMULA_START = ("=", "+", "-", "@", "\t", "\r")  # a spreadsheet reads a cell starting so as a formula


class ReportError(Exception):
    def __init__(self, kind, message):
        super().__init__(message)
        self.kind = kind


# ---- reading: one row at a time ------------------------------------------------
def open_input(name):
    """A binary handle on a regular file (a FIFO or a device is refused, never read)."""
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as e:
        raise ReportError("io", f"{name}: cannot read: {e.strerror}")
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise ReportError("io", f"{name}: not a regular file (a sweep's CSV was expected)")
    os.set_blocking(fd, True)
    return os.fdopen(fd, "rb")


def text_lines(name, handle):
    """The file's lines as text, each checked to be UTF-8 and under MAX_LINE_BYTES."""
    line = 0
    while True:
        raw = handle.readline(MAX_LINE_BYTES + 1)  # a line of MAX_LINE_BYTES and its newline
        if not raw:
            return
        line += 1
        if len(raw) > MAX_LINE_BYTES and not raw.endswith(b"\n"):
            raise ReportError("parse", f"{name}: line {line}: longer than {MAX_LINE_BYTES >> 20} MB "
                                       "(not a nearcap sweep CSV)")
        if line == 1 and raw.startswith(b"\xef\xbb\xbf"):
            raw = raw[3:]  # a byte order mark (a spreadsheet's UTF-8 export) is not part of the first column's name
        try:
            yield raw.decode("utf-8")
        except UnicodeDecodeError as e:
            raise ReportError("parse", f"{name}: line {line}: not UTF-8 (byte 0x{raw[e.start]:02x} at byte "
                                       f"{e.start + 1} of the line)")


def parsed_rows(files):
    """Each data row of the files, checked and converted, in order: (status, name, line, row) with status
    "rejected" (row None), "refused" or "row"."""
    for name in files:
        with open_input(name) as handle:
            reader = csv.reader(text_lines(name, handle), strict=True)  # strict: a quote left open is an error
            start = 1  # the line the record being read starts on
            try:
                header = next(reader, None)
                if header is None:
                    raise ReportError("parse", f"{name}: empty file, not a nearcap sweep CSV")
                named = set()
                for column in header:  # which of two columns of one name is read would be a guess
                    if column in named:
                        raise ReportError("parse", f"{name}: line 1: column '{column}' appears twice in the header")
                    named.add(column)
                missing = [c for c in REQUIRED if c not in header]
                if missing:
                    raise ReportError("schema", f"{name}: line 1: missing column '{missing[0]}' "
                                               f"(not a nearcap sweep CSV, or one from an older nearcap)")
                converter = RowConverter(header, name)
                method_index = converter.index["method"]
                while True:
                    start = reader.line_num + 1
                    fields = next(reader, None)
                    if fields is None:
                        break
                    if not fields:
                        continue  # a blank line
                    line = reader.line_num
                    if len(fields) != len(header):  # a row cut off, or joined with another, is never read
                        raise ReportError("parse", f"{name}: line {line}: {len(fields)} fields, the header has "
                                                   f"{len(header)}")
                    if fields[method_index] == "rejected":
                        yield "rejected", name, line, None
                        continue
                    r = converter.row(fields, line)
                    yield ("refused" if r["refused"] else "row"), name, line, r
            except csv.Error as e:
                if "unexpected end of data" in str(e):  # as tune says it
                    raise ReportError("parse", f"{name}: line {start}: a quoted field is not closed")
                if "field larger than field limit" in str(e):  # a quote left open in a large file
                    raise ReportError("parse", f"{name}: line {start}: a quoted field is not closed (it runs on "
                                               f"past {csv.field_size_limit()} characters)")
                raise ReportError("parse", f"{name}: line {start}: {e}")


class RowConverter:
    """A CSV row (a list of fields) as a dict of the columns the report reads, numbers converted."""
    TEXT = ["configuration", "kind", "method", "variant", "fallback"]
    INTEGERS = INTEGER_COLUMNS + PASS_COLUMNS

    def __init__(self, header, name):
        self.index = {c: k for k, c in enumerate(header)}  # each name once (parsed_rows checks it)
        self.name = name
        self.text = [(c, self.index[c]) for c in self.TEXT]
        self.integers = [self.index[c] for c in self.INTEGERS]
        self.floats = [self.index[c] for c in FLOAT_COLUMNS]
        self.decisions = [(c, self.index[c]) for c in DECISION_COLUMNS if c in self.index]
        self.again = self.index.get(AGAIN_COLUMN)
        self.cap_mismatch = self.index["cap_mismatch"]

    def fail(self, line, column, value, what):
        raise ReportError("parse", f"{self.name}: line {line}: column '{column}': '{value}' is not {what}")

    def check_in_range(self, line, column, value, number):
        """A decimal beyond double's range reads as inf, or as 0 below it: the sweep writes neither so."""
        mantissa = value.split("e")[0].split("E")[0]
        if (number == 0 and mantissa.strip("-0.")) or (math.isinf(number) and value not in ("inf", "-inf")):
            self.fail(line, column, value, "a number the sweep writes (within double's range)")

    def optional_count(self, line, column, value):
        """A count of a column that is empty where the row has none (None then)."""
        if not value:
            return None
        if not INTEGERS_AS_WRITTEN.match(value):
            self.fail(line, column, value, "an integer")
        count = int(value)
        if count < 0:
            self.fail(line, column, value, "a count (it is negative)")
        if count > MAX_COUNT:
            self.fail(line, column, value, "a count a sweep writes (over 2^53)")
        return count

    def row(self, fields, line):
        """The row's columns; `fields` has the header's field count (parsed_rows checks it)."""
        joined = ",".join(fields[k] for k in self.integers)
        if not INTEGERS_AS_WRITTEN.match(joined):
            for c, k in zip(self.INTEGERS, self.integers):
                if not INTEGERS_AS_WRITTEN.match(fields[k]):
                    self.fail(line, c, fields[k], "an integer")
        integers = [int(fields[k]) for k in self.integers]
        if not NUMBERS_AS_WRITTEN.match(",".join(fields[k] for k in self.floats)):
            for c, k in zip(FLOAT_COLUMNS, self.floats):
                if not NUMBERS_AS_WRITTEN.match(fields[k]):
                    self.fail(line, c, fields[k], "a number")
        floats = [float(fields[k]) for k in self.floats]
        for c, k, v in zip(FLOAT_COLUMNS, self.floats, floats):
            if v == 0 or math.isinf(v):
                self.check_in_range(line, c, fields[k], v)
        if "-" in joined:  # every integer column is a count or an index (and the sweep writes no -0)
            for c, k in zip(self.INTEGERS, self.integers):
                if fields[k].startswith("-"):
                    self.fail(line, c, fields[k], "a count or an index (it is negative)")
        if integers and max(integers) > MAX_COUNT:
            for c, k in zip(self.INTEGERS, self.integers):
                if int(fields[k]) > MAX_COUNT:
                    self.fail(line, c, fields[k], "a count a sweep writes (over 2^53)")
        r = dict(zip(self.INTEGERS, integers))
        if r["refused"] > 1:  # a flag, as `nearcap tune` reads it
            self.fail(line, "refused", fields[self.index["refused"]], "0 or 1")
        if r["wrong"] > r["pixels_seen"]:
            raise ReportError("parse", f"{self.name}: line {line}: column 'wrong': {r['wrong']} wrong pixels of "
                                       f"{r['pixels_seen']} seen (pixels_seen)")
        if r["cracks"] > r["wrong"]:
            raise ReportError("parse", f"{self.name}: line {line}: column 'cracks': {r['cracks']} cracks of "
                                       f"{r['wrong']} wrong pixels (a crack is a wrong pixel)")
        for c, v in zip(FLOAT_COLUMNS, floats):
            if c in TIME_COLUMNS and not (math.isfinite(v) and v >= 0):
                self.fail(line, c, fields[self.index[c]], "a time (finite, not negative)")
            if c in MAGNITUDE_COLUMNS and v < 0:
                self.fail(line, c, fields[self.index[c]], f"a magnitude (the sweep writes no negative {c})")
        r.update(zip(FLOAT_COLUMNS, floats))
        for c, k in self.text:
            r[c] = fields[k]
        if not r["configuration"]:
            self.fail(line, "configuration", "", "a configuration id (it is empty)")
        r["cap_mismatch"] = self.optional_count(line, "cap_mismatch", fields[self.cap_mismatch])
        for c, k in self.decisions:
            r[c] = self.optional_count(line, c, fields[k])
        for c in DECISION_COLUMNS:
            r.setdefault(c, None)
        r[AGAIN_COLUMN] = None
        value = fields[self.again] if self.again is not None else ""
        if value:  # empty where the row has no second timing
            if not NUMBERS_AS_WRITTEN.match(value):
                self.fail(line, AGAIN_COLUMN, value, "a number")
            again = float(value)
            self.check_in_range(line, AGAIN_COLUMN, value, again)
            if not (math.isfinite(again) and again >= 0):
                self.fail(line, AGAIN_COLUMN, value, "a time (finite, not negative)")
            r[AGAIN_COLUMN] = again
        # A method under a non-default variant is its own series: "zpplus [light-projection=glfrustum]".
        if r["variant"] != "default":
            r["method"] = f'{r["method"]} [{r["variant"]}]'
        if r["configuration"].startswith("path:"):
            try:
                r["frame"] = int(r["configuration"].rsplit(":", 1)[1])
            except ValueError:
                raise ReportError("parse", f"{self.name}: line {line}: configuration '{r['configuration']}': a "
                                           "path's configuration ends in its frame number")
        return r


class Reservoir:
    """Points (x, y) in arrival order up to `cap`, then a uniform sample of `cap` of them (Algorithm R, fixed
    seed); `seq` keeps each point's arrival number so that samples merge back in order."""

    def __init__(self, cap, seed):
        self.cap, self.seen, self.rng = cap, 0, random.Random(seed)
        self.seq, self.x, self.y = array.array("q"), array.array("d"), array.array("d")

    def add(self, seq, x, y):
        self.seen += 1
        if len(self.seq) < self.cap:
            self.seq.append(seq)
            self.x.append(x)
            self.y.append(y)
            return
        k = self.rng.randrange(self.seen)
        if k < self.cap:
            self.seq[k], self.x[k], self.y[k] = seq, x, y


class Totals:
    """Everything the sections draw, folded row by row.  Per-(configuration, light) comparisons between methods
    (the case-D claim, the policy's cost, the exact reference's time) are folded when a configuration's rows
    end: a sweep writes them together."""

    def __init__(self, table):
        self.settings = table
        self.timing = table.role("timing-baseline")
        self.kept = {table.role(r) for r in settings_table.ROLES} - {None}  # the methods whose rows the comparisons read
        self.feature_methods = [table.role(r) for r in FEATURE_ROLES if table.role(r) is not None]
        self.rows, self.rejected, self.configurations = 0, 0, 0
        self.refused = defaultdict(int)  # method -> refused frames
        self.methods = set()
        self.per = defaultdict(lambda: {"ms": 0.0, "wrong": 0, "cracks": 0, "rows": 0, "with_cracks": 0,
                                        "frag_pass": 0, "frag_fail": 0})
        self.ref_ms, self.ref_pairs = 0, 0
        self.buckets = defaultdict(lambda: [0] * len(BUCKETS))
        self.decisions = {}  # method -> [rows, occluders, truth, fn, fp, frames with cracks, cracks, wrong, ms, frags]
        self.paths = {}  # path name -> {"table": {(frame, light, method): (ms, cracks, cases)}, "totals": ...}
        self.feature_range = {f: [0, 0, math.inf, -math.inf] for f, _ in FEATURES}  # values, positive, min, max
        keys = [(f, m, cracked) for f, _ in FEATURES for m in self.feature_methods for cracked in (False, True)]
        self.feature_points = {key: Reservoir(FEATURE_POINTS, seed) for seed, key in enumerate(keys)}
        self.case_d = {"pairs": 0, "without_d": 0, "with_d": 0, "after_fallback": 0, "switches": 0, "unnecessary": 0}
        self.case_d_examples = []  # the first 8 in (configuration, light) order
        self.policy_cost = {}
        self.kind_configurations = defaultdict(int)
        self.kind_cracks = defaultdict(lambda: defaultdict(int))
        self.hashes = array.array("q")  # one per configuration, to find one given twice
        self.noise = Reservoir(NOISE_POINTS, len(keys))  # x: Z-pass's second timing over its first, per row
        self.noise_sums = [0.0, 0.0]  # those rows' first and second timings, summed
        self.group = None

    def add(self, r, name, line):
        c, light, m = r["configuration"], r["light"], r["method"]
        g = self.group
        if g is None or g["configuration"] != c:
            self.end_group()
            g = self.group = {"configuration": c, "seen": {}, "lights": OrderedDict(), "kinds": set()}
            self.hashes.append(hash(c))
        where = g["seen"].get((light, m))
        if where is not None:
            raise ReportError("parse", f"{name}: line {line}: a second row for configuration '{c}' light {light} "
                                       f"method {m} (first: {where})")
        g["seen"][(light, m)] = f"{name} line {line}"
        lights = g["lights"].setdefault(light, {"ref": 0.0, "rows": {}})
        lights["ref"] = r["reference_ms"]
        if m in self.kept:
            lights["rows"][m] = {k: r[k] for k in ("cracks", "float_D", "fallback", "zfail_objects", "frame_ms",
                                                   "zpass_wrong_occluders", "volume_fragments", "near_cap_fragments",
                                                   "near_cap_ms")}
        g["kinds"].add(r["kind"])

        seq = self.rows
        self.rows += 1
        self.methods.add(m)
        p = self.per[m]
        p["ms"] += r["frame_ms"]
        p["wrong"] += r["wrong"]
        p["cracks"] += r["cracks"]
        p["rows"] += 1
        p["with_cracks"] += r["cracks"] > 0
        p["frag_pass"] += r["volume_depth_pass"]
        p["frag_fail"] += r["volume_depth_fail"]
        ratio = timing_ratio(r[AGAIN_COLUMN], r["frame_ms"])
        if ratio is not None and base_method(m) == self.timing:
            self.noise.add(seq, ratio, 0.0)
            self.noise_sums[0] += r["frame_ms"]
            self.noise_sums[1] += r[AGAIN_COLUMN]
        b = self.buckets[m]
        for k, bucket in enumerate(BUCKETS):
            b[k] += r["wrong_r_" + bucket]
        if r["false_negatives"] is not None:
            d = self.decisions.setdefault(m, [0, 0, 0, 0, 0, 0, 0, 0, 0, 0])
            d[0] += 1
            d[1] += r["occluders"]
            d[2] += r["zpass_wrong_occluders"]
            d[3] += r["false_negatives"]
            d[4] += r["false_positives"]
            d[5] += r["cracks"] > 0
            d[6] += r["cracks"]
            d[7] += r["wrong"]
            d[8] += r["frame_ms"]
            d[9] += r["volume_fragments"]
        if c.startswith("path:"):
            path = self.paths.setdefault(r["kind"], {"table": {}, "totals": {}})
            path["table"][(r["frame"], light, m)] = (r["frame_ms"], r["cracks"],
                                                     tuple(r["exact_" + k] for k in CASES), r[AGAIN_COLUMN])
            t = path["totals"].setdefault(m, [0, 0, 0])
            t[0] += r["wrong"]
            t[1] += r["cracks"]
            t[2] += r["frame_ms"]
        elif c.startswith("sample:"):
            self.kind_cracks[r["kind"]][m] += r["cracks"]
        points = m in self.feature_methods
        for f, _ in FEATURES:
            v = r[f]
            if not math.isfinite(v):
                continue
            a = abs(v)
            fr = self.feature_range[f]
            fr[0] += 1
            if a > 0:
                fr[1] += 1
                fr[2] = min(fr[2], a)
                fr[3] = max(fr[3], a)
            if points:
                self.feature_points[(f, m, r["cracks"] > 0)].add(seq, a if f == "light_near_distance" else v,
                                                                  r["cracks"])

    def end_group(self):
        g, self.group = self.group, None
        if g is None:
            return
        self.configurations += 1
        c = g["configuration"]
        if c.startswith("sample:"):
            for kind in g["kinds"]:
                self.kind_configurations[kind] += 1
        for light, entry in g["lights"].items():
            self.ref_ms += entry["ref"]
            self.ref_pairs += 1
            rows = entry["rows"]
            self.fold_case_d(c, light, rows)
            self.fold_policy_cost(rows)

    def fold_case_d(self, c, light, rows):
        s = self.case_d
        s["pairs"] += 1
        role = self.settings.role
        zc, zp = rows.get(role("corrected-zpplus")), rows.get(role("published-zpplus"))
        zf = rows.get(role("zfail-baseline"))
        if zc is None:
            return
        if zc["fallback"] and not zc["zfail_objects"]:
            s["after_fallback"] += zc["cracks"] > 0
            return
        baseline = zf["cracks"] if zf is not None else 0  # cracks every method has (depth precision)
        if zc["cracks"] > baseline and zc["float_D"] == 0:
            s["without_d"] += 1
            example = (c, light, zc["cracks"], zc["float_D"], zc["fallback"])
            if len(self.case_d_examples) < 8 or example[:2] < self.case_d_examples[-1][:2]:
                bisect.insort(self.case_d_examples, example)
                del self.case_d_examples[8:]
        if zc["cracks"] > baseline and zc["float_D"] > 0:
            s["with_d"] += 1
        if zc["zfail_objects"] > 0:
            s["switches"] += 1
            if zp is not None and zp["cracks"] == 0:
                s["unnecessary"] += 1

    def fold_policy_cost(self, rows):
        """Issue 12's cost targets: where Z-pass is right (every occluder's exact near-cap empty), the policy's
        frame time and fragments against Z-pass's; elsewhere against ZP+ corrected's."""
        role = self.settings.role
        z, p = rows.get(role("timing-baseline")), rows.get(role("switch-policy"))
        zp = rows.get(role("corrected-zpplus"))
        if z is None or p is None or z["zpass_wrong_occluders"] is None:
            return
        where, base = ("Z-pass right", z) if z["zpass_wrong_occluders"] == 0 else ("elsewhere", zp)
        if base is None:
            return
        s_ = self.policy_cost.setdefault(where, [0, 0.0, 0.0, 0, 0, 0.0])
        s_[0] += 1
        s_[1] += p["frame_ms"]
        s_[2] += base["frame_ms"]
        s_[3] += p["volume_fragments"] + p["near_cap_fragments"]
        s_[4] += base["volume_fragments"] + base["near_cap_fragments"]
        s_[5] += p["near_cap_ms"]


def read_rows(files, table):
    totals = Totals(table)
    for status, name, line, r in parsed_rows(files):
        if status == "rejected":
            totals.rejected += 1
        elif status == "refused":
            totals.refused[r["method"]] += 1
        else:
            totals.add(r, name, line)
    totals.end_group()
    if not totals.rows:
        raise ReportError("parse", f"{files[0]}: no rows to report on")
    hashes = numpy.frombuffer(totals.hashes, dtype=numpy.int64)
    ordered = numpy.sort(hashes)
    repeated = ordered[1:][ordered[1:] == ordered[:-1]]
    if len(repeated):
        find_repeated_configuration(files, set(int(h) for h in repeated))
    return totals


def find_repeated_configuration(files, repeated):
    """Names the first configuration met again after other configurations (a second row for it, or its rows
    apart); a hash collision between two configurations is no error."""
    first_row, groups_started, current = {}, {}, None
    for status, name, line, r in parsed_rows(files):
        if status != "row":
            continue
        c = r["configuration"]
        starts = c != current
        current = c
        if hash(c) not in repeated:
            continue
        key = (c, r["light"], r["method"])
        if key in first_row:
            raise ReportError("parse", f"{name}: line {line}: a second row for configuration '{c}' light "
                                       f"{key[1]} method {key[2]} (first: {first_row[key]})")
        first_row[key] = f"{name} line {line}"
        if starts and c in groups_started:
            raise ReportError("parse", f"{name}: line {line}: configuration '{c}' again after other configurations "
                                       f"(first: {groups_started[c]}); a configuration's rows must be together, "
                                       "as nearcap sweep writes them")
        groups_started.setdefault(c, f"{name} line {line}")


def legend(ax, **options):
    """A legend when the axes have labelled series (matplotlib warns otherwise)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**options)


def csv_cell(value):
    """A table cell as written to CSV: text a spreadsheet would run as a formula (OWASP: a cell starting with
    = + - @ tab or CR) gets a leading single quote; numbers, negative ones included, stay numbers."""
    if isinstance(value, str) and value.startswith(FORMULA_START):
        try:
            float(value)
        except ValueError:
            return "'" + value
    return value


class Report:
    def __init__(self, totals, out):
        self.t, self.out = totals, out
        self.rows, self.rejected = totals.rows, totals.rejected
        self.settings = totals.settings
        self.methods = self.settings.sorted(totals.methods)
        self.plots, self.sections = [], []
        self.policy, self.policy_source = None, None
        self.noise = noise_floor(totals.noise.x, totals.noise.seen)  # None: not measured
        if self.noise is not None:  # for means over many rows, as the Pareto plot's
            self.noise["mean_ratio"] = totals.noise_sums[1] / totals.noise_sums[0]
        self.path_noise = {}  # path name -> its noise floor (per frame, the lights summed, as its time plot)
        self.writing = None  # the file being written, for an error message

    def save(self, fig, name, points):
        self.writing = name
        fig.savefig(self.out / name, dpi=110, bbox_inches="tight")
        plt.close(fig)
        self.plots.append({"file": name, "points": points})
        return name

    def table(self, header, body, csv_name=None):
        if csv_name:
            self.writing = csv_name
            with open(self.out / csv_name, "w", newline="", encoding="utf-8") as f:
                w = csv.writer(f)
                w.writerow([csv_cell(h) for h in header])
                w.writerows([csv_cell(v) for v in row] for row in body)
        cells = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
        lines = [f"<tr>{cells}</tr>"]
        for row in body:
            lines.append("<tr>" + "".join(f"<td>{html.escape(fmt(v))}</td>" for v in row) + "</tr>")
        return "<table>" + "".join(lines) + "</table>"

    # ---- 1. speed against error ---------------------------------------------
    def pareto(self):
        per = self.t.per
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
        points = 0
        for ax, metric, label in ((axes[0], "wrong", "wrong pixels (all rows)"), (axes[1], "cracks", "cracks (all rows)")):
            xs = {m: per[m]["ms"] / max(1, per[m]["rows"]) for m in self.methods}
            ys = {m: per[m][metric] for m in self.methods}
            for k, m in enumerate(self.methods):
                ax.scatter([xs[m]], [ys[m]], s=60, color=self.settings.colour(m),
                           marker=MARKERS[k % len(MARKERS)],
                           label=as_label(m), zorder=3, edgecolors="k", linewidths=0.4)
                points += 1
            front = pareto_front([(xs[m], ys[m]) for m in self.methods])
            ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=1, label="Pareto front", zorder=2)
            ax.set_yscale("symlog", linthresh=1)
            ax.set_ylim(bottom=-0.3)
            ax.set_xlabel("mean frame time per row (ms)")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        # One legend for both panels, outside the data (labels beside the points overlapped).
        legend(axes[1], fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
        fig.suptitle("speed against error, per method (the table below gives the numbers)")
        if self.noise is None:
            noise = "no noise floor measured"
        else:
            noise = ("noise floor (Z-pass timed twice): second/first {:.3g} to {:.3g} per frame (5th-95th pct.), "
                     "{:.3g} summed").format(*band(self.noise), self.noise["mean_ratio"])
        fig.supxlabel(f"times: the float32 pipeline emulated on the CPU, not a GPU's; {noise}", fontsize=9, y=-0.04)
        img = self.save(fig, "pareto.png", points)
        header = ["method", "rows", "wrong", "cracks", "rows with cracks", "mean frame ms", "volume frags depth-pass",
                  "volume frags depth-fail"]
        body = [[m, per[m]["rows"], per[m]["wrong"], per[m]["cracks"], per[m]["with_cracks"],
                 per[m]["ms"] / max(1, per[m]["rows"]), per[m]["frag_pass"], per[m]["frag_fail"]] for m in self.methods]
        refusals = ", ".join(f"{m} {n}" for m, n in sorted(self.t.refused.items()))
        rejected = f", {plural(self.rejected, 'configuration')} rejected (the scene did not load)" if self.rejected else ""
        text = (f"<p>{plural(self.t.configurations, 'configuration')}, {plural(self.rows, 'row')}"
                f"{rejected}"
                f"{f'; frames the float pipeline refused (float32 transforms degenerate): {refusals}' if refusals else ''}. "
                f"Exact reference: {self.t.ref_ms / max(1, self.t.ref_pairs):.1f} ms per (configuration, light) "
                f"on average. Z-pass counts on depth-passing fragments and Z-fail on failing ones: the volume "
                f"pass's split says which of the two had more to do.</p><p>{html.escape(noise_text(self.noise))}</p>")
        self.sections.append(("Speed against error", text + f'<img src="{img}">' +
                              self.table(header, body, "summary.csv")))

    # ---- 2. paths --------------------------------------------------------------
    def paths(self):
        by_path = self.t.paths
        if not by_path:
            return
        files = plot_names(sorted(by_path), "path_")
        timing = self.settings.role("timing-baseline")
        parts = []
        for name in sorted(by_path):
            table = by_path[name]["table"]
            frames = sorted({f for (f, l, m) in table})
            lights = sorted({l for (f, l, m) in table})
            # Time relative to Z-pass (all methods on one axis), then cracks per frame as small multiples (one
            # panel per method: ten crack lines on one axis hid each other), then the exact case counts.
            columns = min(5, len(self.methods))
            grid_rows = math.ceil(len(self.methods) / columns)
            fig = plt.figure(figsize=(11, 4.8 + 1.6 * grid_rows))
            grid = fig.add_gridspec(2 + grid_rows, columns, height_ratios=[2.2] + [1.0] * grid_rows + [1.6],
                                    hspace=0.55, wspace=0.3)
            timed = fig.add_subplot(grid[0, :])
            cases = fig.add_subplot(grid[-1, :], sharex=timed)
            points = 0
            for k, m in enumerate(self.methods):
                rel, cr = [], []
                for f in frames:
                    ms = sum(table[(f, l, m)][0] for l in lights if (f, l, m) in table)
                    base = sum(table[(f, l, timing)][0] for l in lights if (f, l, timing) in table)
                    rel.append(ms / base if base > 0 else math.nan)
                    cr.append(sum(table[(f, l, m)][1] for l in lights if (f, l, m) in table))
                timed.plot(frames, rel, color=self.settings.colour(m), label=as_label(m))
                small = fig.add_subplot(grid[1 + k // columns, k % columns], sharex=timed)
                small.plot(frames, cr, color=self.settings.colour(m), lw=1.2)
                small.set_title(as_label(shorten(m, 28)), fontsize=8, color=self.settings.colour(m))
                small.tick_params(labelsize=7)
                if max(cr, default=0) > 0:
                    small.set_yscale("symlog", linthresh=1)
                    small.set_ylim(bottom=-0.3)
                else:  # no log axis over nothing
                    small.set_ylim(-0.5, 1)
                    small.set_yticks([0])
                    small.text(0.5, 0.55, "no cracks", transform=small.transAxes, ha="center", fontsize=8,
                               color="0.4")
                if k % columns == 0:
                    small.set_ylabel("cracks", fontsize=8)
                small.grid(alpha=0.3)
                points += 2 * len(frames)
            timed.axhline(1.0, color="k", lw=0.5)
            ratios = []
            for f in frames:
                pairs = [table[(f, l, timing)] for l in lights if (f, l, timing) in table]
                ratio = timing_ratio(sum(p[3] for p in pairs) if pairs and all(p[3] is not None for p in pairs)
                                     else None, sum(p[0] for p in pairs))
                if ratio is not None:
                    ratios.append(ratio)
            floor = self.path_noise[name] = noise_floor(ratios)
            if floor is None:
                noise = "no noise floor measured"
            else:
                low, high = band(floor)
                timed.axhspan(low, high, color="0.82", zorder=0,
                              label=f"noise floor: Z-pass timed twice\n({low:.2f} to {high:.2f}, 5th-95th pct.)")
                noise = f"the grey band is the noise floor, Z-pass's frame timed twice: {low:.2f} to {high:.2f}"
            timed.set_ylabel("frame time / Z-pass's")
            timed.set_title(f"frame time relative to Z-pass, float32 pipeline emulated on the CPU, one timing per "
                            f"frame; {noise}", fontsize=9)
            legend(timed, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
            bottom = [0] * len(frames)
            first_method = self.methods[0]
            for k, (c, col) in enumerate(zip(CASES, ["#c7e9c0", "#9ecae1", "#fdd0a2", "#fdae6b", "#e6550d"])):
                vals = [sum(table[(f, l, first_method)][2][k] for l in lights if (f, l, first_method) in table)
                        for f in frames]
                cases.bar(frames, vals, bottom=bottom, color=col, label=c, width=1.0)
                bottom = [b + v for b, v in zip(bottom, vals)]
                points += len(frames)
            cases.set_ylabel("exact quad cases")
            cases.set_xlabel("frame")
            legend(cases, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0, title="case")
            fig.suptitle(f"path {as_label(shorten(name))}")
            img = self.save(fig, files[name], points)
            path_totals = by_path[name]["totals"]
            totals = [[m] + (path_totals[m][:2] if m in path_totals else [0, 0]) +
                      [(path_totals[m][2] if m in path_totals else 0) / len(frames)] for m in self.methods]
            parts.append(f"<h3>{html.escape(name)} ({len(frames)} frames)</h3><img src=\"{html.escape(img)}\">" +
                         f"<p>{html.escape(noise_text(floor))}</p>" +
                         self.table(["method", "wrong", "cracks", "mean frame ms"], totals))
        self.sections.append(("Camera paths", "<p>Per frame: time relative to Z-pass (the paper's Figure 9 "
                                              "style), cracks, and the exact classification of the silhouette "
                                              "quads against the near plane.</p>" + "".join(parts)))

    # ---- 3. features -----------------------------------------------------------
    def features(self):
        shown = [m for m in self.t.feature_methods if m in self.methods]
        fig, axes = plt.subplots(4, 3, figsize=(13, 13))
        points, seen = 0, 0
        for ax, (feature, label) in zip(axes.flat, FEATURES):
            for m in shown:
                parts = [self.t.feature_points[(feature, m, cracked)] for cracked in (False, True)]
                seq = numpy.concatenate([numpy.frombuffer(p.seq, dtype=numpy.int64) for p in parts])
                order = numpy.argsort(seq, kind="stable")
                xs = numpy.concatenate([numpy.frombuffer(p.x, dtype=numpy.float64) for p in parts])[order]
                ys = numpy.concatenate([numpy.frombuffer(p.y, dtype=numpy.float64) for p in parts])[order]
                # Z-pass cracks most: its points go under the others', lighter.
                under = m == self.settings.role("timing-baseline")
                ax.scatter(xs, ys, s=8, alpha=0.45 if under else 0.7, color=self.settings.colour(m),
                           label=as_label(m),
                           zorder=1 if under else 2, linewidths=0)
                points += len(xs)
                seen += sum(p.seen for p in parts)
            count, positives, smallest, largest = self.t.feature_range[feature]
            if positives and largest / smallest > 100:
                if positives < count:  # zeros too (the light in the near plane)
                    ax.set_xscale("symlog", linthresh=smallest)
                else:
                    ax.set_xscale("log")
            ax.set_yscale("symlog", linthresh=1)
            ax.set_ylim(bottom=-0.3)
            ax.set_xlabel(("|" + label + "|") if feature == "light_near_distance" else label, fontsize=8)
            ax.tick_params(axis="x", labelsize=7, labelrotation=30)
            if ax.get_xscale() == "linear":
                ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(5))
            else:
                ax.xaxis.set_major_locator(matplotlib.ticker.LogLocator(numticks=6) if ax.get_xscale() == "log"
                                           else matplotlib.ticker.SymmetricalLogLocator(
                                               base=10, linthresh=ax.xaxis.get_transform().linthresh))
                if ax.get_xscale() == "symlog":
                    # A decade a tick over twenty decades prints the labels
                    # over each other: at most six, evenly spaced.
                    lo, hi = ax.get_xlim()
                    ticks = [t for t in ax.xaxis.get_major_locator().tick_values(lo, hi) if lo <= t <= hi]
                    ax.xaxis.set_major_locator(
                        matplotlib.ticker.FixedLocator(ticks[::max(1, math.ceil(len(ticks) / 6))]))
            ax.set_ylabel("cracks", fontsize=8)
            ax.grid(alpha=0.3)
        for ax in list(axes.flat)[len(FEATURES):]:
            ax.axis("off")
        legend_at = list(axes.flat)[len(FEATURES)]
        handles, labels = axes.flat[0].get_legend_handles_labels()
        if handles:
            legend_at.legend(handles, labels, loc="center", fontsize=9, markerscale=3, title="method")
        fig.tight_layout(rect=(0, 0, 1, 0.97))
        fig.suptitle("cracks against the conditioning features, one point per (configuration, light, method)")
        img = self.save(fig, "features.png", points)
        note = ""
        if points < seen:
            note = (f"<p>{points} of {seen} points drawn: past {FEATURE_POINTS} per feature, method and "
                    "cracked-or-not, a uniform sample of that many (rows with cracks and without sampled "
                    "apart, so that the rare cracked rows keep their points).</p>")
        self.sections.append(("Cracks against conditioning", note + f'<img src="{img}">'))

    # ---- 4. crack distance -----------------------------------------------------
    def distances(self):
        fig, ax = plt.subplots(figsize=(9, 4))
        width = 0.8 / max(1, len(self.methods))
        points = 0
        body = []
        for k, m in enumerate(self.methods):
            totals = list(self.t.buckets[m])
            ax.bar([i + k * width for i in range(len(BUCKETS))], totals, width=width, color=self.settings.colour(m),
                   label=as_label(m))
            points += len(BUCKETS)
            body.append([m] + totals)
        ax.set_xticks([i + 0.4 - width / 2 for i in range(len(BUCKETS))])
        ax.set_xticklabels(BUCKET_LABELS)
        ax.set_yscale("symlog", linthresh=1)
        ax.set_xlabel("crack distance: largest proven-constant square half-width (pixels); >= 1/2 is a crack")
        ax.set_ylabel("wrong pixels")
        ax.set_title("wrong pixels by crack distance, per method")
        legend(ax, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
        img = self.save(fig, "crack_distance.png", points)
        self.sections.append(("Crack distance", "<p>Wrong pixels by how far the exact status is proven constant "
                                                "around them: below 1/2 pixel is rasterization noise at a shadow "
                                                "boundary, 1/2 and above a crack.</p>" + f'<img src="{img}">' +
                              self.table(["method"] + BUCKET_LABELS, body, "crack_distance.csv")))

    # ---- 5. the case-D claim ---------------------------------------------------
    def case_d(self):
        if self.settings.role("corrected-zpplus") not in self.methods:
            return
        s = self.t.case_d
        examples = [list(e) for e in self.t.case_d_examples]
        body = [["(configuration, light) pairs", s["pairs"]],
                ["ZP+ corrected cracks more than Z-fail, no case-D quad", s["without_d"]],
                ["ZP+ corrected cracks more than Z-fail despite case D", s["with_d"]],
                ["ZP+ corrected has cracks after falling back to Z-fail (no light frustum)", s["after_fallback"]],
                ["case-D switches to Z-fail", s["switches"]],
                ["  of which ZP+ without the switch had no crack",
                 s["unnecessary"] if self.settings.role("published-zpplus") in self.methods else "-"]]
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
        if not self.t.decisions:
            return
        header = ["method", "occluder decisions", "Z-pass wrong (exact)", "Z-fail where needed",
                  "false negatives", "false positives", "Z-pass where right", "frames with cracks", "cracks",
                  "wrong", "mean frame ms", "volume fragments"]
        body = []
        for m in self.methods:
            d = self.t.decisions.get(m)
            if d is None:
                continue
            n, occluders, truth, fn, fp, with_cracks, cracks, wrong, ms, frags = d
            body.append([m, occluders, truth, truth - fn, fn, fp, occluders - truth - fp, with_cracks, cracks,
                         wrong, fmt(ms / n), frags])
        text = ("<p>Each occluder of each (configuration, light) drawn with Z-pass or Z-fail: by the methods "
                "themselves (all one or the other) and by the rules shipped engines use "
                "(<code>nearcap sweep --policies</code>; docs/sweeps-and-report.md, \"Engine baselines\"). The exact truth: Z-pass is "
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
        text = (f"<p>From <code>{html.escape(escaped(self.policy_source))}</code>: {who} {capped} {rule}. Fitted by <code>"
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
            text += self.table(["feature", "weight", "mean", "scale"], weights, "policy_weights.csv")
        else:
            text += "<p>No logistic model: no feature, no weight.</p>"
            self.table(["feature", "weight", "mean", "scale"], weights, "policy_weights.csv")  # the CSV, header only
        costs = []
        for method, cm in p.get("cost_models", {}).items():
            errors = prov.get("cost", {}).get(method, {})
            costs.append([method, fmt(float(cm["intercept_ms"])), fmt(float(cm["ms_per_mtriangle"])),
                          fmt(float(cm["ms_per_mfragment"])),
                          fmt(100 * float(errors.get("train_median_relative_error", float("nan")))),
                          fmt(100 * float(errors.get("held_out_median_relative_error", float("nan"))))])
        cost_header = ["method", "ms", "ms per M triangles", "ms per M fragments", "train error %",
                       "held-out error %"]
        if costs:
            text += "<p>Cost models (frame time from the work drawn; median relative error in %):</p>"
            text += self.table(cost_header, costs, "policy_costs.csv")
        else:
            self.table(cost_header, costs, "policy_costs.csv")  # the CSV, header only: the decision reads none
        unpriced = p.get("unpriced_frames")
        if isinstance(unpriced, dict):  # a version 5 policy: one tier
            unpriced = [unpriced]
        if isinstance(unpriced, list) and unpriced:
            fit = prov.get("unpriced_frames", {})
            tiers = ", ".join(f"at most {html.escape(str(t.get('max_occluder_triangles')))} triangles: "
                              f"<code>{html.escape(str(t.get('method')))}</code>"
                              for t in unpriced if isinstance(t, dict))
            text += (f"<p>Unpriced frames: where every occluder has {tiers}, the decision draws that method "
                     f"without pricing (tiers of the largest occluder, the first that holds it; fitted on "
                     f"{html.escape(str(fit.get('frames', '?')))} training frames, "
                     f"{html.escape(str(fit.get('unpriced_frames', '?')))} of them unpriced).</p>")
        self.sections.append(("The switch policy's fitted models", text))

    # ---- 5d. the policy's cost against its targets ---------------------------
    def policy_cost(self):
        """Issue 12's cost targets (Totals.fold_policy_cost); pairs are the (configuration, light) where all
        three rows are present."""
        sums = self.t.policy_cost
        if not sums:
            return
        body = []
        role = self.settings.role
        for where, against, target, allowed in (("Z-pass right", role("timing-baseline"), "within 5 %", 0.05),
                                                ("elsewhere", role("corrected-zpplus"), "no more", 0.0)):
            if where not in sums:
                continue
            n, ms, base_ms, frags, base_frags, cap_ms = sums[where]
            met_ms = "met" if ms <= base_ms * (1 + allowed) else "missed"
            met_frags = "met" if frags <= base_frags * (1 + allowed) else "missed"
            body.append([where, n, against, fmt(ms), fmt(base_ms), fmt(100 * (ms / base_ms - 1)) if base_ms else "",
                         frags, base_frags, fmt(100 * (frags / base_frags - 1)) if base_frags else "", fmt(cap_ms),
                         target, met_ms, met_frags])
        text = ("<p>The switch policy's cost where Z-pass is right (every occluder's exact near-cap empty: the "
                "target is within 5 % of Z-pass) and elsewhere (no more than ZP+ corrected), summed over the "
                "(configuration, light) pairs with all three rows. Frame times are the emulation's, measured "
                "row by row while other configurations run; fragments are the volume and near-cap passes' "
                "(deterministic).</p>")
        self.sections.append(("The policy's cost", text + self.table(
            ["pairs", "count", "against", "policy ms", "their ms", "ms +%", "policy fragments", "their fragments",
             "fragments +%", "policy near-cap ms", "target", "time target", "fragments target"], body,
            "policy_cost.csv")))

    # ---- 6. sampler by kind ----------------------------------------------------
    def kinds(self):
        if not self.t.kind_configurations:
            return
        header = ["kind", "configurations"] + [f"{m} cracks" for m in self.methods]
        body = []
        for k in sorted(self.t.kind_configurations):
            body.append([k, self.t.kind_configurations[k]] + [self.t.kind_cracks[k].get(m, 0) for m in self.methods])
        self.sections.append(("Hard cases by kind", self.table(header, body, "by_kind.csv")))

    # ---- 7. the methods ----------------------------------------------------------
    def method_key(self):
        """Each series' method as the settings table describes it, and a variant's choices."""
        body = []
        for m in self.methods:
            base = base_method(m)
            known = base in self.settings.label
            what = self.settings.label[base] if known else "not in the settings table (a CSV from another nearcap?)"
            if m != base:
                what += "; under " + self.settings.variant_text(m[len(base) + 2:-1])
            body.append([m, self.settings.kind[base] if known else "", what])
        self.sections.append(("The methods", "<p>The series above, described by the settings table of the nearcap "
                                             "program that ran the report (<code>nearcap settings</code>).</p>" +
                              self.table(["method", "kind", "what it is"], body, "methods.csv")))

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
        self.method_key()
        toc = "".join(f'<li><a href="#s{k}">{html.escape(t)}</a></li>' for k, (t, _) in enumerate(self.sections))
        body = "".join(f'<h2 id="s{k}">{html.escape(t)}</h2>{c}' for k, (t, c) in enumerate(self.sections))
        page = f"""<!doctype html><html><head><meta charset="utf-8"><title>nearcap sweep report</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}} img{{max-width:100%}}
table{{border-collapse:collapse;margin:0.5em 0 1.5em}} td,th{{border:1px solid #ccc;padding:2px 8px;text-align:right}}
th{{background:#eee}} td:first-child{{text-align:left}}</style></head><body>
<h1>nearcap sweep report</h1><p>From {html.escape(escaped(', '.join(self.sources)))}. Each row of a sweep is one
(configuration, light, method); "wrong" counts pixels whose shadow status differs from the exact reference,
"cracks" those among them whose exact status is proven constant over the whole pixel (docs/methods.md, "Crack distance").
Times are the float pipeline's emulation on the CPU, not a GPU's.</p><ul>{toc}</ul>{body}</body></html>"""
        self.writing = "index.html"
        (self.out / "index.html").write_text(page, encoding="utf-8")
        self.writing = "report.json"
        (self.out / "report.json").write_text(json.dumps(
            {"rows": self.rows, "rejected": self.rejected, "refused": sum(self.t.refused.values()),
             "methods": self.methods, "configurations": self.t.configurations, "plots": self.plots,
             "noise_floor": None if self.noise is None else dict(self.noise, paths=self.path_noise)},
            indent=1) + "\n",
            encoding="utf-8")


def timing_ratio(again, first):
    """Z-pass's second timing over its first, or None where the row has no second timing (or a time of 0, which
    a frame under the CSV's 0.1 µs resolution rounds to)."""
    if again is None or not (math.isfinite(again) and math.isfinite(first)) or again <= 0 or first <= 0:
        return None
    return again / first


def noise_floor(ratios, seen=None):
    """The spread of the ratio between two timings of the same frame: its NOISE_PERCENTILES and median, over
    `ratios` (a uniform sample of `seen` when given and larger); None without any."""
    if not len(ratios):
        return None
    low, high = numpy.percentile(numpy.asarray(ratios, dtype=float), NOISE_PERCENTILES)
    pairs = len(ratios) if seen is None else seen
    return {"pairs": pairs, "sampled": pairs > len(ratios), f"p{NOISE_PERCENTILES[0]}": float(low),
            "median": float(numpy.median(ratios)), f"p{NOISE_PERCENTILES[1]}": float(high)}


def band(floor):
    """A noise floor's band as numbers: (low, high)."""
    return floor[f"p{NOISE_PERCENTILES[0]}"], floor[f"p{NOISE_PERCENTILES[1]}"]


def noise_text(floor):
    """The noise floor in a sentence, or that none was measured."""
    if floor is None:
        return ("No noise floor was measured: no row has a second timing of Z-pass's frame (column "
                f"{AGAIN_COLUMN}; Z-pass was not among the sweep's --methods, or the CSV is from an older "
                "nearcap), so how noisy these single timings are is unknown.")
    low, high = band(floor)
    sample = " (percentiles of a uniform sample of them)" if floor["sampled"] else ""
    return (f"Noise floor (Z-pass's frame timed twice in the same sweep, {plural(floor['pairs'], 'pair')}{sample}): "
            f"the second timing over the first is {low:.3g} to {high:.3g} (5th to 95th percentile, median "
            f"{floor['median']:.3g}). Two single frames' times whose ratio lies inside that band are not told apart "
            "by these timings." + (f" Summed over those frames, the second timings over the first: "
                                   f"{floor['mean_ratio']:.3g}, the noise in a mean frame time (the plot's x, the table's "
                                   "mean frame ms)."
                                   if "mean_ratio" in floor else ""))


def pareto_front(points):
    front = []
    for x, y in sorted(points):
        if not front or y < front[-1][1]:
            front.append((x, y))
    return front


def safe(name):
    return "".join(ch if ch.isascii() and ch.isalnum() or ch in "-_" else "_" for ch in name)


def plot_names(names, prefix):
    """One PNG file name per name, unique: PREFIX + the name with other characters than ASCII letters, digits,
    '-' and '_' made '_'; where two names would give the same file (or a name is long), a short hash of the
    name is added."""
    stems = {n: safe(n) for n in names}
    count = defaultdict(int)
    for s in stems.values():
        count[s] += 1
    files = {}
    for n, s in stems.items():
        if count[s] > 1 or len(s) > 80:
            s = f"{s[:80]}_{hashlib.sha1(n.encode('utf-8', 'surrogatepass')).hexdigest()[:8]}"
        files[n] = f"{prefix}{s}.png"
    if len(set(files.values())) < len(files):  # a hash equal to another name's own text: number them
        files = {n: f"{prefix}{k}.png" for k, n in enumerate(names)}
    return files


def plural(n, noun):
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def shorten(text, limit=80):
    return text if len(text) <= limit else text[:limit - 3] + "..."


def as_label(text):
    """Text from the CSV as a matplotlib label: its "$" are dollars, not mathtext."""
    return text.replace("$", r"\$")


def fmt(v):
    if isinstance(v, float):
        return f"{v:.3g}" if abs(v) < 1000 else f"{v:.0f}"
    return str(v)


def read_policy(policy):
    policy_json = settings_table.load_json(policy, "policy")
    if not isinstance(policy_json, dict) or policy_json.get("format") != "nearcap-policy":
        raise ReportError("parse", f"{policy}: format: not a nearcap policy")
    version = policy_json.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or \
            not POLICY_VERSIONS[0] <= version <= POLICY_VERSIONS[1]:
        raise ReportError("schema", f"{policy}: version: {json.dumps(version)} is not a version this nearcap reads "
                                    f"({POLICY_VERSIONS[0]} to {POLICY_VERSIONS[1]})")
    return policy_json


def same_file(a, b):
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def main(argv):
    args, valued = [], {"--out": None, "--policy": None, "--settings": None}
    k = 0
    while k < len(argv):
        if argv[k] in valued:
            if k + 1 == len(argv) or argv[k + 1].startswith("--"):
                raise ReportError("usage", f"{argv[k]} needs a value")
            valued[argv[k]] = argv[k + 1]
            k += 2
        elif argv[k].startswith("--"):
            raise ReportError("usage", f"unknown option {argv[k]} (the options are --out, --settings, --policy)")
        else:
            args.append(argv[k])
            k += 1
    out, policy, settings = valued["--out"], valued["--policy"], valued["--settings"]
    if not args or out is None or settings is None:
        raise ReportError("usage", "usage: sweep_report.py RESULTS.csv [MORE.csv ...] --out DIR --settings TABLE.json "
                                   "[--policy FILE] (TABLE.json: what `nearcap settings` prints)")
    target = Path(out)
    try:
        if target.exists() and not target.is_dir():
            raise ReportError("io", f"{out}: exists and is not a directory")
        if target.is_dir() and not os.access(target, os.W_OK | os.X_OK):
            raise ReportError("io", f"{out}: cannot write the report there: {os.strerror(13)}")
    except OSError as e:  # a name too long, a loop of links
        raise ReportError("io", f"{out}: cannot write the report there: {e.strerror}")
    policy_json = read_policy(policy) if policy is not None else None
    table = settings_table.read(settings)
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, [])  # this process's signal mask, restored after the cleanup
    try:
        parent = target.resolve().parent
        parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=".nearcap-report-", dir=parent))
    except OSError as e:
        raise ReportError("io", f"{out}: cannot write the report there: {e.strerror}")
    try:
        totals = read_rows(args, table)
        report = Report(totals, staging)
        report.sources = args
        report.policy, report.policy_source = policy_json, policy
        try:
            report.write()
        except OSError as e:
            raise ReportError("io", f"{out}: cannot write the report ({report.writing}): {e.strerror}; nothing "
                                    "was written there")
        inputs = args + ([policy] if policy is not None else []) + [settings]
        staged = sorted(staging.iterdir())
        for f in staged:
            for i in inputs:
                if same_file(target / f.name, i):
                    raise ReportError("io", f"{out}: the report would replace {target / f.name}, which is its input "
                                            f"{i}; nothing was written (choose another --out)")
        # The pages move into DIR whole: a stop signal waits until they have.
        signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
        try:
            target.mkdir(exist_ok=True)
            for f in staged:
                os.replace(f, target / f.name)
        except OSError as e:
            raise ReportError("io", f"{out}: cannot write the report: {e.strerror}")
    finally:
        signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)  # the cleanup runs to its end
        shutil.rmtree(staging, ignore_errors=True)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
    try:
        print(f"report: {report.rows} rows, {len(report.plots)} plots, {target / 'index.html'}", flush=True)
    except OSError as e:
        # Nothing more reaches it: the interpreter's own flush at exit would fail again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        raise ReportError("io", f"standard output: cannot write what the command printed: {e.strerror}")


CONTROL_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def escaped(text):
    """A message's control characters as escapes, as nearcap writes them (io/utf8_text.hpp): a line feed, a carriage
    return and a tab as \\n, \\r and \\t, another C0 character or DEL as \\xHH, C1 as \\u00HH, and a byte of a
    file name that is not UTF-8 (decoded by Python as a lone surrogate) as \\xHH."""
    out = []
    for c in text:
        o = ord(c)
        if c in CONTROL_ESCAPES:
            out.append(CONTROL_ESCAPES[c])
        elif o < 0x20 or o == 0x7F:
            out.append(f"\\x{o:02x}")
        elif 0x80 <= o <= 0x9F:
            out.append(f"\\u{o:04x}")
        elif 0xDC80 <= o <= 0xDCFF:
            out.append(f"\\x{o - 0xDC00:02x}")
        else:
            out.append(c)
    return "".join(out)


def one_line(text, limit=400):
    text = escaped(str(text))
    return text if len(text) <= limit else text[:limit - 3] + "..."


def run(argv):
    """main, with every failure as one line on stderr and exit code 2."""
    sys.stdout.reconfigure(errors="surrogateescape")  # a file name's bytes as given, UTF-8 or not
    try:
        main(argv)
        return 0
    except (ReportError, settings_table.InputError) as e:
        line = f"nearcap: error ({e.kind}): {one_line(e)}"
    except MemoryError:
        line = "nearcap: error (resource): out of memory while building the report"
    except Exception as e:  # a bug in this script: its traceback goes to a log, not to the terminal
        try:
            fd, log = tempfile.mkstemp(prefix="nearcap-report-", suffix=".log")
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(" ".join(["sweep_report.py"] + argv) + "\n" + traceback.format_exc())
            where = f"its traceback is in {log}"
        except OSError as log_error:
            where = f"its traceback could not be saved: {log_error.strerror}"
        line = (f"nearcap: error (io): the report script stopped on {type(e).__name__}: {one_line(e, 200)} "
                f"(a bug in the report; {where})")
    print(line, file=sys.stderr)
    return 2


STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def stop_on_signal(signum, frame):
    """SIGINT, SIGTERM or SIGHUP (nearcap forwards SIGTERM when it is stopped; Ctrl-C and a closed terminal reach
    both): one exit that runs the cleanup, the signals that follow ignored so that it finishes."""
    for s in STOP_SIGNALS:
        signal.signal(s, signal.SIG_IGN)
    raise SystemExit(128 + signum)


if __name__ == "__main__":
    for stop in STOP_SIGNALS:
        if signal.getsignal(stop) is not signal.SIG_IGN:  # an ignored one (nohup, a background job) stays so
            signal.signal(stop, stop_on_signal)
    sys.exit(run(sys.argv[1:]))
