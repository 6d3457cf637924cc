#pragma once
// Shared by the layers tests and generated_heads_test: every property issue 4 asks of a layered
// head, checked on the model itself (not on build_layers' own report, except the volumes).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "layering/layers.h"

namespace layers_test {

// `m` and `rep` from build_layers on a head surface with the five parts; `label` names it in the output.
inline void expect_valid_head_layers(const layering::FeModel& m, const layering::LayerReport& rep,
                                     const std::string& label) {
  std::printf("%s: %zu wedges, %zu shell triangles, %zu nodes, min scaled Jacobian %.3f, %zu columns thinned "
              "(min scale %.2f)\n",
              label.c_str(), rep.wedges, rep.shell_triangles, rep.nodes, rep.min_scaled_jacobian, rep.reduced_columns,
              rep.min_depth_scale);
  double min_j = 1e9, min_v = 1e9;
  std::size_t wedges = 0;
  for (const auto& b : m.blocks)
    if (b.dim == 3)
      for (std::size_t e = 0; e < b.size(); ++e, ++wedges) {
        Eigen::Vector3d p[6];
        for (int k = 0; k < 6; ++k) p[k] = m.nodes[b.conn[6 * e + k]];
        min_j = std::min(min_j, layering::wedge_scaled_jacobian(p));
        min_v = std::min(min_v, layering::wedge_volume(p));
      }
  ASSERT_GT(wedges, 0u);  // else the bounds below would hold by their starting values
  EXPECT_EQ(wedges, rep.wedges);
  EXPECT_GT(min_v, 0.0);
  EXPECT_GE(min_j, 0.2);  // issue 4: min scaled Jacobian >= 0.2
  EXPECT_EQ(layering::count_intersecting_faces(m), 0u);
  // One per layer of data/materials.json's head stacks: forehead 2, each cheek 4, chin 3.
  EXPECT_EQ(rep.volumes.size(), 13u);
  for (const auto& v : rep.volumes) {
    std::printf("%s: %-20s %6zu wedges  V/(mid-area*t) %+5.1f %%  V/(skin-area*t) %+5.1f %%\n", label.c_str(),
                v.group.c_str(), v.wedges, 100 * (v.volume / v.mid_area_volume - 1),
                100 * (v.volume / v.skin_area_volume - 1));
    // 5 %: issue 4. The reference is the area of the unthinned offset surface at the layer's mid-depth
    // (Steiner: an inward offset of a convex face shrinks, by ~(d1+d2)/2R ≈ 20 % for the cheek bone at
    // R ≈ 80 mm, which no correct mesh could hide); any local thinning or leaning column counts against it.
    EXPECT_NEAR(v.volume / v.mid_area_volume, 1.0, 0.05) << v.group;
  }
  // Which way the surfaces look. head_skin is the contact master (outward: the enclosed volume by
  // the divergence theorem is the head's, > 1 litre; inward it is negative); each part's skin
  // surface looks away from the head's centre and its bone_inner toward it. A reversed skin
  // winding had passed every layers test (sweep L) and was seen only by assemble's.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : m.nodes) centre += p;
  centre /= double(m.nodes.size());
  auto outwardness = [&](const layering::Block& b) {  // Σ area-normal · (centroid - centre), or 6 V
    double s = 0;
    for (std::size_t e = 0; e < b.size(); ++e) {
      const Eigen::Vector3d a = m.nodes[b.conn[3 * e]] - centre, q = m.nodes[b.conn[3 * e + 1]] - centre,
                            c = m.nodes[b.conn[3 * e + 2]] - centre;
      s += a.dot(q.cross(c));
    }
    return s;
  };
  const layering::Block* head_skin = m.find("head_skin");
  ASSERT_NE(head_skin, nullptr);
  EXPECT_GT(outwardness(*head_skin) / 6, 1e6) << "head_skin does not bound the head's volume outward";
  std::size_t part_surfaces = 0;
  for (const auto& b : m.blocks) {
    if (b.dim != 2) continue;
    const auto ends_with = [&](const std::string& tail) {
      return b.name.size() > tail.size() && b.name.compare(b.name.size() - tail.size(), tail.size(), tail) == 0;
    };
    if (ends_with("_skin_surface")) {
      EXPECT_GT(outwardness(b), 0.0) << b.name;
      ++part_surfaces;
    }
    if (ends_with("_bone_inner")) {
      EXPECT_LT(outwardness(b), 0.0) << b.name;
      ++part_surfaces;
    }
  }
  EXPECT_EQ(part_surfaces, 8u);  // forehead, cheeks and chin: skin and bone each
  for (const char* g : {"forehead_skin", "forehead_bone", "left_cheek_fat", "right_cheek_muscle", "chin_bone",
                        "head_skin", "back_of_head", "left_cheek_bone_inner"})
    EXPECT_NE(m.find(g), nullptr) << g;
}

}  // namespace layers_test
