#!/usr/bin/python3
"""Converts solve's results.msh into an XDMF time series (one step per output time; data in a .h5
beside it) and a .vtu of the last output time, for ParaView. Every cell carries the number of its
physical group as cell data "part"; <out>_parts.csv names them (face parts, tissues, straps, and
the groups of nodes only, the rim and the strap ends, as vertex cells).
Run with /usr/bin/python3 (Debian meshio, numpy).

    /usr/bin/python3 solve/msh_to_vtu.py results.msh results.xdmf

meshio reads the mesh; the $NodeData blocks (one per field and time) are parsed here because
meshio keeps only the last block of each name.
"""
import os
import sys

import meshio
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pipeline"))
from read_mesh_or_raise import read_mesh_or_raise  # noqa: E402


def node_data_blocks(path):
    """Yields (name, time, tags, values) for every $NodeData block of an ASCII msh file."""
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            if line.strip() != "$NodeData":
                continue
            n_str = int(next(lines))
            name = [next(lines).strip().strip('"') for _ in range(n_str)][0]
            n_real = int(next(lines))
            reals = [float(next(lines)) for _ in range(n_real)]
            n_int = int(next(lines))
            ints = [int(next(lines)) for _ in range(n_int)]
            ncomp, n = ints[1], ints[2]
            data = np.loadtxt([next(lines) for _ in range(n)], ndmin=2)
            yield name, reals[0] if reals else 0.0, data[:, 0].astype(np.int64), data[:, 1:1 + ncomp]


CELL_DIM = {"vertex": 0, "triangle": 2, "quad": 2, "tetra": 3, "hexahedron": 3, "wedge": 3}


def part_labels(mesh, keep):
    """The physical group of every kept cell as a number 0..n-1 (cell data "part": ParaView's
    Threshold picks a face part with it; the group names alone do not reach a .vtu), and the
    names in that order. Numbered by (dimension, gmsh tag), as a tag may repeat across dimensions."""
    by_key = {(int(dim), int(tag)): name for name, (tag, dim) in mesh.field_data.items()}
    keys = sorted(by_key)
    number = {k: i for i, k in enumerate(keys)}
    physical = mesh.cell_data.get("gmsh:physical", [])
    labels = []
    for i in keep:
        dim = CELL_DIM[mesh.cells[i].type]
        tags = physical[i] if i < len(physical) else np.full(len(mesh.cells[i].data), -1)
        labels.append(np.array([number.get((dim, int(t)), -1) for t in tags], dtype=np.int32))
    return [by_key[k] for k in keys], labels


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: msh_to_vtu.py results.msh out.xdmf")
    src, dst = sys.argv[1], sys.argv[2]
    # The .vtu of the last frame is named after the output: an output named .vtu was written as
    # XDMF and then replaced by that frame, and the time series was lost (exit 0).
    if not dst.endswith(".xdmf"):
        sys.exit(f"msh_to_vtu: {dst}: the output must be named .xdmf (the last frame goes beside it as .vtu)")
    try:
        mesh = read_mesh_or_raise(src, file_format="gmsh")
    except Exception as e:  # meshio raises many types
        sys.exit(f"msh_to_vtu: {src}: cannot read: {e}")
    # meshio keeps the points in file order; map node tags to rows via the node order of the file
    tags = []
    with open(src) as f:
        lines = iter(f)
        for line in lines:
            if line.strip() == "$Nodes":
                n_blocks = int(next(lines).split()[0])
                for _ in range(n_blocks):
                    _, _, _, n = map(int, next(lines).split())
                    tags += [int(next(lines)) for _ in range(n)]
                    for _ in range(n):
                        next(lines)
                break
    row = {t: i for i, t in enumerate(tags)}
    frames = {}
    for name, time, ntags, values in node_data_blocks(src):
        arr = np.zeros((len(mesh.points), values.shape[1]))
        arr[[row[t] for t in ntags]] = values
        frames.setdefault(time, {})[name] = arr[:, 0] if values.shape[1] == 1 else arr
    keep = [i for i, c in enumerate(mesh.cells) if c.type in CELL_DIM]
    cells = [mesh.cells[i] for i in keep]
    if not frames:
        sys.exit(f"msh_to_vtu: {src}: no $NodeData blocks")
    part_names, part_of_cells = part_labels(mesh, keep)
    # meshio's TimeSeriesWriter puts its .h5 in the working directory, named after the xdmf stem:
    # write in the destination directory under temporary names, then rename (no half files).
    dst = os.path.abspath(dst)
    ddir, base = os.path.split(dst)
    stem = os.path.splitext(base)[0]
    cwd = os.getcwd()
    try:
        os.makedirs(ddir, exist_ok=True)  # as the C++ stages do
        os.chdir(ddir)
    except OSError as e:
        sys.exit(f"msh_to_vtu: {dst}: cannot write in {ddir}: {e.strerror}")
    try:
        with meshio.xdmf.TimeSeriesWriter(stem + ".tmp.xdmf") as w:
            w.write_points_cells(mesh.points, cells)
            for t in sorted(frames):
                w.write_data(t, point_data=frames[t], cell_data={"part": part_of_cells})
        os.replace(stem + ".tmp.h5", stem + ".h5")
        with open(stem + ".tmp.xdmf") as f:
            text = f.read().replace(stem + ".tmp.h5", stem + ".h5")
        with open(stem + ".tmp.xdmf", "w") as f:
            f.write(text)
        os.replace(stem + ".tmp.xdmf", base)
    finally:
        os.chdir(cwd)
    last = frames[max(frames)]
    vtu = os.path.splitext(dst)[0] + ".vtu"
    vtu_tmp = vtu + ".tmp.vtu"
    meshio.write(vtu_tmp, meshio.Mesh(mesh.points, cells, point_data=last, cell_data={"part": part_of_cells}))
    os.replace(vtu_tmp, vtu)
    legend = os.path.splitext(dst)[0] + "_parts.csv"
    with open(legend + ".tmp", "w") as f:
        f.write("part,name\n" + "".join(f"{i},{n}\n" for i, n in enumerate(part_names)))
    os.replace(legend + ".tmp", legend)
    print(f"msh_to_vtu: {len(frames)} time steps -> {dst}, last -> {vtu}, cell data \"part\" named in {legend}",
          file=sys.stderr)


if __name__ == "__main__":
    main()
