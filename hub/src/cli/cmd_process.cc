// `process RECIPE SESSIONS...`: one processing recipe (pipeline/processing_recipe.h) applied to
// many recorded sessions, side by side (--jobs), each into SESSION/processed/NAME/: the markers
// (markers.trc and/or markers.c3d), the rigid bodies' poses when the recipe has bodies, and
// process.json (the recipe as applied, the calibration used, the outputs, when). A session's raw
// log and files are never written; results already there are kept unless --overwrite. A session
// that fails is reported and the others go on; the exit status is 1 when any failed.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/reconstruct_session.h"
#include "ingest/session.h"
#include "io/trajectory_file.h"
#include "pipeline/processing_recipe.h"
#include "util/regular_file.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxRecipeBytes = 1 << 20;

struct ProcessArgs {
  std::string recipe;
  std::vector<std::string> sessions;
  int jobs = 1;
  bool overwrite = false;
  std::string progress_file;
};

// The recipe with its relative paths made the recipe file's own.
pipeline::ProcessingRecipe LoadRecipe(const std::string& path) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(ReadRegularFile(path, kMaxRecipeBytes, "a processing recipe"));
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(path + ": not a JSON recipe (" + error.what() + ")");
  }
  pipeline::ProcessingRecipe recipe;
  try {
    recipe = pipeline::RecipeFromJson(doc, path);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(error.what());
  }
  const fs::path base = fs::absolute(path).parent_path();
  for (std::string* file : {&recipe.calibration, &recipe.labels, &recipe.bodies}) {
    if (file->empty() || fs::path(*file).is_absolute()) continue;
    *file = (base / *file).lexically_normal().string();
  }
  return recipe;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

void ProcessSession(const pipeline::ProcessingRecipe& recipe, const std::string& session, bool overwrite,
                    bool progress, const std::string& progress_file) {
  if (!fs::is_regular_file(fs::path(session) / "session.json"))
    throw std::runtime_error(session + ": not a session (no session.json)");
  const fs::path out = fs::path(session) / "processed" / recipe.name;
  if (fs::exists(out / "process.json") && !overwrite)
    throw std::runtime_error(session + ": already processed by recipe '" + recipe.name + "' (" + out.string() +
                             "); --overwrite replaces those results");
  fs::create_directories(out);
  ReconstructArgs args;
  args.session = session;
  args.calibration = recipe.calibration.empty() ? SessionCalibration(session) : recipe.calibration;
  args.force_calibration = recipe.force_calibration;
  args.output = (out / ("markers." + recipe.outputs.front())).string();
  args.matcher = recipe.matcher;
  args.assignment = recipe.assignment;
  args.no_predictions = !recipe.predictions;
  args.chain.hindsight.enabled = recipe.hindsight_swaps;
  args.chain.max_spline_gap_s = recipe.max_spline_gap_s;
  args.chain.recon.threads = recipe.threads;
  args.labels = recipe.labels;
  args.bodies = recipe.bodies;
  args.body_smoothing.half_window = recipe.bodies_window;
  args.body_smoothing.degree = recipe.bodies_degree;
  args.progress = progress;
  args.progress_file = progress_file;
  const std::string started = UtcNow();
  ReconstructSession(args);
  std::vector<std::string> files = {fs::path(args.output).filename().string()};
  if (recipe.outputs.size() > 1) {
    const fs::path second = out / ("markers." + recipe.outputs[1]);
    WriteTrajectories(ReadTrajectories(args.output), second.string());
    files.push_back(second.filename().string());
  }
  if (!recipe.bodies.empty()) files.push_back("markers.bodies.tsv");
  const nlohmann::json report = {{"format", "mocap-processed"},
                                 {"version", 1},
                                 {"session", fs::absolute(session).lexically_normal().string()},
                                 {"recipe", pipeline::RecipeToJson(recipe)},
                                 {"calibration", fs::absolute(args.calibration).lexically_normal().string()},
                                 {"outputs", files},
                                 {"started", started},
                                 {"finished", UtcNow()}};
  std::ofstream(out / "process.json") << report.dump(2) << "\n";
  std::printf("%s: processed by recipe '%s' into %s\n", session.c_str(), recipe.name.c_str(), out.c_str());
}

void RunProcess(const ProcessArgs& args) {
  if (!args.progress_file.empty() && args.sessions.size() != 1)
    throw UsageError("--progress-file follows one session; " + std::to_string(args.sessions.size()) + " were given");
  const pipeline::ProcessingRecipe recipe = LoadRecipe(args.recipe);
  const size_t jobs = std::min(static_cast<size_t>(args.jobs), args.sessions.size());
  std::atomic<size_t> next{0};
  std::mutex report_mutex;
  std::vector<std::string> failed;
  auto work = [&] {
    for (size_t i = next++; i < args.sessions.size(); i = next++) {
      try {
        ProcessSession(recipe, args.sessions[i], args.overwrite, jobs == 1, args.progress_file);
      } catch (const std::exception& error) {
        std::lock_guard<std::mutex> lock(report_mutex);
        std::fprintf(stderr, "mocap-hub: error: %s\n", error.what());
        failed.push_back(args.sessions[i]);
      }
    }
  };
  std::vector<std::thread> workers;
  for (size_t j = 1; j < jobs; ++j) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  std::fflush(stdout);
  if (!failed.empty()) {
    throw std::runtime_error(std::to_string(failed.size()) + " of " + std::to_string(args.sessions.size()) +
                             " sessions not processed (above)");
  }
}

}  // namespace

void AddProcessCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "process", "One processing recipe (JSON) applied to sessions: results in SESSION/processed/NAME/");
  auto args = std::make_shared<ProcessArgs>();
  command->add_option("recipe", args->recipe, "Processing recipe (docs/cli.md: its fields)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("sessions", args->sessions, "Session directories")->required()->check(CLI::ExistingDirectory);
  command->add_option("-j,--jobs", args->jobs, "Sessions processed side by side")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  command->add_flag("--overwrite", args->overwrite,
                    "Replace results this recipe already wrote (the session's own files are never written)");
  command->add_option("--progress-file", args->progress_file,
                      "Keep the progress as JSON {step, done, total} in FILE (one session only)");
  command->callback([args]() { RunProcess(*args); });
}

}  // namespace mocap
