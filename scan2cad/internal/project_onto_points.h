#pragma once
/// Internal to scan2cad/reconstruct: moving a Poisson mesh onto the denoised points it was made
/// from, and untangling the crossings that move makes at thin parts.
///
/// Poisson approximates: its implicit function is smooth over a few point spacings, so thin or
/// sharply curved features (ear rims, the nostrils, under the nose tip) come out rounded by
/// 1-3 mm although the denoised points lie on them. project_onto_points moves mesh vertices
/// along their normals onto a local quadric of the points whose oriented normals agree with
/// theirs (an MLS-style projection; CGAL projects a point set onto its own jets, not one set
/// onto another). Where Poisson had rounded off a part thinner than two point spacings (an
/// ear's fin), the two sides, each moved onto its own points, can pass through each other;
/// untangle_crossings cuts those faces out, fills each gap with a faired patch and projects the
/// patch again, so the fin keeps the height the projection gave it (repair would cut the
/// crossing faces out and fill the gap flat).
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

/// k-d tree over points [mm] (CGAL's spatial search), for the steps after Poisson that look at
/// the points near each mesh vertex.
class PointTree {
  using TraitsBase = CGAL::Search_traits_3<pipeline::Kernel>;
  using PointPmap = CGAL::Pointer_property_map<pipeline::Point>::type;
  using Traits = CGAL::Search_traits_adapter<std::size_t, PointPmap, TraitsBase>;

 public:
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  /// the points of `pn` (normals ignored); the tree keeps its own copy
  explicit PointTree(const std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn);
  /// the k nearest points of p, nearest first (first: point index, second: squared distance)
  Search nearest(const pipeline::Point& p, unsigned k) const {
    return Search(*tree_, p, k, 0, true, Search::Distance(ppmap_));
  }
  const pipeline::Point& point(std::size_t i) const { return pts_[i]; }

 private:
  std::vector<pipeline::Point> pts_;
  PointPmap ppmap_;
  std::unique_ptr<Search::Tree> tree_;
};

/// +1 when the points' oriented normals point out of the mesh like its vertex normals, else -1
/// (an MST orientation is consistent but may be globally inward): a vote of every vertex with
/// its nearest point.
double point_normal_sign(const pipeline::SurfaceMesh& mesh,
                         const std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn, const PointTree& tree);

struct ProjectionStats {
  std::size_t vertices = 0, moved = 0, unsupported = 0;
  double mean_move_mm = 0, max_move_mm = 0;  ///< over the moved vertices [mm]
};

/// Moves `vertices` of `mesh`, all at once (fits on the unmoved mesh), each along its vertex
/// normal onto the weighted least-squares quadric (height over its tangent plane, Gaussian
/// weights) of its k nearest points whose oriented normal n_j satisfies sign · n_j · n_v ≥ 0.5
/// (within 60 deg: the other side of a thin part is left out).
///
/// @param[in,out] mesh      triangle mesh [mm]
/// @param[in]     vertices  the vertices to move
/// @param[in]     sign      point_normal_sign(mesh, pn, tree)
/// @param[in]     pn, tree  oriented denoised points [mm] and their tree
/// @param[in]     k         neighbours looked at (≥ 6)
/// @param[in]     spacing_mm   mean point spacing [mm]: a vertex whose nearest agreeing point is
///                farther than 2 spacings (a scan hole) stays
/// @param[in]     max_move_mm  a vertex whose move would exceed this stays (the fit extrapolates)
ProjectionStats project_onto_points(pipeline::SurfaceMesh& mesh, const std::vector<pipeline::VertexIndex>& vertices,
                                    double sign, const std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn,
                                    const PointTree& tree, unsigned k, double spacing_mm, double max_move_mm);

struct UntangleStats {
  int rounds = 0;                    ///< rounds that cut something
  std::size_t faces_cut = 0;         ///< crossing faces and their one-rings, over all rounds
  std::size_t piece_faces_removed = 0;  ///< faces of pieces the cuts severed (removed with them)
  std::size_t gaps_filled = 0;       ///< gaps filled with a faired patch
  std::size_t vertices_projected = 0;  ///< patch vertices moved onto the points
  std::size_t crossing_left = 0;     ///< faces still crossing another at the end (repair cuts them)
};

/// Cuts out the faces that cross another face and their one-rings (the largest component is
/// kept), fills each gap the cut made with fill_hole (faired, ~spacing_mm edges) and projects
/// the patch's inner vertices with project_onto_points; repeated while faces cross, at most
/// `max_rounds` times. A gap that reaches a border the mesh had before the round (a scan hole
/// left open for repair) is left open with it.
///
/// @param[in,out] mesh  triangle mesh [mm], consistently oriented
/// @param[in]     sign, pn, tree, k, spacing_mm, max_move_mm  as for project_onto_points
/// @param[in]     max_rounds  ≥ 0 (0: nothing is done but the final count)
UntangleStats untangle_crossings(pipeline::SurfaceMesh& mesh, double sign,
                                 const std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn,
                                 const PointTree& tree, unsigned k, double spacing_mm, double max_move_mm,
                                 int max_rounds);

}  // namespace scan2cad::internal
