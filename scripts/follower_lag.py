#!/usr/bin/env python3
"""The follower's lag behind the set-points it received, from a `robossis teleop` output folder.

For every row of follower.csv while the follower is enabled: the distance (mm) from its commanded position to the
set-point the leader sent DELAY_S earlier (leader.csv's sent_* columns; the link's one-way delay, --link-delay-ms),
the newest one sent by then. Prints the median, the 90th percentile and the largest lag (and when), and summary.json's
position_drift_mm and position_drift_max_mm beside them.

Example: scripts/follower_lag.py OUT --delay-s 0.1
"""
import argparse
import bisect
import csv
import json
import math
import pathlib
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=pathlib.Path, help="the output folder of robossis teleop")
    parser.add_argument("--delay-s", type=float, default=0.0, help="the link's one-way delay (s)")
    a = parser.parse_args()
    try:
        follower = list(csv.DictReader(open(a.out / "follower.csv")))
        leader = list(csv.DictReader(open(a.out / "leader.csv")))
        summary = json.load(open(a.out / "summary.json"))
    except OSError as e:
        print(f"follower_lag.py: {e}", file=sys.stderr)
        return 1
    sent_t = [float(r["t_s"]) for r in leader]
    lags = []
    for r in follower:
        if r["state"] != "enabled":
            continue
        t = float(r["t_s"])
        i = bisect.bisect_right(sent_t, t - a.delay_s) - 1
        if i < 0:
            continue
        s = [float(leader[i][f"sent_{c}_mm"]) for c in "xyz"]
        c = [float(r[f"cmd_{c}_mm"]) for c in "xyz"]
        lags.append((math.dist(c, s), t))
    if not lags:
        print(f"follower_lag.py: {a.out}: the follower never followed", file=sys.stderr)
        return 1
    lags.sort()
    drift = summary.get("position_drift_mm")
    print(f"lag median {lags[len(lags) // 2][0]:.2f} mm, p90 {lags[int(0.9 * len(lags))][0]:.2f} mm, "
          f"max {lags[-1][0]:.2f} mm at {lags[-1][1]:.2f} s; position_drift_mm "
          f"{'null' if drift is None else f'{drift:.3f}'}, position_drift_max_mm {summary.get('position_drift_max_mm'):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
