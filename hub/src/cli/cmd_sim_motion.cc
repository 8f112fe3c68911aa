// `sim motion`: writes a synthetic motion (a person-sized marker cloud walking a circle) as TRC,
// for trying the system without recorded motions.
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "io/trc.h"
#include "simcore/synthetic_motion.h"

namespace mocap {

void AddSimMotionCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim");
  CLI::App* command = sim.add_subcommand("motion", "Write a synthetic walking motion (TRC)");
  struct Args {
    SyntheticMotionOptions motion;
    std::string output;
  };
  auto args = std::make_shared<Args>();
  command->add_option("-o,--output", args->output, "TRC file to write")->required();
  command->add_option("--markers", args->motion.markers, "Number of markers")->capture_default_str();
  command->add_option("--frames", args->motion.frames, "Number of frames")->capture_default_str();
  command->add_option("--rate", args->motion.rate_hz, "Frame rate, Hz")->capture_default_str();
  args->motion.up_axis = 1;
  AddUpAxisOption(*command, &args->motion.up_axis, false, "Vertical axis");
  command->add_option("--seed", args->motion.seed, "Seed")->capture_default_str();
  command->callback([args] {
    CheckOptions(args->motion);
    WriteTrc(MakeSyntheticMotion(args->motion), args->output);
    std::printf("%s: %d markers, %d frames at %g Hz\n", args->output.c_str(), args->motion.markers,
                args->motion.frames, args->motion.rate_hz);
  });
}

}  // namespace mocap
