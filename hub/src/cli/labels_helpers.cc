// The naming step of reconstruct and labels apply (see labels_helpers.h).
#include "cli/labels_helpers.h"

#include <fstream>
#include <stdexcept>

#include "cli/commands.h"
#include "labels/marker_set.h"
#include "pipeline/take_outputs.h"

namespace mocap {

void AddLabellerOptions(CLI::App& command, LabellerChoice* choice, const std::string& explain_flag) {
  command
      .add_option("--labeller", choice->labeller,
                  "Whole-take labeller: trial (frame by frame, refined by distances) or subject (a subject model "
                  "initialised on the take: leaves unnamed what it cannot tell, docs/labels.md)")
      ->check(CLI::IsMember({"trial", "subject"}))
      ->capture_default_str();
  command.add_option(explain_flag, choice->explain,
                     "Write every labelling decision to this file, one line each (--labeller subject)");
}

std::string NameTakeFromFile(const std::string& marker_set_path, int up_axis, MarkerTrajectories* markers,
                             const LabellerChoice& choice) {
  const bool subject = choice.labeller == "subject";
  if (!subject && !choice.explain.empty())
    throw UsageError("the decision log is written by the subject labeller only (--labeller subject)");
  const MarkerSet set = ReadMarkerSetFile(marker_set_path);
  pipeline::TakeNaming naming;
  try {
    naming = pipeline::NameTake(set, up_axis, markers,
                                subject ? pipeline::TakeLabeller::kSubject : pipeline::TakeLabeller::kTrial);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(marker_set_path + ": " + error.what());
  }
  if (!choice.explain.empty()) {
    std::ofstream out(choice.explain);
    for (const std::string& line : naming.decisions) out << line << '\n';
    if (naming.decisions_made > naming.decisions.size())
      out << (naming.decisions_made - naming.decisions.size()) << " more decisions not kept\n";
    if (!out) throw std::runtime_error(choice.explain + ": cannot write");
  }
  return naming.Describe();
}

}  // namespace mocap
