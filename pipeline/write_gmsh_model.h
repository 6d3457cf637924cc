#pragma once
/// Writing gmsh's current model to a .msh file, atomically and whole. Every stage that writes a
/// .msh (fit, surface_mesh, layers, straps, assemble, solve) writes it through this function.
///
/// Why not gmsh::write inside write_atomic alone: gmsh writes through a C FILE* and does not look
/// at its write errors, so a full disk or a file-size limit left a truncated .msh with exit 0
/// (surface_mesh under `ulimit -f 20`: 20,480 of 50,699 bytes, "done"); and a folder it cannot
/// write in gave "Unable to open file '<dir>/.tmp.<pid>.out.msh'", naming the temporary file and
/// no reason, as an internal error (exit 3).
#include <functional>
#include <string>

namespace pipeline {

/// Writes the model of the open gmsh session (pipeline::GmshSession) to `path` as MSH 4.1 ASCII,
/// physical groups only (Mesh.SaveAll 0), through write_atomic.
///
/// @param[in] path    output .msh
/// @param[in] append  if set, called with the temporary file's path after gmsh has written it, to
///                    append sections of its own (solve's $NodeData frames)
/// @throws Error(io) naming `path`: the folder cannot be written in (with the system's reason), or
///         the file came out incomplete (require_complete_msh); nothing is left at `path` then.
void write_gmsh_model(const std::string& path, const std::function<void(const std::string& tmp_path)>& append = {});

/// Checks that a written .msh file is whole: its `$Name` … `$EndName` sections pair up, it holds
/// $Nodes and $Elements, and it ends with a section's end line.
/// @param[in] file  the file to read
/// @param[in] name  the path to name in the message (the final output, not a temporary one)
/// @throws Error(io) "<name>: written incompletely (20480 bytes, cut inside $Nodes): disk full or a
///         file size limit?"
void require_complete_msh(const std::string& file, const std::string& name);

}  // namespace pipeline
