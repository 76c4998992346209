#!/usr/bin/env python3
"""Fig. 14 analogue: commanded vs tracked ring trajectories, absolute error over time, box-and-whisker plots.

Reads errors.csv and summary.json written by `robossis track-eval` (or the demo). Usage:
  tracking_fig14.py --errors errors.csv --summary summary.json [--title T] --out fig.png
"""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--errors", required=True)
    ap.add_argument("--summary", required=True)
    ap.add_argument("--title", default="Tracking accuracy")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    d = np.genfromtxt(a.errors, delimiter=",", names=True)
    with open(a.summary) as f:
        s = json.load(f)
    step = max(1, len(d) // 20000)  # long takes: plot every step-th frame (statistics use all of them)
    v = d[::step]
    t = v["t_s"] - v["t_s"][0]
    fig, ax = plt.subplots(3, 2, figsize=(13, 10), gridspec_kw={"height_ratios": [2, 1.2, 1.4]})
    z0 = round(float(np.mean(v["ref_z_mm"])))  # z sits far from x, y (the ring's height): plot it about its mean
    for name, c in zip(("x", "y", "z"), ("C0", "C1", "C2")):
        off = z0 if name == "z" else 0
        label = "z - %d tracked" % z0 if name == "z" else "%s tracked" % name
        ax[0, 0].plot(t, v["trk_%s_mm" % name] - off, color=c, lw=1.2, label=label)
        ax[0, 0].plot(t, v["ref_%s_mm" % name] - off, color="k", lw=0.8, ls="--")
    ax[0, 0].set_ylabel("position (mm)")
    ax[0, 0].set_title("Translation: tracked (colour) vs commanded (dashed)")
    ax[0, 0].legend(fontsize=8, ncol=3)
    for name, c in zip(("roll", "pitch", "yaw"), ("C3", "C4", "C5")):
        ax[0, 1].plot(t, v["trk_%s_deg" % name], color=c, lw=1.2, label="%s tracked" % name)
        ax[0, 1].plot(t, v["ref_%s_deg" % name], color="k", lw=0.8, ls="--")
    ax[0, 1].set_ylabel("angle (deg)")
    ax[0, 1].set_title("Rotation (RPY): tracked vs commanded")
    ax[0, 1].legend(fontsize=8, ncol=3)
    ax[1, 0].plot(t, v["e_mm"], color="C0", lw=0.8)
    ax[1, 0].set_ylabel("|translation error| (mm)")
    ax[1, 0].set_xlabel("time (s)")
    ax[1, 1].plot(t, v["r_deg"], color="C3", lw=0.8)
    ax[1, 1].set_ylabel("|rotation error| (deg)")
    ax[1, 1].set_xlabel("time (s)")
    te, re = s["translation_error_mm"], s["rotation_error_deg"]
    ax[2, 0].boxplot([np.abs(d["ex_mm"]), np.abs(d["ey_mm"]), np.abs(d["ez_mm"]), d["e_mm"]],
                     labels=["|x|", "|y|", "|z|", "norm"], showfliers=True, flierprops={"markersize": 2})
    ax[2, 0].set_ylabel("error (mm)")
    ax[2, 0].set_title("mean %.3f mm, max %.3f mm (paper: 0.32 / 1.8 mm)" % (te["mean"], te["max"]), fontsize=10)
    ax[2, 1].boxplot([np.abs(d["rx_deg"]), np.abs(d["ry_deg"]), np.abs(d["rz_deg"]), d["r_deg"]],
                     labels=["|about x|", "|about y|", "|about z|", "angle"], showfliers=True,
                     flierprops={"markersize": 2})
    ax[2, 1].set_ylabel("error (deg)")
    ax[2, 1].set_title("mean %.4f°, max %.4f° (paper: 0.07 / 0.27°)" % (re["mean"], re["max"]), fontsize=10)
    for row in ax:
        for x in row:
            x.grid(alpha=0.3)
    fig.suptitle("%s — clock offset %.4f s, registration RMS %.3f mm, %d frames used, %d excluded"
                 % (a.title, s["time_offset_s"], s["registration_rms_mm"], s["frames_used"], s["frames_excluded"]))
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
