// landmarks: detects facial landmarks on an aligned head (output of align) and writes them as
// JSON (frame of align.h, mm; format in README.md). A user's file (--user) replaces detection
// after validation (names, numbers, left/right sides, distance to the surface). Either way the
// head must be in the frame (require_head_frame: a raw or upside-down scan is refused, exit 2).
//
// Inputs:  --in    aligned head surface (PLY from align, mm)
//          --user  optional landmarks JSON to use instead of detection
// Outputs: --out   landmarks JSON
//
// Sample runs:
//   landmarks --in build/cases/medium_onesize/head/aligned.ply --out landmarks.json
//   landmarks --in aligned.ply --user my_landmarks.json --out landmarks.json
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/read_landmarks.h"
#include "pipeline/read_scan.h"
#include "pipeline/require_landmarks_on_surface.h"
#include "pipeline/units.h"
#include "scan2cad/align.h"
#include "scan2cad/landmarks.h"

int main(int argc, char** argv) {
  std::string in, out, user;
  pipeline::Cli cli("landmarks", "Detects facial landmarks on an aligned head (x lateral, y up, z out of the face; mm).");
  cli.option("-i", "--in", &in, "aligned head surface (PLY, OFF, OBJ or STL; mm)", pipeline::required);
  cli.option("-o", "--out", &out, "landmarks (JSON)", pipeline::required);
  cli.option("-u", "--user", &user, "user landmarks (JSON) replacing detection");
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--in", in}, {"--user", user}, {"--out", out}});
    pipeline::require_extension("--out", out, {".json"});
    pipeline::require_writable_outputs({out});
    // 1. Input (run_main has logged the options)
    pipeline::Progress progress("landmarks", 0);
    const auto head = pipeline::read_surface_mesh(in);
    const double extent_mm = pipeline::largest_extent(head.points());
    pipeline::require_mm(in, extent_mm, "head");
    pipeline::require_real_size(in, extent_mm, "head", false);
    pipeline::naming_file(in, [&] { scan2cad::require_head_frame(head); });
    // 2. Detect, or validate the user's file against the head
    scan2cad::Landmarks l;
    if (user.empty()) {
      progress.step("detecting");
      l = pipeline::naming_file(in, [&] { return scan2cad::detect_landmarks(head); });
      for (const std::string& name : scan2cad::guessed_landmarks(l))
        std::fprintf(stderr,
                     "landmarks: warning: %s is a guess (confidence %.2f: no clear feature, or it and its other side do "
                     "not mirror each other, which lowers both): check %s, or give your own (--user FILE; through "
                     "make, LANDMARKS=FILE)\n",
                     name.c_str(), l.points.at(name).confidence, out.c_str());
    } else {
      l = scan2cad::read_landmarks(user);
      std::map<std::string, double> off_mm;
      pipeline::require_landmarks_on_surface(l.points, head, user, 10.0, &off_mm);
      for (const std::string& note : scan2cad::user_landmark_notes(l, head, off_mm))
        pipeline::log("landmarks", "note: " + user + ": " + note);
      // a user's own points are kept, but no stage uses them: said, so a misspelt name shows
      for (const auto& [name, point] : l.points)
        if (!pipeline::is_head_landmark_name(name))
          pipeline::log("landmarks", "note: " + user + ": landmark " + name + " is none of the nine the stages use; kept in " + out);
    }
    scan2cad::require_adult_face(l, user.empty() ? in : user);
    // 3. Write atomically
    pipeline::write_text_atomic(out, scan2cad::landmarks_json(l));
    std::ostringstream s;
    s << l.source;
    if (l.source == "detected" && l.window_scale != 1.0)
      s << " (a head outside the sizes detection was set on: its lengths scaled by "
        << pipeline::format_number(std::round(l.window_scale * 100) / 100) << ")";
    s << ": face length " << scan2cad::face_length(l) << " mm, face width " << scan2cad::face_width(l) << " mm";
    progress.finish(s.str());
    return 0;
  });
}
