"""Makes niosh_medium_landmarks.json, the hand-picked ("user") landmarks of the NIOSH medium
headform in its given frame (y up, face toward +z, x lateral; the STL is symmetric about x = 0
within 1.6 mm mean nearest-point distance of its mirror image).

How the positions were picked: midsagittal points by rule on the vertices with |x| < 2.5 mm
(pronasale = largest z; sellion = smallest z between the pronasale and 60 mm above it; menton =
lowest vertex of the chin front, i.e. with z > sellion z - 30 mm); lateral points by reading
horizontal slices (|x| extent per z at y steps of 10 mm) and choosing the positions by hand
(zygion = widest point of the cheekbone in front of the ear, tragion = front of the ear at
the ear canal level, gonion = angle of the jaw), then snapping each to the nearest vertex.
Run: /usr/bin/python3 make_niosh_medium_landmarks.py <NIOSH_medium_20k.stl> niosh_medium_landmarks.json
(written atomically: the output is replaced only by a complete file; with `> file` the shell had
emptied the committed file before a wrong path made the script fail).
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "pipeline"))
from read_mesh_or_raise import read_mesh_or_raise  # noqa: E402

if len(sys.argv) != 3:
    sys.exit("usage: make_niosh_medium_landmarks.py NIOSH_medium_20k.stl out.json")
src, dst = sys.argv[1], sys.argv[2]
try:
    p = read_mesh_or_raise(src).points.astype(float)
except (OSError, ValueError) as e:
    sys.exit(f"make_niosh_medium_landmarks: {src}: cannot read: {e}")
# The hand-picked points are NIOSH medium's: on another head (NIOSH large was taken, exit 0) they
# would be snapped to whatever vertex lies nearest. Its box is 173.0 x 285.7 x 233.1 mm.
extent = p.max(axis=0) - p.min(axis=0)
if np.abs(extent - [173.0, 285.7, 233.1]).max() > 1.0:
    sys.exit(f"make_niosh_medium_landmarks: {src}: spans {extent.round(1).tolist()} mm, not NIOSH medium's "
             "[173.0, 285.7, 233.1]: these hand-picked landmarks are that head's only")


def snap(q):
    return p[np.argmin(np.linalg.norm(p - np.asarray(q, float), axis=1))]


mid = p[np.abs(p[:, 0]) < 2.5]
prn = mid[np.argmax(mid[:, 2])]
band = mid[(mid[:, 1] > prn[1] + 10) & (mid[:, 1] < prn[1] + 60) & (mid[:, 2] > 0)]
sel = band[np.argmin(band[:, 2])]
chin = mid[mid[:, 2] > sel[2] - 30]
men = chin[np.argmin(chin[:, 1])]
hand = {  # read from slices, then snapped
    "zygion_left": [70, -10, 5], "zygion_right": [-70, -10, 5],
    "tragion_left": [72, -2, -12], "tragion_right": [-72, -2, -12],
    "gonion_left": [57, -75, -5], "gonion_right": [-57, -75, -5],
}
lm = {"sellion": sel, "pronasale": prn, "menton": men}
lm.update({k: snap(v) for k, v in hand.items()})
out = {
    "frame": "x lateral (+x = subject's left), y up, z out of the face; mm",
    "source": "user",
    "landmarks": {k: {"position": [round(float(c), 3) for c in v], "confidence": 1.0} for k, v in lm.items()},
    "measures_mm": {
        "face_length": round(float(np.linalg.norm(men - sel)), 2),
        "face_width": round(float(np.linalg.norm(lm["zygion_left"] - lm["zygion_right"])), 2),
    },
}
tmp = os.path.join(os.path.dirname(os.path.abspath(dst)), f".tmp.{os.getpid()}.{os.path.basename(dst)}")
try:
    with open(tmp, "w") as f:
        f.write(json.dumps(out, indent=2) + "\n")
    os.replace(tmp, dst)
except OSError as e:
    if os.path.exists(tmp):
        os.remove(tmp)
    sys.exit(f"make_niosh_medium_landmarks: {dst}: cannot write: {e.strerror}")
