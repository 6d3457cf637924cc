#pragma once
/// The check, before any work, that a remeshing's target edge fits the machine: an edge far below
/// the surface's scale asks for more triangles than memory and patience hold (repair --edge 0.001
/// on NIOSH medium ran until killed; fit --edge 0.3 and surface_mesh --size 0.5 ran for minutes
/// past 1 GB). Shared by repair, fit and surface_mesh.
#include <string>

#include "pipeline/surface_mesh.h"

namespace pipeline {

/// How many equilateral triangles of edge `edge_mm` (sqrt(3)/4 e² each) cover `area_mm2`: the
/// estimate the check below and surface_mesh's retry budget hold a remeshing to.
double triangles_for_edge(double area_mm2, double edge_mm);

/// Refuses `edge_mm` if equilateral triangles of that edge (sqrt(3)/4 e² each) would cover
/// `surface` more than `max_triangles` times.
/// @param[in] option  the command-line option, for the message ("--edge")
/// @throws Error(usage) "--edge 0.001 mm would make ~4e+11 triangles on this 167890 mm2 surface,
///         more than 10 million: choose a longer edge"
void require_affordable_edge(const std::string& option, double edge_mm, const SurfaceMesh& surface,
                             double max_triangles);

}  // namespace pipeline
