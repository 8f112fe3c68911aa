// Captures: names that cannot escape the sessions directory, one capture at a time, sessions
// that survive a killed service as "interrupted" and stay readable.
#include "service/capture.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

#include <gtest/gtest.h>

#include "io/live_points.h"
#include "service/api_error.h"
#include "util/temporary_directory_testing.h"

namespace mocap::service {
namespace {
namespace fs = std::filesystem;

class CaptureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "sessions");
    std::ofstream(dir_ / "cal.json") << "{}";
    base_.rate_hz = 100;
    base_.camera_ids = {1, 2};
  }
  // The disk's free space is what free_ says (the real one is whatever the machine has).
  Captures Make() {
    return Captures((dir_ / "sessions").string(), (dir_ / "cal.json").string(), base_, disk_,
                    [this](const std::string&) { return free_; });
  }
  int StatusOf(const std::function<void()>& f) {
    try {
      f();
    } catch (const ApiError& e) {
      return e.status;
    }
    return 0;
  }

  const testing::TemporaryDirectory temp_{"capture_test"};
  const fs::path dir_ = temp_.path();
  SessionInfo base_;
  CaptureDiskOptions disk_;
  uint64_t free_ = uint64_t{1} << 40;
};

constexpr uint64_t kMiB = 1024 * 1024;
constexpr uint64_t kSecond = 1'000'000'000;

TEST(SessionName, OnlyPlainNames) {
  EXPECT_TRUE(ValidSessionName("take_01.walk-2"));
  for (const std::string& bad : {std::string(""), std::string(".hidden"), std::string(".."), std::string("../x"),
                                 std::string("a/b"), std::string("a b"), std::string("ä"), std::string(65, 'a')})
    EXPECT_FALSE(ValidSessionName(bad)) << bad;
}

TEST_F(CaptureTest, StartWriteStopGivesACompleteSession) {
  Captures captures = Make();
  IngestStats stats;
  stats.nodes[1].frames = 10;
  captures.Start("take1", stats, 1'000'000'000);
  ASSERT_NE(captures.writer(), nullptr);
  const uint8_t datagram[] = {1, 2, 3};
  captures.writer()->AppendDatagram(datagram, sizeof(datagram), 5);
  pipeline::LiveFrame frame;
  frame.frame_number = 7;
  frame.points.resize(2);
  frame.points[0].marker = 3;
  frame.points[0].id = 40;
  frame.points[1].id = 12;  // provisional
  frame.label_names = std::make_shared<const std::vector<std::string>>(std::vector<std::string>{"R.ASIS", "L.ASIS"});
  frame.points[0].label = 1;
  captures.AddPublished(frame);
  EXPECT_EQ(StatusOf([&] { captures.Start("take2", stats, 2); }), 409);
  stats.nodes[1].frames = 25;
  stats.nodes[1].dropped_frames = 2;
  const nlohmann::json summary = captures.Stop(stats, 3'000'000'000);
  EXPECT_EQ(summary["name"], "take1");
  EXPECT_EQ(summary["frame_sets"], 1);
  EXPECT_EQ(captures.writer(), nullptr);
  const SessionInfo info = LoadSessionInfo((dir_ / "sessions" / "take1").string());
  EXPECT_EQ(info.extra["capture_state"], "complete");
  EXPECT_EQ(info.camera_frames, 15u);
  EXPECT_EQ(info.dropped_camera_frames, 2u);
  EXPECT_EQ(info.source, "serve");
  EXPECT_TRUE(fs::exists(dir_ / "sessions" / "take1" / "calibration.json"));
  const LivePoints live = ReadLivePoints((dir_ / "sessions" / "take1" / "live_points.tsv").string());
  EXPECT_EQ(live.points.frame_numbers, std::vector<uint64_t>{7});
  EXPECT_EQ(live.points.names, (std::vector<std::string>{"T40", "P1"}));
  // The name published on the marker is kept with its point; the provisional one is unnamed.
  EXPECT_EQ(live.identity.names, std::vector<std::string>{"L.ASIS"});
  EXPECT_EQ(live.identity.name, (std::vector<int32_t>{0, -1}));
  EXPECT_EQ(live.identity.track, (std::vector<int64_t>{40, 12}));  // as published
  EXPECT_EQ(StatusOf([&] { captures.Stop(stats, 4); }), 409);
  EXPECT_EQ(StatusOf([&] { captures.Start("take1", stats, 5); }), 409);  // exists
  EXPECT_EQ(StatusOf([&] { captures.Start("../escape", stats, 5); }), 400);
  EXPECT_FALSE(fs::exists(dir_ / "escape"));
}

TEST_F(CaptureTest, AKilledCaptureIsMarkedInterruptedAtTheNextStart) {
  {
    Captures captures = Make();
    captures.Start("crash", IngestStats(), 1);
    captures.writer()->Flush();
    // The service dies here: no Stop, the writer is never finished.
    const nlohmann::json listed = captures.List();
    ASSERT_EQ(listed.size(), 1u);
    EXPECT_EQ(listed[0]["state"], "capturing");
  }
  Captures restarted = Make();
  EXPECT_EQ(restarted.RecoverInterrupted(), std::vector<std::string>{"crash"});
  EXPECT_EQ(restarted.List()[0]["state"], "interrupted");
  EXPECT_TRUE(restarted.RecoverInterrupted().empty());
  // A damaged session.json is listed as unreadable, not fatal.
  fs::create_directories(dir_ / "sessions" / "broken");
  std::ofstream(dir_ / "sessions" / "broken" / "session.json") << "{ nope";
  const nlohmann::json listed = restarted.List();
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0]["name"], "broken");
  EXPECT_EQ(listed[0]["state"], "unreadable");
  EXPECT_TRUE(restarted.RecoverInterrupted().empty());
}

TEST_F(CaptureTest, SessionFilesAreListedAndOnlyThoseCanBeNamed) {
  Captures captures = Make();
  captures.Start("walk", IngestStats{}, 1'000'000'000);
  captures.Stop(IngestStats{}, 2'000'000'000);
  const fs::path session = dir_ / "sessions" / "walk";
  const std::string trc = "PathFileType\t4\n";
  std::ofstream(session / "markers.trc") << trc;
  fs::create_directories(session / "sub");
  std::ofstream(session / ".hidden") << "x";
  std::ofstream(dir_ / "secret.txt") << "outside";
  fs::create_symlink(dir_ / "secret.txt", session / "link.txt");

  const nlohmann::json described = captures.Describe("walk");
  EXPECT_EQ(described["name"], "walk");
  EXPECT_EQ(described["state"], "complete");
  std::vector<std::string> names;
  for (const auto& f : described["files"]) names.push_back(f["name"].get<std::string>());
  EXPECT_NE(std::find(names.begin(), names.end(), "markers.trc"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "session.json"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "live_points.tsv"), names.end());
  for (const char* hidden : {"sub", ".hidden", "link.txt"})
    EXPECT_EQ(std::find(names.begin(), names.end(), hidden), names.end()) << hidden;
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const auto& f : described["files"]) {
    if (f["name"] == "markers.trc") {
      EXPECT_EQ(f["bytes"], trc.size());
    }
  }

  EXPECT_EQ(fs::path(captures.FilePath("walk", "markers.trc")), session / "markers.trc");
  for (const auto& named : std::vector<std::pair<std::string, std::string>>{
           {"walk", "link.txt"}, {"walk", "sub"}, {"walk", ".hidden"}, {"walk", "../../secret.txt"},
           {"walk", "missing.trc"}, {"..", "secret.txt"}, {"nope", "session.json"}, {"walk/..", "secret.txt"}})
    EXPECT_EQ(StatusOf([&] { captures.FilePath(named.first, named.second); }), 404)
        << named.first << " " << named.second;
  EXPECT_EQ(StatusOf([&] { captures.Describe("nope"); }), 404);
  EXPECT_EQ(StatusOf([&] { captures.Describe(".."); }), 404);
}

// Housekeeping: a deleted session is moved aside whole (nothing recorded is lost), a renamed one
// keeps its content, notes are kept in notes.txt and shown in the summary; the running capture
// and names a session cannot have are refused.
TEST_F(CaptureTest, SessionsAreDeletedRenamedAndAnnotatedButNeverTheRunningCapture) {
  Captures captures = Make();
  captures.Start("walk", IngestStats{}, 1 * kSecond);
  captures.Stop(IngestStats{}, 2 * kSecond);
  captures.Start("run", IngestStats{}, 3 * kSecond);
  EXPECT_EQ(StatusOf([&] { captures.Delete("run", 4 * kSecond); }), 409);
  EXPECT_EQ(StatusOf([&] { captures.Rename("run", "run2"); }), 409);
  EXPECT_EQ(StatusOf([&] { captures.SetNotes("run", "x"); }), 409);
  EXPECT_EQ(StatusOf([&] { captures.Rename("walk", "run"); }), 409);  // taken
  EXPECT_EQ(StatusOf([&] { captures.Rename("walk", "../up"); }), 400);
  EXPECT_EQ(StatusOf([&] { captures.Rename("nope", "x"); }), 404);
  EXPECT_EQ(StatusOf([&] { captures.SetNotes("walk", std::string(Captures::kMaxNotesBytes + 1, 'a')); }), 400);

  const nlohmann::json noted = captures.SetNotes("walk", "subject 3\nknee brace");
  EXPECT_EQ(noted["notes"], "subject 3\nknee brace");
  const nlohmann::json renamed = captures.Rename("walk", "walk_s3");
  EXPECT_EQ(renamed["name"], "walk_s3");
  EXPECT_EQ(renamed["state"], "complete");
  EXPECT_EQ(renamed["notes"], "subject 3\nknee brace");
  EXPECT_FALSE(fs::exists(dir_ / "sessions" / "walk"));
  EXPECT_FALSE(captures.SetNotes("walk_s3", "").contains("notes"));

  const uintmax_t log_bytes = fs::file_size(dir_ / "sessions" / "walk_s3" / "raw.mlog");
  const nlohmann::json deleted = captures.Delete("walk_s3", 5 * kSecond);
  const fs::path moved = deleted["moved_to"].get<std::string>();
  EXPECT_EQ(moved.parent_path(), dir_ / "sessions" / ".deleted");
  EXPECT_EQ(fs::file_size(moved / "raw.mlog"), log_bytes);  // kept whole
  EXPECT_EQ(StatusOf([&] { captures.Describe("walk_s3"); }), 404);
  for (const nlohmann::json& s : captures.List()) EXPECT_NE(s["name"], "walk_s3");
  // A second session of the same name deleted in the same second is kept beside the first.
  captures.Stop(IngestStats{}, 6 * kSecond);
  captures.Rename("run", "walk_s3");
  EXPECT_NE(captures.Delete("walk_s3", 5 * kSecond)["moved_to"], moved.string());
}

// The probe: a full disk ended serve (flush failed, exit 1) and left session.json "capturing"
// with 0 frame sets. Now the capture ends "failed: disk full" and the service goes on.
TEST_F(CaptureTest, ALowDiskRefusesAStartAndEndsARunningCaptureFailedDiskFull) {
  disk_.start_free_mb = 10;
  disk_.warn_free_mb = 20;
  disk_.stop_free_mb = 2;
  Captures captures = Make();
  free_ = 5 * kMiB;
  EXPECT_EQ(StatusOf([&] { captures.Start("low", IngestStats{}, kSecond); }), 507);
  EXPECT_FALSE(fs::exists(dir_ / "sessions" / "low"));
  free_ = 30 * kMiB;
  IngestStats stats;
  captures.Start("fills", stats, kSecond);
  EXPECT_TRUE(fs::exists(dir_ / "sessions" / "fills" / ".reserve"));
  pipeline::LiveFrame frame;
  for (int i = 0; i < 3; ++i) captures.AddPublished(frame);
  stats.nodes[1].frames = 6;
  EXPECT_TRUE(captures.Tick(stats, kSecond + kSecond / 2).is_null());
  free_ = 15 * kMiB;  // below warn: still capturing
  EXPECT_TRUE(captures.Tick(stats, 2 * kSecond).is_null());
  EXPECT_TRUE(captures.Disk()["low"].get<bool>());
  free_ = 1 * kMiB;
  const nlohmann::json failed = captures.Tick(stats, 3 * kSecond);
  ASSERT_FALSE(failed.is_null());
  EXPECT_EQ(failed["state"], "failed");
  EXPECT_EQ(failed["reason"], "disk full");
  EXPECT_EQ(failed["frame_sets"], 3);
  EXPECT_FALSE(captures.running());
  EXPECT_EQ(captures.last(), failed);
  const SessionInfo info = LoadSessionInfo((dir_ / "sessions" / "fills").string());
  EXPECT_EQ(info.extra["capture_state"], "failed");
  EXPECT_EQ(info.extra["failure"], "disk full");
  EXPECT_EQ(info.frame_sets, 3u);
  EXPECT_EQ(info.camera_frames, 6u);
  EXPECT_FALSE(fs::exists(dir_ / "sessions" / "fills" / ".reserve"));
  // A restarted service lists it as failed, not interrupted.
  Captures restarted = Make();
  EXPECT_TRUE(restarted.RecoverInterrupted().empty());
  EXPECT_EQ(restarted.List()[0]["state"], "failed");
  std::printf("disk below stop_free_mb: capture %s after %d frame sets, reason '%s'\n",
              failed["state"].get<std::string>().c_str(), failed["frame_sets"].get<int>(),
              failed["reason"].get<std::string>().c_str());
}

// The probe: a killed capture reported frame_sets 0; session.json now follows it every second.
TEST_F(CaptureTest, SessionJsonCountsFollowARunningCapture) {
  Captures captures = Make();
  IngestStats stats;
  captures.Start("live", stats, kSecond);
  pipeline::LiveFrame frame;
  for (int i = 0; i < 5; ++i) captures.AddPublished(frame);
  stats.nodes[1].frames = 10;
  captures.Tick(stats, kSecond + kSecond / 2);
  EXPECT_EQ(LoadSessionInfo((dir_ / "sessions" / "live").string()).frame_sets, 0u);
  captures.Tick(stats, 2 * kSecond + 1);
  const SessionInfo info = LoadSessionInfo((dir_ / "sessions" / "live").string());
  EXPECT_EQ(info.frame_sets, 5u);
  EXPECT_EQ(info.camera_frames, 10u);
  EXPECT_EQ(info.extra["capture_state"], "capturing");
}

// A write that fails for another reason (here the file-size limit: EFBIG) ends the capture with
// that reason at the next turn; nothing is thrown into the frame path.
TEST_F(CaptureTest, AFailedWriteEndsTheCaptureWithItsReason) {
  Captures captures = Make();
  captures.Start("big", IngestStats{}, kSecond);
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = saved;
  small.rlim_cur = 64 * 1024;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::vector<uint8_t> datagram(1000, 7);
  for (int i = 0; i < 200; ++i) captures.writer()->AppendDatagram(datagram.data(), datagram.size(), 1);
  const nlohmann::json failed = captures.Tick(IngestStats{}, 2 * kSecond);
  setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous);
  ASSERT_FALSE(failed.is_null());
  EXPECT_EQ(failed["state"], "failed");
  EXPECT_NE(failed["reason"].get<std::string>().find("File too large"), std::string::npos) << failed.dump();
  EXPECT_EQ(LoadSessionInfo((dir_ / "sessions" / "big").string()).extra["capture_state"], "failed");
}

// What `record` refused before it was serve's loop ("holds a recorded session already"), and serve
// too: a capture never overwrites a session. A named capture under an existing name is a
// conflict; a direct capture into a directory holding a raw log is refused with SessionWriter's
// words; either way the session's log and session.json stay as they were.
TEST_F(CaptureTest, AnExistingSessionIsNeverOverwritten) {
  Captures captures = Make();
  captures.Start("take", IngestStats{}, kSecond);
  const uint8_t datagram[] = {1, 2, 3, 4};
  captures.writer()->AppendDatagram(datagram, sizeof(datagram), 5);
  captures.Stop(IngestStats{}, 2 * kSecond);
  const fs::path session = dir_ / "sessions" / "take";
  const auto log_size = fs::file_size(session / "raw.mlog");
  const auto json_time = fs::last_write_time(session / "session.json");
  try {
    captures.Start("take", IngestStats{}, 3 * kSecond);
    ADD_FAILURE() << "a capture was started over an existing session";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 409);
    EXPECT_NE(std::string(e.what()).find("session 'take' exists already"), std::string::npos) << e.what();
  }
  DirectCapture direct;
  direct.dir = session.string();
  try {
    captures.StartDirect(direct, IngestStats{}, 3 * kSecond);
    ADD_FAILURE() << "a direct capture was started over an existing session";
  } catch (const ApiError& e) {
    EXPECT_NE(std::string(e.what()).find("holds a recorded session already"), std::string::npos) << e.what();
  }
  EXPECT_EQ(captures.writer(), nullptr);
  EXPECT_EQ(fs::file_size(session / "raw.mlog"), log_size);
  EXPECT_EQ(fs::last_write_time(session / "session.json"), json_time);
  EXPECT_EQ(LoadSessionInfo(session.string()).extra["capture_state"], "complete");
  // Any entry of that name counts for a named capture, not only a finished session.
  fs::create_directories(dir_ / "sessions" / "stray");
  EXPECT_EQ(StatusOf([&] { captures.Start("stray", IngestStats{}, 4 * kSecond); }), 409);
  EXPECT_FALSE(fs::exists(dir_ / "sessions" / "stray" / "session.json"));
}

pipeline::LiveFrame FrameReceivedAt(uint64_t number, uint64_t last_receive_ns) {
  pipeline::LiveFrame frame;
  frame.frame_number = number;
  frame.last_receive_ns = last_receive_ns;
  return frame;
}

// record --frames N on a hub without sessions directory: exactly N frame sets counted and told,
// however many are published, and the limit reached at the Nth.
TEST_F(CaptureTest, ADirectCaptureCountsExactlyItsFrameSets) {
  Captures captures(std::string(), (dir_ / "cal.json").string(), base_, disk_, [this](const std::string&) {
    return free_;
  });
  captures.Lock();  // nothing to lock
  EXPECT_EQ(StatusOf([&] { captures.Start("named", IngestStats{}, kSecond); }), 409);
  EXPECT_EQ(StatusOf([&] { captures.StartDirect(DirectCapture{}, IngestStats{}, kSecond); }), 400);
  std::vector<uint64_t> told;
  DirectCapture direct;
  direct.dir = (dir_ / "out" / "rec").string();
  direct.max_frame_sets = 3;
  direct.on_frame = [&told](const FrameSet& set, const pipeline::LiveFrame& frame) {
    EXPECT_EQ(set.frame_number, frame.frame_number);
    told.push_back(frame.frame_number);
  };
  captures.StartDirect(direct, IngestStats{}, kSecond);
  ASSERT_NE(captures.WriterFor(kSecond), nullptr);
  for (uint64_t n = 0; n < 5; ++n) {
    EXPECT_EQ(captures.limit_reached(), n >= 3) << n;
    FrameSet set;
    set.frame_number = n;
    captures.AddPublished(FrameReceivedAt(n, kSecond + n), set);
  }
  EXPECT_EQ(told, (std::vector<uint64_t>{0, 1, 2}));
  const nlohmann::json summary = captures.Stop(IngestStats{}, 2 * kSecond);
  EXPECT_EQ(summary["frame_sets"], 3);
  EXPECT_EQ(summary["name"], "rec");
  const SessionInfo info = LoadSessionInfo(direct.dir);
  EXPECT_EQ(info.frame_sets, 3u);
  EXPECT_EQ(info.source, "record");
  EXPECT_EQ(info.extra["capture_state"], "complete");
  EXPECT_TRUE(fs::exists(fs::path(direct.dir) / "calibration.json"));
  EXPECT_FALSE(fs::exists(fs::path(direct.dir) / ".reserve"));
  EXPECT_FALSE(captures.limit_reached());  // the next capture starts afresh
}

// record --duration S: datagrams the kernel received from the end on are not logged, sets whose
// last datagram came then not counted, and the end reached by the clock without any datagram too;
// record --idle-timeout: silence after data ends it.
TEST_F(CaptureTest, ADirectCaptureEndsAtItsReceiveTimeAndAfterSilence) {
  Captures captures = Make();
  DirectCapture direct;
  direct.dir = (dir_ / "timed").string();
  direct.end_receive_ns = 5 * kSecond;
  captures.StartDirect(direct, IngestStats{}, kSecond);
  EXPECT_NE(captures.WriterFor(5 * kSecond - 1), nullptr);
  captures.AddPublished(FrameReceivedAt(0, 5 * kSecond - 1));
  EXPECT_FALSE(captures.limit_reached());
  EXPECT_EQ(captures.WriterFor(5 * kSecond), nullptr);
  EXPECT_TRUE(captures.limit_reached());
  captures.AddPublished(FrameReceivedAt(1, 5 * kSecond));
  EXPECT_EQ(captures.Stop(IngestStats{}, 6 * kSecond)["frame_sets"], 1);

  direct.dir = (dir_ / "quiet").string();
  captures.StartDirect(direct, IngestStats{}, kSecond);
  captures.Tick(IngestStats{}, 5 * kSecond - 1);
  EXPECT_FALSE(captures.limit_reached());
  captures.Tick(IngestStats{}, 5 * kSecond);
  EXPECT_TRUE(captures.limit_reached());
  captures.Stop(IngestStats{}, 6 * kSecond);

  direct.dir = (dir_ / "idle").string();
  direct.end_receive_ns = 0;
  direct.idle_ns = kSecond;
  captures.StartDirect(direct, IngestStats{}, kSecond);
  captures.Tick(IngestStats{}, 10 * kSecond);
  EXPECT_FALSE(captures.limit_reached()) << "silence before any datagram is waiting, not idling";
  ASSERT_NE(captures.WriterFor(10 * kSecond), nullptr);
  captures.Tick(IngestStats{}, 11 * kSecond);
  EXPECT_FALSE(captures.limit_reached());
  captures.Tick(IngestStats{}, 11 * kSecond + 1);
  EXPECT_TRUE(captures.limit_reached());
}

// A record into a serve's sessions directory takes that directory's lock: refused while a serve
// holds it, and a serve started meanwhile is refused (neither relabels the other's session).
TEST_F(CaptureTest, ADirectCaptureIntoAServesSessionsDirectoryTakesItsLock) {
  std::optional<Captures> serve;
  serve.emplace((dir_ / "sessions").string(), (dir_ / "cal.json").string(), base_, disk_,
                [this](const std::string&) { return free_; });
  serve->Lock();
  Captures record(std::string(), (dir_ / "cal.json").string(), base_, disk_, [this](const std::string&) {
    return free_;
  });
  DirectCapture direct;
  direct.dir = (dir_ / "sessions" / "rec").string();
  EXPECT_EQ(StatusOf([&] { record.StartDirect(direct, IngestStats{}, kSecond); }), 409);
  EXPECT_FALSE(fs::exists(dir_ / "sessions" / "rec"));
  EXPECT_EQ(record.writer(), nullptr);

  Captures later = Make();  // a serve started while the record runs
  serve.reset();             // the first serve has gone
  record.StartDirect(direct, IngestStats{}, kSecond);
  EXPECT_THROW(later.Lock(), std::runtime_error);
  record.Stop(IngestStats{}, 2 * kSecond);
  EXPECT_NO_THROW(later.Lock());
  EXPECT_EQ(LoadSessionInfo(direct.dir).extra["capture_state"], "complete");
}

// The probe: a second serve on the same sessions directory relabelled the first's running
// capture "interrupted". The directory is now locked by the first.
TEST_F(CaptureTest, ASecondServiceOnTheSessionsDirectoryIsRefused) {
  Captures first = Make();
  first.Lock();
  first.Start("running", IngestStats{}, kSecond);
  Captures second = Make();
  try {
    second.Lock();
    ADD_FAILURE() << "a second lock was granted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is in use by another serve or record (pid " + std::to_string(getpid()) + ")"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(first.List()[0]["state"], "capturing");
}

}  // namespace
}  // namespace mocap::service
