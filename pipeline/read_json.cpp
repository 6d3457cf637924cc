#include "pipeline/read_json.h"

#include <cstdio>
#include <functional>
#include <set>
#include <vector>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"

namespace pipeline {

namespace {

// nlohmann keeps the last of two equal keys in one object without a word, so a deck with a second
// "end_time" further down would run with it and the first one read by the user would be ignored.
// JSON (RFC 8259) leaves such a file's meaning open; we refuse it, naming the key by its path.
class RepeatedKeyCheck {
 public:
  explicit RepeatedKeyCheck(const std::string& name) : name_(name) {}

  bool operator()(int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        // an element of an array has no key of its own: it is named "<array>[]"
        containers_.push_back({event == E::object_start, in_array() ? path_of("[]") : path_of(pending_key_), {}});
        pending_key_.clear();
        break;
      case E::key: {
        const std::string key = parsed.get<std::string>();
        if (!containers_.back().keys.insert(key).second)
          throw bad_input(name_, "key \"" + path_of(key) + "\" appears twice in one object");
        pending_key_ = key;
        break;
      }
      case E::object_end:
      case E::array_end:
        containers_.pop_back();
        pending_key_.clear();
        break;
      case E::value:
        pending_key_.clear();
        break;
    }
    return true;
  }

 private:
  struct Container {
    bool is_object;
    std::string path;  // dotted keys from the top, e.g. "contacts[].friction"
    std::set<std::string> keys;
  };

  bool in_array() const { return !containers_.empty() && !containers_.back().is_object; }
  std::string path_of(const std::string& key) const {
    const std::string parent = containers_.empty() ? "" : containers_.back().path;
    if (key == "[]") return parent + key;
    return parent.empty() ? key : parent + "." + key;
  }

  const std::string& name_;
  std::vector<Container> containers_;
  std::string pending_key_;
};

}  // namespace

nlohmann::json parse_json(const std::string& text, const std::string& name) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw bad_input(name, "empty JSON file");
  try {
    RepeatedKeyCheck check(name);
    return nlohmann::json::parse(text, std::ref(check));
  } catch (const nlohmann::json::exception& e) {
    // Python's json.dump writes NaN and Infinity, which JSON has not: the parser's own message
    // ("invalid literal; last read: '...N'") did not say so (sweep J).
    const bool non_finite = text.find("NaN") != std::string::npos || text.find("Infinity") != std::string::npos;
    throw bad_input(name, "not valid JSON: " + json_error_text(e) +
                              (non_finite ? " (NaN and Infinity are not JSON numbers: write finite numbers)" : ""));
  }
}

std::string json_error_text(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  const auto tag_end = what.find("] ");
  // nlohmann quotes the bytes it read last: those of a binary file given as a deck went to the
  // terminal raw. Bytes outside printable ASCII are shown as \xNN.
  std::string text;
  for (const char c : tag_end == std::string::npos ? what : what.substr(tag_end + 2)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      text += c;
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      text += hex;
    }
  }
  return text;
}

nlohmann::json read_json(const std::string& path) { return parse_json(read_text(path), path); }

std::string first_unknown_key(const nlohmann::json& object, const std::set<std::string>& known) {
  if (!object.is_object()) return "";
  for (const auto& item : object.items())
    if (!known.count(item.key()) && item.key().rfind("_", 0) != 0) return item.key();
  return "";
}

}  // namespace pipeline
