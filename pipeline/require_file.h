#pragma once
/// require_file: the checks every reader of a user's file makes before parsing it.
///
/// Input: a path. Returns when it names an existing, non-empty file; otherwise throws
/// pipeline::Error(bad_input) with one line naming it: "no such file", "is a directory, expected
/// a file", "not a regular file (a device, pipe or socket)", "file is empty" or "cannot be read:
/// Permission denied" (the system's reason). A link to a file is the file.
#include <string>

namespace pipeline {

void require_file(const std::string& path);

}  // namespace pipeline
