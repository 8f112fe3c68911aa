// Real recordings (../shared/data/subjects; skipped, saying so, where it is missing): a template
// from hdm_bd.trc's names, hdm_mm.trc (another person) calibrated from its own first 2 s and
// solved over its 20 s. The legs stand still in those 2 s: calibration refuses unless told to
// keep the template's centres. The targets (RMS <= 10 mm, max <= 30 mm) are NOT reached
// yet (12.3 mm, max 138 mm: the legs' template centres, docs/skeletons.md): an expected failure;
// asserted too: every frame solved and the RMS reached today with a little room, so that a
// regression shows.
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "io/trc.h"
#include "simcore/expected_failure.h"
#include "skeleton/skeleton_space.h"
#include "skeleton/skeleton_template.h"
#include "skeleton/subject_calibration.h"
#include "skeleton/trial_solve.h"

namespace mocap {
namespace {

TEST(RealSubjects, HdmTemplateCalibratedOnAnotherPerson) {
  const std::string dir = MOCAP_SUBJECTS_DIR;
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "../shared/data missing: no " << dir;
  std::vector<std::string> unplaced;
  const Skeleton skeleton_template = SkeletonTemplateFromNames(ReadTrc(dir + "/hdm_bd.trc").names, &unplaced);
  EXPECT_TRUE(unplaced.empty());
  const MarkerTrajectories world = ReadTrc(dir + "/hdm_mm.trc");
  const MarkerTrajectories markers = ToSkeletonSpace(world, DetectUpAxis(world));
  SubjectCalibrationOptions options;
  EXPECT_THROW(CalibrateSubject(skeleton_template, markers, options), std::invalid_argument);
  options.keep_template_centres = true;
  const SubjectCalibration calibration = CalibrateSubject(skeleton_template, markers, options);
  const TrialSolve solve = SolveTrial(calibration.skeleton, markers, SkeletonSolveOptions{});
  std::printf("hdm_mm: calibrated from 2 s (scale %.3f, fit rms %.2f mm); solved %zu of %zu frames: marker residual "
              "rms %.2f mm, max %.2f mm, %.3f ms per frame\n",
              calibration.scale, calibration.rms_mm, solve.solved_frames, markers.NumFrames(), solve.rms_mm,
              solve.max_mm, 1000.0 * solve.seconds / markers.NumFrames());
  EXPECT_EQ(solve.solved_frames, markers.NumFrames());
  EXPECT_LE(solve.rms_mm, 14.0);
  testing::ExpectFailure("issue 36: marker residual RMS <= 10 mm, max <= 30 mm", [&] {
    EXPECT_LE(solve.rms_mm, 10.0);
    EXPECT_LE(solve.max_mm, 30.0);
  });
}

}  // namespace
}  // namespace mocap
