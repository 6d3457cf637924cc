#pragma once
/// Positions the respirator on the head (paper: symmetry plane on the sagittal plane, vertical plane
/// parallel to the coronal plane, 3 mm minimum gap; vertical position from the landmarks) and puts
/// head, respirator and straps into one solver model plus the two solver decks (solve/README.md).
#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "layering/layers.h"

namespace meshing {

/// Landmark name → position [mm] (landmarks JSON of the pipeline, read by pipeline::read_landmarks).
/// @throws Error(bad_input) naming the file as that reader does, or if sellion or menton is missing.
std::map<std::string, Eigen::Vector3d> read_landmarks(const std::string& path);

/// Checks that `model`, read from `path`, is what `layers` writes for `kind` ("head" or
/// "respirator"): wedge layers and the surface groups the later stages use (head_skin;
/// respirator_inner and respirator_rim), every wedge with a positive scaled Jacobian, and not an
/// assembled model. A surface.msh given instead went through assemble with exit 0 and made a
/// model with no tissue that solve refused.
/// @throws Error(bad_input) naming `path` and what is missing, or the first inverted wedge.
void require_layered(const layering::FeModel& model, const std::string& path, const std::string& kind);

/// Checks that `straps` (read from `path`) is what the straps stage writes: groups strap_top and
/// strap_bottom of quads, and for each strap and side its attachment point
/// (strap_<s>_attach_<side>) and end (strap_<s>_end_<side>), and no head or respirator. A file
/// without them (renamed groups, no $PhysicalNames, a model or surface given instead) went
/// through assemble with exit 0 and made a model with no straps, or failed in the placement with
/// a gap of -74 mm.
/// @throws Error(bad_input) naming `path` and the first group missing.
void require_straps(const layering::FeModel& straps, const std::string& path);

/// Every landmark of `lm` (read from `path`) within `max_mm` of the head's skin (its head_skin
/// group, else all its triangles). The landmarks stage puts them on the aligned surface, which the
/// layered skin follows to 2 mm (the generated medium and both NIOSH heads: 0.8, 1.9 and 1.9 mm at
/// worst, a tragion or the pronasale); one far off (another head's file, a hand edit in another
/// frame) made straps hang on a coordinate of 1e300. 10 mm as segment's check: at 20 mm NIOSH
/// medium's landmarks, 12-18.5 mm off NIOSH large's skin, were taken for NIOSH large's.
/// @throws Error(bad_input) naming `path` and the landmark.
void require_landmarks_near_skin(const layering::FeModel& head, const std::map<std::string, Eigen::Vector3d>& lm,
                                 const std::string& path, double max_mm = 10);

struct PlaceOptions {
  double gap_mm = 3.0;            ///< minimum distance respirator–skin [mm], > 0
  double bridge_offset_mm = 5.0;  ///< rim top this far below the sellion (seal over the nasal bridge) [mm]
  double max_rim_off_mm = 15.0;   ///< largest median rim–skin distance after placement [mm] (require_rim_on_face)
};

/// Translation [mm] to add to every respirator node. No rotation: the respirator and the head come
/// in the canonical frame (x lateral, y up, z out of the face), so the respirator's vertical plane
/// is already parallel to the coronal plane. x: rim's symmetry plane onto the sagittal plane of
/// sellion/menton; y: rim top at sellion − bridge_offset; z: bisection until the minimum
/// respirator–skin distance equals gap_mm (±0.001 mm).
/// @param head  model with a "head_skin" triangle group (outward) or triangle groups of parts
/// @param resp  model with "respirator_inner" and "respirator_rim" groups (as layers writes them)
/// The placed respirator's rim must then lie on the face (require_rim_on_face with
/// opt.max_rim_off_mm).
/// @param gap_out  measured minimum gap after placement [mm]
/// @param rim_out  its rim's distances to the skin after placement (may be null)
/// @throws Error(bad_input) missing groups, or a rim off the face; Error(algorithm) if no
///         placement reaches the gap.
struct RimOnFace;
Eigen::Vector3d place_respirator(const layering::FeModel& head, const std::map<std::string, Eigen::Vector3d>& lm,
                                 const layering::FeModel& resp, const PlaceOptions& opt, double* gap_out,
                                 RimOnFace* rim_out = nullptr);

/// How the rim of a respirator shifted by `shift` meets the head's skin: the unsigned distances
/// [mm] of its "respirator_rim" nodes to the skin (head_surface). On the generated
/// 30 cases the median is 4.8-9.9 mm and the largest 8.8-15.7 mm (meshing/README.md).
struct RimOnFace {
  double median_mm = 0, max_mm = 0;
  std::size_t nodes = 0;
};
RimOnFace rim_to_skin(const layering::FeModel& head, const layering::FeModel& resp, const Eigen::Vector3d& shift);

/// Refuses a placed respirator whose rim does not meet the face: median rim–skin distance over
/// `max_median_mm` (straps' and assemble's --max-rim-off-mm, 15 mm by default: 1.5 times the
/// largest median of the 30 cases). Every stage exited 0 on cups that do not seal (sweep K): half a cup, a cup
/// without its chin part or its lower half (placed tilted, touching only the nose: medians 36-49
/// mm), a cup aligned inside out (the dome on the nose, rim 32-83 mm off), a 200 mm cup whose rim
/// hung 72 mm below the chin (median 51 mm); the gap of 3 mm was then the nose's.
/// @throws pipeline::Error(bad_input) naming the respirator and the distances.
void require_rim_on_face(const RimOnFace& rim, double max_median_mm);

/// Minimum distance between the respirator (all its nodes, all its element faces) and the head skin
/// [mm]; negative if a respirator node lies inside the head.
double respirator_gap(const layering::FeModel& head, const layering::FeModel& resp);

/// Nodes of the respirator's rim: its "respirator_rim" lines as layers writes them, sorted, once each.
/// @throws pipeline::Error(bad_input) "respirator: no respirator_rim group (run layers --kind
///         respirator first)" if the group is missing or empty.
std::vector<int> rim_nodes(const layering::FeModel& resp);

/// Triangles (outward) of the head's contact surface: "head_skin", or every triangle group.
std::vector<std::array<int, 3>> head_surface(const layering::FeModel& head);

struct AssembleReport {
  Eigen::Vector3d shift{0, 0, 0};  ///< applied to the respirator [mm]
  double gap_mm = 0;               ///< measured respirator–skin gap after placement
  double strap_gap_mm = 0;         ///< minimum strap node distance to the skin
  double attach_offset_mm = 0;     ///< largest distance of a strap attachment point to its rim node
  std::size_t intersecting_pairs = 0;  ///< element faces of different bodies intersecting (0 required)
  double rim_median_mm = 0, rim_max_mm = 0;  ///< rim–skin distances after placement (RimOnFace)
  std::size_t wedges = 0, quads = 0, nodes = 0;
};

/// Merges head layers, the placed respirator layers and the straps (already in the head frame) into
/// one model; adds point groups attach_<strap>_<side> on the respirator rim nodes nearest to the
/// straps' attachment points. @throws Error(algorithm) if any two bodies intersect after placement;
/// Error(bad_input) "--straps: strap_top_attach_left lies 2.23 mm from the respirator's rim ..." if an
/// attachment point is more than 0.5 mm from every rim node (straps placed the respirator otherwise).
layering::FeModel assemble_model(const layering::FeModel& head, const layering::FeModel& resp,
                                 const layering::FeModel& straps, const std::map<std::string, Eigen::Vector3d>& lm,
                                 const PlaceOptions& opt, AssembleReport* report);

/// Refuses straps too near the skin for the shell thickness the decks give them: `straps` lays
/// each band's mid-surface at least strap_clearance_mm (1 mm, straps.h; no option) + half its
/// --thickness-mm off the skin,
/// and assemble's --strap-thickness-mm must be the same, since the straps' .msh holds only the
/// mid-surface. Straps laid for 1 mm, assembled with 5 mm, began ~1 mm inside the head with exit
/// 0. The mid-surface must be at least half the thickness off the skin.
/// @param strap_gap_mm  the least distance of a strap node from the skin (AssembleReport)
/// @throws pipeline::Error(bad_input) naming `straps_path`: "the straps lie 1.55 mm off the skin,
///         under half the 5 mm of --strap-thickness-mm: ..."
void require_straps_clear_for_thickness(double strap_gap_mm, double strap_thickness_mm, const std::string& straps_path);

/// The "materials" object of a solver deck from parsed data/materials.json: density, E, nu and
/// rigid of each material whose name does not start with '_', checked as solve checks them
/// (pipeline::why_material_unusable), so a unit slip stops at assemble, before any deck is written.
/// @throws Error(bad_input) naming the entry: "materials.skin.E: expected a number".
nlohmann::json deck_materials(const nlohmann::json& materials);

/// The mass-proportional damping [1/ms] of both decks from parsed data/materials.json's
/// "damping": {"stage1_alpha_per_ms": ...}; 0.5 when the file gives none. The paper gives it for
/// stage I (c = 0.5 m … 3 m); stage II uses it too until the simulation issue settles stage II's
/// damping (the paper's stage II has viscous contact damping 2·m·ω·v instead, meshing/README.md).
/// @throws Error(bad_input) "damping.stage1_alpha_per_ms: ..." unless a finite number >= 0.
double stage1_damping_alpha(const nlohmann::json& materials);

/// The penalty scale s (contact stiffness k = s·m/Δt², DESIGN.md) of every contact pair of both
/// decks, from parsed data/materials.json's "contact": {"penalty_scale": ...}; 0.1 when the file
/// gives none.
/// @throws Error(bad_input) "contact.penalty_scale: ..." unless a number in (0, 1], the range solve
///         accepts.
double contact_penalty_scale(const nlohmann::json& materials);

/// Solver deck (solve/README.md) for stage 1 (strap wrapping, head and respirator fixed, strap ends
/// pulled to the attachment points in 0–100 ms, held to 200 ms) or stage 2 (respirator released,
/// straps tied to it, bone and back of head fixed, 0–150 ms, starts from stage 1's state).
/// @param materials  parsed data/materials.json
nlohmann::json make_deck(const layering::FeModel& model, const nlohmann::json& materials, int stage,
                         double strap_thickness_mm, const std::string& stage1_state);

}  // namespace meshing
