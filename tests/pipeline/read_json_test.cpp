// pipeline::read_json / parse_json: one bad-input error naming the file, without nlohmann's tag.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "pipeline/error.h"
#include "pipeline/read_json.h"
#include "../bad_input_message.h"
#include "../scratch_dir.h"

namespace {

// The error's kind and message, or an empty message when nothing was thrown.
pipeline::Error error_of(const std::string& path) {
  try {
    pipeline::read_json(path);
  } catch (const pipeline::Error& e) {
    return e;
  }
  return pipeline::Error(pipeline::ErrorKind::algorithm, "");
}

}  // namespace

TEST(read_json, reads_a_document) {
  const auto path = scratch_dir() / "good.json";
  std::ofstream(path) << R"({"gap_mm": 3, "parts": ["chin"]})";
  const nlohmann::json j = pipeline::read_json(path.string());
  EXPECT_EQ(j.at("gap_mm").get<int>(), 3);
  EXPECT_EQ(j.at("parts").at(0).get<std::string>(), "chin");
}

TEST(read_json, missing_empty_and_malformed_files_are_bad_input_naming_the_file) {
  const auto dir = scratch_dir() / "bad";
  std::filesystem::create_directories(dir);
  const std::string missing = (dir / "missing.json").string(), empty = (dir / "empty.json").string(),
                    truncated = (dir / "truncated.json").string();
  std::ofstream(empty) << " \n";
  std::ofstream(truncated) << R"({"a": [1, 2)";
  for (const std::string& path : {missing, empty, truncated}) {
    const pipeline::Error e = error_of(path);
    EXPECT_EQ(e.kind, pipeline::ErrorKind::bad_input) << path;
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
  }
  EXPECT_NE(std::string(error_of(empty).what()).find("empty JSON file"), std::string::npos);
  EXPECT_EQ(std::string(error_of(missing).what()), missing + ": no such file");
  // a folder read as a file gave "empty JSON file"; a 0-byte file is caught before parsing
  EXPECT_EQ(std::string(error_of(dir.string()).what()), dir.string() + ": is a directory, expected a file");
  const std::string zero = (dir / "zero.json").string();
  std::ofstream(zero).close();
  EXPECT_EQ(std::string(error_of(zero).what()), zero + ": file is empty");
  EXPECT_NE(std::string(error_of(truncated).what()).find("not valid JSON: parse error at line 1"), std::string::npos)
      << error_of(truncated).what();
  EXPECT_THROW(pipeline::parse_json("[1,", "deck"), pipeline::Error);
  // a binary file given as a deck: the bytes nlohmann quotes went to the terminal raw
  try {
    pipeline::parse_json(std::string("\x7f" "ELF\x02\x01", 6), "deck");
    ADD_FAILURE() << "no error";
  } catch (const pipeline::Error& e) {
    EXPECT_NE(std::string(e.what()).find("last read: '\\x7f'"), std::string::npos) << e.what();
  }
}

// nlohmann keeps the last of two equal keys silently: a deck's second "end_time" would have won.
TEST(read_json, a_key_repeated_in_one_object_is_refused_by_its_path) {
  const auto message = [](const std::string& text) {
    return bad_input_message([&] { pipeline::parse_json(text, "deck.json"); });
  };
  EXPECT_EQ(message(R"({"end_time": 5, "dt": 1, "end_time": 50})"),
            "deck.json: key \"end_time\" appears twice in one object");
  EXPECT_EQ(message(R"({"contact": {"friction": 0.3, "friction": 0}})"),
            "deck.json: key \"contact.friction\" appears twice in one object");
  EXPECT_EQ(message(R"({"ties": [{"name": "a"}, {"name": "b", "tolerance": 1, "name": "c"}]})"),
            "deck.json: key \"ties[].name\" appears twice in one object");
  EXPECT_EQ(message(R"({"a": [[{"x": 1, "x": 2}]]})"), "deck.json: key \"a[][].x\" appears twice in one object");
  // the same key in different objects, at different depths or in sibling array elements, is fine
  EXPECT_EQ(message(R"({"name": 1, "ties": [{"name": "a"}, {"name": "b"}], "contact": {"name": {"name": 2}}})"),
            "no error");
  const nlohmann::json j = pipeline::parse_json(R"({"a": {"x": 1}, "b": {"x": 2}, "x": [3]})", "deck.json");
  EXPECT_EQ(j.at("b").at("x").get<int>(), 2);
  EXPECT_EQ(j.at("x").at(0).get<int>(), 3);
}
