#!/usr/bin/env python3
"""Fig. 9 analogue (paper §V-A): joint velocities, step rate per motor, and the step/direction lines.

Reads DIR/joints.csv and DIR/pulses.csv written by `robossis move`, `robossis transfer` or `robossis demo`.
Usage: transfer_fig9.py --dir DIR [--motor N] --out FILE.png   (N = 1..6, default 4: the first linear actuator)
"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

NAMES = ["theta_1", "theta_2", "theta_3", "d_1", "d_2", "d_3"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", required=True)
    ap.add_argument("--motor", type=int, default=4)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    j = np.genfromtxt(f"{a.dir}/joints.csv", delimiter=",", names=True)
    p = np.genfromtxt(f"{a.dir}/pulses.csv", delimiter=",", names=True)
    p = np.atleast_1d(p)
    t = j["time_s"]
    fig, ax = plt.subplots(4, 1, figsize=(11, 11))
    for k, name in enumerate(["d1_dot_mm_s", "d2_dot_mm_s", "d3_dot_mm_s"]):
        ax[0].plot(t, j[name], label=NAMES[3 + k] + " (mm/s)")
    for k, name in enumerate(["theta1_dot_deg_s", "theta2_dot_deg_s", "theta3_dot_deg_s"]):
        ax[0].plot(t, j[name], "--", label=NAMES[k] + " (deg/s)")
    ax[0].set(title="joint velocities, eq. 15", xlabel="time (s)")
    ax[0].legend(ncol=3, fontsize=8)
    # Step rate per motor over 20 ms bins.
    edges = np.arange(t[0], t[-1] + 0.02, 0.02)
    for m in range(1, 7):
        sel = p[p["motor"] == m] if p.size else p
        if sel.size == 0:
            continue
        signed, _ = np.histogram(sel["time_s"], bins=edges, weights=sel["direction"])
        ax[1].plot(edges[:-1], signed / 0.02, label=NAMES[m - 1])
    ax[1].set(title="signed step rate per motor (steps/s, 20 ms bins): proportional to the joint velocity",
              xlabel="time (s)")
    ax[1].legend(ncol=3, fontsize=8)
    sel = p[p["motor"] == a.motor] if p.size else p
    steps_col = f"steps{a.motor}"
    ax[2].plot(t, j[steps_col], label=f"steps issued, motor {NAMES[a.motor - 1]}")
    ax[2].set(title="steps issued (net)", xlabel="time (s)")
    ax[2].legend()
    # STEP and DIR lines around the reversal (or the middle of the motion).
    if sel.size > 1:
        dirs = sel["direction"]
        flips = np.nonzero(np.diff(dirs))[0]
        centre = sel["time_s"][flips[0]] if flips.size else sel["time_s"][sel.size // 2]
        w = 0.15
        win = sel[(sel["time_s"] > centre - w) & (sel["time_s"] < centre + w)]
        pulse_width = 20e-6  # drawn width of a STEP pulse
        for e in win:
            ax[3].plot([e["time_s"], e["time_s"], e["time_s"] + pulse_width, e["time_s"] + pulse_width],
                       [0, 1, 1, 0], color="tab:blue", lw=0.8)
        ax[3].step(win["time_s"], 1.5 + 0.5 * (win["direction"] > 0), where="post", color="tab:orange")
        ax[3].set(title=f"STEP (blue) and DIR (orange, high = +) of {NAMES[a.motor - 1]} around t = {centre:.2f} s",
                  xlabel="time (s)", yticks=[])
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
