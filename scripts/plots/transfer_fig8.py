#!/usr/bin/env python3
"""Fig. 8 analogue (paper §V): HC vs RSR position, dynamic scaling, raw HC and RSR velocity/acceleration.

Reads DIR/transfer_1khz.csv (the controller's 1 kHz view) and DIR/setpoints.csv (the 10 kHz set-point, possibly
decimated) written by `robossis transfer` or `robossis demo`.
Usage: transfer_fig8.py --dir DIR --out FILE.png
"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    slow = np.genfromtxt(f"{a.dir}/transfer_1khz.csv", delimiter=",", names=True)
    sp = np.genfromtxt(f"{a.dir}/setpoints.csv", delimiter=",", names=True)
    t = slow["time_s"]
    hx = slow["hc_x_mm"] - slow["hc_x_mm"][0]
    # Raw HC as the controller sees it: finite differences of the last delivered pose on the 1 kHz grid.
    hv = np.gradient(np.stack([slow["hc_x_mm"], slow["hc_y_mm"], slow["hc_z_mm"]]), t, axis=1)
    ha = np.gradient(hv, t, axis=1)
    ts = sp["time_s"]
    fig, ax = plt.subplots(3, 2, figsize=(12, 10))
    ax[0, 0].plot(t, hx, label="HC (hand), x", color="tab:gray")
    ax[0, 0].plot(ts, sp["x_mm"], label="RSR set-point, x", color="tab:blue")
    ax[0, 0].set(title="(a) position", xlabel="time (s)", ylabel="mm")
    ax[0, 0].legend()
    ax[0, 1].plot(slow["hc_speed_mm_s"], slow["scale_linear"], ".", ms=2)
    ax[0, 1].set(title="(b) dynamic scaling S (eq. 11) vs hand speed", xlabel="|v_HC| (mm/s)", ylabel="S",
                 xlim=(0, max(40.0, np.percentile(slow["hc_speed_mm_s"], 99.5))))
    ax[1, 0].plot(t, np.linalg.norm(hv, axis=0), color="tab:gray")
    ax[1, 0].set(title="(c) raw HC speed |v| (breakage)", xlabel="time (s)", ylabel="mm/s", yscale="symlog")
    ax[1, 1].plot(t, np.linalg.norm(ha, axis=0), color="tab:gray")
    ax[1, 1].set(title="(d) raw HC acceleration |a|", xlabel="time (s)", ylabel="mm/s²", yscale="symlog")
    ax[2, 0].plot(ts, sp["speed_mm_s"], label="|v|", color="tab:blue")
    ax[2, 0].plot(ts, sp["vx_mm_s"], label="v_x", color="tab:green", lw=0.8)
    ax[2, 0].axhline(10.0, ls="--", color="tab:red", label="cap 10 mm/s")
    ax[2, 0].set(title="(e) RSR set-point velocity", xlabel="time (s)", ylabel="mm/s")
    ax[2, 0].legend()
    ax[2, 1].plot(ts, sp["ax_mm_s2"], label="a_x", color="tab:green", lw=0.8)
    ax[2, 1].plot(ts, sp["accel_mm_s2"], label="|a|", color="tab:blue", lw=0.8)
    ax[2, 1].set(title="(f) RSR set-point acceleration", xlabel="time (s)", ylabel="mm/s²")
    ax[2, 1].legend()
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
