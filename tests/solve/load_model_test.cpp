// Reading models: gmsh .msh round trip, surfaces of 3D groups, deck errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>

#include "pipeline/error.h"
#include "solve/load_model.h"
#include "solve/make_block.h"
#include "solve/solver.h"
#include "solve/write_results.h"
#include "../bad_input_message.h"
#include "../scratch_dir.h"

namespace {
namespace fs = std::filesystem;
using solve::ElementType;

// ∮ x·n dA = 3V for a closed outward-oriented surface (divergence theorem).
double flux(const solve::Model& m, const std::vector<std::array<int, 3>>& tris) {
  double s = 0;
  for (const auto& t : tris) {
    const double* a = &m.X[3 * t[0]];
    const double* b = &m.X[3 * t[1]];
    const double* c = &m.X[3 * t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    s += (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 2;
  }
  return s;
}

}  // namespace

// The boundary of a 3D group read from a .msh is closed and outward: its flux ∮x·n dA is 3V
// (exact up to round-off: 1e-9 relative). The named face groups survive the round trip.
TEST(read_msh, surface_of_3d_group_is_closed_and_outward) {
  const std::string path = (scratch_dir() / "round_trip.msh").string();
  for (ElementType t : {ElementType::wedge6, ElementType::hex8, ElementType::tet4}) {
    solve::BlockSpec b;
    b.type = t;
    b.nx = 3; b.ny = 2; b.nz = 2;
    b.size = {3, 2, 2};
    b.jitter = 0.2;
    const solve::Model src = solve::make_block(b, {"m", 1e-3, 1, 0.3, false});
    solve::write_mesh_msh(src, path);
    const solve::Model m = solve::read_msh(path);
    ASSERT_EQ(m.n_nodes(), src.n_nodes());
    EXPECT_NEAR(flux(m, m.surface("block")), 3 * 12.0, 1e-9 * 36) << solve::element_name(t);
    EXPECT_EQ(m.group("xmin"), src.group("xmin"));
    EXPECT_EQ(m.surface("zmax").size(), src.surface("zmax").size());
  }
}

// Every node group of a model reads back from what write_mesh_msh (results.msh) writes, with its
// nodes: the groups that are neither parts nor surfaces too (in a case's model the respirator's rim,
// lines, and the strap ends, points). They had been left out, so the nodes whose forces forces.csv
// tracks could not be picked in gmsh or ParaView.
TEST(write_mesh_msh, every_node_group_reads_back_with_its_nodes) {
  solve::BlockSpec b;
  b.nx = 3; b.ny = 2; b.nz = 2;
  solve::Model src = solve::make_block(b, {"m", 1e-3, 1, 0.3, false});
  src.node_groups["strap_end"] = {5};
  src.node_groups["rim"] = {0, 1, 2, 3};
  const std::string path = (scratch_dir() / "groups.msh").string();
  solve::write_mesh_msh(src, path);
  const solve::Model m = solve::read_msh(path);
  ASSERT_EQ(m.n_nodes(), src.n_nodes());
  EXPECT_EQ(m.node_groups, src.node_groups);
  EXPECT_EQ(m.group("strap_end"), std::vector<int>{5});
}

// A deck's defaults are those solve/README.md documents (assemble's decks set none of these, so
// every pipeline run takes them): a dt_scale default of 1.0 for 0.9 passed every test (sweep N).
TEST(apply_deck, defaults_are_the_documented_ones) {
  solve::Model m = solve::make_block({}, {"m", 1e-3, 1, 0.3, false});
  solve::apply_deck(m, R"({"materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3}},
                           "parts": [{"group": "block", "material": "m"}],
                           "ties": [{"group_a": "xmin", "group_b": "xmax", "tolerance": 5}],
                           "contact": [{"slave": "zmin", "master": "zmax"}],
                           "control": {"end_time": 2}})",
                    "d.json");
  const solve::Control& c = m.control;
  EXPECT_EQ(c.dt_scale, 0.9);
  EXPECT_EQ(c.damping_alpha, 0.0);
  EXPECT_EQ(c.dt_target, 0.0);
  EXPECT_EQ(c.dt_update_interval, 100);
  EXPECT_EQ(c.hourglass, 0.1);
  EXPECT_EQ(c.output_interval, 0.0);   // run: end_time / 10
  EXPECT_EQ(c.history_interval, 0.0);  // run: output_interval / 10
  EXPECT_EQ(c.energy_tolerance, 0.05);
  EXPECT_EQ(c.penetration_tolerance, 1.0);
  ASSERT_EQ(m.contacts.size(), 1u);
  EXPECT_EQ(m.contacts[0].penalty_scale, 0.1);
  EXPECT_EQ(m.contacts[0].damping_ratio, 0.0);
  EXPECT_EQ(m.contacts[0].friction, 0.0);
  EXPECT_FALSE(m.contacts[0].two_sided);
  EXPECT_EQ(m.contacts[0].name, "zmin_on_zmax");
  ASSERT_EQ(m.ties.size(), 1u);
  EXPECT_EQ(m.ties[0].name, "xmin-xmax");
  EXPECT_EQ(m.output.node_data.size(), 5u);
}

// Deck errors name the deck and the key.
TEST(apply_deck, errors_name_the_key) {
  const solve::Model base = solve::make_block({}, {"m", 1e-3, 1, 0.3, false});
  auto message = [&](const std::string& deck) {
    solve::Model m = base;
    return bad_input_message([&] { solve::apply_deck(m, deck, "d.json"); });
  };
  const std::string mat = R"("materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3}}, "parts": [{"group": "block", "material": "m"}])";
  EXPECT_NE(message("{" + mat + "}").find("control"), std::string::npos);
  EXPECT_NE(message("{" + mat + R"(, "control": {"end_time": -1}})").find("end_time"), std::string::npos);
  EXPECT_NE(message("{" + mat + R"(, "control": {"end_time": 1, "dt_sclae": 1}})").find("dt_sclae"), std::string::npos);
  EXPECT_NE(message("{" + mat + R"(, "fixed": [{"group": "nope"}], "control": {"end_time": 1}})").find("nope"),
            std::string::npos);
  EXPECT_NE(message("{" + mat + R"(, "prescribed": [{"group": "xmin", "type": "velocity", "dof": "w", "curve": [[0,1]]}], "control": {"end_time": 1}})")
                .find("dof"),
            std::string::npos);
  EXPECT_NE(message(R"({"materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.5}}, "parts": [{"group": "block", "material": "m"}], "control": {"end_time": 1}})")
                .find("nu"),
            std::string::npos);
  EXPECT_EQ(message("{" + mat + R"(, "control": {"end_time": 1}})"), "no error");
  // Values that ran with exit 0 (fuzzed decks, 2026-12-06): each names its key.
  const auto with = [&](const std::string& rest) { return message("{" + mat + ", " + rest + "}"); };
  EXPECT_EQ(with(R"("control": {"end_time": 1, "damping_alpha": 1e12})"),
            "block + d.json: control.damping_alpha must be in [0, 1000] [1/ms]");
  EXPECT_EQ(with(R"("control": {"end_time": 1, "energy_tolerance": 1e9})"),
            "block + d.json: control.energy_tolerance must be in (0, 1]");
  EXPECT_EQ(with(R"("control": {"end_time": 1, "dt_update_interval": 1.5})"),
            "d.json: control.dt_update_interval: 1.5, expected a whole number of steps");
  for (const char* dofs : {"", "xxz"})
    EXPECT_EQ(with(std::string(R"("fixed": [{"group": "zmin", "dofs": ")") + dofs + R"("}], "control": {"end_time": 1})"),
              std::string("d.json: fixed[zmin].dofs: '") + dofs + "', expected some of x, y, z, each once");
  // a misspelt required key is named, not reported as missing
  EXPECT_EQ(with(R"("contol": {"end_time": 1})"), "d.json: unknown top-level key 'contol'");
  EXPECT_EQ(with(R"("control": {"end_time_ms": 1})"), "d.json: control.end_time_ms: unknown key");
  EXPECT_EQ(with(R"("initial_state": {"file": ""}, "control": {"end_time": 1})"),
            "d.json: initial_state.file: empty (leave initial_state out to start at rest)");
  EXPECT_EQ(with(R"("ties": [{"group_a": "xmin", "group_b": "xmax", "tolerance": -1}], "control": {"end_time": 1})"),
            "block + d.json: tie 'xmin-xmax': tolerance must be > 0 [mm]");
  const std::string contact = R"({"slave": "zmax", "master": "zmin", "name": "c", "friction": F})";
  auto contacts = [&](const std::string& friction, int n) {
    std::string list;
    for (int i = 0; i < n; ++i) list += (i ? ", " : "") + std::string(contact).replace(contact.find('F'), 1, friction);
    return with(R"("contact": [)" + list + R"(], "control": {"end_time": 1})");
  };
  EXPECT_EQ(contacts("0.5", 1), "no error");
  EXPECT_EQ(contacts("1e9", 1), "block + d.json: contact 'c': friction must be in [0, 2]");
  EXPECT_EQ(contacts("0.5", 2), "block + d.json: two contacts named 'c'");
  EXPECT_EQ(with(R"("contact": [{"slave": "zmax", "master": "zmin", "name": "c"}, )"
                 R"({"slave": "zmax", "master": "zmin", "name": "again"}], "control": {"end_time": 1})"),
            "block + d.json: contacts 'c' and 'again' both press 'zmax' on 'zmin': a pair once, or its penalty counts twice");
  // A misspelt optional key was read as absent: "frction": 0.3 ran with friction 0. Every object
  // of a deck now refuses keys it does not read; keys starting with "_" are comments.
  const std::string end = R"("control": {"end_time": 1})";
  EXPECT_EQ(with(R"("contact": [{"slave": "zmax", "master": "zmin", "name": "c", "frction": 0.3}], )" + end),
            "d.json: contact[c].frction: unknown key");
  EXPECT_EQ(with(R"("ties": [{"group_a": "xmin", "group_b": "xmax", "tolerence": 0.1}], )" + end),
            "d.json: ties[xmin-xmax].tolerence: unknown key");
  EXPECT_EQ(with(R"("fixed": [{"group": "zmin", "dof": "z"}], )" + end), "d.json: fixed[zmin].dof: unknown key");
  EXPECT_EQ(with(R"("initial_state": {"file": "s.bin", "reset_velocities": true}, )" + end),
            "d.json: initial_state.reset_velocities: unknown key");
  EXPECT_EQ(with(R"("output": {"history": ["zmin"]}, )" + end), "d.json: output.history: unknown key");
  EXPECT_EQ(message(R"({"materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3}}, )"
                    R"("parts": [{"group": "block", "material": "m", "thickness": 2}], )" + end + "}"),
            "d.json: parts[block].thickness: group 'block' is solid, its thickness is its mesh's (thickness is for membranes)");
  EXPECT_EQ(message(R"({"materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3, "rigd": true}}, )"
                    R"("parts": [{"group": "block", "material": "m"}], )" + end + "}"),
            "d.json: materials.m.rigd: unknown key");
  EXPECT_EQ(message(R"({"materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3}}, )"
                    R"("parts": [{"group": "block", "material": "m", "thick": 1}], )" + end + "}"),
            "d.json: parts[block].thick: unknown key");
  EXPECT_EQ(with(R"("contact": [{"slave": "zmax", "master": "zmin", "_note": "a comment"}], )" + end), "no error");
  // a group that does not exist: the entry that names it is named too
  EXPECT_EQ(with(R"("fixed": [{"group": "zmn", "dofs": "z"}], )" + end), "block + d.json: fixed[zmn]: no physical group named 'zmn'");
  EXPECT_EQ(with(R"("contact": [{"slave": "zmax", "master": "zmn", "name": "c"}], )" + end),
            "block + d.json: contact 'c': no physical group named 'zmn'");
  EXPECT_EQ(with(R"("output": {"history_groups": ["zmax", "top"]}, )" + end),
            "block + d.json: output.history_groups: no physical group named 'top'");
  EXPECT_EQ(with(R"("ties": [{"group_a": "zmax", "group_b": "zmax"}], )" + end),
            "d.json: ties[zmax-zmax]: ties group 'zmax' to itself");
}

// A deck assemble wrote names the model it was made for ("model_check": node count and bounding
// box): medium_onesize's stage I deck on the medium_twosize-m model ran 10 minutes, its strap ends
// driven to points 0.4-6 mm off that model's attachments, and stage II's ties failed naming a
// node. The same model passes; another node count, or a box moved by more than 1 µm, is refused.
TEST(apply_deck, a_deck_made_for_another_model_is_refused) {
  const solve::Model base = solve::make_block({}, {"m", 1e-3, 1, 0.3, false});  // 3 x 3 x 3 nodes, 1 mm
  const auto box = solve::model_bounds_mm(base);
  EXPECT_EQ(box, (std::array<double, 6>{0, 0, 0, 1, 1, 1}));
  const auto message = [&](std::size_t nodes, double high_z_mm) {
    solve::Model m = base;
    const std::string deck =
        R"({"model_check": {"nodes": )" + std::to_string(nodes) + R"(, "bounds_mm": [[0, 0, 0], [1, 1, )" +
        pipeline::format_number(high_z_mm) +
        R"(]]}, "materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3}}, "parts": [{"group": "block", "material": "m"}], )"
        R"("control": {"end_time": 1}})";
    return bad_input_message([&] { solve::apply_deck(m, deck, "d.json"); });
  };
  EXPECT_EQ(message(27, 1), "no error");
  EXPECT_EQ(message(27, 1 + 5e-4), "no error");
  EXPECT_EQ(message(28, 1),
            "d.json: made for a model of 28 nodes from (0.0, 0.0, 0.0) mm to (1.0, 1.0, 1.0) mm, and block has 27 nodes "
            "from (0.0, 0.0, 0.0) mm to (1.0, 1.0, 1.0) mm: the deck of another case, or of an earlier assemble? "
            "(assemble writes the model and its decks together)");
  EXPECT_NE(message(27, 1.1).find("made for a model of 27 nodes from (0.0, 0.0, 0.0) mm to (1.0, 1.0, 1.1) mm"),
            std::string::npos);
  // off by less than the printed 0.1 mm: the gap is named (two equal boxes were shown)
  EXPECT_NE(message(27, 1.01).find("to (1.0, 1.0, 1.0) mm (its highest z differs by 0.01 mm): the deck"),
            std::string::npos)
      << message(27, 1.01);
}

// A contact's slave node without mass is named as outputs name it: by its tag, or by its 1-based
// number in a model built without tags (it was the 0-based index there).
TEST(check_model, massless_slave_node_named_by_tag_or_number) {
  solve::Model m = solve::make_block({}, {"m", 1e-3, 1, 0.3, false});
  const std::size_t loose = m.n_nodes();
  m.X.insert(m.X.end(), {50, 50, 50});  // a node of no element
  m.node_tags.push_back(1000);
  m.node_groups["loose"] = {int(loose)};
  m.contacts.push_back({"touch", "loose", "zmax"});
  m.control.end_time = 1;
  auto message = [](const solve::Model& model) { return bad_input_message([&] { solve::check_model(model); }); };
  EXPECT_NE(message(m).find("contact 'touch': slave node 1000 belongs to no part"), std::string::npos) << message(m);
  m.node_tags.clear();
  EXPECT_NE(message(m).find("contact 'touch': slave node " + std::to_string(loose + 1) + " belongs to no part"),
            std::string::npos)
      << message(m);
  // A load or an initial velocity on it: refused too (the load's share had vanished, exit 0).
  m.contacts.clear();
  m.loads.push_back({"loose", 2, solve::Curve::constant(1.0)});
  EXPECT_NE(message(m).find("loads[loose]: node " + std::to_string(loose + 1) + " belongs to no part (no mass)"),
            std::string::npos)
      << message(m);
  m.loads.clear();
  // a group pressed on itself: refused (no force, 15 times slower steps, exit 0)
  m.contacts.push_back({"self", "zmax", "zmax"});
  EXPECT_NE(message(m).find("contact 'self': slave and master are both 'zmax': self-contact is not modelled"),
            std::string::npos)
      << message(m);
  m.contacts.clear();
  // the same two groups tied twice under two names (either order): refused, as a contact pair twice is
  m.ties.push_back({"glue", "zmin", "zmax", 1e-3});
  m.ties.push_back({"again", "zmax", "zmin", 1e-3});
  EXPECT_NE(message(m).find("ties 'glue' and 'again' both tie 'zmax' to 'zmin': a pair once"), std::string::npos)
      << message(m);
  m.ties.clear();
  m.initial_velocities.push_back({"loose", {0, 0, 1}});
  EXPECT_NE(message(m).find("initial_velocity[loose]: node " + std::to_string(loose + 1) + " belongs to no part"),
            std::string::npos)
      << message(m);
}

// A model that holds a head (group head_skin) in metres or cm is refused before the run: in metres,
// medium_onesize's stage I started 48.7 million steps (ETA 16 days) without a word. A 200 mm block
// standing in for the head passes; the same block in metres and in cm does not; models without a
// head (the solver's own test blocks, a few mm) are not judged by it.
TEST(check_model, a_head_model_not_in_mm_is_refused) {
  solve::BlockSpec b;
  b.size = {200, 200, 200};
  solve::Model m = solve::make_block(b, {"m", 1e-3, 1, 0.3, false});
  m.control.end_time = 1;
  m.node_groups["head_skin"] = m.group("zmax");
  EXPECT_EQ(bad_input_message([&] { solve::check_model(m); }), "no error");
  for (double to_unit : {1e-3, 0.1}) {
    solve::Model scaled = m;
    for (double& x : scaled.X) x *= to_unit;
    const std::string message = bad_input_message([&] { solve::check_model(scaled); });
    EXPECT_EQ(message.rfind(scaled.name + ": largest extent " + pipeline::format_number(200 * to_unit) +
                                " mm, but a head is about 250 mm: ",
                            0),
              0u)
        << message;
    scaled.node_groups.erase("head_skin");
    EXPECT_EQ(bad_input_message([&] { solve::check_model(scaled); }), "no error");
  }
}

// An inverted element is named so that it can be found: by its place in the part (1-based) and its
// centroid. It was "wedge6 element 100", a 0-based index within the part that neither gmsh nor
// the file shows (its gmsh tag was 36873).
TEST(check_model, an_inverted_element_is_named_by_where_it_is) {
  solve::BlockSpec b;
  b.type = solve::ElementType::wedge6;
  b.nx = 2; b.ny = 2; b.nz = 1;
  b.size = {2, 2, 1};
  solve::Model m = solve::make_block(b, {"m", 1e-3, 1, 0.3, false});
  m.control.end_time = 1;
  std::vector<int>& conn = m.parts[0].conn;
  const std::size_t e = 3;  // the 4th element: swap its two end triangles, turning it inside out
  for (int a = 0; a < 3; ++a) std::swap(conn[6 * e + std::size_t(a)], conn[6 * e + 3 + std::size_t(a)]);
  const std::string message = bad_input_message([&] { solve::Solver s(m); });
  EXPECT_NE(message.find("part 'block': wedge6 element 4 of the part, centred at ("), std::string::npos) << message;
  EXPECT_NE(message.find(" mm, is inverted or degenerate (Jacobian -"), std::string::npos) << message;
}

// A one-sided master whose triangles face into the solid they lie on (a model edited by hand) is
// refused when the deck is read: it showed only as a 6 mm "penetration" at the first step, or not
// at all where no slave lay over it. Two-sided masters have no outside and are not judged.
TEST(apply_deck, a_master_facing_into_its_solid_is_refused) {
  const solve::Model base = solve::make_block({}, {"m", 1e-3, 1, 0.3, false});
  const auto message = [&](bool flip, bool two_sided) {
    solve::Model m = base;
    if (flip)
      for (auto& t : m.surfaces.at("zmax")) std::swap(t[1], t[2]);
    const std::string deck =
        R"({"materials": {"m": {"density": 1e-3, "E": 1, "nu": 0.3}}, "parts": [{"group": "block", "material": "m"}], )"
        R"("contact": [{"slave": "zmin", "master": "zmax", "two_sided": )" + std::string(two_sided ? "true" : "false") +
        R"(}], "control": {"end_time": 1}})";
    return bad_input_message([&] { solve::apply_deck(m, deck, "d.json"); });
  };
  EXPECT_EQ(message(false, false), "no error");
  const std::size_t n = base.surfaces.at("zmax").size();
  EXPECT_EQ(message(true, false), "d.json: contact 'zmin_on_zmax': " + std::to_string(n) + " of the " +
                                      std::to_string(n) + " triangles of master 'zmax' face into the solid they lie on "
                                      "(the first centred at (0.3, 0.2, 1.0) mm): a master faces outward by the "
                                      "right-hand rule (or give the pair two_sided)");
  EXPECT_EQ(message(true, true), "no error");
}
