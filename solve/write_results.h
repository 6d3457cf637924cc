#pragma once
/// Results files of a run: the mesh in gmsh .msh 4.1 and nodal data blocks ($NodeData, one per
/// field and output time), which gmsh shows as views with time steps and meshio/ParaView read.
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "solve/model.h"

namespace solve {

/// Writes the model's parts and named surfaces (triangles), one physical group each, its other
/// node groups (the rim's and the strap ends' nodes) as point groups, and all nodes
/// (the model's gmsh node tags) to `path` as msh 4.1 ASCII, through the gmsh API, atomically and
/// checked whole (pipeline::write_gmsh_model).
/// @param[in] append  if set, called with the temporary file after the mesh is in it, to append
///                    $NodeData blocks (append_node_data) before the file is checked and renamed
/// @throws pipeline::Error(io) if gmsh cannot write or the file comes out incomplete.
void write_mesh_msh(const Model& m, const std::string& path,
                    const std::function<void(const std::string& tmp_path)>& append = {});

/// Appends one $NodeData block: `values` is #nodes×ncomp (ncomp 1 or 3), time [ms], step index.
void append_node_data(std::ostream& out, const Model& m, const std::string& name, double time, int step,
                      const std::vector<double>& values, int ncomp);

/// Components per node of an output field: 3 for "displacement" and "velocity", else 1.
int node_data_components(const std::string& field);

/// The most bytes the $NodeData blocks of one output time can take: every field of
/// m.output.node_data, each value in at most the 17 characters append_node_data gives it
/// (" -1.23456789e-300"). For the room a run's results need before it starts.
double node_data_bytes_max(const Model& m);

}  // namespace solve
