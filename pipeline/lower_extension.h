#pragma once
/// lower_extension: a path's extension as the stages compare it, lower case with the dot
/// ("scan.PLY" -> ".ply", "a/b" -> ""). Readers, writers and require_extension all go through it,
/// so an ending one accepts is an ending the others handle.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace pipeline {

inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace pipeline
