// Processing jobs with a stand-in for `mocap-hub process` (a shell script that answers as the
// command does): requests checked before anything runs, one child at a time, its state, progress,
// log and outputs, results never replaced without "overwrite", a failing child named as failed.
#include "service/processing_jobs.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <filesystem>
#include <fstream>
#include <thread>

#include "service/api_error.h"

namespace mocap::service {
namespace {

namespace fs = std::filesystem;

// Answers as `mocap-hub process RECIPE SESSION --progress-file FILE [--overwrite]` does: output
// lines, the progress file, process.json beside the recipe. A session holding "fail" fails it
// (status 3); one holding "slow" takes a while.
constexpr const char* kStandIn = R"(#!/bin/sh
out=$(dirname "$2")
echo "process $2 $3 $6"
printf '{"step":"reconstruct","done":4,"total":8}\n' > "$5"
[ -f "$3/slow" ] && sleep 1
if [ -f "$3/fail" ]; then echo "mocap-hub: error: the raw log is unreadable"; exit 3; fi
printf '{"outputs":["markers.trc","markers.c3d"]}\n' > "$out/process.json"
)";

class ProcessingJobsTest : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("processing_jobs_test_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "sessions");
    options_.executable = (root_ / "stand-in.sh").string();
    std::ofstream(options_.executable) << kStandIn;
    fs::permissions(options_.executable, fs::perms::owner_all);
    options_.sessions_dir = (root_ / "sessions").string();
    options_.labels = (root_ / "serve-set.json").string();
    std::ofstream(options_.labels) << "{}";
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path Session(const std::string& name) {
    const fs::path dir = root_ / "sessions" / name;
    fs::create_directories(dir);
    std::ofstream(dir / "session.json") << "{}";
    return dir;
  }

  // Polls (as the hub's loop does) until the job is finished; bounded.
  static nlohmann::json WaitFinished(ProcessingJobs& jobs, uint64_t id) {
    for (int i = 0; i < 1000; ++i) {
      jobs.Poll();
      const nlohmann::json list = jobs.Jobs();
      for (const nlohmann::json& job : list["jobs"])
        if (job["id"] == id && (job["state"] == "done" || job["state"] == "failed")) return job;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "job " << id << " did not finish: " << jobs.Jobs().dump();
    return {};
  }

  static int Status(const std::function<void()>& f) {
    try {
      f();
    } catch (const ApiError& e) {
      return e.status;
    }
    return 0;
  }

  fs::path root_;
  ProcessingJobsOptions options_;
};

TEST_F(ProcessingJobsTest, AJobRunsTheCommandAndReportsItsProgressLogAndOutputs) {
  const fs::path session = Session("walk");
  ProcessingJobs jobs(options_);
  const nlohmann::json queued =
      jobs.Start("walk", {{"recipe", {{"name", "gait"}, {"labels", "serve"}, {"outputs", {"trc", "c3d"}}}}});
  EXPECT_EQ(queued["state"], "queued");
  EXPECT_EQ(queued["recipe"], "gait");
  // The recipe as the command reads it: checked, with serve's file resolved.
  std::ifstream in(session / "processed" / "gait" / "recipe.json");
  const nlohmann::json recipe = nlohmann::json::parse(in);
  EXPECT_EQ(recipe["format"], "mocap-recipe");
  EXPECT_EQ(recipe["labels"], fs::absolute(options_.labels).lexically_normal().string());

  const nlohmann::json done = WaitFinished(jobs, queued["id"].get<uint64_t>());
  EXPECT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["exit_status"], 0);
  EXPECT_EQ(done["progress"]["done"], 4);
  EXPECT_EQ(done["progress"]["total"], 8);
  EXPECT_EQ(done["outputs"], nlohmann::json({"markers.trc", "markers.c3d"}));
  ASSERT_EQ(done["log"].size(), 1u);
  const std::string line = done["log"][0];
  EXPECT_NE(line.find((session / "processed" / "gait" / "recipe.json").string()), std::string::npos) << line;
  EXPECT_EQ(line.find("--overwrite"), std::string::npos) << line;  // none was asked for

  // Results are kept: the same recipe again is refused unless the request says overwrite.
  EXPECT_EQ(Status([&] { jobs.Start("walk", {{"recipe", {{"name", "gait"}}}}); }), 409);
  const nlohmann::json again = jobs.Start("walk", {{"recipe", {{"name", "gait"}}}, {"overwrite", true}});
  const nlohmann::json redone = WaitFinished(jobs, again["id"].get<uint64_t>());
  EXPECT_EQ(redone["state"], "done");
  EXPECT_NE(redone["log"][0].get<std::string>().find("--overwrite"), std::string::npos);
}

TEST_F(ProcessingJobsTest, AFailingCommandFailsItsJobWithItsLog) {
  const fs::path session = Session("broken");
  std::ofstream(session / "fail") << "";
  ProcessingJobs jobs(options_);
  const nlohmann::json queued = jobs.Start("broken", {{"recipe", nlohmann::json::object()}});
  const nlohmann::json failed = WaitFinished(jobs, queued["id"].get<uint64_t>());
  EXPECT_EQ(failed["state"], "failed");
  EXPECT_EQ(failed["exit_status"], 3);
  EXPECT_NE(failed["reason"].get<std::string>().find("status 3"), std::string::npos);
  EXPECT_EQ(failed["log"].back(), "mocap-hub: error: the raw log is unreadable");
  EXPECT_EQ(failed["outputs"], nlohmann::json::array());
}

TEST_F(ProcessingJobsTest, OneChildAtATimeTheOthersQueued) {
  std::ofstream(Session("first") / "slow") << "";
  Session("second");
  ProcessingJobs jobs(options_);
  const uint64_t first = jobs.Start("first", {{"recipe", nlohmann::json::object()}})["id"];
  const uint64_t second = jobs.Start("second", {{"recipe", nlohmann::json::object()}})["id"];
  jobs.Poll();
  const nlohmann::json list = jobs.Jobs()["jobs"];
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0]["id"], second);  // newest first
  EXPECT_EQ(list[0]["state"], "queued");
  EXPECT_EQ(list[1]["state"], "running");
  // The same session and recipe cannot be queued twice.
  EXPECT_EQ(Status([&] { jobs.Start("second", {{"recipe", nlohmann::json::object()}}); }), 409);
  EXPECT_EQ(WaitFinished(jobs, first)["state"], "done");
  EXPECT_EQ(WaitFinished(jobs, second)["state"], "done");
}

TEST_F(ProcessingJobsTest, RequestsAreCheckedBeforeAnythingRuns) {
  const fs::path session = Session("walk");
  std::ofstream(session / "set.json") << "{}";
  fs::create_symlink("/etc/passwd", session / "linked.json");
  ProcessingJobs jobs(options_);
  const std::pair<nlohmann::json, int> refused[] = {
      {{{"recipe", {{"bodies", "serve"}}}}, 400},                  // serve has no bodies file
      {{{"recipe", {{"labels", "missing.json"}}}}, 400},
      {{{"recipe", {{"labels", "../walk/set.json"}}}}, 400},       // only plain names
      {{{"recipe", {{"labels", "/etc/passwd"}}}}, 400},
      {{{"recipe", {{"labels", "linked.json"}}}}, 400},            // a link is not a file of the session
      {{{"recipe", {{"labels", 3}}}}, 400},
      {{{"recipe", {{"matcher", "fastest"}}}}, 400},
      {{{"recipe", {{"name", "a/b"}}}}, 400},
      {{{"recipe", {{"format", "mocap-recipe"}}}}, 400},
      {{{"recipe", {{"colour", "red"}}}}, 400},                    // unknown recipe field
      {{{"recipe", nlohmann::json::array()}}, 400},
      {{{"recipe", nlohmann::json::object()}, {"overwrite", "yes"}}, 400},
      {{{"recipe", nlohmann::json::object()}, {"extra", 1}}, 400},
  };
  for (const auto& [request, status] : refused)
    EXPECT_EQ(Status([&, r = request] { jobs.Start("walk", r); }), status) << request.dump();
  EXPECT_EQ(Status([&] { jobs.Start("nosuch", {{"recipe", nlohmann::json::object()}}); }), 404);
  EXPECT_EQ(Status([&] { jobs.Start("..", {{"recipe", nlohmann::json::object()}}); }), 404);
  EXPECT_EQ(jobs.Jobs()["jobs"].size(), 0u);
  EXPECT_FALSE(fs::exists(session / "processed"));
  // A file of the session is accepted.
  EXPECT_EQ(jobs.Start("walk", {{"recipe", {{"labels", "set.json"}}}})["state"], "queued");
}

TEST_F(ProcessingJobsTest, AProgramThatCannotRunFailsTheJob) {
  Session("walk");
  options_.executable = (root_ / "no-such-program").string();
  ProcessingJobs jobs(options_);
  const uint64_t id = jobs.Start("walk", {{"recipe", nlohmann::json::object()}})["id"];
  const nlohmann::json failed = WaitFinished(jobs, id);
  EXPECT_EQ(failed["state"], "failed");
  EXPECT_NE(failed["reason"].get<std::string>().find("cannot run"), std::string::npos) << failed.dump();
}

}  // namespace
}  // namespace mocap::service
