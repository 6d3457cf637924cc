#pragma once
/// read_msh: the nodes and named physical groups of a gmsh .msh file, read with the gmsh API.
///
/// Input:  path of a .msh file, 2.x or 4.x, ASCII or binary, starting with $MeshFormat (or
///         $Comments); gmsh's older MSH 1 ($NOD) is refused.
/// Output: MshFile: every node once, in increasing tag order (not gmsh's entity order, which can
///         change between runs: read_msh.cpp), with its file tag and coordinates; every physical
///         group in gmsh's order with its elements, one block per entity and element type, as
///         0-based indices into the nodes.
/// Throws pipeline::Error(bad_input) naming the file when it is missing, a directory, empty, does
/// not start with $MeshFormat (gmsh would run it as a .geo script), is unreadable by gmsh, has no
/// nodes, or has a node with a NaN or infinite coordinate or an element on a node it lacks; and,
/// in an ASCII file (what the stages and gmsh write), when a section is not closed (gmsh skips
/// the rest of the file silently), a physical group is named twice or one name is given to two
/// groups of one dimension (gmsh keeps one name a group, stages find groups by name; gmsh and
/// meshio write neither, in binary files either), or, in 2.x and 4.1, a block count its section
/// cannot hold or an element tag that is not a positive integer, one element a line (libgmsh
/// aborts or crashes on these). Whether groups must exist, be named or hold one element type is
/// the caller's rule.
///
/// Shared by layering (read_fe_model) and solve (read_msh): gmsh reads every .msh version,
/// which a hand-written reader would have to re-implement, and one reader checks the nodes once.
#include <cstddef>
#include <string>
#include <vector>

namespace pipeline {

/// Elements of one gmsh element type (2 triangle, 3 quadrangle, 4 tetrahedron, 5 hexahedron,
/// 6 wedge, ...) from one entity of a group.
struct MshElements {
  int gmsh_type = 0;
  int nodes_per_element = 0;
  std::vector<int> conn;  ///< #elements × nodes_per_element, 0-based indices into MshFile's nodes
};

struct MshGroup {
  int dim = 0;       ///< 0 points, 1 lines, 2 surfaces, 3 volumes
  int tag = 0;       ///< the physical group's tag
  std::string name;  ///< its name; empty when the file gives none
  std::vector<MshElements> elements;
};

struct MshFile {
  std::vector<std::size_t> node_tags;  ///< the file's tag of each node
  std::vector<double> xyz;             ///< 3 finite coordinates per node
  std::vector<MshGroup> groups;
  std::size_t n_nodes() const { return node_tags.size(); }
};

MshFile read_msh(const std::string& path);

}  // namespace pipeline
