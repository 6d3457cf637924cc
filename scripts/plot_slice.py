#!/usr/bin/python3
"""Plot a planar slice through surface meshes, with the scan points near the plane, to PNG.

How the places where a reconstruction misses its reference were looked at (scan2cad/README.md):
  scripts/plot_slice.py --axis x --at 1.0 --window -172 -150 -125 -103 --points scan.ply \
      --out lip.png NIOSH_medium_20k.stl reconstructed.ply repaired.ply
The first mesh is drawn thick (the reference), the others thin; points within --slab of the
plane are drawn grey. Meshes and points are read with meshio (STL, PLY, OFF, OBJ, ...).
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pipeline"))
from read_mesh_or_raise import read_mesh_or_raise  # noqa: E402

AXES = {"x": 0, "y": 1, "z": 2}


def slice_segments(points, triangles, axis, at):
    """Segments where the plane coordinate[axis] == at cuts the triangles: array (n, 2, 3)."""
    d = points[:, axis] - at
    side = d[triangles] > 0
    cut = triangles[side.any(axis=1) & ~side.all(axis=1)]
    segments = []
    for t in cut:
        ends = []
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if (d[a] > 0) != (d[b] > 0):
                w = d[a] / (d[a] - d[b])
                ends.append(points[a] + w * (points[b] - points[a]))
        if len(ends) == 2:
            segments.append(ends)
    return np.array(segments).reshape(-1, 2, 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("meshes", nargs="+", help="triangle meshes; the first is drawn as the reference")
    ap.add_argument("--axis", choices=AXES, required=True, help="the plane's normal axis")
    ap.add_argument("--at", type=float, required=True, help="the plane's coordinate [mm]")
    ap.add_argument("--window", type=float, nargs=4, metavar=("H0", "H1", "V0", "V1"), required=True,
                    help="plot range of the two other axes, in x, y, z order [mm]")
    ap.add_argument("--points", help="point cloud whose points near the plane are drawn")
    ap.add_argument("--slab", type=float, default=0.3, help="half thickness of the point slab [mm] (0.3)")
    ap.add_argument("--out", required=True, help="PNG to write")
    a = ap.parse_args()
    axis = AXES[a.axis]
    h, v = [i for i in range(3) if i != axis]
    plt.figure(figsize=(8, 8))
    colours = ["k", "r", "b", "g", "m"]
    for i, path in enumerate(a.meshes):
        try:
            m = read_mesh_or_raise(path)
            tri = m.cells_dict["triangle"]
        except Exception as e:  # one line naming the file, as every stage does
            sys.exit(f"plot_slice: {path}: cannot read a triangle mesh ({e})")
        c = colours[i % len(colours)]
        segments = slice_segments(m.points.astype(float), tri, axis, a.at)
        for s in segments:
            plt.plot(s[:, h], s[:, v], c + "-", lw=1.8 if i == 0 else 1.0)
        inside = [s for s in segments if all(a.window[0] <= q[h] <= a.window[1] and a.window[2] <= q[v] <= a.window[3]
                                             for q in s)]
        print(f"plot_slice: {path}: {len(segments)} segments, {len(inside)} inside the window")
        plt.plot([], [], c + "-", label=path)
    if a.points:
        try:
            p = read_mesh_or_raise(a.points).points
        except Exception as e:
            sys.exit(f"plot_slice: {a.points}: cannot read points ({e})")
        near = np.abs(p[:, axis] - a.at) < a.slab
        print(f"plot_slice: {a.points}: {int(near.sum())} points within {a.slab} mm of the plane")
        plt.plot(p[near, h], p[near, v], ".", color="grey", ms=3, label=f"points within {a.slab} mm")
    plt.xlim(a.window[0], a.window[1])
    plt.ylim(a.window[2], a.window[3])
    plt.xlabel("xyz"[h] + " [mm]")
    plt.ylabel("xyz"[v] + " [mm]")
    plt.title(f"{a.axis} = {a.at} mm")
    plt.gca().set_aspect("equal")
    plt.grid(True, lw=0.3)
    plt.legend(fontsize=8)
    if not a.out.lower().endswith(".png"):
        sys.exit(f"plot_slice: {a.out}: the output is a PNG: name it .png")
    out_dir = os.path.dirname(os.path.abspath(a.out))
    tmp = os.path.join(out_dir, f".tmp.{os.getpid()}.{os.path.basename(a.out)}")
    try:
        os.makedirs(out_dir, exist_ok=True)
        plt.savefig(tmp, dpi=90)
        os.replace(tmp, a.out)
    except OSError as e:  # one line, as for the inputs (it was a traceback)
        if os.path.exists(tmp):
            os.remove(tmp)
        sys.exit(f"plot_slice: {a.out}: cannot write: {e.strerror}")


if __name__ == "__main__":
    main()
