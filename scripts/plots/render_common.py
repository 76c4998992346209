"""Shared reading of the render-compare traces (CSV written by `robossis render-compare`)."""
import csv


TEXT_COLUMNS = ("status", "penetration_counted_as")


class TraceColumns(dict):
    """A trace's columns by name, each converted on first use (numbers as floats, TEXT_COLUMNS as text): a figure
    reads about a dozen of the trace's 42 columns, and converting all of them took most of a figure's time."""

    def __init__(self, header, rows):
        super().__init__()
        self._index = {key: i for i, key in enumerate(header)}
        self._rows = rows

    def __missing__(self, key):
        i = self._index[key]  # KeyError for a column the trace does not have
        column = [r[i] for r in self._rows] if key in TEXT_COLUMNS else [float(r[i]) for r in self._rows]
        self[key] = column
        return column

    def __contains__(self, key):
        return key in self._index

    def keys(self):
        return self._index.keys()


def read_trace(path):
    """Columns of a trace CSV (see TraceColumns)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, [])
        rows = list(reader)
    return TraceColumns(header, rows)


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
