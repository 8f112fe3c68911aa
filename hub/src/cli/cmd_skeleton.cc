// `skeleton` commands: templates from marker sets, subject calibration, the per-frame solve with
// BVH / ASF+AMC / .mot output.
//   skeleton template (--trc TRIAL.trc|.c3d | --marker-set SET.json) -o TEMPLATE.json
//   skeleton calibrate TEMPLATE.json TRIAL.trc -o SUBJECT.json [--start S] [--duration S] [--up ...]
//   skeleton solve SUBJECT.json TRIAL.trc [--bvh F] [--asf F --amc F] [--mot F] [--up ...]
//   skeleton sim TEMPLATE.json -o DIR [--motion rom|gait] [--duration S] [--rate HZ] [--seed N] ...
//   skeleton eval --truth DIR --skeleton SUBJECT.json --mot SOLVED.mot [--json]
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "io/trajectory_file.h"
#include "io/trc.h"
#include "labels/marker_set.h"
#include "skeleton/motion_files.h"
#include "skeleton/skeleton_eval.h"
#include "skeleton/skeleton_sim.h"
#include "skeleton/skeleton_space.h"
#include "skeleton/skeleton_template.h"
#include "skeleton/subject_calibration.h"
#include "skeleton/trial_solve.h"

namespace mocap {
namespace {

struct TemplateArgs {
  std::string trc, marker_set, output;
};

void RunTemplate(const TemplateArgs& args) {
  if (args.trc.empty() == args.marker_set.empty()) throw UsageError("skeleton template: give one of --trc or --marker-set");
  const std::vector<std::string> names =
      args.trc.empty() ? ReadMarkerSetFile(args.marker_set).names : ReadTrajectories(args.trc).names;
  std::vector<std::string> unplaced;
  Skeleton skeleton;
  try {
    skeleton = SkeletonTemplateFromNames(names, &unplaced);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error((args.trc.empty() ? args.marker_set : args.trc) + ": " + error.what());
  }
  WriteSkeletonFile(skeleton, args.output);
  std::printf("%s: %zu segments, %zu markers placed", args.output.c_str(), skeleton.NumSegments(),
              skeleton.markers.size());
  if (!unplaced.empty()) {
    std::printf(", %zu not placed:", unplaced.size());
    for (const std::string& name : unplaced) std::printf(" %s", name.c_str());
  }
  std::printf("\n");
}

int UpAxisOf(const MarkerTrajectories& markers, int up_axis, const std::string& path) {
  if (up_axis >= 0) return up_axis;
  const int detected = DetectUpAxis(markers);
  if (detected < 0) throw std::runtime_error(path + ": cannot detect the vertical axis (give --up)");
  return detected;
}

struct CalibrateArgs {
  std::string skeleton, trial, output;
  int up_axis = -1;
  SubjectCalibrationOptions options;
};

void RunCalibrate(const CalibrateArgs& args) {
  CheckOptions(args.options);
  const Skeleton skeleton = ReadSkeletonFile(args.skeleton);
  const MarkerTrajectories world = ReadTrajectories(args.trial);
  const MarkerTrajectories markers = ToSkeletonSpace(world, UpAxisOf(world, args.up_axis, args.trial));
  SubjectCalibration calibration;
  try {
    calibration = CalibrateSubject(skeleton, markers, args.options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(args.trial + ": " + error.what());
  }
  WriteSkeletonFile(calibration.skeleton, args.output);
  std::printf("%s: scale %.3f, %d frames, marker residual rms %.2f mm, max %.2f mm\n", args.output.c_str(),
              calibration.scale, calibration.frames_used, calibration.rms_mm, calibration.max_mm);
  for (const JointCalibration& joint : calibration.joints)
    std::printf("  %-16s turned %6.1f deg  %s  %.1f mm from its parent's joint\n", joint.segment.c_str(),
                joint.range_deg, joint.functional ? "functional centre" : "template centre  ", joint.length_mm);
}

struct SolveArgs {
  std::string skeleton, trial, bvh, asf, amc, mot;
  int up_axis = -1;
  SkeletonSolveOptions options;
};

void RunSolve(const SolveArgs& args) {
  CheckOptions(args.options);
  if (args.amc.empty() != args.asf.empty()) throw UsageError("skeleton solve: --asf and --amc go together");
  const Skeleton skeleton = ReadSkeletonFile(args.skeleton);
  const MarkerTrajectories world = ReadTrajectories(args.trial);
  const MarkerTrajectories markers = ToSkeletonSpace(world, UpAxisOf(world, args.up_axis, args.trial));
  const TrialSolve solve = SolveTrial(skeleton, markers, args.options);
  if (solve.solved_frames == 0) throw std::runtime_error(args.trial + ": no frame could be solved");
  if (!args.bvh.empty()) WriteBvh(skeleton, solve.motion, args.bvh);
  if (!args.asf.empty()) {
    WriteAsf(skeleton, args.asf);
    WriteAmc(skeleton, solve.motion, args.amc);
  }
  if (!args.mot.empty()) WriteMot(skeleton, solve.motion, args.mot);
  std::printf("%s: %zu of %zu frames solved, marker residual rms %.2f mm, max %.2f mm, %.3f ms per frame\n",
              args.trial.c_str(), solve.solved_frames, markers.NumFrames(), solve.rms_mm, solve.max_mm,
              1000.0 * solve.seconds / std::max<size_t>(1, markers.NumFrames()));
}

struct SimArgs {
  std::string skeleton, output, motion = "rom";
  int up_axis = 2;
  SkeletonSimOptions options;
};

// DIR/truth.trc (world, named markers), truth.mot (true angles), truth.skeleton.json (the subject).
void RunSim(SimArgs args) {
  try {
    args.options.motion = SkeletonSimMotionFromName(args.motion);
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  CheckOptions(args.options);
  const Skeleton skeleton = ReadSkeletonFile(args.skeleton);
  const SkeletonSimulation sim = SimulateSkeleton(skeleton, args.options);
  std::filesystem::create_directories(args.output);
  const std::filesystem::path dir(args.output);
  WriteTrc(ToWorld(sim.markers, args.up_axis), (dir / "truth.trc").string());
  WriteMot(sim.subject, sim.motion, (dir / "truth.mot").string());
  WriteSkeletonFile(sim.subject, (dir / "truth.skeleton.json").string());
  std::printf("%s: %zu frames of %s at %.0f Hz, %zu markers on %zu segments\n", args.output.c_str(),
              sim.markers.NumFrames(), args.motion.c_str(), args.options.rate_hz, sim.subject.markers.size(),
              sim.subject.NumSegments());
}

struct EvalArgs {
  std::string truth, skeleton, mot;
  bool json = false;
};

void RunEval(const EvalArgs& args) {
  const std::filesystem::path dir(args.truth);
  const Skeleton truth = ReadSkeletonFile((dir / "truth.skeleton.json").string());
  const std::string truth_mot = (dir / "truth.mot").string();
  const SkeletonMotion truth_motion = MotionFromMot(truth, ReadMot(truth_mot), truth_mot);
  const Skeleton estimate = ReadSkeletonFile(args.skeleton);
  const SkeletonMotion estimate_motion = MotionFromMot(estimate, ReadMot(args.mot), args.mot);
  SkeletonEvalReport report;
  try {
    report = EvaluateSkeleton(truth, truth_motion, estimate, estimate_motion);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(args.skeleton + ": " + error.what());
  }
  if (args.json) {
    std::printf("{\"joints\": [");
    for (size_t i = 0; i < report.joints.size(); ++i) {
      const JointAngleError& j = report.joints[i];
      std::printf("%s{\"segment\": \"%s\", \"rms_deg\": %.4f, \"frames\": %zu, \"length_truth_mm\": %.3f, "
                  "\"length_error_mm\": %.3f}",
                  i ? ", " : "", j.segment.c_str(), j.rms_deg, j.frames, report.lengths[i].truth_mm,
                  report.lengths[i].error_mm);
    }
    std::printf("]}\n");
    return;
  }
  std::printf("%-16s %9s %-24s %12s %10s\n", "joint", "rms deg", "per dof", "length mm", "error mm");
  for (size_t i = 0; i < report.joints.size(); ++i) {
    const JointAngleError& j = report.joints[i];
    std::string dofs;
    for (double d : j.dof_rms_deg) dofs += (dofs.empty() ? "" : " ") + std::to_string(d).substr(0, 5);
    std::printf("%-16s %9.3f %-24s %12.1f %10.2f\n", j.segment.c_str(), j.rms_deg, dofs.c_str(),
                report.lengths[i].truth_mm, report.lengths[i].error_mm);
  }
}

}  // namespace

void AddSkeletonCommands(CLI::App& app) {
  CLI::App& group = CommandGroup(app, "skeleton");
  {
    CLI::App* command = group.add_subcommand("template", "A skeleton template built by rules from a marker set's names");
    auto args = std::make_shared<TemplateArgs>();
    command->add_option("--trc", args->trc, "A named marker file (.trc or .c3d) whose names to use")
        ->check(CLI::ExistingFile);
    command->add_option("--marker-set", args->marker_set, "A marker set (labels learn) whose names to use")
        ->check(CLI::ExistingFile);
    command->add_option("-o,--output", args->output, "Template to write (JSON)")->required();
    command->callback([args] { RunTemplate(*args); });
  }
  {
    CLI::App* command = group.add_subcommand("calibrate", "A subject's skeleton from a static or range-of-motion trial");
    auto args = std::make_shared<CalibrateArgs>();
    command->add_option("template", args->skeleton, "Skeleton template (skeleton template)")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("trial", args->trial, "Named marker file (.trc or .c3d)")->required()->check(CLI::ExistingFile);
    command->add_option("-o,--output", args->output, "Calibrated skeleton to write (JSON)")->required();
    command->add_option("--start", args->options.start_s, "Window start, seconds into the trial")->capture_default_str();
    command->add_option("--duration", args->options.duration_s, "Window length, seconds")->capture_default_str();
    command->add_option("--max-frames", args->options.max_frames, "Frames of the window in the joint fit")
        ->capture_default_str();
    command->add_option("--min-joint-range", args->options.min_joint_range_deg,
                        "A joint turning less (deg) has no functional centre")
        ->capture_default_str();
    command->add_flag("--keep-template-centres", args->options.keep_template_centres,
                      "Keep the scaled template's centre for joints that barely move (else refused)");
    AddUpAxisOption(*command, &args->up_axis, true, "Vertical axis of the trial: x, y, z or auto");
    command->callback([args] { RunCalibrate(*args); });
  }
  {
    CLI::App* command = group.add_subcommand("solve", "Root pose and joint angles per frame from named markers");
    auto args = std::make_shared<SolveArgs>();
    command->add_option("skeleton", args->skeleton, "Calibrated skeleton (skeleton calibrate)")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("trial", args->trial, "Named marker file (.trc or .c3d)")->required()->check(CLI::ExistingFile);
    command->add_option("--bvh", args->bvh, "BVH file to write");
    command->add_option("--asf", args->asf, "Acclaim skeleton file to write (with --amc)");
    command->add_option("--amc", args->amc, "Acclaim motion file to write (with --asf)");
    command->add_option("--mot", args->mot, "OpenSim .mot table of joint angles to write");
    command->add_option("--loss-scale", args->options.loss_scale_mm, "Robust (Cauchy) loss scale, mm")->capture_default_str();
    AddUpAxisOption(*command, &args->up_axis, true, "Vertical axis of the trial: x, y, z or auto");
    command->callback([args] { RunSolve(*args); });
  }
  {
    CLI::App* command = group.add_subcommand("sim", "A simulated subject with known joint angles: truth markers and angles");
    auto args = std::make_shared<SimArgs>();
    command->add_option("template", args->skeleton, "Skeleton template (skeleton template)")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("-o,--output", args->output, "Directory for truth.trc, truth.mot, truth.skeleton.json")
        ->required();
    command->add_option("--motion", args->motion, "rom (range of motion) or gait")->capture_default_str();
    command->add_option("--duration", args->options.duration_s, "Seconds")->capture_default_str();
    command->add_option("--rate", args->options.rate_hz, "Frames per second")->capture_default_str();
    command->add_option("--scale", args->options.scale, "Subject size against the template")->capture_default_str();
    command->add_option("--wobble", args->options.wobble_mm, "Soft-tissue swing of each marker, mm")
        ->capture_default_str();
    command->add_option("--seed", args->options.seed, "Seed of the subject's proportions and markers")
        ->capture_default_str();
    AddUpAxisOption(*command, &args->up_axis, false, "Vertical axis of the written markers: x, y or z");
    command->callback([args] { RunSim(*args); });
  }
  {
    CLI::App* command = group.add_subcommand("eval", "Joint-angle and segment-length errors against skeleton sim's truth");
    auto args = std::make_shared<EvalArgs>();
    command->add_option("--truth", args->truth, "Directory skeleton sim wrote")->required()->check(CLI::ExistingDirectory);
    command->add_option("--skeleton", args->skeleton, "Calibrated skeleton")->required()->check(CLI::ExistingFile);
    command->add_option("--mot", args->mot, "Solved angles (skeleton solve --mot)")->required()->check(CLI::ExistingFile);
    command->add_flag("--json", args->json, "JSON report on stdout");
    command->callback([args] { RunEval(*args); });
  }
}

}  // namespace mocap
