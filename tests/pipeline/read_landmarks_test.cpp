// pipeline::read_landmarks, the one reader of landmarks files (landmarks --user, segment, straps,
// assemble): each way a file can be wrong gives one bad-input line naming the file and the landmark.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "../bad_input_message.h"
#include "../scratch_dir.h"
#include "pipeline/atomic_write.h"
#include "pipeline/read_landmarks.h"

namespace {

// The nine landmarks of a head, left ones at x = 60, right ones at x = -60, the midline at x = 0.
nlohmann::json nine_landmarks() {
  nlohmann::json j;
  j["source"] = "user";
  for (const auto& name : pipeline::head_landmark_names()) {
    const double x = name.find("_left") != std::string::npos ? 60 : name.find("_right") != std::string::npos ? -60 : 0;
    j["landmarks"][name] = {{"position", {x, 10.0, 80.0}}, {"confidence", 0.8}};
  }
  return j;
}

// The message read_landmarks gives for `j` written to a file, after the file's name.
std::string message_for(const nlohmann::json& j, const std::string& name = "edited.json") {
  const std::string path = (scratch_dir() / name).string();
  pipeline::write_text_atomic(path, j.dump(2));
  return bad_input_message([&] { pipeline::read_landmarks(path, pipeline::head_landmark_names()); }, path);
}

}  // namespace

TEST(read_landmarks, reads_positions_and_confidences_and_keeps_extra_landmarks) {
  nlohmann::json j = nine_landmarks();
  j["landmarks"]["subnasale"] = {{"position", {0.0, -5.0, 95.5}}};  // no confidence: 1
  j["landmarks"]["menton"]["position"] = {0.5, -110.25, 70.0};
  const std::string path = (scratch_dir() / "good.json").string();
  pipeline::write_text_atomic(path, j.dump());
  const auto lm = pipeline::read_landmarks(path, pipeline::head_landmark_names());
  ASSERT_EQ(lm.size(), 10u);
  EXPECT_EQ(lm.at("menton").position, Eigen::Vector3d(0.5, -110.25, 70.0));
  EXPECT_EQ(lm.at("menton").confidence, 0.8);
  EXPECT_EQ(lm.at("subnasale").confidence, 1.0);
  EXPECT_EQ(lm.at("zygion_right").position.x(), -60.0);
}

TEST(read_landmarks, names_the_file_and_the_landmark_for_each_problem) {
  EXPECT_EQ(message_for(nine_landmarks()), "no error");
  EXPECT_EQ(message_for(nlohmann::json::array({1, 2})), "no \"landmarks\" object");
  EXPECT_EQ(message_for({{"landmarks", {1, 2}}}), "no \"landmarks\" object");
  auto with = [](const std::string& name, const std::string& key, const nlohmann::json& value) {
    nlohmann::json j = nine_landmarks();
    j["landmarks"][name][key] = value;
    return j;
  };
  EXPECT_EQ(message_for(with("menton", "position", {1, 2})), "landmark menton: \"position\" is not [x, y, z]");
  EXPECT_EQ(message_for(with("menton", "position", "0 0 0")), "landmark menton: \"position\" is not [x, y, z]");
  EXPECT_EQ(message_for(with("menton", "position", {1, "x", 3})), "landmark menton: a coordinate is not a finite number");
  EXPECT_EQ(message_for(with("menton", "position", {1, nullptr, 3})),
            "landmark menton: a coordinate is not a finite number");
  // JSON has no NaN, and a number too large for a double is refused by the parser, naming it
  const std::string huge = (scratch_dir() / "huge.json").string();
  std::string text = with("menton", "position", {1, 2, 12345}).dump();
  pipeline::write_text_atomic(huge, text.replace(text.find("12345"), 5, "1e999"));
  EXPECT_EQ(bad_input_message([&] { pipeline::read_landmarks(huge, {}); }, huge),
            "not valid JSON: number overflow parsing '1e999'");
  EXPECT_EQ(message_for(with("sellion", "confidence", "high")),
            "landmark sellion: confidence \"high\", expected a number 0..1");
  EXPECT_EQ(message_for(with("sellion", "confidence", nullptr)),
            "landmark sellion: confidence null, expected a number 0..1");
  EXPECT_EQ(message_for(with("sellion", "confidence", 1.5)), "landmark sellion: confidence 1.5, expected 0..1");
  nlohmann::json missing = nine_landmarks();
  missing["landmarks"].erase("pronasale");
  EXPECT_EQ(message_for(missing), "landmark pronasale missing");
}

// +x is the subject's left in align's frame; a mirrored head (or a scan not aligned) puts the
// left landmarks at x < 0, and segment, straps and assemble would build the other side's parts.
TEST(read_landmarks, refuses_a_left_landmark_on_the_right_and_the_reverse) {
  nlohmann::json j = nine_landmarks();
  j["landmarks"]["zygion_left"]["position"][0] = -60;
  EXPECT_EQ(message_for(j), "landmark zygion_left: x = -60, expected > 0 (the subject's left is +x): "
                            "is the head mirrored, or not aligned?");
  j = nine_landmarks();
  j["landmarks"]["gonion_right"]["position"][0] = 0;
  EXPECT_EQ(message_for(j), "landmark gonion_right: x = 0, expected < 0 (the subject's right is -x): "
                            "is the head mirrored, or not aligned?");
  // an extra sided landmark is held to the same rule
  j = nine_landmarks();
  j["landmarks"]["cheilion_left"] = {{"position", {-20.0, -60.0, 90.0}}};
  EXPECT_EQ(message_for(j).rfind("landmark cheilion_left: x = -20, expected > 0", 0), 0u);
}

// Only the names the caller asks for are required: straps and assemble need sellion and menton.
TEST(read_landmarks, requires_only_the_names_asked_for) {
  nlohmann::json j;
  j["landmarks"]["sellion"] = {{"position", {0.0, 0.0, 90.0}}};
  j["landmarks"]["menton"] = {{"position", {0.0, -115.0, 75.0}}};
  const std::string path = (scratch_dir() / "two.json").string();
  pipeline::write_text_atomic(path, j.dump());
  EXPECT_EQ(pipeline::read_landmarks(path, {"sellion", "menton"}).size(), 2u);
  EXPECT_EQ(bad_input_message([&] { pipeline::read_landmarks(path, pipeline::head_landmark_names()); }, path),
            "landmark pronasale missing");  // the first missing in head_landmark_names' order
}
