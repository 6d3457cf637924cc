"""Renders a segmented mesh (PLY with int face property "part", as written by `segment`) in
front (+z) and side (+x, subject's left) views, parts coloured, to a PNG.

Usage: /usr/bin/python3 layering/render_parts.py segmented.ply out.png [title]
A plain PLY parser is used because meshio cannot read binary PLY files with extra face
properties.
"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

NAMES = ["back_of_head", "forehead", "left_cheek", "right_cheek", "chin"]
COLOURS = ["#bbbbbb", "#e6a23c", "#409eff", "#67c23a", "#c45cd6"]
TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4",
         "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1", "int32": "i4", "uint32": "u4",
         "float32": "f4", "float64": "f8"}


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        body = f.read()
    fmt = [l.split()[1] for l in header if l.startswith("format")][0]
    elements, cur = [], None
    for l in header:
        w = l.split()
        if w[0] == "element":
            cur = [w[1], int(w[2]), []]
            elements.append(cur)
        elif w[0] == "property":
            cur[2].append(w[1:])
    end = "<" if fmt == "binary_little_endian" else ">"
    out, pos = {}, 0
    if fmt == "ascii":
        tokens = body.split()
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if p[0] == "list":
                        n = int(tokens[pos]); pos += 1
                        row[p[-1]] = [float(t) for t in tokens[pos:pos + n]]; pos += n
                    else:
                        row[p[-1]] = float(tokens[pos]); pos += 1
                rows.append(row)
            out[name] = rows
    else:
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if p[0] == "list":
                        ct, it = np.dtype(end + TYPES[p[1]]), np.dtype(end + TYPES[p[2]])
                        n = int(np.frombuffer(body, ct, 1, pos)[0]); pos += ct.itemsize
                        row[p[-1]] = np.frombuffer(body, it, n, pos).tolist(); pos += n * it.itemsize
                    else:
                        t = np.dtype(end + TYPES[p[0]])
                        row[p[-1]] = np.frombuffer(body, t, 1, pos)[0]; pos += t.itemsize
                rows.append(row)
            out[name] = rows
    pts = np.array([[r["x"], r["y"], r["z"]] for r in out["vertex"]], float)
    faces = [r["vertex_indices"] for r in out["face"]]
    part = np.array([int(r.get("part", 0)) for r in out["face"]])
    return pts, faces, part


def main():
    pts, faces, part = read_ply(sys.argv[1])
    tris = np.array([pts[f[:3]] for f in faces])
    fig = plt.figure(figsize=(15, 6))
    # Matplotlib 3D: view from +z (front), +x (subject's left side) and a view framing the face
    # parts from the front-left and a little below (shows the nose's sides and the cheek-nose
    # fold, where the forehead part meets the cheeks); y up.
    views = [(0, 0, "front (+z)", False), (0, 90, "left side (+x)", False),
             (-15, 35, "face (front-left, from below)", True)]
    for k, (elev, azim, label, close_up) in enumerate(views):
        ax = fig.add_subplot(1, 3, k + 1, projection="3d")
        # Plot with matplotlib axes (X=z, Y=x, Z=y) so that elev/azim give the wanted views.
        poly = tris[:, :, [2, 0, 1]]
        n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        n /= np.linalg.norm(n, axis=1, keepdims=True) + 1e-12
        # Direction toward the viewer in the head frame (matplotlib X=z, Y=x, Z=y).
        e, a = np.radians(elev), np.radians(azim)
        view = np.array([np.cos(e) * np.sin(a), np.sin(e), np.cos(e) * np.cos(a)])
        shade = 0.35 + 0.65 * np.clip(n @ view, 0, 1)
        base = np.array([matplotlib.colors.to_rgb(COLOURS[p % 5]) for p in part])
        col = base * shade[:, None]
        coll = Poly3DCollection(poly, facecolors=col, edgecolors="none")
        ax.add_collection3d(coll)
        shown = pts
        if close_up and (part > 0).any():
            shown = tris[part > 0].reshape(-1, 3)
        lo, hi = shown.min(0), shown.max(0)
        c, r = (lo + hi) / 2, (hi - lo).max() / 2
        ax.set_xlim(c[2] - r, c[2] + r); ax.set_ylim(c[0] - r, c[0] + r); ax.set_zlim(c[1] - r, c[1] + r)
        ax.view_init(elev=elev, azim=azim)
        ax.set_proj_type("ortho")
        ax.set_box_aspect((1, 1, 1), zoom=1.0 if close_up else 1.5)
        ax.set_axis_off()
        ax.set_title(label)
    handles = [plt.Rectangle((0, 0), 1, 1, color=COLOURS[i]) for i in range(5)]
    fig.legend(handles, NAMES, loc="lower center", ncol=5)
    if len(sys.argv) > 3:
        fig.suptitle(sys.argv[3])
    fig.savefig(sys.argv[2], dpi=90, bbox_inches="tight")


if __name__ == "__main__":
    main()
