#pragma once
/// Loading a model: a gmsh mesh with named physical groups plus the JSON deck of solve/README.md.
#include <array>
#include <string>

#include "solve/model.h"

namespace solve {

/// Reads the mesh and applies the deck.
/// @param msh_path   gmsh .msh (2.x or 4.x, ASCII or binary; MSH 1 refused: pipeline/read_msh.h) with named physical groups
/// @param deck_path  JSON deck (format: solve/README.md)
/// @return the checked model (check_model passed)
/// @throws pipeline::Error(bad_input) with one line naming the file and the problem (missing,
///         unreadable, no physical groups, unsupported element in a part, bad deck key, ...).
Model load_model(const std::string& msh_path, const std::string& deck_path);

/// Reads only the mesh: nodes, node groups of every named physical group, surfaces (triangles of
/// 2D groups, quads split in two; boundary faces, outward, of 3D groups) and the elements of each
/// group (kept in Model::parts with material = -1 until a deck assigns one).
/// Uses the gmsh C++ API (gmsh::open, model::getPhysicalGroups, getEntitiesForPhysicalGroup,
/// mesh::getNodes/getElements): it reads every .msh version, ASCII or binary, which a hand-written
/// reader would have to re-implement.
Model read_msh(const std::string& msh_path);

/// Applies a deck (JSON text) to a mesh-only model (from read_msh or make_block: parts present
/// in the model but not in the deck are dropped; a deck part must name a group with elements).
/// `deck_name` is used in messages. Ends with check_model. @throws pipeline::Error(bad_input).
void apply_deck(Model& m, const std::string& deck_json, const std::string& deck_name);

/// The model's bounding box [mm]: lowest x, y, z, then highest. A deck's "model_check" holds it
/// (with the node count) for the model it was made for, and apply_deck refuses another model.
std::array<double, 6> model_bounds_mm(const Model& m);

}  // namespace solve
