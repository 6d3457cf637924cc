#pragma once
/// Facial landmarks of an aligned head (frame of align.h: x lateral, +x = the subject's left;
/// y up; z out of the face; mm) and their JSON file (format: see README.md, "landmarks").
///
/// Detected: sellion, pronasale, menton (midline profile x = 0), zygion_left/right,
/// tragion_left/right, gonion_left/right (surface, each side on its own). Methods in
/// landmarks_detect.cpp; each point carries a confidence in [0, 1].
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "pipeline/read_landmarks.h"
#include "pipeline/surface_mesh.h"

namespace scan2cad {

using Landmark = pipeline::Landmark;  ///< position [mm] in the head frame, confidence 0 … 1

struct Landmarks {
  std::string source = "detected";  ///< "detected" or "user"
  std::map<std::string, Landmark> points;
  double window_scale = 1;  ///< detected: landmark_window_scale of the head; user: 1
};

/// The landmarks every file must hold (pipeline::head_landmark_names; extras such as subnasale are
/// allowed).
const std::vector<std::string>& required_landmarks();

/// Detection's windows (the ear 80-190 mm behind the nose tip, standing 10 mm out of the side of
/// the head; the cheek 0-40 mm below the sellion; ramps 4 mm wide, ray grids 0.5 mm apart, ...)
/// were set and checked on the NIOSH medium and large headforms and the five generated heads,
/// whose nose tips lie 80.9-94.3 mm from their mentons. Outside this range of nose-to-chin
/// spans [mm] every length of detection is scaled.
inline constexpr double min_tuned_nose_chin_mm = 80, max_tuned_nose_chin_mm = 95;

/// The scale of detection for a head whose nose tip lies `span_mm` from its menton: 1 within the
/// tuned range, else the span over the range's nearer end, clamped to 0.7-1.4 (spans of 56-133
/// mm, past a child's and the largest adult's). Scaled by the span over NIOSH medium's within
/// the range too, the generated large head's landmarks moved up to 2 mm and its left cheek's
/// layers came out 7 % thin, and with the ear's 10 mm scaled (1.09) the temple in front of
/// NIOSH large's ear joined the ear (its tragion moved 11 mm under re-meshing).
double landmark_window_scale_of_span(double span_mm);

/// The scale of detection for a head: landmark_window_scale_of_span of its nose tip's distance to
/// its menton, both on the midline section, the menton found with the chin window at the
/// previous scale, twice from 1 (the nose tip and chin are found with unscaled windows on heads
/// 0.75-1.3 times NIOSH medium's size; the ear, cheek and sellion are not: with fixed windows
/// the medium head scaled by 0.8 got its tragia 25 mm off at confidence 0.93, and scaled by 1.2
/// its sellion on the nose bridge and its zygia 45 mm off, sweep O 2026-12-07).
/// @param[in] head  as for detect_landmarks
/// @throws pipeline::Error(algorithm) if the midline section or the chin is not found
double landmark_window_scale(const pipeline::SurfaceMesh& head);

/// Detects the landmarks on an aligned head, every length of detection (windows, ramps, grids,
/// the soft extremes' widths, the lengths confidences are measured in) times
/// landmark_window_scale(head).
/// @param[in] head  closed or open triangle surface in the head frame [mm]; not modified
/// @return all required landmarks
/// @pre    `head` is in the frame: on a head that is not (upside down, say) detection may find
///         landmarks elsewhere with low confidences rather than throw; scan2cad::require_head_frame
///         (align.h) refuses such a head, and the landmarks program calls it first.
/// @throws pipeline::Error(algorithm) if the midline profile, the nose, the chin, the ears or
///         the cheeks cannot be found.
Landmarks detect_landmarks(const pipeline::SurfaceMesh& head);

/// The landmarks detection could only guess: confidence below `below`, in name order. On the
/// NIOSH and the five generated heads every landmark scores 0.28 or more; on a sphere the
/// sellion (no nasal root) scores 0. Detection goes on regardless; the caller warns.
std::vector<std::string> guessed_landmarks(const Landmarks& l, double below = 0.1);

/// Menton–sellion distance [mm].
double face_length(const Landmarks& l);
/// Zygion–zygion distance [mm].
double face_width(const Landmarks& l);

/// Face measures outside any adult's, with room to spare: the NIOSH panel spans face lengths of
/// 93.5-133.5 mm; its medium and large heads have face widths (this zygion-zygion) of ~138-145.
inline constexpr double min_face_length_mm = 70, max_face_length_mm = 170;
inline constexpr double min_face_width_mm = 90, max_face_width_mm = 200;

/// Checks that the landmarks measure an adult's face: face length and width within the bounds
/// above. A NIOSH head three times too large (857 mm, read as mm) went through repair, align and
/// landmarks with a face 352 mm wide and exit 0.
/// @throws pipeline::Error(bad_input) naming `path` (the head, or the user's landmarks file).
void require_adult_face(const Landmarks& l, const std::string& path);

/// The landmarks as JSON (frame, source, landmarks, measures_mm).
std::string landmarks_json(const Landmarks& l);

/// What is odd about a user's landmarks on this head, one sentence each, for the landmarks
/// program to log as notes (the points are kept where the user put them: a hand-picked point may
/// be meant where detection does not look). A point in the air, or another head's (the generated
/// large head's landmarks lie within 6 mm of the medium head, its tragia 35-38 mm from the medium
/// head's own), went through every stage without a word (sweep J).
/// @param[in] user          the user's landmarks, in the head's frame [mm]
/// @param[in] head          the aligned head; detection runs on it (about 3 s on a medium head)
/// @param[in] off_surface_mm  each landmark's distance to `head` [mm], by name
///                          (pipeline::require_landmarks_on_surface gives it)
/// @return "landmark sellion is 6.4 mm off the head's surface; kept where it is" for each point
///         more than 2 mm off, then "landmark tragion_left is 30 mm from where detection puts it on
///         this head (confidence 0.71): another head's landmarks?" for each more than 15 mm from
///         the detected one; nothing of the second kind where detection finds no face.
std::vector<std::string> user_landmark_notes(const Landmarks& user, const pipeline::SurfaceMesh& head,
                                             const std::map<std::string, double>& off_surface_mm);

/// Reads and validates a landmarks file (a user's or ours) with pipeline::read_landmarks: every
/// required name present, positions 3 finite numbers, confidence in [0, 1], left points at x > 0
/// and right at x < 0. `source` is "user".
/// @throws pipeline::Error(bad_input) naming `path` and the first problem.
Landmarks read_landmarks(const std::string& path);

}  // namespace scan2cad
