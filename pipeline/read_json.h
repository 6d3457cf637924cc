#pragma once
/// JSON inputs (decks, landmarks, materials, parameters): every stage reads them through these,
/// so a missing, empty or malformed file gives one bad-input line naming it, never an internal
/// error with nlohmann's exception tag.
#include <set>
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

/// The first key of `object` that is not in `known` and does not start with "_" (a comment), or ""
/// when there is none (or `object` is not an object). For inputs whose optional keys have
/// defaults: a misspelt one ("frction") would otherwise be read as absent, without a word.
std::string first_unknown_key(const nlohmann::json& object, const std::set<std::string>& known);

}  // namespace pipeline
