// Test helper: the NIOSH medium headform STL of the shared data as a merged ASCII PLY (meshio
// merges the STL's per-triangle vertices), as a previous pipeline stage writes a head.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "file_text.h"

/// Writes <dir>/medium.ply (dir created if needed) with /usr/bin/python3 + meshio.
/// @return the path
/// @throws std::runtime_error with python's stderr if the conversion failed (gtest fails the
///         test there, rather than let it go on with no file)
inline std::string niosh_medium_ply(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "medium.ply").string(), log = (dir / "medium.ply.log").string();
  const std::string cmd = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + SHARED_DATA_DIR +
                          "/headforms/NIOSH_medium_20k.stl'); meshio.write('" + path +
                          "', meshio.Mesh(m.points.astype(float), m.cells), binary=False)\" 2>" + log;
  if (std::system(cmd.c_str()) != 0) {
    throw std::runtime_error("converting NIOSH_medium_20k.stl to " + path + " failed: " + file_text(log));
  }
  return path;
}
