#pragma once
// Shared by the align tests: random poses, metre files, and frame comparison.
#include <Eigen/Geometry>
#include <algorithm>
#include <vector>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "pipeline/write_mesh.h"
#include "scan2cad/align.h"
#include "../scratch_dir.h"

namespace align_test {

inline std::string data(const std::string& rel) { return std::string(SHARED_DATA_DIR) + "/" + rel; }

/// A random rigid pose [mm]: uniform random rotation, translation up to ±500 mm per axis.
inline Eigen::Matrix4d random_pose(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(-500.0, 500.0);
  Eigen::Quaterniond q(N(rng), N(rng), N(rng), N(rng));
  q.normalize();
  Eigen::Matrix4d G = Eigen::Matrix4d::Identity();
  G.block<3, 3>(0, 0) = q.toRotationMatrix();
  G.block<3, 1>(0, 3) = Eigen::Vector3d(U(rng), U(rng), U(rng));
  return G;
}

/// Writes `mesh` moved by G and converted to metres to a temporary PLY, reads it back through
/// the user path (unit detection, soup repair) and returns it [mm].
inline pipeline::SurfaceMesh posed_in_metres(pipeline::SurfaceMesh mesh, const Eigen::Matrix4d& G,
                                             const std::string& name, double expected_mm,
                                             unsigned shuffle_seed = 42) {
  Eigen::Matrix4d S = G;
  S.topRows(3) *= 1e-3;  // mm → m
  scan2cad::apply_transform(mesh, S);
  // Shuffle the face order so the posed copy is sampled differently (otherwise the fixed-seed
  // sampling would see exactly the moved samples and the test could not show sampling noise).
  // With the same shuffle, every pose sees the same samples (moved): vary `shuffle_seed` with the
  // pose to see different samplings.
  std::vector<pipeline::FaceIndex> fs(mesh.faces().begin(), mesh.faces().end());
  std::shuffle(fs.begin(), fs.end(), std::mt19937(shuffle_seed));
  pipeline::SurfaceMesh shuffled;
  for (auto v : mesh.vertices()) shuffled.add_vertex(mesh.point(v));
  for (auto f : fs) {
    std::vector<pipeline::VertexIndex> vs;
    for (auto v : vertices_around_face(mesh.halfedge(f), mesh)) vs.push_back(v);
    shuffled.add_face(vs);
  }
  mesh = shuffled;
  const auto dir = scratch_dir() / "metres";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / (name + ".ply")).string();
  pipeline::write_surface_mesh(path, mesh);
  pipeline::Unit unit = pipeline::Unit::automatic;
  auto back = scan2cad::load_surface_any_unit(path, expected_mm, &unit);
  EXPECT_EQ(unit, pipeline::Unit::m) << "metres detected";
  return back;
}

/// Rotation angle [deg] and origin offset [mm] between two rigid transforms.
inline void frame_error(const Eigen::Matrix4d& A, const Eigen::Matrix4d& B, double& angle_deg, double& offset_mm) {
  const Eigen::Matrix3d D = A.block<3, 3>(0, 0) * B.block<3, 3>(0, 0).transpose();
  angle_deg = std::acos(std::clamp((D.trace() - 1.0) / 2.0, -1.0, 1.0)) * 180.0 / M_PI;
  // Where each puts the same input point: compare the images of the original's frame origin.
  const Eigen::Vector4d o = B.inverse() * Eigen::Vector4d(0, 0, 0, 1);
  offset_mm = (A * o).head<3>().norm();
}

}  // namespace align_test
