#pragma once
/// Internals of build_layers: node columns (offset direction, depth scale, levels), their
/// detection-and-fix loop, and the element-face soup used by the intersection test.
#include <Eigen/Core>

#include <array>
#include <map>
#include <string>
#include <vector>

#include "layering/layers.h"
#include "pipeline/progress.h"

namespace layering::internal {

using Tri = std::array<int, 3>;

struct PartTris {
  std::string name;
  std::vector<Tri> tris;
  Stack stack;  ///< empty for rigid shells
};

struct Input {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<PartTris> parts, shells;
  bool respirator = false;
};

/// One column per skin node: node(i, k) = nodes[i] + scale[i] · levels[k] · dir[i].
struct Columns {
  std::vector<int> skin;                  ///< skin node ids (nodes of layered parts)
  std::vector<Eigen::Vector3d> dir;       ///< by node id: unit offset direction (0 off the skin)
  std::vector<double> scale;              ///< by node id: depth scale in (0, 1]
  std::vector<int> max_level;             ///< by node id: deepest level any incident part needs
  std::vector<double> levels;             ///< common depth partition [mm], levels[0] = 0
  std::map<std::string, std::vector<int>> tissue_of_level;  ///< part → tissue index of level k→k+1
  int smoothing_passes = 0;               ///< Laplacian passes the directions got (from smoothing_mm)
  Eigen::Vector3d position(const std::vector<Eigen::Vector3d>& x, int i, int k) const {
    return x[i] + scale[i] * levels[k] * dir[i];
  }
  std::size_t reduced_columns() const;
  double min_scale() const;
};

/// Skin-edge neighbours of each node (over every layered part's triangles), sorted.
std::vector<std::vector<int>> skin_neighbours(const Input& in);

/// Largest depth slope between neighbouring columns [mm of depth per mm along the skin] after a
/// column was thinned. 0.6 (31°): the old limit, 0.15 of the scale per edge, was 0.39-0.42 for the
/// cheeks' 18 mm at 6.4-7 mm edges and spread each thinned spot over ~4 edges (~28 mm) of every
/// part, the forehead's 7 mm columns under the nose included, costing the shortwide head's left
/// cheek 5.1 % of its volume (6.4 mm surface). 0.8 keeps a little more volume but the deep wedges
/// at the taper reach min scaled Jacobian 0.204 (large head), too close to 0.2.
inline constexpr double kMaxDepthSlope = 0.6;

/// Lowers column scales until, along every skin edge (i, j), the depths of the two columns at the
/// deepest level both use, min(D_i, D_j) with D = levels[max_level], differ by at most
/// kMaxDepthSlope × the edge length: a thinned spot tapers off over the same width in mm at any
/// mesh size, and a shallow neighbour (a 7 mm forehead column beside an 18 mm cheek column) is
/// dragged down less than a deep one, whose deep wedges the same scale jump would shear more.
/// `nbr`: skin-edge neighbours of each node; `x`: skin node positions.
void limit_depth_gradient(const std::vector<std::vector<int>>& nbr, const std::vector<Eigen::Vector3d>& x,
                          Columns& c);

/// Orients every triangle so its normal points away from the offset side (head: away from the
/// centroid; respirator: toward −z, the face), then computes directions, levels and ray caps.
Columns make_columns(Input& in, const LayerOptions& opt);

/// Detect-and-fix loop: scales column depths down (and pulls directions toward the face normal)
/// around every wedge below the quality threshold or whose faces intersect another element.
/// Its last pass is the layers' intersection check: it tests every element face of the model
/// build_layers then writes (the same nodes, wedges and shells).
/// @return the intersecting face pairs left, all between shell triangles (rigid parts, which no
///         column moves: a self-intersecting surface); 0 on a clean model
/// @throws Error(bad_input) for a skin triangle that is itself too distorted;
///         Error(algorithm) if not clean after opt.max_fix_iterations passes.
std::size_t fix_columns(const Input& in, const LayerOptions& opt, Columns& c, pipeline::Progress* progress);

/// Deduplicated triangles of every element face of `m` (wedge triangles, wedge and shell quads split
/// along the diagonal through their smallest node id, shell triangles); owner[t] = (block, element).
void element_faces(const FeModel& m, std::vector<Tri>* tris, std::vector<std::pair<int, int>>* owner);

}  // namespace layering::internal
