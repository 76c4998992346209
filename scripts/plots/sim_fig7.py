#!/usr/bin/python3
"""Fig. 7 analogue of the Bullet simulation: commanded vs measured ring pose (translation, rotation), the pose
error, and the actuator forces against the Jacobian statics (J^-T). Reads the trajectory.csv of `robossis sim`.

Usage: sim_fig7.py --csv trajectory.csv [--title TEXT] --out fig.png
"""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    cols = {}
    for key in rows[0]:
        vals = []
        for r in rows:
            try:
                vals.append(float(r[key]))
            except ValueError:
                vals.append(math.nan)
        cols[key] = vals
    return cols


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--csv", required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    c = read(a.csv)
    t = c["time_s"]
    fig, ax = plt.subplots(4, 1, figsize=(9, 12), sharex=True)
    colors = ["tab:red", "tab:green", "tab:blue"]
    for k, axis in enumerate(["x_mm", "y_mm", "z_mm"]):
        ax[0].plot(t, c["cmd_" + axis], color=colors[k], lw=2.5, alpha=0.35, label=f"{axis[0]} commanded")
        ax[0].plot(t, c["meas_" + axis], color=colors[k], lw=1, ls="--", label=f"{axis[0]} measured (Bullet)")
    ax[0].set_ylabel("position (mm)")
    ax[0].set_title("(a) translation")
    ax[0].legend(ncol=3, fontsize=7)
    for k, axis in enumerate(["roll_deg", "pitch_deg", "yaw_deg"]):
        ax[1].plot(t, c["cmd_" + axis], color=colors[k], lw=2.5, alpha=0.35, label=f"{axis.split('_')[0]} commanded")
        ax[1].plot(t, c["meas_" + axis], color=colors[k], lw=1, ls="--", label=f"{axis.split('_')[0]} measured")
    ax[1].set_ylabel("angle (deg)")
    ax[1].set_title("(b) rotation (roll-pitch-yaw)")
    ax[1].legend(ncol=3, fontsize=7)
    ax[2].plot(t, c["translation_error_mm"], color="tab:purple", lw=1, label="translation error (mm)")
    ax[2].set_ylabel("translation error (mm)")
    ax2 = ax[2].twinx()
    ax2.plot(t, c["rotation_error_deg"], color="tab:orange", lw=1, label="rotation error (deg)")
    ax2.set_ylabel("rotation error (deg)")
    ax[2].set_title("(c) deviation of the measured ring pose from the commanded one (paper: ~0.2 mm, ~0.1 deg)")
    h1, l1 = ax[2].get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax[2].legend(h1 + h2, l1 + l2, fontsize=7)
    for k in range(3):
        ax[3].plot(t, c[f"force{k + 1}_n"], color=colors[k], lw=1, label=f"linear drive {k + 1} (Bullet)")
        ax[3].plot(t, c[f"statics_force{k + 1}_n"], color=colors[k], lw=2.5, alpha=0.3, label=f"J^-T statics {k + 1}")
    ax[3].set_ylabel("actuator force (N)")
    ax[3].set_xlabel("time (s)")
    ax[3].set_title("(d) linear actuator forces vs Jacobian statics")
    ax[3].legend(ncol=3, fontsize=7)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
