#!/usr/bin/python3
"""Renders a front and a side view of a surface mesh (PLY/OFF/STL/OBJ, read with meshio) to one
PNG, flat-shaded with a headlight, so a generated headform or respirator can be looked at.

Usage: /usr/bin/python3 render_views.py MESH OUT.png [--title TEXT]
Frame: x lateral (+x = subject's left), y up, z out of the face. Front view looks along -z
(the subject's left appears on the image's right), side view looks along -x (face to the right).
"""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "pipeline"))
from read_mesh_or_raise import read_mesh_or_raise  # noqa: E402


def draw(ax, pts, tris, view_dir, right, up, title):
    """Painter's algorithm: project, sort by depth, shade by |n·view|."""
    v = pts[tris]                                    # #F×3×3
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-12)[:, None]
    facing = n @ view_dir                            # > 0: faces the viewer
    keep = facing > 0
    v, n, facing = v[keep], n[keep], facing[keep]
    depth = (v.mean(axis=1) @ view_dir)
    order = np.argsort(depth)
    v, facing = v[order], facing[order]
    xy = np.stack([v @ right, v @ up], axis=-1)      # #F×3×2
    shade = 0.15 + 0.85 * facing
    colors = np.stack([shade * 0.93, shade * 0.80, shade * 0.70, np.ones_like(shade)], axis=1)
    ax.add_collection(PolyCollection(xy, facecolors=colors, edgecolors="none", antialiaseds=False))
    ax.set_xlim(xy[..., 0].min() - 5, xy[..., 0].max() + 5)
    ax.set_ylim(xy[..., 1].min() - 5, xy[..., 1].max() + 5)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.tick_params(labelsize=7)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    try:
        m = read_mesh_or_raise(a.mesh)
    except Exception as e:  # one clear line, non-zero exit
        sys.exit(f"render_views.py: {a.mesh}: cannot read mesh: {e}")
    tris = m.cells_dict.get("triangle")
    if tris is None or len(tris) == 0:
        sys.exit(f"render_views.py: {a.mesh}: no triangles")
    pts = np.asarray(m.points, dtype=float)
    fig, axs = plt.subplots(1, 2, figsize=(8, 4.6), dpi=80)
    draw(axs[0], pts, tris, np.array([0, 0, 1.0]), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]),
         "front (looking at the face) [mm]")
    draw(axs[1], pts, tris, np.array([-1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, 1.0, 0]),
         "side (subject's right, face to the right) [mm]")
    if a.title:
        fig.suptitle(a.title, fontsize=10)
    fig.tight_layout()
    tmp = f"{a.out}.tmp{os.getpid()}"  # renamed when complete, so a failed run leaves no PNG
    try:
        fig.savefig(tmp, format="png")
        os.replace(tmp, a.out)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        sys.exit(f"render_views.py: {a.out}: cannot write the PNG ({e})")


if __name__ == "__main__":
    main()
