#pragma once
/// JSON inputs (decks, landmarks, materials, parameters): every stage reads them through these,
/// so a missing, empty or malformed file gives one bad-input line naming it, never an internal
/// error with nlohmann's exception tag.
#include <string>

#include <nlohmann/json.hpp>

namespace pipeline {

/// Parses `text`, which came from `name` (a file path or a description, used in the error).
///
/// @throws Error(bad_input) "name: empty JSON file" or "name: not valid JSON: <where and why>"
///         (nlohmann's message without its "[json.exception.parse_error.101]" tag), or
///         "name: key "a.b" appears twice in one object" (nlohmann would keep the last silently)
nlohmann::json parse_json(const std::string& text, const std::string& name);

/// nlohmann's message without its "[json.exception.type_error.302] " tag, for a user's error line.
std::string json_error_text(const nlohmann::json::exception& e);

/// Reads and parses the JSON file at `path`. @throws Error(bad_input) as read_text and parse_json.
nlohmann::json read_json(const std::string& path);

}  // namespace pipeline
