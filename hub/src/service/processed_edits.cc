// Edit logs of a recipe's results (see processed_edits.h).
#include "service/processed_edits.h"

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "edit/edit_apply.h"
#include "edit/edit_output.h"
#include "io/trajectory_file.h"
#include "service/api_error.h"

namespace mocap::service {
namespace fs = std::filesystem;
namespace {

constexpr const char* kLogFile = "edits.json";
const char* const kInputs[] = {"markers.trc", "markers.c3d"};

bool RegularFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(fs::symlink_status(path, ec));
}

// The marker files of the results: the first is the one edited, every one gets an edited twin.
std::vector<std::string> Inputs(const fs::path& dir) {
  std::vector<std::string> inputs;
  for (const char* name : kInputs)
    if (RegularFile(dir / name)) inputs.push_back(name);
  if (inputs.empty()) throw ApiError(404, "these results hold no markers.trc or markers.c3d to edit");
  return inputs;
}

std::string EditedName(const std::string& input) { return "edited" + input.substr(input.find('.')); }

nlohmann::json Base(const fs::path& dir, const std::vector<std::string>& inputs, const nlohmann::json& log) {
  nlohmann::json outputs = nlohmann::json::array();
  for (const std::string& input : inputs)
    if (RegularFile(dir / EditedName(input))) outputs.push_back(EditedName(input));
  if (!outputs.empty() && RegularFile(dir / "edited.filled.tsv")) outputs.push_back("edited.filled.tsv");
  return {{"edits", log}, {"input", inputs.front()}, {"outputs", outputs}};
}

}  // namespace

nlohmann::json ReadProcessedEdits(const fs::path& dir) {
  const std::vector<std::string> inputs = Inputs(dir);
  nlohmann::json log = edit::EditLogToJson(edit::EditLog{});
  if (RegularFile(dir / kLogFile)) {
    try {
      log = edit::EditLogToJson(edit::ReadEditLog((dir / kLogFile).string()));
    } catch (const std::exception& error) {
      throw ApiError(500, std::string("the saved edit log cannot be read: ") + error.what());
    }
  }
  return Base(dir, inputs, log);
}

nlohmann::json WriteProcessedEdits(const fs::path& dir, const nlohmann::json& body) {
  const std::vector<std::string> inputs = Inputs(dir);
  edit::EditLog log;
  edit::EditedTake take;
  edit::EditReport report;
  try {
    log = edit::EditLogFromJson(body, "edits");
  } catch (const std::invalid_argument& error) {
    throw ApiError(400, error.what());
  }
  take = edit::EditedTake::FromMeasured(ReadTrajectories((dir / inputs.front()).string()));
  try {
    report = edit::ApplyEdits(log, &take);
  } catch (const std::invalid_argument& error) {
    throw ApiError(400, error.what());
  }
  const nlohmann::json saved = edit::EditLogToJson(log);
  {
    const fs::path tmp = dir / (std::string(kLogFile) + ".tmp");
    std::ofstream out(tmp);
    out << saved.dump(1) << "\n";
    out.close();
    if (!out) throw ApiError(500, "cannot write " + tmp.string());
    fs::rename(tmp, dir / kLogFile);
  }
  for (const std::string& input : inputs) edit::WriteEditedTake(take, (dir / EditedName(input)).string());
  nlohmann::json answer = Base(dir, inputs, saved);
  answer["operations"] = report.lines;
  nlohmann::json spikes = nlohmann::json::array();
  for (const auto& s : report.spikes)
    spikes.push_back({{"marker", s.marker}, {"frame", s.frame}, {"removed", s.removed}});
  answer["spikes"] = spikes;
  nlohmann::json filled = nlohmann::json::array();
  for (const edit::FilledStretch& s : edit::FilledStretches(take))
    filled.push_back({{"marker", s.marker},
                      {"first_frame", s.first_frame},
                      {"last_frame", s.last_frame},
                      {"method", edit::FillMethodName(s.method)}});
  answer["filled"] = filled;
  return answer;
}

}  // namespace mocap::service
