// require_file: see require_file.h.
#include "pipeline/require_file.h"

#include <filesystem>

#include "pipeline/error.h"

namespace pipeline {

void require_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw bad_input(path, "no such file");
  if (fs::is_directory(path, ec)) throw bad_input(path, "is a directory, expected a file");
  // /dev/zero was read until memory ran out, and a pipe with no writer blocked the stage.
  if (!fs::is_regular_file(path, ec)) throw bad_input(path, "not a regular file (a device, pipe or socket)");
  if (fs::file_size(path, ec) == 0) throw bad_input(path, "file is empty");
}

}  // namespace pipeline
