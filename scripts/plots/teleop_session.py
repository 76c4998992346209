#!/usr/bin/env python3
"""A teleoperation session (`robossis teleop`, `robossis replay`, `robossis demo`): hand vs follower pose, the
forces on the hand, the follower's distance to its joint limits, and the loop periods.

Reads DIR/leader.csv, DIR/follower.csv and DIR/loop_periods.csv.
Usage: teleop_session.py --dir DIR --out FILE.png
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
    lead = np.genfromtxt(f"{a.dir}/leader.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    fol = np.genfromtxt(f"{a.dir}/follower.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    per = np.genfromtxt(f"{a.dir}/loop_periods.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    fig, ax = plt.subplots(2, 2, figsize=(13, 9))
    t = lead["t_s"]
    for axis, color in (("x", "tab:blue"), ("y", "tab:orange"), ("z", "tab:green")):
        hand = lead[f"hand_{axis}_mm"] - lead[f"hand_{axis}_mm"][0]
        ax[0, 0].plot(t, hand, color=color, alpha=0.35, lw=0.8, label=f"hand {axis} (device, from start)")
        meas = fol[f"meas_{axis}_mm"] - fol[f"meas_{axis}_mm"][0]
        ax[0, 0].plot(fol["t_s"], meas, color=color, lw=1.5, label=f"follower {axis} (measured, from start)")
    ax[0, 0].set(title="hand vs follower position", xlabel="time (s)", ylabel="mm")
    ax[0, 0].legend(fontsize=7, ncol=2)
    f = np.sqrt(lead["fx_n"] ** 2 + lead["fy_n"] ** 2 + lead["fz_n"] ** 2)
    tau = np.sqrt(lead["tx_nm"] ** 2 + lead["ty_nm"] ** 2 + lead["tz_nm"] ** 2)
    ax[0, 1].plot(t, f, label="|force| (N)")
    ax[0, 1].plot(t, 10 * tau, label="10 x |torque| (N·m)")
    ax[0, 1].set(title="wrench displayed on the hand", xlabel="time (s)", ylabel="N, 0.1 N·m")
    ax[0, 1].legend()
    ax[1, 0].plot(fol["t_s"], fol["min_limit_margin_si"], color="tab:red")
    ax[1, 0].axhline(0, color="k", lw=0.8)
    ax[1, 0].set(title="follower: tightest joint-limit margin (measured; < 0 = violated)", xlabel="time (s)",
                 ylabel="m (stroke) or rad (rotary, cone)")
    for loop, color in (("leader", "tab:blue"), ("follower", "tab:green")):
        sel = per["loop"] == loop
        if np.any(sel):
            ax[1, 1].bar(per["period_us"][sel], per["count"][sel], width=1.0, color=color, alpha=0.7, label=loop)
    ax[1, 1].set(title="loop periods (start to start)", xlabel="µs", ylabel="ticks", yscale="log")
    ax[1, 1].legend()
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
