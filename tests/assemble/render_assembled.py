"""Renders an assembled model (assemble's model.msh) front and side, parts coloured, to a PNG.
Usage: /usr/bin/python3 render_assembled.py model.msh out.png"""
import sys
import meshio
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

m = meshio.read(sys.argv[1])
colors = {"forehead": "#e8b27d", "left_cheek": "#d98c6c", "right_cheek": "#c97a5a", "chin": "#b5654a",
          "back_of_head": "#bbbbbb", "respirator_inner": "#3b7dd8", "strap_top": "#2a9d4b", "strap_bottom": "#8e44ad"}
polys = []
for name, blocks in m.cell_sets_dict.items():
    key = name[:-len("_skin_surface")] if name.endswith("_skin_surface") else name
    if key not in colors:
        continue
    for ctype, idx in blocks.items():
        cells = m.cells_dict[ctype][idx]
        polys.append((m.points[cells], colors[key], name))
fig = plt.figure(figsize=(12, 6))
for k, (elev, azim, title) in enumerate([(0, 0, "front (+z toward viewer)"), (0, 90, "side (face to the left)")]):
    ax = fig.add_subplot(1, 2, k + 1, projection="3d")
    for verts, col, name in polys:
        ax.add_collection3d(Poly3DCollection(verts, facecolor=col, edgecolor="k", linewidths=0.05,
                                             alpha=0.55 if name == "respirator_inner" else 1.0))
    ax.set_xlim(-110, 110); ax.set_ylim(-170, 130); ax.set_zlim(-120, 180)
    ax.view_init(elev=elev, azim=azim, vertical_axis="y") if "vertical_axis" in ax.view_init.__code__.co_varnames \
        else ax.view_init(elev=elev, azim=azim)
    ax.set_box_aspect((220, 300, 300))
    ax.set_title(title); ax.set_xlabel("x"); ax.set_ylabel("y"); ax.set_zlabel("z")
handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colors.values()]
fig.legend(handles, list(colors.keys()), loc="lower center", ncol=8, fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
