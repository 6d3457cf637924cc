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

// The nine landmarks of a head, left ones at x = 60, right ones at x = -60, the midline at x = 0;
// sellion at y = 40, pronasale at 0, menton at -70, the gonia at -40, the others at 10.
nlohmann::json nine_landmarks() {
  nlohmann::json j;
  j["source"] = "user";
  for (const auto& name : pipeline::head_landmark_names()) {
    const double x = name.find("_left") != std::string::npos ? 60 : name.find("_right") != std::string::npos ? -60 : 0;
    const double y = name == "sellion"                  ? 40
                     : name == "pronasale"              ? 0
                     : name == "menton"                 ? -70
                     : name.rfind("gonion", 0) == 0     ? -40
                                                        : 10;
    j["landmarks"][name] = {{"position", {x, y, 80.0}}, {"confidence", 0.8}};
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
  // one of the stages' names in another case is a slip, not a landmark of the user's own
  j["landmarks"]["Sellion"] = j["landmarks"]["sellion"];
  EXPECT_EQ(message_for(j), "landmark \"Sellion\": the name is \"sellion\" (lower case)");
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
  // 1e308 is a double, and crashed the surface check's exact predicates (a floating-point trap)
  EXPECT_EQ(message_for(with("menton", "position", {1e308, -77, 74})),
            "landmark menton: coordinate 1e+308 is beyond +-10000 mm (not a point on a head in mm)");
  EXPECT_EQ(message_for(with("menton", "position", {0, -77, -20000})),
            "landmark menton: coordinate -20000 is beyond +-10000 mm (not a point on a head in mm)");
  EXPECT_EQ(message_for(with("sellion", "confidence", "high")),
            "landmark sellion: confidence \"high\", expected a number 0..1");
  EXPECT_EQ(message_for(with("sellion", "confidence", nullptr)),
            "landmark sellion: confidence null, expected a number 0..1");
  EXPECT_EQ(message_for(with("sellion", "confidence", 1.5)), "landmark sellion: confidence 1.5, expected 0..1");
  // a misspelt confidence was read as absent, as 1; a comment key is allowed
  EXPECT_EQ(message_for(with("sellion", "confidnce", 0.2)),
            "landmark sellion: unknown key \"confidnce\" (a landmark has \"position\" and \"confidence\")");
  EXPECT_EQ(message_for(with("sellion", "_note", "moved by hand")), "no error");
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

// The profile's order in y: swapped by hand, or a head upside down, went through landmarks --user,
// straps and assemble; only segment refused it.
TEST(read_landmarks, refuses_a_profile_out_of_order_in_y) {
  auto with_y = [](const std::string& name, double y) {
    nlohmann::json j = nine_landmarks();
    j["landmarks"][name]["position"][1] = y;
    return j;
  };
  EXPECT_EQ(message_for(with_y("menton", 10.5)),
            "menton y 10.5 not at least 30 mm below sellion y 40: is the head aligned (y up)?");
  nlohmann::json swapped = nine_landmarks();
  std::swap(swapped["landmarks"]["sellion"], swapped["landmarks"]["menton"]);
  EXPECT_EQ(message_for(swapped), "menton y 40 not at least 30 mm below sellion y -70: is the head aligned (y up)?");
  EXPECT_EQ(message_for(with_y("pronasale", 45)), "pronasale y 45 not between menton and sellion: are the landmarks swapped?");
  EXPECT_EQ(message_for(with_y("pronasale", -80)), "pronasale y -80 not between menton and sellion: are the landmarks swapped?");
  // a side's tragion and gonion swapped by hand (segment cut cheeks 30 % smaller, exit 0)
  nlohmann::json ear_and_jaw = nine_landmarks();
  std::swap(ear_and_jaw["landmarks"]["tragion_left"], ear_and_jaw["landmarks"]["gonion_left"]);
  EXPECT_EQ(message_for(ear_and_jaw), "gonion_left y 10 not at least 20 mm below tragion_left y -40: are the landmarks swapped?");
  EXPECT_EQ(message_for(with_y("gonion_right", -5)),
            "gonion_right y -5 not at least 20 mm below tragion_right y 10: are the landmarks swapped?");
  // only what the file has is compared (straps and assemble need only sellion and menton)
  nlohmann::json two;
  two["landmarks"]["sellion"] = {{"position", {0, 40, 80}}};
  two["landmarks"]["menton"] = {{"position", {0, -70, 80}}};
  const std::string path = (scratch_dir() / "two.json").string();
  pipeline::write_text_atomic(path, two.dump());
  EXPECT_EQ(bad_input_message([&] { pipeline::read_landmarks(path, {"sellion", "menton"}); }, path), "no error");
}

// A file in cm or m had been reported as a head not aligned, and a menton 25 mm to the side was
// taken and put the respirator 12 mm off centre (sweep J).
TEST(read_landmarks, a_file_in_cm_or_m_and_a_midline_point_to_the_side_are_named) {
  auto scaled = [](double f) {
    nlohmann::json j = nine_landmarks();
    for (auto& [name, l] : j["landmarks"].items())
      for (auto& c : l["position"]) c = c.get<double>() * f;
    return j;
  };
  EXPECT_EQ(message_for(scaled(0.1)), "sellion and menton are 11 apart, and no face is under 30 mm: landmarks in cm? "
                                      "(positions are in mm, in align's frame)");
  EXPECT_EQ(message_for(scaled(0.001)).rfind("sellion and menton are 0.11 apart, and no face is under 30 mm: landmarks in m?", 0), 0u);
  nlohmann::json side = nine_landmarks();
  side["landmarks"]["menton"]["position"][0] = 25.0;
  EXPECT_EQ(message_for(side), "landmark menton: x = 25, expected within 10 mm of the symmetry plane x = 0: is the head "
                               "aligned, or the point picked off the midline?");
  side["landmarks"]["menton"]["position"][0] = -25.0;  // to the subject's right: the same (only +x was tried: sweep L)
  EXPECT_EQ(message_for(side), "landmark menton: x = -25, expected within 10 mm of the symmetry plane x = 0: is the head "
                               "aligned, or the point picked off the midline?");
  side["landmarks"]["menton"]["position"][0] = -9.5;  // a real face's asymmetry
  EXPECT_EQ(message_for(side), "no error");
}

// A capitalised key was reported as a missing position, and NaN (which Python's json.dump writes)
// with the parser's message alone (sweep J).
TEST(read_landmarks, a_capitalised_key_and_nan_are_named) {
  nlohmann::json j = nine_landmarks();
  j["landmarks"]["sellion"]["Position"] = j["landmarks"]["sellion"]["position"];
  j["landmarks"]["sellion"].erase("position");
  EXPECT_EQ(message_for(j), "landmark sellion: unknown key \"Position\" (a landmark has \"position\" and \"confidence\")");
  const std::string path = (scratch_dir() / "nan.json").string();
  std::string text = nine_landmarks().dump();
  text.replace(text.find("-70.0"), 5, "NaN");
  pipeline::write_text_atomic(path, text);
  const std::string nan = bad_input_message([&] { pipeline::read_landmarks(path, {}); }, path);
  EXPECT_EQ(nan.rfind("not valid JSON: ", 0), 0u) << nan;
  EXPECT_NE(nan.find("(NaN and Infinity are not JSON numbers: write finite numbers)"), std::string::npos) << nan;
}
