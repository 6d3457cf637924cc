#pragma once
/// Surface reconstruction: a scanned point cloud [mm] becomes a triangle mesh.
///
/// Steps: (1) grid simplification, (2) outlier removal (CGAL::remove_outliers' test on the mean
/// distance to the k nearest points, then on the 4 nearest: isolated points), (3) jet smoothing,
/// dropping points the jet moves far (spikes), (4) normals by jet fitting and minimum-spanning-
/// tree orientation that does not cross thin parts (internal/orient_normals.h) when the cloud
/// has none, then the points of thin parts smoothed again over their own side
/// (internal/refit_on_own_side.h), (5) one CGAL reconstruction:
///   - poisson          screened-free Poisson (CGAL::poisson_surface_reconstruction_delaunay):
///                      closed, smooth, fills scan holes; the default for heads;
///   - advancing_front  interpolating advancing front on the smoothed points: keeps open
///                      boundaries; the default for respirators;
///   - scale_space      CGAL scale-space: 4 weighted-PCA smoothings, an advancing front on
///                      the smoothed points, its triangles put back on the unsmoothed ones.
/// (6) Poisson only: the faces it made where the scan has no points are cut out (repair fills
/// those holes with fairing), then every output vertex is moved onto a local quadric of its
/// nearest unsmoothed points whose normals agree with it (Poisson rounds ear rims and the nose by
/// 1-3 mm; the jet smoothing rounds creases already), and faces that move made cross are cut out
/// and refilled (internal/project_onto_points.h).
/// The defaults come from measurements on noisy NIOSH headform scans; see README.md. Respirator
/// scans of the whole cup (a thin closed shell, wall ~1.5 mm, no normals): the two sides are
/// separated before normal orientation and only the inner side (toward the face) is kept and
/// smoothed (step 4 then replaces step 3); the result is an open sheet whose border is the rim.
#include <cstddef>
#include <string>
#include <vector>

#include "pipeline/surface_mesh.h"
#include "scan2cad/scan_kind.h"

namespace scan2cad {

enum class ReconstructMethod { poisson, advancing_front, scale_space };

/// Parses "poisson", "advancing_front", "scale_space" or "auto" (→ default for `kind`).
/// @throws pipeline::Error(usage) otherwise.
ReconstructMethod parse_reconstruct_method(const std::string& name, ScanKind kind);
std::string reconstruct_method_name(ReconstructMethod m);

struct ReconstructOptions {
  ReconstructMethod method = ReconstructMethod::poisson;
  /// neighbours for spacing, outliers, normals and smoothing; default 24, range 6–200
  int neighbors = 24;
  /// a point is an outlier when its mean distance to its k neighbours exceeds this many times
  /// the cloud's mean k-NN spacing, or the same on its 4 nearest neighbours; default 3, range > 1
  double outlier_factor = 3.0;
  /// grid simplification cell [mm] applied before reconstruction (0 = none); dense scans are
  /// thinned to this spacing, which bounds time and memory; default 0.8 mm
  double simplify_cell_mm = 0.8;
  /// density cap (0 = none): a scan of more points is cut, before everything else, to a seeded
  /// random subset of this many (a scan of the same surface at a lower density), so the cost of
  /// the k-NN steps and Poisson no longer grows with the scanner's density. Default 250,000:
  /// above the acceptance scans (200,000 surface points + 1 % outliers), whose accuracy is
  /// measured (tests/scan2cad/head_acceptance_test.cpp) and which it leaves untouched.
  /// Not applied to thin-shell respirator scans (both sides of the wall must stay resolved).
  std::size_t density_reference_points = 250000;
  /// Poisson: relative residual at which the conjugate-gradient solve stops (CGAL's default is
  /// Eigen's, machine epsilon: CG iterates far below what the contouring can use); default 1e-6
  double poisson_solver_tolerance = 1e-6;
  /// grid cell [mm] applied again after jet smoothing, when the points lie on the surface
  /// (0 = none); bounds the cost of normals and Poisson by the surface area. Default 0 (off):
  /// at 0.8 mm it thinned the NIOSH large ears away (acceptance test, 200k points: p95
  /// 0.315 mm, Hausdorff 8.6 mm at the ear); it speeds up 1M-point scans (see README.md)
  double denoised_cell_mm = 0;
  /// grid cell [mm] of the points given to Poisson, applied after the normals (0 = all points);
  /// the hole cut and the projection still use all denoised points. Default 1 mm: 1M-point
  /// NIOSH medium scan, Poisson 24.6 + 16.4 s CPU -> 9.1 + 8.2 s, p95 0.176 -> 0.180 mm
  /// (scan2cad/README.md, "Poisson on a thinned copy")
  double poisson_cell_mm = 1.0;
  /// Poisson: the points of thin parts (those with the other side among their k nearest, found
  /// by the own-side refit) all go to Poisson, only the others are thinned to poisson_cell_mm.
  /// Default on: the top of NIOSH large's ear fin (~1.5 mm across) is 1.08 mm from the projected
  /// surface with the fin thinned too, 0.57 mm with it kept (README.md, session 14). No effect
  /// without the refit
  bool poisson_keep_thin_parts = true;
  /// Poisson contouring accuracy: largest distance of a facet to the implicit surface [mm];
  /// default 0.05, range > 0
  double poisson_distance_mm = 0.05;
  /// Poisson: move each output vertex onto a local quadric of the denoised points whose normals
  /// agree with it (internal/project_onto_points.h); 0 = off, else the largest move [mm]
  /// (a larger one is an extrapolation and the vertex stays). Default 3 mm
  double projection_max_move_mm = 3.0;
  /// Poisson with projection: the points projected onto are the unsmoothed ones (outliers and
  /// spikes removed, before jet smoothing), each with its denoised point's oriented normal, and
  /// the quadric takes projection_neighbors of them; false: the denoised (jet-smoothed) points
  /// and `neighbors`, as until 2026-12-03. Default true: acceptance scans, Hausdorff / p95 [mm],
  /// NIOSH large 1.823 / 0.188 -> 1.505 / 0.170, generated medium 0.943 / 0.168 -> 0.874 / 0.153
  /// (scan2cad/README.md, session 18). Off with denoised_cell_mm > 0
  bool projection_onto_unsmoothed = true;
  /// neighbours of the projection's quadric on the unsmoothed points; default 64 (32: p95
  /// 0.198-0.212 mm, the noise shows through; 96: NIOSH large's ear flap rounded), range 6-200
  int projection_neighbors = 64;
  /// Poisson with projection: rounds of internal::untangle_crossings after it (faces the projection
  /// made cross are cut out, each gap filled with a faired patch that is projected again); 0 =
  /// none, the crossings are left to repair, which fills them flat. Default 3
  int untangle_rounds = 3;
  /// Poisson: faces with a vertex farther than this many point spacings from every denoised
  /// point (Poisson's fill of a scan hole) are cut out, so repair fills the hole with fairing
  /// that continues the surface around it; 0 = keep Poisson's fill. Default 2
  double hole_cut_spacings = 2.0;
  /// normal orientation: extra cost of a link of the minimum spanning tree that runs along the
  /// normals instead of within the tangent planes, so the tree does not cross thin parts (ear
  /// ridges) to the other side (internal/orient_normals.h); 0 = CGAL's weights. Default 2: NIOSH
  /// large at 150,000 / 300,000 points, repair failed / 9.9 mm with 0, 3.4 / 2.4 mm with 2
  /// (1 gave 3.7 / 2.7, 4 gave 3.5 / 2.3; scan2cad/README.md)
  double orientation_crossing_weight = 2.0;
  /// once the normals are oriented, the points with the other side of a thin part among their
  /// k nearest (an ear's ridge) are smoothed again from their unsmoothed positions, and get
  /// new normals, over their own side's neighbours only (n_i . n_j > refit_min_cos), so the two
  /// sides no longer pull each other flat (internal/refit_on_own_side.h). Off when
  /// denoised_cell_mm > 0. Acceptance scans: NIOSH large 3.15 -> 2.23 mm, NIOSH medium 3.96 ->
  /// 3.79 mm, the generated heads the same bytes (no point has the other side in reach)
  bool refit_on_own_side = true;
  /// default 0.5 (60 deg); 0.3 and 0.7 were no better on the five NIOSH scans of
  /// scan2cad/README.md ("Thin parts smoothed over their own side")
  double refit_min_cos = 0.5;
  /// advancing front: longest edge of a facet, in multiples of the point spacing (longer
  /// facets are vetoed and left as holes for repair); default 5, range > 1
  double max_edge_spacings = 5.0;
  /// [mm], 0 = no check: points that span less than this once the outliers are removed are
  /// refused as an object of another kind. The CLI sets it to 0.6 of the kind's size when it
  /// detected the unit (pipeline::smallest_real_share_of_extent): the unit's own check sees the
  /// outliers too, which made a cup scan given as a head 159 mm across instead of 112.
  double min_extent_mm = 0;
  /// [mm], 0 = no check: nor more than this (the CLI: 1.6 of the kind's size when it detected the
  /// unit, pipeline::largest_real_share_of_extent): a head given as a respirator
  double max_extent_mm = 0;
  /// [mm], 0 = no check: a head's points farther apart than this (the mean spacing to 6
  /// neighbours, outliers removed) are refused. Default 2: at 2.5 mm (a 20,000-point scan of
  /// NIOSH medium) the reconstruction loses the ears, ~1 mm thick folds, and landmarks puts the
  /// tragia 40 mm off, on the temple, with nothing to say so (sweep O); at 1.6 mm (50,000 points)
  /// an ear lost is warned about by landmarks, at 1.2 mm (100,000) the landmarks are within
  /// 1.8 mm. Not applied to respirators.
  double max_head_spacing_mm = 2.0;
  /// the points of a table or turntable the object stood on are removed after the outliers
  /// (remove_support_plane.h); false keeps them
  bool remove_support = true;
};

/// What reconstruct did, for the log and the tests.
struct ReconstructStats {
  std::size_t input_points = 0, outliers_removed = 0, points_used = 0;
  bool normals_estimated = false;
  double spacing_mm = 0;  ///< mean k-NN spacing of the points used [mm]
  /// respirator scans without normals: both sides of a thin wall were found and separated
  /// before normal orientation (see reconstruct.cpp, orient_thin_shell); wall_mm = median
  /// distance between the two sides [mm]
  bool thin_shell = false;
  double wall_mm = 0;
  std::size_t outer_side_points = 0;  ///< thin shell: points of the outer side, left out
  std::size_t vertices = 0, faces = 0;
  /// Poisson output vertices moved onto the points, left in place (no support: scan holes),
  /// and the mean and largest move [mm]
  std::size_t projected_vertices = 0, unprojected_vertices = 0;
  /// Poisson faces cut out where the scan has no points (ReconstructOptions::hole_cut_spacings)
  std::size_t faces_cut = 0;
  double projection_mean_mm = 0, projection_max_mm = 0;
  /// points of the table or turntable the object stood on, removed (remove_support_plane.h)
  std::size_t support_points_removed = 0;
  /// points left after step 1 (density cap and grid)
  std::size_t points_after_thinning = 0;
  /// wall and process-CPU seconds of each step, in order (the CPU time counts all threads of
  /// the process, so it is only the step's own when nothing else runs in the process)
  struct StepTime {
    std::string step;
    double wall_s = 0, cpu_s = 0;
  };
  std::vector<StepTime> step_times;
};

/// Reconstructs a triangle mesh from `cloud`.
///
/// @param[in]  cloud  #P points [mm], normals optional (unit, any orientation is re-checked)
/// @param[in]  kind   head or respirator (orientation check for closed heads)
/// @param[in]  opt    ReconstructOptions
/// @param[out] stats  optional
/// @return a triangle mesh [mm], outward-oriented (Poisson: oriented before its hole fills are cut)
/// @throws pipeline::Error(bad_input) when the cloud has fewer than 100 points (after outlier
///         removal) — too few to define a surface —, spans less than opt.min_extent_mm or more than opt.max_extent_mm, lies on
///         a plane or a line, or fills a volume; Error(algorithm) when CGAL fails.
pipeline::SurfaceMesh reconstruct(const pipeline::PointCloud& cloud, ScanKind kind,
                                  const ReconstructOptions& opt, ReconstructStats* stats = nullptr);

}  // namespace scan2cad
