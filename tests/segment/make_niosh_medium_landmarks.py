"""Makes niosh_medium_landmarks.json, the hand-picked ("user") landmarks of the NIOSH medium
headform in its given frame (y up, face toward +z, x lateral; the STL is symmetric about x = 0
within 1.6 mm mean nearest-point distance of its mirror image).

How the positions were picked: midsagittal points by rule on the vertices with |x| < 2.5 mm
(pronasale = largest z; sellion = smallest z between the pronasale and 60 mm above it; menton =
lowest vertex of the chin front, i.e. with z > sellion z - 30 mm); lateral points by reading
horizontal slices (|x| extent per z at y steps of 10 mm) and choosing the positions by hand
(zygion = widest point of the cheekbone in front of the ear, tragion = front of the ear at
the ear canal level, gonion = angle of the jaw), then snapping each to the nearest vertex.
Run: /usr/bin/python3 make_niosh_medium_landmarks.py <NIOSH_medium_20k.stl> > niosh_medium_landmarks.json
"""
import json
import sys

import meshio
import numpy as np

p = meshio.read(sys.argv[1]).points.astype(float)


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
print(json.dumps(out, indent=2))
