// `mesh drive`: an OBJ mesh bound to a capture's markers at a static frame (rigid ICP + Kabsch,
// then RBF weights; registration/marker_driven_mesh.h) and deformed by every frame, written as a
// point cache Blender reads (.pc2 or .mdd) in the capture's frame; --bound-mesh writes the mesh
// as bound (the OBJ to import in Blender under the cache).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "archive/archive_format.h"
#include "cli/commands.h"
#include "io/trajectory_file.h"
#include "registration/marker_driven_mesh.h"
#include "registration/mesh_binding_file.h"
#include "registration/obj_mesh.h"
#include "registration/point_cache.h"

namespace mocap {
namespace {

struct MeshDriveArgs {
  std::string mesh, markers, output, bound_mesh, binding, kernel = "thin-plate";
  size_t static_frame = 0;
  MarkerDrivenMeshOptions options;
  bool json = false;
};

void RunMeshDrive(const MeshDriveArgs& args) {
  MarkerDrivenMeshOptions options = args.options;
  try {
    options.rbf.kernel = RbfKernelFromName(args.kernel);
    PointCacheFormatOf(args.output);
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  CheckOptions(options);
  const ObjMesh mesh = ReadObj(args.mesh);
  std::string markers_path = args.markers;
  if (std::filesystem::is_directory(markers_path)) markers_path = (std::filesystem::path(markers_path) / "markers.trc").string();
  const MarkerTrajectories motion =
      IsArchivePath(markers_path) ? DecompressTrajectories(ReadArchiveFile(markers_path)) : ReadTrajectories(markers_path);
  if (args.static_frame >= motion.NumFrames())
    throw UsageError("--static-frame: " + std::to_string(args.static_frame) + " is past the capture's " +
                     std::to_string(motion.NumFrames()) + " frames");
  const auto frame_markers = [&](size_t f) {
    return std::vector<Eigen::Vector3d>(motion.points.begin() + static_cast<std::ptrdiff_t>(f * motion.NumMarkers()),
                                        motion.points.begin() + static_cast<std::ptrdiff_t>((f + 1) * motion.NumMarkers()));
  };
  std::unique_ptr<MarkerDrivenMesh> driven;
  try {
    driven = std::make_unique<MarkerDrivenMesh>(mesh.vertices, mesh.faces, frame_markers(args.static_frame), options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(args.mesh + " on " + markers_path + " frame " + std::to_string(args.static_frame) + ": " +
                             error.what());
  }
  if (!args.bound_mesh.empty()) WriteObj(mesh, args.bound_mesh, &driven->bound_vertices());
  if (!args.binding.empty()) {
    try {
      WriteMeshBindingFile(EncodeMeshBinding(*driven, motion.names, mesh.faces), args.binding);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(args.binding + ": " + error.what());
    }
  }
  PointCacheWriter writer;
  writer.Open(args.output, mesh.vertices.size(), motion.NumFrames(), motion.rate_hz);
  std::vector<Eigen::Vector3d> vertices = driven->bound_vertices();
  size_t held = 0;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    if (!driven->Deform(frame_markers(f), &vertices)) ++held;  // fewer than 4 markers: the last shape stays
    writer.WriteFrame(vertices);
  }
  writer.Close();
  if (args.json) {
    const nlohmann::json out = {{"point_cache", args.output}, {"vertices", mesh.vertices.size()},
                                {"frames", motion.NumFrames()}, {"driving_markers", driven->NumDrivingMarkers()},
                                {"alignment_rms_mm", driven->alignment_rms_mm()}, {"held_frames", held}};
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%s: %zu vertices x %zu frames at %g Hz, driven by %zu markers (%s); mesh placed %.3f mm RMS from "
                "the static markers; %zu frame(s) held for want of 4 markers\n",
                args.output.c_str(), mesh.vertices.size(), motion.NumFrames(), motion.rate_hz,
                driven->NumDrivingMarkers(), args.kernel.c_str(), driven->alignment_rms_mm(), held);
  }
}

}  // namespace

void AddMeshDriveCommand(CLI::App& app) {
  CLI::App* command = CommandGroup(app, "mesh").add_subcommand(
      "drive", "Bind an OBJ mesh to the markers of a static frame and write its motion as a point cache (.pc2/.mdd)");
  auto args = std::make_shared<MeshDriveArgs>();
  command->add_option("--mesh", args->mesh, "Mesh to drive (.obj), in any frame and pose")->required()->check(CLI::ExistingFile);
  command->add_option("--markers", args->markers, "Capture: marker file (.trc, .c3d, .mca) or session directory")
      ->required()
      ->check(CLI::ExistingPath);
  command->add_option("--static-frame", args->static_frame, "Frame index (0-based row) the mesh is bound at");
  command->add_option("--kernel", args->kernel, "RBF kernel: thin-plate or gaussian");
  command->add_option("--gaussian-width-mm", args->options.rbf.gaussian_width_mm,
                      "Gaussian kernel width, mm (default: twice the markers' mean spacing)")
      ->check(FiniteRange(0, 1e6));
  command->add_option("--max-alignment-rms-mm", args->options.max_alignment_rms_mm,
                      "Refuse a binding whose markers lie farther than this from the mesh after ICP, mm")
      ->check(FiniteRange(1e-3, 1e6));
  command->add_option("--bound-mesh", args->bound_mesh, "Also write the mesh as bound, in the capture's frame (.obj)");
  command->add_option("--binding", args->binding,
                      "Also write the binding the console plays (.mdb: bound vertices, triangles, RBF weights)");
  command->add_option("-o,--output", args->output, "Point cache to write (.pc2 or .mdd)")->required();
  command->add_flag("--json", args->json, "Print one JSON object");
  command->callback([args] { RunMeshDrive(*args); });
}

}  // namespace mocap
