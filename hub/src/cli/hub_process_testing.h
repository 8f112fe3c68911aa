// Test side: runs the built mocap-hub (MOCAP_HUB_EXE, defined by the test target) as a child
// process in a working directory and captures its exit status, stdout and stderr. Shared by the
// CLI tests, which judge the program the way a user meets it.
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace mocap {

struct HubRun {
  int status = -1;
  std::string out;
  std::string err;
};

inline std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// `mocap-hub ARGS` run in workdir; stdout and stderr land in workdir's stdout.txt/stderr.txt.
inline HubRun RunHub(const std::string& workdir, const std::string& args) {
  const std::string command = "cd '" + workdir + "' && '" + MOCAP_HUB_EXE + "' " + args +
                              " > stdout.txt 2> stderr.txt";
  HubRun run;
  const int raw = std::system(command.c_str());
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  run.out = ReadAll(workdir + "/stdout.txt");
  run.err = ReadAll(workdir + "/stderr.txt");
  return run;
}

// A failure is exactly one line on stderr, naming the cause, with a non-zero status.
inline void ExpectOneLineError(const HubRun& run, const std::string& cause) {
  EXPECT_NE(run.status, 0);
  EXPECT_EQ(run.err.rfind("mocap-hub: error: ", 0), 0u) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_NE(run.err.find(cause), std::string::npos) << run.err;
}

}  // namespace mocap
