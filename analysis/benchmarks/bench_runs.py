"""The per-method figures of repeated `nearcap render --bench` runs, as the
render_*_table.sh scripts lay them out: ROOT/VARIANT/NAME/R/bench.csv for
the runs R = 1 .. REPEATS of one path under one variant (a culling mode, a
vertex layout)."""
import csv
import statistics

from script_errors import reading


def median_of_means(root, variant, name, repeats, column):
    """Per method: the median over the runs of the method's mean `column`
    (a bench.csv column of milliseconds) over the path's frames."""
    runs = []
    for r in range(1, repeats + 1):
        path = f"{root}/{variant}/{name}/{r}/bench.csv"
        per = {}
        with reading(path, "a render --bench CSV"), open(path, newline="", encoding="utf-8") as f:
            for row in csv.DictReader(f):
                per.setdefault(row["method"], []).append(float(row[column]))
        runs.append({m: sum(v) / len(v) for m, v in per.items()})
    return {m: statistics.median(run[m] for run in runs) for m in runs[0]}
