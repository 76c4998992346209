#!/usr/bin/python3
"""Fig. 5 analogue: two workspace boundary meshes side by side (RSR and sigma.7), read from the binary PLY files
that `robossis workspace ...` / `robossis demo` write (coordinates in mm or deg, as the file names say).

Usage: workspace_fig5.py --left A.ply --left-label RSR --right B.ply --right-label sigma.7 \
           --axes "x (mm),y (mm),z (mm)" --title "..." --out fig.png
"""
import argparse
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    nv = nf = None
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            nv = int(words[2])
        if words[:2] == ["element", "face"]:
            nf = int(words[2])
    if nv is None or nf is None or "format binary_little_endian 1.0" not in header:
        sys.exit(f"{path}: not a binary little-endian PLY with vertex and face elements")
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end).reshape(nv, 3)
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=nf, offset=end + 12 * nv)
    return vertices.astype(float), faces["i"].astype(int)


def draw(ax, path, label, axes, color):
    v, f = read_ply(path)
    tris = v[f]
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    light = np.array([0.4, -0.5, 0.77])
    shade = 0.35 + 0.65 * np.clip(normals @ light, 0, 1)
    base = np.array(matplotlib.colors.to_rgb(color))
    ax.add_collection3d(Poly3DCollection(tris, facecolors=shade[:, None] * base, linewidths=0))
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_xlabel(axes[0])
    ax.set_ylabel(axes[1])
    ax.set_zlabel(axes[2])
    size = hi - lo
    ax.set_title(f"{label}\n{size[0]:.0f} x {size[1]:.0f} x {size[2]:.0f}, {len(f)} triangles", fontsize=9)
    ax.view_init(elev=22, azim=-60)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--left", required=True)
    p.add_argument("--left-label", required=True)
    p.add_argument("--right", required=True)
    p.add_argument("--right-label", required=True)
    p.add_argument("--axes", required=True, help="three comma-separated axis labels")
    p.add_argument("--right-axes", help="axis labels of the right plot (default: --axes)")
    p.add_argument("--title", required=True)
    p.add_argument("--out", required=True)
    a = p.parse_args()
    fig = plt.figure(figsize=(10, 4.8))
    draw(fig.add_subplot(1, 2, 1, projection="3d"), a.left, a.left_label, a.axes.split(","), "tab:blue")
    draw(fig.add_subplot(1, 2, 2, projection="3d"), a.right, a.right_label,
         (a.right_axes or a.axes).split(","), "tab:orange")
    fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
