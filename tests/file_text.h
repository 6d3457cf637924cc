// Test helper: the whole content of a file, to check a program's output or its stderr log.
//
//   file_text(path)   the file's bytes ("" if it cannot be read)
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

inline std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
