"""Shared reading of the render-compare traces (CSV written by `robossis render-compare`)."""
import csv


def read_trace(path):
    """Columns of a trace CSV as a dict of lists (numbers as floats, 'status' and 'penetration_counted_as' as text)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for key in rows[0].keys() if rows else []:
        if key in ("status", "penetration_counted_as"):
            cols[key] = [r[key] for r in rows]
        else:
            cols[key] = [float(r[key]) for r in rows]
    return cols


def norm3(cols, a, b, c):
    return [(x * x + y * y + z * z) ** 0.5 for x, y, z in zip(cols[a], cols[b], cols[c])]


def parse_args(argv, usage):
    """--traces A.csv,B.csv --labels a,b [--title T] --out FILE.png"""
    import argparse
    p = argparse.ArgumentParser(description=usage)
    p.add_argument("--traces", required=True)
    p.add_argument("--labels", required=True)
    p.add_argument("--title", default="")
    p.add_argument("--out", required=True)
    args = p.parse_args(argv)
    traces = args.traces.split(",")
    labels = args.labels.split(",")
    if len(traces) != len(labels):
        p.error("--traces and --labels need the same number of entries")
    return args, traces, labels
