"""One line per layers_report.json (as written by `layers --report`): the checks of issue 4.
Usage: python3 summarize_layers_reports.py <label>=<layers_report.json> ...
Columns: wedges, shell triangles, min scaled Jacobian, min wedge volume [mm3], intersecting face
pairs, thinned columns, and per part x layer the range of volume / (mid-depth offset area x t) - 1,
of volume / (skin area x t) - 1, and of the same ratio over full-depth triangles only; then, per
head, the range of volume / (mid-depth offset area x t) - 1 over each part's layers."""
import json
import sys

if len(sys.argv) < 2 or any("=" not in a for a in sys.argv[1:]):
    sys.exit("usage: summarize_layers_reports.py LABEL=layers_report.json ...")
print("%-20s %6s %6s %6s %5s %5s %5s  %-15s %-15s %-13s" % ("surface", "wedges", "shells", "minSJ", "minV", "cross", "thin",
                                                          "V/(mid-A t)-1", "V/(skin-A t)-1", "full-depth"))
for arg in sys.argv[1:]:
    label, path = arg.split("=", 1)
    try:
        with open(path) as f:
            d = json.load(f)
        v = d["volumes"]
        if not v:
            raise ValueError("no volumes")
    except (OSError, ValueError, KeyError, TypeError) as e:  # one line, not a traceback
        sys.exit(f"summarize_layers_reports: {path}: not a layers report ({type(e).__name__}: {e})")
    mid = [x["volume_mm3"] / x["mid_area_x_thickness_mm3"] - 1 for x in v]
    skin = [x["volume_mm3"] / x["skin_area_x_thickness_mm3"] - 1 for x in v]
    full = [x["full_depth_volume_mm3"] / x["full_depth_mid_area_x_thickness_mm3"] - 1 for x in v]
    beyond = [x["group"] for x, m in zip(v, mid) if abs(m) > 0.05]
    print("%-20s %6d %6d %6.3f %5.2f %5d %5d  %+5.1f..%+5.1f %%  %+5.1f..%+5.1f %%  %+4.1f..%+4.1f %%  beyond 5 %%: %s" % (
        label, d["wedges"], d["shell_triangles"], d["min_scaled_jacobian"], d["min_volume_mm3"],
        d["intersecting_face_pairs"], d["reduced_columns"], 100 * min(mid), 100 * max(mid), 100 * min(skin),
        100 * max(skin), 100 * min(full), 100 * max(full), ", ".join(beyond) or "none"))
    parts = {}
    for x, m in zip(v, mid):
        part = x["group"].rsplit("_", 1)[0]
        parts.setdefault(part, []).append(m)
    print("%-20s per part V/(mid-A t)-1: %s" % ("", ", ".join(
        "%s %+.1f..%+.1f %%" % (p, 100 * min(m), 100 * max(m)) for p, m in parts.items())))
