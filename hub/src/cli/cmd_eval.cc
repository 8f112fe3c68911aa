// `eval`: reconstruction accuracy of a result TRC against the truth TRC (DESIGN.md metrics).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "eval/body_accuracy.h"
#include "scoring/marker_accuracy.h"
#include "io/live_points.h"
#include "io/trajectory_file.h"
#include "io/visibility.h"

namespace mocap {
namespace {

struct EvalArgs {
  std::string truth;
  std::string result;
  std::string session;
  std::string visibility;
  bool json = false;
  MarkerEvalOptions options;
  std::string bodies_truth, bodies_result;  // pose files (sim project --bodies, reconstruct --bodies)
};

void RunEval(const EvalArgs& args) {
  CheckOptions(args.options);
  const MarkerTrajectories truth = ReadTrajectories(args.truth);
  // A capture's live_points.tsv judges what serve published live, frame by frame.
  const bool live = std::filesystem::path(args.result).extension() == ".tsv";
  std::optional<LivePoints> live_points;
  if (live) live_points = ReadLivePoints(args.result);
  const MarkerTrajectories result = live ? std::move(live_points->points) : ReadTrajectories(args.result);
  std::string visibility_path = args.visibility;
  if (visibility_path.empty() && !args.session.empty()) {
    visibility_path = (std::filesystem::path(args.session) / "visibility.tsv").string();
    if (!std::filesystem::exists(visibility_path)) {
      throw std::runtime_error(args.session + ": session has no visibility.tsv (not a simulated session?)");
    }
  }
  std::optional<MarkerVisibility> visibility;
  if (!visibility_path.empty()) visibility = ReadVisibility(visibility_path);
  MarkerEvalReport report;
  try {
    report = EvaluateMarkers(truth, result, visibility ? &*visibility : nullptr, args.options,
                             live_points ? &live_points->identity : nullptr);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(std::string("cannot compare ") + args.truth + " and " + args.result + ": " +
                             error.what());
  }
  std::optional<BodyEvalReport> bodies;
  if (!args.bodies_truth.empty()) {
    const std::string result_poses = args.bodies_result.empty()
                                         ? args.result.substr(0, args.result.find_last_of('.')) + ".bodies.tsv"
                                         : args.bodies_result;
    try {
      bodies = EvaluateBodies(ReadBodyPoses(args.bodies_truth), ReadBodyPoses(result_poses),
                              visibility ? &*visibility : nullptr);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(std::string("cannot compare ") + args.bodies_truth + " and " + result_poses + ": " +
                               error.what());
    }
  }
  if (args.json) {
    nlohmann::json out = report.ToJson();
    if (bodies) out["rigid_bodies"] = bodies->ToJson();
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::fputs(report.ToText().c_str(), stdout);
    if (bodies) std::fputs(bodies->ToText().c_str(), stdout);
  }
}

}  // namespace

void AddEvalCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("eval", "Accuracy of reconstructed markers against the truth");
  auto args = std::make_shared<EvalArgs>();
  command->add_option("--truth", args->truth, "Ground-truth TRC (e.g. SESSION/truth.trc)")->required();
  command->add_option("--result", args->result, "Reconstructed TRC, or a capture's live_points.tsv")->required();
  CLI::Option* session = command->add_option(
      "--session", args->session, "Simulated session: count as missing only markers >= 2 cameras saw");
  command->add_option("--visibility", args->visibility, "visibility.tsv to use instead of --session's")
      ->excludes(session);
  command->add_option("--gate-mm", args->options.gate_mm, "Matching gate, mm")->capture_default_str();
  command->add_option("--names-from-frame", args->options.names_from_frame,
                      "Name shares count each truth marker's points from its Nth frame on (live: after settling)")
      ->capture_default_str();
  command->add_option("--bodies-truth", args->bodies_truth,
                      "True rigid-body poses (SESSION/truth.bodies.tsv): pose errors of the result's bodies")
      ->check(CLI::ExistingFile);
  command->add_option("--bodies-result", args->bodies_result, "Result poses (default: RESULT with .bodies.tsv)")
      ->check(CLI::ExistingFile);
  command->add_flag("--json", args->json, "Print one JSON object on stdout");
  command->callback([args] { RunEval(*args); });
}

}  // namespace mocap
