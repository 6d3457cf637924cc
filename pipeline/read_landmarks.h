#pragma once
/// Reading a landmarks file (written by `landmarks`, or a user's edit of one): the one reader of
/// landmarks, so that segment, straps and assemble judge and word a bad position, confidence or
/// side the same way as `landmarks --user` does. Format: scan2cad/README.md, "landmarks".
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace pipeline {

/// One facial landmark in the aligned head's frame (x lateral, +x = the subject's left; y up;
/// z out of the face).
struct Landmark {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [mm]
  double confidence = 1.0;                              ///< 0 (a guess) … 1 (a clear feature)
};

/// The largest coordinate a landmark may have [mm]: an aligned head lies within ~300 mm of its
/// origin; 10 m leaves room for any frame while refusing the absurd (1e308 crashed a check).
inline constexpr double max_landmark_coordinate_mm = 1e4;

/// The nine landmarks of a head's file, the ones `landmarks` detects and segment needs: sellion,
/// pronasale, menton, and zygion, tragion and gonion, each left and right.
const std::vector<std::string>& head_landmark_names();

/// Whether `name` is one of head_landmark_names().
bool is_head_landmark_name(const std::string& name);

/// Reads the "landmarks" object of `path`: name → {"position": [x, y, z], "confidence": c}.
/// "confidence" is optional (1 when absent); a landmark's other keys are refused, except comments
/// ("_..."). Landmarks of other names are kept (and held to the side rule below).
///
/// @param[in] path      the JSON file
/// @param[in] required  names the caller needs; other landmarks in the file are kept as well
/// @return every landmark of the file, by name
/// @throws Error(bad_input) naming `path` and the first problem: no "landmarks" object; a position
///         that is not three finite numbers; an unknown key in a landmark; a confidence that is
///         not a number in [0, 1]; a required name missing; a "*_left" landmark at x <= 0 or a
///         "*_right" one at x >= 0 (a mirrored head, or one not in align's frame); sellion and
///         menton under 30 mm apart where 10 or 1000 times that is an adult's face (60-200 mm: a
///         file in cm or m); a sellion, pronasale or menton more than 10 mm off x = 0; a menton less
///         than 30 mm below the sellion (a head not y-up, or the two swapped), a pronasale not
///         between them in y, or a gonion less than 20 mm below the tragion of its side (on the
///         NIOSH and generated heads it is 51-73 mm below).
std::map<std::string, Landmark> read_landmarks(const std::string& path, const std::vector<std::string>& required);

}  // namespace pipeline
