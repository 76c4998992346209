#!/usr/bin/env python3
"""Smoothness vs delay of the motion-transfer filter settings (written by `robossis demo`, transfer/tradeoff.csv).
Usage: transfer_tradeoff.py --csv FILE --out FILE.png
"""
import argparse
import csv

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    for r in rows:
        d = float(r["delay_ms"])
        ax[0].plot(d, float(r["max_accel_mm_s2"]), "o")
        ax[0].annotate(r["label"], (d, float(r["max_accel_mm_s2"])), fontsize=7)
        ax[1].plot(d, float(r["max_jerk_mm_s3"]), "o")
        ax[1].annotate(r["label"], (d, float(r["max_jerk_mm_s3"])), fontsize=7)
    ax[0].set(xlabel="hand → set-point delay (ms)", ylabel="peak acceleration (mm/s²)", yscale="log",
              title="smoothness vs delay (fig8 scenario)")
    ax[1].set(xlabel="hand → set-point delay (ms)", ylabel="peak jerk (mm/s³)", yscale="log")
    for x in ax:
        x.axvline(50, ls="--", color="gray")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
