#!/usr/bin/python3
"""Where is the jaw angle on an aligned head? An analysis aid for the gonion detector, not a test.

Usage: jaw_lower_border.py aligned.ply landmarks.json [picture.png]

Seen from the subject's left (rays along -x on a 0.5 mm (y, z) grid, the grid the lateral
landmarks use), the head is a depth map x(y, z). The lower border of the mandible is where the
vertical profile x(y) at a fixed z bends most sharply (its most negative curvature), and the jaw
angle (gonion) would be the back end of that border where it turns up into the ramus. For every
column z between the tragion and the menton this prints the height of the strongest bend and its
curvature [1/mm], after a Gaussian smoothing of the depth map (sigma 3 mm). Compare the
curvature with the ear's (~0.1/mm) and look at how far the border jumps between neighbouring
columns: a corner detector built on it is only as stable as that line.
"""
import json
import sys

import meshio
import numpy as np
from scipy import ndimage

STEP_MM, SIGMA_MM = 0.5, 3.0


def depth_map(points, triangles, z_range, y_range):
    """Max x of the surface over a (y, z) grid: the first hit of rays cast along -x."""
    zs = np.arange(*z_range, STEP_MM)
    ys = np.arange(*y_range, STEP_MM)
    depth = np.full((len(ys), len(zs)), np.nan)
    for tri in triangles:
        p = points[tri]
        if p[:, 0].max() < 10.0:  # the right side and the midline
            continue
        iz = np.arange(max(0, int(np.ceil((p[:, 2].min() - z_range[0]) / STEP_MM))),
                       min(len(zs) - 1, int(np.floor((p[:, 2].max() - z_range[0]) / STEP_MM))) + 1)
        iy = np.arange(max(0, int(np.ceil((p[:, 1].min() - y_range[0]) / STEP_MM))),
                       min(len(ys) - 1, int(np.floor((p[:, 1].max() - y_range[0]) / STEP_MM))) + 1)
        if len(iz) == 0 or len(iy) == 0:
            continue
        a = np.array([[p[1, 2] - p[0, 2], p[2, 2] - p[0, 2]], [p[1, 1] - p[0, 1], p[2, 1] - p[0, 1]]])
        if abs(np.linalg.det(a)) < 1e-12:
            continue
        gz, gy = np.meshgrid(zs[iz], ys[iy])
        u, v = np.linalg.inv(a) @ np.vstack([(gz - p[0, 2]).ravel(), (gy - p[0, 1]).ravel()])
        inside = (u >= 0) & (v >= 0) & (u + v <= 1)
        x = p[0, 0] + u * (p[1, 0] - p[0, 0]) + v * (p[2, 0] - p[0, 0])
        cells = depth[np.ix_(iy, iz)].ravel()
        better = inside & (np.isnan(cells) | (x > cells))
        cells[better] = x[better]
        depth[np.ix_(iy, iz)] = cells.reshape(len(iy), len(iz))
    return ys, zs, depth


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    mesh = meshio.read(sys.argv[1])
    marks = {k: np.array(v["position"]) for k, v in json.load(open(sys.argv[2]))["landmarks"].items()}
    tragion, menton, gonion = marks["tragion_left"], marks["menton"], marks["gonion_left"]
    ys, zs, depth = depth_map(mesh.points, mesh.cells_dict["triangle"], (tragion[2] - 60, menton[2] + 40),
                              (menton[1] - 30, tragion[1] + 15))
    known = ~np.isnan(depth)
    s = SIGMA_MM / STEP_MM
    weight = ndimage.gaussian_filter(known.astype(float), s)
    smooth = ndimage.gaussian_filter(np.where(known, depth, 0.0), s) / np.maximum(weight, 1e-9)
    smooth[weight < 0.5] = np.nan
    dy = np.gradient(smooth, STEP_MM, axis=0)
    curvature = np.gradient(dy, STEP_MM, axis=0) / (1 + dy**2) ** 1.5  # of the profile x(y)
    rows = (ys > menton[1]) & (ys < gonion[1] - 3)  # below the ear lobe (the detected gonion is 5 mm under it)
    border = []
    for j, z in enumerate(zs):
        if z < tragion[2] - 15 or z > menton[2] - 15 or np.all(np.isnan(curvature[rows, j])):
            continue
        k = np.nanargmin(curvature[rows, j])
        border.append((z, ys[rows][k], curvature[rows, j][k]))
    border = np.array(border)
    print("left side; gonion detected at y %.1f z %.1f; tragion y %.1f z %.1f; menton y %.1f z %.1f"
          % (gonion[1], gonion[2], tragion[1], tragion[2], menton[1], menton[2]))
    print("column z [mm]  lower border y [mm]  curvature [1/mm]")
    for z, y, k in border[::10]:
        print("%12.1f  %19.1f  %16.3f" % (z, y, k))
    jumps = np.abs(np.diff(border[:, 1]))
    print("largest jump of the border between neighbouring 0.5 mm columns: %.1f mm" % jumps.max())
    if len(sys.argv) > 3:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 8))
        ax.imshow(np.nan_to_num(dy), origin="lower", extent=[zs[0], zs[-1], ys[0], ys[-1]], cmap="gray",
                  vmin=-2, vmax=2)
        ax.scatter(border[:, 0], border[:, 1], c=border[:, 2], s=4, cmap="jet")
        for name in ("tragion_left", "gonion_left", "zygion_left", "menton"):
            ax.plot(marks[name][2], marks[name][1], "r+", ms=14, mew=2)
            ax.annotate(name, (marks[name][2], marks[name][1]), color="r")
        ax.set_xlabel("z [mm]")
        ax.set_ylabel("y [mm]")
        fig.savefig(sys.argv[3], dpi=80)


if __name__ == "__main__":
    main()
