#pragma once
/// Helper of build_part_model (internal): the curves and points gmsh's createTopology made between
/// the parts, numbered and directed by node tags instead of by memory address.

namespace scan2cad::internal {

/// Rebuilds the CURRENT gmsh model (discrete entities with their nodes and elements, no physical
/// groups yet, no parametrization) so that nothing in it depends on where gmsh's objects lie in
/// memory:
///   - points are numbered by their node's tag, curves by the node tags on them in increasing
///     order, compared as words (the smallest first; curves meeting at a corner share it);
///   - a curve runs from its end point of smaller node tag, its lines in that order; a closed one
///     has its point moved to its smallest node (unless another curve ends there too) and runs
///     from it toward the smaller of that node's two neighbours;
///   - a surface lists its boundary curves in tag order, each signed + when it runs along the
///     surface's triangles;
///   - every entity lists its nodes in tag order. Surfaces keep their tags; element tags stay.
/// Why: gmsh 4.8's createTopology sorts by pointer, so the heap layout chose these, and the same
/// fitted head meshed from a relative and from an absolute path gave two different surface.msh
/// files. gmsh 4.8's API cannot renumber an entity in place (no setTag), hence the rebuild.
void number_topology_by_node_tags();

}  // namespace scan2cad::internal
