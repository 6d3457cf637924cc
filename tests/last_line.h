// Test helper: the last line of a program's stderr, where the stages put their one error line
// (after the options and progress lines).
//
//   last_line(text)       the last non-empty line of `text`, without its newline
//   last_line_of(path)    the same for the file at `path` ("" if it cannot be read)
#pragma once

#include <filesystem>
#include <string>

#include "file_text.h"

inline std::string last_line(const std::string& text) {
  const std::string trimmed = text.substr(0, text.find_last_not_of('\n') + 1);
  return trimmed.substr(trimmed.find_last_of('\n') + 1);
}

inline std::string last_line_of(const std::filesystem::path& path) { return last_line(file_text(path)); }
