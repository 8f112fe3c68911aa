// `register SOURCE TARGET`: aligns two point sets, each an OBJ mesh's vertices or one frame of a
// marker file: rigid (Kabsch on same-named markers when both are marker files sharing 3 or more
// names, rigid ICP otherwise), then optionally non-rigid (RBF, thin-plate or Gaussian). Prints the
// motion and the residuals; -o writes the registered source (an OBJ keeps its faces).
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "archive/archive_format.h"
#include "cli/commands.h"
#include "geometry/rigid_fit.h"
#include "io/trajectory_file.h"
#include "registration/obj_mesh.h"
#include "registration/rbf.h"
#include "registration/rigid_icp.h"

namespace mocap {
namespace {

// The RBF solve is dense: (centres + 4)^2 doubles, 32 MB at this bound.
constexpr size_t kMaxRbfCentres = 2000;

struct PointSet {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::string> names;  // markers only
  bool is_mesh = false;
  ObjMesh mesh;
  double rate_hz = 0.0;
};

bool IsObjPath(const std::string& path) {
  return path.size() >= 4 && (path.compare(path.size() - 4, 4, ".obj") == 0 || path.compare(path.size() - 4, 4, ".OBJ") == 0);
}

PointSet LoadPointSet(const std::string& path, size_t frame) {
  PointSet set;
  if (IsObjPath(path)) {
    set.is_mesh = true;
    set.mesh = ReadObj(path);
    set.points = set.mesh.vertices;
    return set;
  }
  const MarkerTrajectories motion =
      IsArchivePath(path) ? DecompressTrajectories(ReadArchiveFile(path)) : ReadTrajectories(path);
  if (frame >= motion.NumFrames())
    throw UsageError(path + ": frame index " + std::to_string(frame) + " is past its " +
                     std::to_string(motion.NumFrames()) + " frames");
  for (size_t m = 0; m < motion.NumMarkers(); ++m)
    if (motion.Has(frame, m)) {
      set.points.push_back(motion.At(frame, m));
      set.names.push_back(motion.names[m]);
    }
  set.rate_hz = motion.rate_hz;
  return set;
}

struct RegisterArgs {
  std::string source, target, output;
  size_t source_frame = 0, target_frame = 0;
  std::string rbf = "none";
  RbfOptions rbf_options;
  RigidIcpOptions icp;
  bool json = false;
};

// Source-target pairs by marker name, when both sets are markers.
std::vector<std::pair<size_t, size_t>> NamedPairs(const PointSet& source, const PointSet& target) {
  std::vector<std::pair<size_t, size_t>> pairs;
  if (source.is_mesh || target.is_mesh) return pairs;
  std::map<std::string, size_t> index;
  for (size_t j = 0; j < target.names.size(); ++j) index[target.names[j]] = j;
  for (size_t i = 0; i < source.names.size(); ++i) {
    const auto found = index.find(source.names[i]);
    if (found != index.end()) pairs.emplace_back(i, found->second);
  }
  return pairs;
}

double PairRms(const std::vector<Eigen::Vector3d>& moved, const PointSet& target,
               const std::vector<std::pair<size_t, size_t>>& pairs) {
  double sum = 0.0;
  for (const auto& [i, j] : pairs) sum += (moved[i] - target.points[j]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(pairs.size()));
}

// Pairs for the non-rigid step and for the residual: by name, else each point of the smaller set
// with its nearest point in the larger one.
std::vector<std::pair<size_t, size_t>> NearestPairs(const std::vector<Eigen::Vector3d>& moved, const PointSet& target) {
  std::vector<std::pair<size_t, size_t>> pairs;
  if (moved.size() <= target.points.size()) {
    const NearestPoints nearest(target.points);
    for (size_t i = 0; i < moved.size(); ++i) pairs.emplace_back(i, nearest.Nearest(moved[i], nullptr));
  } else {
    const NearestPoints nearest(moved);
    for (size_t j = 0; j < target.points.size(); ++j) pairs.emplace_back(nearest.Nearest(target.points[j], nullptr), j);
  }
  return pairs;
}

void RunRegister(const RegisterArgs& args) {
  CheckOptions(args.icp);
  CheckOptions(args.rbf_options);
  if (args.rbf != "none") {
    try {
      RbfKernelFromName(args.rbf);
    } catch (const std::invalid_argument& error) {
      throw UsageError(std::string("--rbf: ") + error.what() + " (or none)");
    }
  }
  const PointSet source = LoadPointSet(args.source, args.source_frame);
  const PointSet target = LoadPointSet(args.target, args.target_frame);
  if (!args.output.empty()) {
    if (source.is_mesh && !IsObjPath(args.output))
      throw UsageError("-o: '" + args.output + "' must be an .obj, as the source is a mesh");
    try {
      if (!source.is_mesh) OutputTrajectoryFormatOf(args.output);
    } catch (const std::invalid_argument& error) {
      throw UsageError(std::string("-o: ") + error.what());
    }
  }
  if (source.points.size() < 3 || target.points.size() < 3)
    throw std::runtime_error("register: " + std::to_string(source.points.size()) + " source and " +
                             std::to_string(target.points.size()) + " target points; at least 3 each");
  std::vector<std::pair<size_t, size_t>> named = NamedPairs(source, target);
  if (named.size() < 3) named.clear();
  SimilarityTransform transform;
  std::string method;
  if (!named.empty()) {
    std::vector<Eigen::Vector3d> from, to;
    for (const auto& [i, j] : named) {
      from.push_back(source.points[i]);
      to.push_back(target.points[j]);
    }
    transform = FitRigid(from, to);
    method = "kabsch by name (" + std::to_string(named.size()) + " markers)";
  } else {
    // A mesh target's faces give normals: point-to-plane refinement after the nearest-vertex ICP.
    const std::vector<Eigen::Vector3d> normals =
        target.is_mesh ? VertexNormals(target.mesh.vertices, target.mesh.faces) : std::vector<Eigen::Vector3d>{};
    const bool planes = target.is_mesh && !target.mesh.faces.empty();
    transform = AlignRigidIcp(source.points, target.points, args.icp, planes ? &normals : nullptr).target_from_source;
    method = planes ? "rigid ICP (point-to-plane on the target's faces)" : "rigid ICP";
  }
  std::vector<Eigen::Vector3d> moved;
  for (const Eigen::Vector3d& p : source.points) moved.push_back(transform.Apply(p));
  const auto pairs_of = [&](const std::vector<Eigen::Vector3d>& points) {
    return named.empty() ? NearestPairs(points, target) : named;
  };
  const std::vector<std::pair<size_t, size_t>> rigid_pairs = pairs_of(moved);
  const double rigid_rms = PairRms(moved, target, rigid_pairs);
  double final_rms = rigid_rms;
  if (args.rbf != "none") {
    RbfOptions options = args.rbf_options;
    options.kernel = RbfKernelFromName(args.rbf);
    // Centres: the source side of each pair (one per source point at most), moved onto its target.
    std::vector<Eigen::Vector3d> centres;
    std::vector<bool> used(moved.size(), false);
    std::vector<Eigen::Vector3d> shifts;
    for (const auto& [i, j] : rigid_pairs) {
      if (used[i]) continue;
      used[i] = true;
      centres.push_back(moved[i]);
      shifts.push_back(target.points[j] - moved[i]);
    }
    if (centres.size() > kMaxRbfCentres)
      throw std::runtime_error("register: " + std::to_string(centres.size()) + " RBF centres, more than " +
                               std::to_string(kMaxRbfCentres) +
                               " (the RBF system is dense): make the smaller set (markers) one of the two");
    Eigen::MatrixXd values(static_cast<Eigen::Index>(shifts.size()), 3);
    for (size_t k = 0; k < shifts.size(); ++k) values.row(static_cast<Eigen::Index>(k)) = shifts[k].transpose();
    const Eigen::MatrixXd shift = RbfInterpolator(centres, options).Interpolate(moved, values);
    for (size_t i = 0; i < moved.size(); ++i) moved[i] += shift.row(static_cast<Eigen::Index>(i)).transpose();
    final_rms = PairRms(moved, target, pairs_of(moved));
    method += " + " + args.rbf + " RBF (" + std::to_string(centres.size()) + " centres)";
  }
  if (!args.output.empty()) {
    if (source.is_mesh) {
      WriteObj(source.mesh, args.output, &moved);
    } else {
      MarkerTrajectories out;
      out.rate_hz = source.rate_hz;
      out.names = source.names;
      out.AddFrame(0);
      for (size_t i = 0; i < moved.size(); ++i) out.At(0, i) = moved[i];
      WriteTrajectories(out, args.output);
    }
  }
  const Eigen::Matrix3d& r = transform.rotation;
  if (args.json) {
    nlohmann::json rotation = nlohmann::json::array();
    for (int row = 0; row < 3; ++row) rotation.push_back({r(row, 0), r(row, 1), r(row, 2)});
    const nlohmann::json out = {{"method", method},
                                {"rotation", rotation},
                                {"translation", {transform.translation.x(), transform.translation.y(), transform.translation.z()}},
                                {"pairs", rigid_pairs.size()},
                                {"rigid_rms_mm", rigid_rms},
                                {"rms_mm", final_rms}};
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%s: %zu source points onto %zu target points\n", method.c_str(), source.points.size(),
                target.points.size());
    std::printf("target_from_source rotation [[%.6f %.6f %.6f] [%.6f %.6f %.6f] [%.6f %.6f %.6f]] translation "
                "[%.3f %.3f %.3f] mm\n",
                r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2),
                transform.translation.x(), transform.translation.y(), transform.translation.z());
    std::printf("residual over %zu pairs: %.3f mm RMS rigid, %.3f mm RMS final\n", rigid_pairs.size(), rigid_rms,
                final_rms);
  }
}

}  // namespace

void AddRegisterCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "register", "Align two point sets (OBJ vertices or one frame of markers): rigid ICP/Kabsch, then optional RBF");
  auto args = std::make_shared<RegisterArgs>();
  command->add_option("source", args->source, "Set to move: .obj, or a marker file (.trc, .c3d, .mca)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("target", args->target, "Set to align onto: .obj, or a marker file")->required()->check(CLI::ExistingFile);
  command->add_option("--source-frame", args->source_frame, "Frame index (0-based row) of a marker source");
  command->add_option("--target-frame", args->target_frame, "Frame index (0-based row) of a marker target");
  command->add_option("--rbf", args->rbf, "Non-rigid step after the rigid one: none, thin-plate or gaussian");
  command->add_option("--gaussian-width-mm", args->rbf_options.gaussian_width_mm,
                      "Gaussian kernel width, mm (default: twice the mean spacing of the centres)")
      ->check(FiniteRange(0, 1e6));
  command->add_option("--max-iterations", args->icp.max_iterations, "ICP iterations per start (1-10000)");
  command->add_option("--max-pair-distance-mm", args->icp.max_pair_distance_mm,
                      "ICP leaves out pairs farther apart than this, mm (0: none)")
      ->check(FiniteRange(0, 1e9));
  command->add_option("-o,--output", args->output, "Registered source: .obj for a mesh source, else .trc/.c3d");
  command->add_flag("--json", args->json, "Print one JSON object");
  command->callback([args] { RunRegister(*args); });
}

}  // namespace mocap
