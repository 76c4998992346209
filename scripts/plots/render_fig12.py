#!/usr/bin/env python3
"""Fig. 12 analogue: (a) the RSR joints (actuator strokes d_i and spherical-joint angles) during the motion, with
their limits, for the first method; (b) force and (c) torque magnitude fed back to the hand by every method.

Usage: render_fig12.py --traces a.csv,b.csv --labels pointcloud,proxy --out fig12.png
"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

from render_common import norm3, parse_args, read_trace


def main(argv):
    args, traces, labels = parse_args(argv, __doc__)
    fig, axes = plt.subplots(4, 1, figsize=(11, 10), sharex=True)
    data = [read_trace(p) for p in traces]
    first = data[0]
    t = first["t_s"]
    for i in range(3):
        axes[0].plot(t, first["d%d_mm" % (i + 1)], lw=0.9, label="d%d" % (i + 1))
        axes[1].plot(t, first["cone%d_deg" % (i + 1)], lw=0.9, label="spherical %d" % (i + 1))
    for y in (214, 354):
        axes[0].axhline(y, color="k", ls="--", lw=1)
    axes[1].axhline(25, color="k", ls="--", lw=1)
    axes[0].set_ylabel("stroke (mm)")
    axes[0].set_title("(a) RSR joints at the commanded pose (%s); dashed: limits" % labels[0])
    axes[1].set_ylabel("spherical joint (deg)")
    for c, label in zip(data, labels):
        axes[2].plot(c["t_s"], norm3(c, "fx_n", "fy_n", "fz_n"), lw=0.8, label=label)
        axes[3].plot(c["t_s"], norm3(c, "tx_nm", "ty_nm", "tz_nm"), lw=0.8, label=label)
    axes[2].set_ylabel("|F| (N)")
    axes[2].set_title("(b) force and (c) torque on the hand")
    axes[3].set_ylabel("|τ| (N·m)")
    axes[3].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=3, loc="upper right")
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1:])
