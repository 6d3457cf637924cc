"""Renders an assembled model (assemble's model.msh) front, side and back-oblique, parts coloured,
to a PNG.  Usage: /usr/bin/python3 render_assembled.py model.msh out.png [title]

Hidden surfaces are removed with a per-pixel depth buffer (hand-written, numpy): matplotlib's 3-D
axes sort whole collections (painter's algorithm), which hid the straps - 1.5 mm off the skin -
behind the head in the previous renders, and no z-buffering renderer (VTK, pyvista, gmsh's GUI) is
available headless here. Orthographic views, flat Lambert shading, 0.4 mm pixels."""
import os
import sys

import matplotlib
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "pipeline"))
from read_mesh_or_raise import read_mesh_or_raise  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"forehead": "#e8b27d", "left_cheek": "#d98c6c", "right_cheek": "#c97a5a", "chin": "#b5654a",
          "back_of_head": "#bbbbbb", "respirator_outer": "#3b7dd8", "strap_top": "#1fa84a",
          "strap_bottom": "#b03fd0"}


def surface_triangles(m):
    """(triangles as (n,3,3) points, colour index per triangle) of the groups in COLORS: skin
    surfaces by head part, the respirator's outer surface (outer faces of its outer layer), straps."""
    tris, cols = [], []
    names = list(COLORS)
    for name, blocks in m.cell_sets_dict.items():
        key = name[:-len("_skin_surface")] if name.endswith("_skin_surface") else name
        if key not in COLORS:
            continue
        for ctype, idx in blocks.items():
            cells = m.cells_dict[ctype][idx]
            if ctype == "triangle":
                t = cells
            elif ctype == "quad":
                t = np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
            elif ctype == "wedge":  # top faces of the outer respirator layer: the visible outside
                t = cells[:, [3, 4, 5]]
            else:
                continue
            tris.append(m.points[t])
            cols.append(np.full(len(t), names.index(key)))
    if not tris:
        return np.zeros((0, 3, 3)), np.zeros(0, dtype=int)
    return np.concatenate(tris), np.concatenate(cols)


def render(tris, cols, view_dir, up, px_mm=0.4):
    """Orthographic z-buffer image (RGB floats) looking along -view_dir (view_dir points to the viewer)."""
    d = np.asarray(view_dir, float)
    d /= np.linalg.norm(d)
    right = np.cross(up, d)
    right /= np.linalg.norm(right)
    upv = np.cross(d, right)
    P = np.stack([tris @ right, tris @ upv, tris @ d], axis=-1)  # (n,3,3): screen x, y, depth
    lo = P[..., :2].reshape(-1, 2).min(0) - 5
    hi = P[..., :2].reshape(-1, 2).max(0) + 5
    W, H = (np.ceil((hi - lo) / px_mm)).astype(int) + 1
    depth = np.full((H, W), -np.inf)
    img = np.ones((H, W, 3))
    rgb = np.array([matplotlib.colors.to_rgb(c) for c in COLORS.values()])
    nrm = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-12)
    shade = 0.35 + 0.65 * np.abs(nrm @ d)
    S = (P[..., :2] - lo) / px_mm
    for k in range(len(tris)):
        (x0, y0), (x1, y1), (x2, y2) = S[k]
        den = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
        if abs(den) < 1e-12:
            continue
        xa, xb = int(np.floor(min(x0, x1, x2))), int(np.ceil(max(x0, x1, x2)))
        ya, yb = int(np.floor(min(y0, y1, y2))), int(np.ceil(max(y0, y1, y2)))
        xs, ys = np.meshgrid(np.arange(xa, xb + 1), np.arange(ya, yb + 1))
        l0 = ((y1 - y2) * (xs - x2) + (x2 - x1) * (ys - y2)) / den
        l1 = ((y2 - y0) * (xs - x2) + (x0 - x2) * (ys - y2)) / den
        l2 = 1 - l0 - l1
        inside = (l0 >= -1e-9) & (l1 >= -1e-9) & (l2 >= -1e-9)
        if not inside.any():
            continue
        z = l0 * P[k, 0, 2] + l1 * P[k, 1, 2] + l2 * P[k, 2, 2]
        xi, yi, zi = xs[inside], ys[inside], z[inside]
        closer = zi > depth[yi, xi]
        xi, yi, zi = xi[closer], yi[closer], zi[closer]
        depth[yi, xi] = zi
        img[yi, xi] = rgb[cols[k]] * shade[k]
    return img[::-1]  # image rows run downward


def main():
    if len(sys.argv) not in (3, 4) or not sys.argv[2].lower().endswith(".png"):
        sys.exit("usage: render_assembled.py model.msh out.png [title]")
    try:
        m = read_mesh_or_raise(sys.argv[1])
    except (OSError, ValueError) as e:
        sys.exit(f"render_assembled: {sys.argv[1]}: cannot read: {e}")
    tris, cols = surface_triangles(m)
    if len(tris) == 0:
        sys.exit(f"render_assembled: {sys.argv[1]}: none of the assembled model's groups ({', '.join(COLORS)})")
    views = [("front", (0, 0, 1)), ("side (from the left, face to the left)", (1, 0, 0)),
             ("back-left", (0.8, 0.25, -0.6))]
    fig, axes = plt.subplots(1, 3, figsize=(15, 6.5))
    for ax, (title, v) in zip(axes, views):
        ax.imshow(render(tris, cols, v, np.array([0.0, 1.0, 0.0])), interpolation="antialiased")
        ax.set_title(title)
        ax.axis("off")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in COLORS.values()]
    fig.legend(handles, list(COLORS), loc="lower center", ncol=len(COLORS), fontsize=9)
    if len(sys.argv) > 3:
        fig.suptitle(sys.argv[3])
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    out = sys.argv[2]
    tmp = os.path.join(os.path.dirname(os.path.abspath(out)), f".tmp.{os.getpid()}.{os.path.basename(out)}")
    try:
        fig.savefig(tmp, dpi=100)
        os.replace(tmp, out)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        sys.exit(f"render_assembled: {out}: cannot write: {e.strerror}")


if __name__ == "__main__":
    main()
