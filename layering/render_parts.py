#!/usr/bin/python3
"""Renders a segmented mesh (PLY with an int face property "part", as `segment` writes it) in a
front (+z), a side (+x, the subject's left) and a close-up face view, parts coloured, to a PNG.

  /usr/bin/python3 layering/render_parts.py segmented.ply out.png [title]

A plain PLY reader is used because meshio cannot read binary PLY files with extra face
properties. A file that cannot be read gives one line naming it, a non-zero exit and no PNG.
"""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

NAMES = ["back_of_head", "forehead", "left_cheek", "right_cheek", "chin"]
COLOURS = ["#bbbbbb", "#e6a23c", "#409eff", "#67c23a", "#c45cd6"]
TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4",
         "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1", "int16": "i2", "uint16": "u2",
         "int32": "i4", "uint32": "u4", "float32": "f4", "float64": "f8"}


def scalar_reader(fmt, body):
    """A function that reads the next value of a PLY type name from the body, in the file's format."""
    if fmt == "ascii":
        tokens = iter(body.split())

        def read_ascii(type_name):
            token = next(tokens)
            return float(token) if TYPES[type_name][0] == "f" else int(token)
        return read_ascii
    if fmt not in ("binary_little_endian", "binary_big_endian"):
        raise ValueError(f"unknown PLY format '{fmt}'")
    end = "<" if fmt == "binary_little_endian" else ">"
    pos = 0

    def read_binary(type_name):
        nonlocal pos
        t = np.dtype(end + TYPES[type_name])
        if pos + t.itemsize > len(body):
            raise ValueError("truncated: the file ends before its last element")
        value = np.frombuffer(body, t, 1, pos)[0].item()
        pos += t.itemsize
        return value
    return read_binary


def read_ply(path):
    """Vertices (n, 3), faces (lists of vertex indices) and each face's part."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError("not a PLY file (no 'ply' on the first line)")
        header = []
        while True:
            line = f.readline()
            if not line:
                raise ValueError("the header has no end_header")
            header.append(line.decode("ascii", "replace").strip())
            if header[-1] == "end_header":
                break
        body = f.read()
    fmt, elements = None, []
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property" and elements:
            elements[-1][2].append(w[1:])
    read = scalar_reader(fmt, body)
    out = {}
    try:
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if p[0] == "list":
                        n = read(p[1])
                        row[p[-1]] = [read(p[2]) for _ in range(n)]
                    else:
                        row[p[-1]] = read(p[0])
                rows.append(row)
            out[name] = rows
    except StopIteration:
        raise ValueError("truncated: the file ends before its last element") from None
    if not out.get("vertex") or not out.get("face"):
        raise ValueError("no vertices or no faces")
    pts = np.array([[r["x"], r["y"], r["z"]] for r in out["vertex"]], float)
    if not np.isfinite(pts).all():
        raise ValueError("a vertex coordinate is not a finite number")
    faces = [r["vertex_indices"] for r in out["face"]]
    if any(len(f) < 3 or min(f) < 0 or max(f) >= len(pts) for f in faces):
        raise ValueError("a face has fewer than 3 vertices or a vertex index out of range")
    # A mesh without the property (reconstruct's, repair's) was drawn grey as back_of_head, exit 0.
    if "part" not in out["face"][0]:
        raise ValueError("its faces have no 'part' property: not segment's output")
    part = np.array([int(r["part"]) for r in out["face"]])
    return pts, faces, part


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("segmented", help="PLY with a face property 'part' (ascii or binary)")
    ap.add_argument("out", help="PNG to write")
    ap.add_argument("title", nargs="?", help="title over the three views")
    args = ap.parse_args()
    try:
        pts, faces, part = read_ply(args.segmented)
    except (OSError, ValueError, KeyError, IndexError) as e:  # one line naming the file, as every stage does
        sys.exit(f"render_parts: {args.segmented}: cannot read a segmented PLY ({e})")
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
    if args.title:
        fig.suptitle(args.title)
    # Written beside the target and renamed, so a failed run leaves no PNG.
    tmp = f"{args.out}.tmp{os.getpid()}"
    try:
        fig.savefig(tmp, format="png", dpi=90, bbox_inches="tight")
        os.replace(tmp, args.out)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        sys.exit(f"render_parts: {args.out}: cannot write the PNG ({e})")
    print(f"render_parts: {args.out}: {len(pts)} vertices, {len(faces)} faces, parts {sorted(set(part.tolist()))}")


if __name__ == "__main__":
    main()
