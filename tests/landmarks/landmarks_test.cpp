// detect_landmarks on the aligned NIOSH medium and large headforms; read_landmarks validation.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "pipeline/error.h"
#include "scan2cad/align.h"
#include "scan2cad/landmarks.h"
#include "../bad_input_message.h"
#include "../scan2cad/test_meshes.h"
#include "../scratch_dir.h"

namespace {

pipeline::SurfaceMesh aligned_head(const char* name) {
  auto mesh = scan2cad::load_surface_any_unit(std::string(SHARED_DATA_DIR) + "/headforms/" + name, 250.0);
  scan2cad::apply_transform(mesh, scan2cad::align(mesh, {}).transform);
  return mesh;
}

}  // namespace

// Face length and width against US workforce anthropometry (means ≈ 120 and 140 mm, SD ≈ 7):
// a head of the NIOSH medium/large panel cells must lie within ±3 SD of the mean (99 to 141
// and 119 to 161 mm); left/right points must mirror each other within 3 mm.
TEST(detect_landmarks, niosh_face_length_and_width_are_anthropometric) {
  for (const char* name : {"NIOSH_medium_20k.stl", "NIOSH_large_20k.stl"}) {
    const auto l = scan2cad::detect_landmarks(aligned_head(name));
    const double len = scan2cad::face_length(l), wid = scan2cad::face_width(l);
    std::printf("%s: face length %.1f mm, face width %.1f mm\n", name, len, wid);
    EXPECT_GT(len, 99.0);
    EXPECT_LT(len, 141.0);
    EXPECT_GT(wid, 119.0);
    EXPECT_LT(wid, 161.0);
    for (const char* p : {"zygion", "tragion", "gonion"}) {
      const auto& a = l.points.at(std::string(p) + "_left").position;
      const auto& b = l.points.at(std::string(p) + "_right").position;
      EXPECT_GT(a.x(), 0.0) << p;
      EXPECT_LT((a - Eigen::Vector3d(-b.x(), b.y(), b.z())).norm(), 3.0) << name << " " << p;
    }
    // Lateral order, each side: the jaw angle well below the ear (tragion) and above the chin
    // (menton), inside the ear's width, behind the cheekbone (zygion); the zygion in front of
    // the ear.
    for (const char* side : {"_left", "_right"}) {
      const auto& go = l.points.at(std::string("gonion") + side).position;
      const auto& tr = l.points.at(std::string("tragion") + side).position;
      const auto& zy = l.points.at(std::string("zygion") + side).position;
      EXPECT_LT(go.y(), tr.y() - 30.0) << name << side;
      EXPECT_GT(go.y(), l.points.at("menton").position.y()) << name << side;
      EXPECT_LT(std::abs(go.x()), std::abs(tr.x())) << name << side;
      EXPECT_LT(go.z(), zy.z()) << name << side;
      EXPECT_GT(zy.z(), tr.z() + 10.0) << name << side;
    }
    // Order along the midline: sellion above pronasale above menton; nose tip most forward.
    EXPECT_GT(l.points.at("sellion").position.y(), l.points.at("pronasale").position.y());
    EXPECT_GT(l.points.at("pronasale").position.y(), l.points.at("menton").position.y());
    EXPECT_GT(l.points.at("pronasale").position.z(), l.points.at("sellion").position.z());
  }
}

// Where the detected landmarks lie on NIOSH medium, in align's frame: the positions detection gave
// on 2026-12-07, the baseline of sweeps J and O (their parts drawn and checked by render_parts.py;
// the hand-picked fixture of tests/segment uses other definitions: its menton is the chin's lowest
// vertex, 15 mm from detection's, which takes the chin's support point 30 deg forward of down).
// The tests above check only the landmarks' order, and a menton sought 30 deg backward passed them
// 11 mm down the chin (face length 115.8 -> 126.8 mm, sweep N). 2 mm: twice the landmarks' move
// under remeshing (every_landmark_stable_under_remeshing, 1 mm), so a change of definition or
// window shows while a change of mesh does not.
TEST(detect_landmarks, niosh_medium_landmarks_stay_where_they_were_found) {
  const auto detected = scan2cad::detect_landmarks(aligned_head("NIOSH_medium_20k.stl"));
  const std::map<std::string, Eigen::Vector3d> found = {
      {"gonion_left", {62.33, -20.60, 2.97}},
      {"gonion_right", {-62.46, -20.94, 3.44}},
      {"menton", {-0.01, -81.91, 84.26}},
      {"pronasale", {0.01, -5.46, 120.06}},
      {"sellion", {-0.00, 32.72, 100.56}},
      {"tragion_left", {77.46, 34.81, 0.20}},
      {"tragion_right", {-77.15, 34.38, 0.36}},
      {"zygion_left", {69.14, 17.51, 31.26}},
      {"zygion_right", {-69.16, 17.43, 31.35}}};
  for (const auto& [name, p] : found) {
    const double d = (detected.points.at(name).position - p).norm();
    std::printf("%s: %.2f mm from where it was found\n", name.c_str(), d);
    EXPECT_LE(d, 2.0) << name << " now at " << detected.points.at(name).position.transpose();
  }
}

// Re-meshing the same head must move every detected landmark by <= 1 mm (issue 3). Each NIOSH
// head (~3 mm edges in the file) is re-meshed three ways with CGAL isotropic remeshing: finer
// (1.5 mm and 2 mm edges) and about as coarse as the file (3 mm: same density, other vertices).
// The largest displacement over the three, per landmark, is what is asserted.
std::map<std::string, double> max_moves_under_remeshing(const char* file) {
  const auto head = aligned_head(file);
  const auto before = scan2cad::detect_landmarks(head);
  std::map<std::string, double> worst;
  for (const double edge_mm : {1.5, 2.0, 3.0}) {
    auto remeshed = head;
    CGAL::Polygon_mesh_processing::isotropic_remeshing(faces(remeshed), edge_mm, remeshed,
                                                       CGAL::parameters::number_of_iterations(3));
    remeshed.collect_garbage();
    const auto after = scan2cad::detect_landmarks(remeshed);
    for (const auto& [name, p] : before.points) {
      const double d = (p.position - after.points.at(name).position).norm();
      worst[name] = std::max(worst[name], d);
      std::printf("%s, remeshed at %.1f mm (%zu faces): %s moved %.2f mm\n", file, edge_mm,
                  std::size_t(remeshed.number_of_faces()), name.c_str(), d);
    }
  }
  return worst;
}

TEST(detect_landmarks, every_landmark_stable_under_remeshing) {
  for (const char* file : {"NIOSH_medium_20k.stl", "NIOSH_large_20k.stl"}) {
    const auto worst = max_moves_under_remeshing(file);
    EXPECT_EQ(worst.size(), scan2cad::required_landmarks().size());
    for (const auto& name : scan2cad::required_landmarks()) {
      ASSERT_TRUE(worst.count(name)) << name;
      std::printf("%s: %s max move %.2f mm\n", file, name.c_str(), worst.at(name));
      EXPECT_LE(worst.at(name), 1.0) << file << " " << name;
    }
  }
}

// A sphere has no nasal root: its sellion is a guess, and said to be; the NIOSH heads have none.
// A head smaller or larger than those detection was set on: NIOSH medium scaled about its frame's
// origin. Detection's lengths scale with the head's nose-to-chin span outside the tuned 80-95 mm,
// so the landmarks are the unscaled head's scaled. With fixed windows (before 2026-12-07) the
// head at 0.8 (a child's, face length 93 mm) got its tragia 25 mm off at confidence 0.93, and at
// 1.2 its zygia 45 mm off, without a warning (sweep O). Measured now: at 0.8 (scale 0.84) within
// 1.7 mm; at 1.2 the scale is only 1.06 (the span over the range's end, 95 mm), the sellion
// comes out 5.8 mm low (4.4 mm at 1.1, where nothing scales: the glabella's window starts on the
// nose bridge) and the points placed from it 2-3.5 mm off.
TEST(detect_landmarks, a_head_scaled_by_08_or_12_gets_its_landmarks_scaled) {
  const auto head = aligned_head("NIOSH_medium_20k.stl");
  const auto unscaled = scan2cad::detect_landmarks(head);
  EXPECT_EQ(unscaled.window_scale, 1.0);
  for (const double c : {0.8, 1.2}) {
    auto scaled_head = head;
    for (auto v : scaled_head.vertices()) {
      const auto& p = scaled_head.point(v);
      scaled_head.point(v) = pipeline::Point(c * p.x(), c * p.y(), c * p.z());
    }
    const auto scaled = scan2cad::detect_landmarks(scaled_head);
    std::printf("scaled by %.1f: window scale %.3f\n", c, scaled.window_scale);
    EXPECT_NEAR(scaled.window_scale, c < 1 ? c * 84.5 / 80 : c * 84.5 / 95, 0.01) << c;
    for (const auto& [name, p] : unscaled.points) {
      const double d = (scaled.points.at(name).position - c * p.position).norm();
      std::printf("  %s: %.2f mm from the unscaled one's, scaled (confidence %.2f)\n", name.c_str(), d,
                  scaled.points.at(name).confidence);
      EXPECT_LE(d, c < 1 ? 2.0 : name == "sellion" ? 7.0 : 4.0) << c << " " << name;
      EXPECT_GE(scaled.points.at(name).confidence, 0.5) << c << " " << name;
    }
  }
  EXPECT_EQ(scan2cad::landmark_window_scale_of_span(70), 70.0 / 80);
  EXPECT_EQ(scan2cad::landmark_window_scale_of_span(87), 1.0);
  EXPECT_EQ(scan2cad::landmark_window_scale_of_span(114), 114.0 / 95);
  EXPECT_EQ(scan2cad::landmark_window_scale_of_span(1000), 1.4);
  EXPECT_EQ(scan2cad::landmark_window_scale_of_span(10), 0.7);
}

TEST(guessed_landmarks, the_sellion_of_a_sphere_but_nothing_on_the_niosh_heads) {
  pipeline::SurfaceMesh sphere;
  const auto soup = test_meshes::sphere_soup(80.0, 60);
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, sphere);
  const auto on_sphere = scan2cad::guessed_landmarks(scan2cad::detect_landmarks(sphere));
  EXPECT_NE(std::find(on_sphere.begin(), on_sphere.end(), "sellion"), on_sphere.end());
  for (const char* name : {"NIOSH_medium_20k.stl", "NIOSH_large_20k.stl"})
    EXPECT_TRUE(scan2cad::guessed_landmarks(scan2cad::detect_landmarks(aligned_head(name))).empty()) << name;
}

namespace {
// Every required landmark, the left ones at x = 50, the right ones at x = -50, the rest at x = 0;
// sellion at y = 40, pronasale at 0, menton at -70 (the profile read_landmarks checks), the gonia
// at -40 (below the tragia), the other sided ones at 0: what read_landmarks accepts, for a test to
// break one thing of.
scan2cad::Landmarks sided_landmarks(double confidence) {
  scan2cad::Landmarks l;
  for (const auto& n : scan2cad::required_landmarks()) {
    const double x = n.find("_left") != std::string::npos ? 50 : n.find("_right") != std::string::npos ? -50 : 0;
    const double y = n == "sellion" ? 40 : n == "menton" ? -70 : n.rfind("gonion", 0) == 0 ? -40 : 0;
    l.points[n] = {Eigen::Vector3d(x, y, 0), confidence};
  }
  return l;
}
}  // namespace

// landmarks.json's measures are of the landmarks they name: a bigonial breadth measured between
// the zygia passed every test (sweep N), and a researcher reports it as a head dimension.
TEST(landmarks_json, measures_are_the_distances_they_name) {
  scan2cad::Landmarks l = sided_landmarks(1.0);
  l.points["zygion_left"].position.x() = 70, l.points["zygion_right"].position.x() = -69;
  l.points["tragion_left"].position.x() = 75, l.points["gonion_right"].position.x() = -61;
  const auto m = nlohmann::json::parse(scan2cad::landmarks_json(l))["measures_mm"];
  EXPECT_DOUBLE_EQ(m["face_length"].get<double>(), 110.0);                 // sellion y 40 to menton y -70
  EXPECT_DOUBLE_EQ(m["face_width"].get<double>(), 139.0);                  // zygion to zygion
  EXPECT_DOUBLE_EQ(m["bitragion_breadth"].get<double>(), 125.0);           // 75 to -50
  EXPECT_DOUBLE_EQ(m["bigonial_breadth"].get<double>(), 111.0);            // 50 to -61
}

TEST(read_landmarks, rejects_a_left_point_on_the_right) {
  const auto path = scratch_dir() / "bad.json";
  scan2cad::Landmarks l = sided_landmarks(1.0);
  std::ofstream(path) << scan2cad::landmarks_json(l);
  EXPECT_NO_THROW(scan2cad::read_landmarks(path.string()));
  l.points["zygion_left"].position.x() = -50;
  std::ofstream(path) << scan2cad::landmarks_json(l);
  EXPECT_EQ(bad_input_message([&] { scan2cad::read_landmarks(path.string()); }, path.string()),
            "landmark zygion_left: x = -50, expected > 0 (the subject's left is +x): is the head mirrored, or not "
            "aligned?");
}

// A head three times too large (read as mm) went through repair, align and landmarks with a face
// 352 mm wide, exit 0; one 0.65 times as large has a child's face. Both are refused, naming the file.
TEST(require_adult_face, refuses_faces_at_another_scale) {
  const scan2cad::Landmarks l = sided_landmarks(1.0);  // face length 110 mm, width 100 mm
  EXPECT_EQ(bad_input_message([&] { scan2cad::require_adult_face(l, "head.ply"); }, "head.ply"), "no error");
  for (const double scale : {3.0, 0.6}) {
    scan2cad::Landmarks scaled = l;
    for (auto& [name, p] : scaled.points) p.position *= scale;
    EXPECT_EQ(bad_input_message([&] { scan2cad::require_adult_face(scaled, "head.ply"); }, "head.ply"),
              "face length " + pipeline::format_number(110 * scale) + " mm and width " +
                  pipeline::format_number(100 * scale) +
                  " mm, outside any adult's (70-170 and 90-200 mm): a head at another scale (its unit?), or landmarks "
                  "misplaced")
        << scale;
  }
}

// confidence is optional (1 when absent), but one that is there and not a number was read as 1.
TEST(read_landmarks, rejects_a_confidence_that_is_not_a_number) {
  const auto path = scratch_dir() / "confidence.json";
  auto j = nlohmann::json::parse(scan2cad::landmarks_json(sided_landmarks(0.5)));
  j["landmarks"]["sellion"].erase("confidence");
  std::ofstream(path) << j.dump();
  const scan2cad::Landmarks read = scan2cad::read_landmarks(path.string());
  EXPECT_EQ(read.points.at("sellion").confidence, 1.0);
  EXPECT_EQ(read.points.at("menton").confidence, 0.5);
  j["landmarks"]["sellion"]["confidence"] = "high";
  std::ofstream(path) << j.dump();
  EXPECT_EQ(bad_input_message([&] { scan2cad::read_landmarks(path.string()); }, path.string()),
            "landmark sellion: confidence \"high\", expected a number 0..1");
}

// A head that is not in the frame is refused before any landmark is looked for: upside down, the
// detection found a "sellion" on the neck (confidence 0, a warning) and landmarks exited 0.
// Aligned heads and small slips (turned 10 deg, pitched 5 deg: within what a hand alignment may
// leave) pass; each larger pose is out of the frame (pitched -10 deg, detection gave a face
// 172 mm long without a warning). Flips and pitches show in the angles, turns, rolls and shifts
// in the mirror distance.
TEST(require_head_frame, refuses_a_head_turned_flipped_or_shifted_out_of_the_frame) {
  struct Pose {
    const char* what;
    Eigen::Vector3d axis;
    double angle_deg;
    Eigen::Vector3d shift_mm;
    bool in_frame;
  };
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ(),
                        none = Eigen::Vector3d::Zero();
  const Pose poses[] = {{"aligned", X, 0, none, true},
                        {"turned 0.5 deg about y", Y, 0.5, none, true},
                        {"shifted 0.5 mm in y", X, 0, {0, 0.5, 0}, true},
                        {"turned 5 deg about y", Y, 5, none, false},
                        {"turned 10 deg about y", Y, 10, none, false},
                        {"pitched 2 deg about x", X, 2, none, false},
                        {"pitched -5 deg about x", X, -5, none, false},
                        {"shifted 5 mm in z", X, 0, {0, 0, 5}, false},
                        {"pitched 10 deg about x", X, 10, none, false},
                        {"pitched -10 deg about x", X, -10, none, false},
                        {"upside down (180 deg about z)", Z, 180, none, false},
                        {"face down (180 deg about x)", X, 180, none, false},
                        {"looking sideways (90 deg about y)", Y, 90, none, false},
                        {"turned 20 deg about y", Y, 20, none, false},
                        {"pitched 30 deg about x", X, 30, none, false},
                        {"rolled 30 deg about z", Z, 30, none, false},
                        {"lying (90 deg about x)", X, 90, none, false},
                        {"shifted 20 mm in x", X, 0, {20, 0, 0}, false}};
  for (const char* name : {"NIOSH_medium_20k.stl", "NIOSH_large_20k.stl"}) {
    const auto head = aligned_head(name);
    for (const Pose& pose : poses) {
      SCOPED_TRACE(std::string(name) + " " + pose.what);
      auto posed = head;
      Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
      T.block<3, 3>(0, 0) = Eigen::AngleAxisd(pose.angle_deg * M_PI / 180.0, pose.axis).toRotationMatrix();
      T.block<3, 1>(0, 3) = pose.shift_mm;
      scan2cad::apply_transform(posed, T);
      const auto e = scan2cad::head_frame_error(posed);
      std::printf("%s %s: align's turn %.3f deg, shift %.3f mm; mirror %.2f mm, face %s %.1f deg, up %.1f deg\n", name,
                  pose.what, e.turn_deg, e.shift_mm, e.mirror_mm, e.face_found ? "found" : "not found", e.face_deg, e.up_deg);
      EXPECT_TRUE(e.realigned);
      // align's measure is the pose itself, within the 1e-4 deg / mm align repeats itself to
      const double turn_deg = std::fmod(std::abs(pose.angle_deg), 360.0);
      EXPECT_NEAR(e.turn_deg, std::min(turn_deg, 360 - turn_deg), 0.01);
      if (pose.in_frame) {
        EXPECT_TRUE(e.face_found);  // (rolled 30 deg, medium has none in x = 0)
      }
      const std::string message = bad_input_message([&] { scan2cad::require_head_frame(e); });
      if (pose.in_frame) {
        EXPECT_EQ(message, "no error");
      } else {
        EXPECT_EQ(message.rfind("the head is not in the head frame (align would turn it by ", 0), 0u) << message;
      }
    }
  }
}

// Where align finds no frame (a cropped or unusual head), the mirror test and the face's angles
// in x = 0 decide.
TEST(require_head_frame, without_a_frame_from_align_the_mirror_and_the_face_decide) {
  scan2cad::HeadFrameError e;
  e.mirror_mm = 0.3;
  const auto message = [&] { return bad_input_message([&] { scan2cad::require_head_frame(e); }); };
  EXPECT_EQ(message(), "no error");
  e.face_found = true, e.face_deg = 3, e.up_deg = 4;
  EXPECT_EQ(message(), "no error");
  e.up_deg = 9;
  EXPECT_EQ(message(), "the head is not in the head frame (face direction 3 deg from +z, up 9 deg from +y, its mirror "
                       "image in x = 0 0.3 mm off it): align it first (align --kind head)");
  e.face_found = false, e.mirror_mm = 7;
  EXPECT_EQ(message(), "the head is not in the head frame (no face found in the plane x = 0, its mirror image in x = 0 "
                       "7.0 mm off it): align it first (align --kind head)");
  e.realigned = true, e.turn_deg = 0.2, e.shift_mm = 0.1;  // align's measure decides where it exists
  EXPECT_EQ(message(), "no error");
}
