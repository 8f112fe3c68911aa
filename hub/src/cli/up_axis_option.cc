// The --up option shared by the commands that take a vertical axis (sim rig, sim motion,
// sim wand, calibrate world).
#include <map>
#include <string>

#include "cli/commands.h"

namespace mocap {

CLI::Option* AddUpAxisOption(CLI::App& command, int* axis, bool allow_auto, const std::string& help) {
  std::map<std::string, int> names{{"x", 0}, {"y", 1}, {"z", 2}};
  if (allow_auto) names["auto"] = -1;
  // The help names the values (not CLI11's "INT:value in {x->0,...}"); the refusal still lists them.
  return command.add_option("--up", *axis, help)
      ->transform(CLI::CheckedTransformer(names, CLI::ignore_case).description(""))
      ->type_name(allow_auto ? "x|y|z|auto" : "x|y|z")
      ->default_str(UpAxisName(*axis));
}

std::string UpAxisName(int axis) {
  switch (axis) {
    case 0: return "x";
    case 1: return "y";
    case 2: return "z";
    default: return "auto";
  }
}

}  // namespace mocap
