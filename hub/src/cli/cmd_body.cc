// `body define`: a rigid body from a capture's markers into the installation's bodies file, and
// `body list`: what the file holds.
//   body define INPUT --name N (--markers A,B,... | --auto) [--frames A:B] [-o bodies.json]
// INPUT is a marker file (.trc/.c3d) or a session directory holding markers.trc (or .c3d).
// --frames takes the file's Frame# numbers (1-based, inclusive); each marker's position is its
// median over those frames. --auto takes every marker present in 90 % of them: a static capture
// with only the object in the volume.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bodies/body_definition.h"
#include "cli/commands.h"
#include "io/trajectory_file.h"

namespace mocap {
namespace {

struct BodyDefineArgs {
  std::string input, name, markers, frames, output = "bodies.json";
  bool automatic = false;
};

std::string MarkerFileOf(const std::string& input) {
  if (!std::filesystem::is_directory(input)) return input;
  for (const char* name : {"markers.trc", "markers.c3d"}) {
    const std::filesystem::path path = std::filesystem::path(input) / name;
    if (std::filesystem::exists(path)) return path.string();
  }
  throw std::runtime_error(input + ": no markers.trc or markers.c3d; reconstruct the session first (mocap-hub "
                           "reconstruct " + input + " --calibration CAL.json -o " + input + "/markers.trc)");
}

// [first, last] frame numbers from "A:B" in Frame# terms (1-based).
std::pair<uint64_t, uint64_t> FrameRange(const std::string& text) {
  if (text.empty()) return {0, UINT64_MAX};
  unsigned long long a = 0, b = 0;
  char colon = 0;
  std::istringstream in(text);
  if (!(in >> a >> colon >> b) || colon != ':' || a < 1 || b < a || !in.eof())
    throw UsageError("--frames '" + text + "': expected A:B with 1 <= A <= B (the file's Frame# numbers)");
  return {a - 1, b - 1};
}

Eigen::Vector3d Median(std::vector<Eigen::Vector3d> samples) {
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> v;
    for (const auto& s : samples) v.push_back(s[k]);
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    out[k] = v[v.size() / 2];
  }
  return out;
}

void RunBodyDefine(const BodyDefineArgs& args) {
  if (args.automatic == !args.markers.empty()) throw UsageError("give either --markers or --auto");
  const std::string path = MarkerFileOf(args.input);
  const MarkerTrajectories t = ReadTrajectories(path);
  const auto [first, last] = FrameRange(args.frames);
  std::vector<size_t> rows;
  for (size_t f = 0; f < t.NumFrames(); ++f)
    if (t.frame_numbers[f] >= first && t.frame_numbers[f] <= last) rows.push_back(f);
  if (rows.empty()) throw std::runtime_error(path + ": no frames in " + (args.frames.empty() ? "the file" : args.frames));
  std::vector<size_t> chosen;
  if (args.automatic) {
    for (size_t m = 0; m < t.NumMarkers(); ++m) {
      size_t present = 0;
      for (size_t f : rows) present += t.Has(f, m);
      if (present >= 0.9 * static_cast<double>(rows.size())) chosen.push_back(m);
    }
  } else {
    std::stringstream in(args.markers);
    for (std::string item; std::getline(in, item, ',');) {
      auto named = std::find(t.names.begin(), t.names.end(), item);
      size_t m = static_cast<size_t>(named - t.names.begin());
      if (named == t.names.end()) {
        char* end = nullptr;
        const unsigned long column = std::strtoul(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || column < 1 || column > t.NumMarkers())
          throw UsageError("--markers: '" + item + "' is neither a marker name nor a column 1-" +
                           std::to_string(t.NumMarkers()) + " of " + path);
        m = column - 1;
      }
      chosen.push_back(m);
    }
  }
  // The chosen markers must move as one piece over the frames (a walking subject's do not).
  std::vector<std::vector<Eigen::Vector3d>> seen(rows.size());
  std::vector<std::string> names;
  for (size_t m : chosen) names.push_back(t.names[m]);
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t m : chosen)
      seen[i].push_back(t.Has(rows[i], m) ? t.At(rows[i], m)
                                         : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  if (const std::string problem = RigidityProblem(seen, names); !problem.empty())
    throw std::runtime_error(path + ": these " + std::to_string(chosen.size()) + " markers are " + problem);
  std::vector<Eigen::Vector3d> positions;
  for (size_t m : chosen) {
    std::vector<Eigen::Vector3d> samples;
    for (size_t f : rows)
      if (t.Has(f, m)) samples.push_back(t.At(f, m));
    if (samples.size() * 2 < rows.size())
      throw std::runtime_error(path + ": marker " + t.names[m] + " is missing in most of the frames chosen");
    positions.push_back(Median(samples));
  }
  std::vector<RigidBodyDefinition> bodies;
  if (std::filesystem::exists(args.output)) bodies = ReadBodiesFile(args.output);
  RigidBodyDefinition body;
  try {
    body = DefineBody(args.name, positions);
    AddBody(bodies, body);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());  // the data's fault, not the command line's
  }
  WriteBodiesFile(bodies, args.output);
  std::printf("%s: body '%s' with %zu markers from %zu frames of %s (%zu bodies in the file)\n", args.output.c_str(),
              body.name.c_str(), body.markers.size(), rows.size(), path.c_str(), bodies.size());
}

}  // namespace

void AddBodyCommands(CLI::App& app) {
  CLI::App& body = CommandGroup(app, "body");
  CLI::App* define = body.add_subcommand("define", "Define a rigid body from a capture's markers (bodies file)");
  auto args = std::make_shared<BodyDefineArgs>();
  define->add_option("input", args->input, "Marker file (.trc/.c3d) or session directory with markers.trc")
      ->required()
      ->check(CLI::ExistingPath);
  define->add_option("--name", args->name, "The body's name")->required();
  define->add_option("--markers", args->markers, "Its markers: names or 1-based columns, comma-separated");
  define->add_flag("--auto", args->automatic, "Every marker present in 90 % of the frames (a static capture)");
  define->add_option("--frames", args->frames, "Frames A:B (the file's Frame#, inclusive); default all");
  define->add_option("-o,--output", args->output, "Bodies file to add it to (created if missing)")
      ->capture_default_str();
  define->callback([args] { RunBodyDefine(*args); });

  CLI::App* list = body.add_subcommand("list", "The bodies of a bodies file");
  auto file = std::make_shared<std::string>("bodies.json");
  list->add_option("file", *file, "Bodies file")->capture_default_str()->check(CLI::ExistingFile);
  list->callback([file] {
    for (const RigidBodyDefinition& b : ReadBodiesFile(*file)) {
      double extent = 0.0;
      for (const auto& m : b.markers)
        for (const auto& n : b.markers) extent = std::max(extent, (m - n).norm());
      std::printf("%-20s %2zu markers, %.1f mm across, pivot (%.1f, %.1f, %.1f)\n", b.name.c_str(), b.markers.size(),
                  extent, b.pivot.x(), b.pivot.y(), b.pivot.z());
    }
  });
}

}  // namespace mocap
