#include "pipeline/read_json.h"

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"

namespace pipeline {

nlohmann::json parse_json(const std::string& text, const std::string& name) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw bad_input(name, "empty JSON file");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(name, "not valid JSON: " + json_error_text(e));
  }
}

std::string json_error_text(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  const auto tag_end = what.find("] ");
  return tag_end == std::string::npos ? what : what.substr(tag_end + 2);
}

nlohmann::json read_json(const std::string& path) { return parse_json(read_text(path), path); }

}  // namespace pipeline
