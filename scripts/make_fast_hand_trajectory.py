#!/usr/bin/env python3
"""Writes data/teleop/fast_hand.csv: a synthetic fast hand trajectory for the teleoperation tests and demo.

The rows are the RSR pose the hand commands (the render-compare replay format, frame F, absolute, starting at the
RSR home pose): t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg at 200 Hz. Each 2 s segment is one full sine
period along one axis, peaking at 250 mm/s (80 mm amplitude; 50 mm along z) or 60 deg amplitude in rotation,
i.e. 25x the 10 mm/s speed cap and far outside the workspace; the last 4 s combine all six axes (a Lissajous
figure). Deterministic: re-running the script reproduces the file byte for byte.

Usage: python3 scripts/make_fast_hand_trajectory.py [OUT.csv]
"""
import math
import sys

HOME = (0.0, 0.0, 284.0, 0.0, 0.0, 0.0)  # data/config/rsr.yaml home_pose (mm, deg)
RATE_HZ = 200
SEGMENT_S = 2.0
W = 2 * math.pi / SEGMENT_S               # one period per segment
AMP = (80.0, 80.0, 50.0, 60.0, 60.0, 60.0)  # 80 mm * W = 251 mm/s peak


def pose(t):
    p = list(HOME)
    k = int(t // SEGMENT_S)
    if k < 6:
        p[k] += AMP[k] * math.sin(W * (t - k * SEGMENT_S))
    else:
        tl = t - 6 * SEGMENT_S
        for axis, ratio in enumerate((1.0, 1.5, 0.5, 1.0, 0.75, 1.25)):
            p[axis] += 0.7 * AMP[axis] * math.sin(ratio * W * tl / 2)
    return p


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "data/teleop/fast_hand.csv"
    duration_s = 6 * SEGMENT_S + 4.0
    n = int(round(duration_s * RATE_HZ))
    with open(out, "w", newline="\n") as f:
        f.write("t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n")
        for i in range(n + 1):
            t = i / RATE_HZ
            f.write("%.4f,%s\n" % (t, ",".join("%.4f" % v for v in pose(t))))


if __name__ == "__main__":
    main()
