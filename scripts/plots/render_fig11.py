#!/usr/bin/env python3
"""Fig. 11 analogue: force and torque magnitude versus the signed distance to the TRUE workspace boundary while
pushing into each edge (negative inside, 0 at the boundary), one colour per rendering method.

Usage: render_fig11.py --traces a.csv,b.csv --labels pointcloud,proxy --out fig11.png
"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

from render_common import norm3, parse_args, read_trace


def main(argv):
    args, traces, labels = parse_args(argv, __doc__)
    fig, (ax_f, ax_t) = plt.subplots(1, 2, figsize=(12, 4.5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, (path, label) in enumerate(zip(traces, labels)):
        c = read_trace(path)
        fmag = norm3(c, "fx_n", "fy_n", "fz_n")
        tmag = norm3(c, "tx_nm", "ty_nm", "tz_nm")
        colour = colours[i % len(colours)]
        for rotational, ax, mag in ((0.0, ax_f, fmag), (1.0, ax_t, tmag)):
            # One line per episode so edges do not join.
            episodes = sorted({e for e, p, r in zip(c["episode"], c["is_push"], c["push_rotational"])
                               if p == 1.0 and r == rotational})
            for j, ep in enumerate(episodes):
                idx = [k for k in range(len(mag)) if c["episode"][k] == ep]
                ax.plot([c["push_signed"][k] for k in idx], [mag[k] for k in idx], color=colour, lw=0.8,
                        alpha=0.8, label=label if j == 0 else None)
    ax_f.axvline(0, color="k", ls="--", lw=1)
    ax_t.axvline(0, color="k", ls="--", lw=1)
    ax_f.set_xlabel("signed distance to the true boundary along the push (mm)")
    ax_f.set_ylabel("|F| (N)")
    ax_f.set_title("(a) translational edges, 10 mm/s")
    ax_t.set_xlabel("signed angle to the true boundary about the push axis (deg)")
    ax_t.set_ylabel("|τ| (N·m)")
    ax_t.set_title("(b) rotational edges, 1 °/s")
    for ax in (ax_f, ax_t):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)


if __name__ == "__main__":
    main(sys.argv[1:])
