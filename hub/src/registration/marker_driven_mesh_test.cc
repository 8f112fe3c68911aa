// A simulated face: markers glued to a known, smoothly deforming surface (a dome with a nose, a
// jaw that opens, cheeks that rise, brows that lift) on a moving head; the mesh comes in its own
// frame. Binding must find the mesh's place from the static frame alone, and the driven vertices
// between the markers must follow the true surface within 1 mm RMS with either kernel, also when
// markers drop out.
#include "registration/marker_driven_mesh.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "io/marker_trajectories.h"

namespace mocap {
namespace {

constexpr int kFrames = 60;

double Logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }
double Bump(double du, double dv, double width) { return std::exp(-(du * du + dv * dv) / (2 * width * width)); }

// The surface point of material coordinates (u, v) at frame t, in the capture's frame (mm).
Eigen::Vector3d FacePoint(double u, double v, int t) {
  const double s = 0.5 - 0.5 * std::cos(2 * M_PI * t / kFrames);   // jaw
  const double s2 = 0.5 - 0.5 * std::cos(4 * M_PI * t / kFrames);  // smile, twice as fast
  const double s3 = std::sin(2 * M_PI * t / kFrames);              // brows up and down
  const double height = 50 * Bump(u / 55.0 * 50.0, v / 75.0 * 50.0, 50.0) + 12 * Bump(u, v - 5, 12.0);
  const double jaw = Logistic(-(v + 10) / 15.0);
  const double cheeks = Bump(u - 35, v + 15, 22.0) + Bump(u + 35, v + 15, 22.0);
  Eigen::Vector3d local(u + 3 * s2 * std::tanh(u / 30.0) * Bump(0, v + 15, 30.0),
                        v - 12 * s * jaw + 4 * s3 * Bump(0, v - 50, 20.0),
                        height - 4 * s * jaw + 5 * s2 * cheeks);
  const Eigen::Matrix3d head = (Eigen::AngleAxisd(0.26 * std::sin(2 * M_PI * t / kFrames), Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(0.14 * s, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
  return head * local + Eigen::Vector3d(30 * std::sin(2 * M_PI * t / kFrames), 1600 + 10 * s, 200);
}

struct Face {
  std::vector<Eigen::Vector2d> marker_uv, vertex_uv;
  std::vector<Eigen::Vector3d> mesh_vertices;  // in the mesh's own frame
  std::vector<std::vector<int>> faces;        // quads of the vertex grid
  SimilarityTransform mesh_from_capture;
  std::vector<bool> between_markers;           // vertex inside the markers' span
};

Face MakeFace() {
  Face face;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-4, 4);
  for (double u = -60; u <= 60; u += 24)
    for (double v = -80; v <= 88; v += 24) face.marker_uv.emplace_back(u + jitter(rng), v + jitter(rng));
  face.mesh_from_capture.rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, -0.4).normalized()).toRotationMatrix();
  face.mesh_from_capture.translation = Eigen::Vector3d(-250, 40, -1700);
  const int columns = 57, rows = 73;  // 2.5 mm apart over 140 x 180 mm
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < rows; ++j) {
      const double u = -70 + 2.5 * i, v = -90 + 2.5 * j;
      face.vertex_uv.emplace_back(u, v);
      face.mesh_vertices.push_back(face.mesh_from_capture.Apply(FacePoint(u, v, 0)));
      face.between_markers.push_back(std::abs(u) <= 56 && v >= -76 && v <= 80);
      if (i + 1 < columns && j + 1 < rows) {
        const int a = i * rows + j;
        face.faces.push_back({a, a + rows, a + rows + 1, a + 1});
      }
    }
  return face;
}

std::vector<Eigen::Vector3d> MarkersAt(const Face& face, int t) {
  std::vector<Eigen::Vector3d> markers;
  for (const Eigen::Vector2d& uv : face.marker_uv) markers.push_back(FacePoint(uv.x(), uv.y(), t));
  return markers;
}

// RMS over the vertices between the markers, all frames; markers listed in `dropped` are gaps in
// odd frames.
double DrivenRms(const Face& face, MarkerDrivenMesh* mesh, const std::vector<size_t>& dropped) {
  double sum = 0.0;
  size_t count = 0;
  std::vector<Eigen::Vector3d> vertices;
  for (int t = 0; t < kFrames; ++t) {
    std::vector<Eigen::Vector3d> markers = MarkersAt(face, t);
    if (t % 2 == 1)
      for (size_t m : dropped) markers[m] = MarkerTrajectories::Gap();
    EXPECT_TRUE(mesh->Deform(markers, &vertices));
    for (size_t i = 0; i < vertices.size(); ++i) {
      if (!face.between_markers[i]) continue;
      sum += (vertices[i] - FacePoint(face.vertex_uv[i].x(), face.vertex_uv[i].y(), t)).squaredNorm();
      ++count;
    }
  }
  return std::sqrt(sum / static_cast<double>(count));
}

TEST(MarkerDrivenMesh, SimulatedFaceWithinOneMillimetre) {
  const Face face = MakeFace();
  ASSERT_GE(face.marker_uv.size(), 40u);
  for (RbfKernel kernel : {RbfKernel::kThinPlate, RbfKernel::kGaussian}) {
    MarkerDrivenMeshOptions options;
    options.rbf.kernel = kernel;
    MarkerDrivenMesh mesh(face.mesh_vertices, face.faces, MarkersAt(face, 0), options);
    // The binding placed the mesh: its rotation within 0.5 degrees of the truth.
    const Eigen::Matrix3d error = mesh.capture_from_mesh().rotation * face.mesh_from_capture.rotation;
    EXPECT_LT(Eigen::AngleAxisd(error).angle(), 0.5 * M_PI / 180.0) << RbfKernelName(kernel);
    const double rms = DrivenRms(face, &mesh, {});
    const double rms_dropped = DrivenRms(face, &mesh, {3, 17, 30});
    std::printf("%s: %.3f mm RMS between markers, %.3f mm with 3 markers missing in odd frames\n",
                RbfKernelName(kernel).c_str(), rms, rms_dropped);
    EXPECT_LT(rms, 1.0) << RbfKernelName(kernel);
    EXPECT_LT(rms_dropped, 1.0) << RbfKernelName(kernel);
  }
}

TEST(MarkerDrivenMesh, DeformingWithoutMarkerMotionKeepsTheBoundMesh) {
  const Face face = MakeFace();
  MarkerDrivenMesh mesh(face.mesh_vertices, face.faces, MarkersAt(face, 0), MarkerDrivenMeshOptions{});
  std::vector<Eigen::Vector3d> vertices;
  ASSERT_TRUE(mesh.Deform(MarkersAt(face, 0), &vertices));
  for (size_t i = 0; i < vertices.size(); ++i) ASSERT_LT((vertices[i] - mesh.bound_vertices()[i]).norm(), 1e-9);
}

TEST(MarkerDrivenMesh, RefusalsAndTooFewMarkers) {
  const Face face = MakeFace();
  std::vector<Eigen::Vector3d> three = MarkersAt(face, 0);
  for (size_t i = 3; i < three.size(); ++i) three[i] = MarkerTrajectories::Gap();
  EXPECT_THROW(MarkerDrivenMesh(face.mesh_vertices, face.faces, three, MarkerDrivenMeshOptions{}), std::invalid_argument);
  // Markers from elsewhere: far from any vertex after the best rigid fit.
  std::vector<Eigen::Vector3d> scattered;
  for (int i = 0; i < 20; ++i) scattered.emplace_back(400.0 * std::sin(i), 300.0 * std::cos(3 * i), 150.0 * i);
  EXPECT_THROW(MarkerDrivenMesh(face.mesh_vertices, face.faces, scattered, MarkerDrivenMeshOptions{}), std::invalid_argument);

  MarkerDrivenMesh mesh(face.mesh_vertices, face.faces, MarkersAt(face, 0), MarkerDrivenMeshOptions{});
  std::vector<Eigen::Vector3d> vertices = {Eigen::Vector3d::Zero()};
  EXPECT_FALSE(mesh.Deform(three, &vertices));
  EXPECT_EQ(vertices.size(), 1u);  // untouched
}

}  // namespace
}  // namespace mocap
