// The streams wired to the service: a HubService on loopback with the own UDP stream and the
// Qualisys RT server; their figures in its status, captures started and stopped through the
// service reaching a Qualisys RT client as the protocol's events, nothing left behind once the
// fan-out is gone.
#include "service/stream_fan_out.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <poll.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <regex>
#include <thread>

#include <gtest/gtest.h>

#include "io/calibration_json.h"
#include "simcore/test_scenes.h"

namespace mocap::service {
namespace {

namespace fs = std::filesystem;

// One Qualisys RT packet: little-endian size (header included) and type, then the body.
struct RtPacket {
  uint32_t type = 99;  // 99: none within the wait
  std::string body;
};

class RtClient {
 public:
  explicit RtClient(uint16_t port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~RtClient() { close(fd_); }
  bool connected() const { return connected_; }

  // The next packet, waiting at most 5 s (a bound that catches a hang, not a timing).
  RtPacket Next() {
    for (int turn = 0; turn < 50; ++turn) {
      if (bytes_.size() >= 8) {
        uint32_t size = 0, type = 0;
        std::memcpy(&size, bytes_.data(), 4);
        std::memcpy(&type, bytes_.data() + 4, 4);
        if (size >= 8 && bytes_.size() >= size) {
          RtPacket p{type, bytes_.substr(8, size - 8)};
          bytes_.erase(0, size);
          return p;
        }
      }
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char buffer[4096];
      const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) break;
      bytes_.append(buffer, static_cast<size_t>(n));
    }
    return {};
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
  std::string bytes_;
};

class StreamFanOutTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("stream_fan_out_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    SaveRigJson(testing::RingRig(4, 1), (dir_ / "calibration.json").string());
    serve_.listen = "127.0.0.1:0";
    serve_.calibration = (dir_ / "calibration.json").string();
    serve_.sessions_dir = (dir_ / "sessions").string();
    serve_.auth.insecure_dev = true;
    serve_.calibration_monitor = false;
    serve_.disk.start_free_mb = 1.0;
    serve_.disk.warn_free_mb = 1.0;
    serve_.disk.stop_free_mb = 0.5;
    streams_.stream.listen = "127.0.0.1:0";
    streams_.qtm_rt = "127.0.0.1:0";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  ServeOptions serve_;
  StreamsOptions streams_;
};

uint16_t PortIn(const std::vector<std::string>& where, const std::string& pattern) {
  const std::regex re(pattern + ":?(\\d+)");
  for (const std::string& line : where) {
    std::smatch m;
    if (std::regex_search(line, m, re)) return static_cast<uint16_t>(std::stoi(m[1]));
  }
  return 0;
}

// The hub's loop on a thread of its own for the test's life; requests wait until it runs.
class RunningHub {
 public:
  explicit RunningHub(HubService& hub) : loop_([this, &hub] { hub.Run(stop_); }) {
    for (int i = 0; i < 500; ++i) {
      try {
        hub.Status();
        return;
      } catch (const ApiError&) {  // not running yet: 503
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
  }
  ~RunningHub() {
    stop_ = true;
    loop_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread loop_;
};

TEST_F(StreamFanOutTest, CapturesReachTheQualisysClientsAsEvents) {
  HubService hub(serve_);
  hub.Bind();
  RunningHub running(hub);
  {
    StreamFanOut streams(serve_, streams_, hub);
    const std::vector<std::string> where = streams.Where();
    ASSERT_EQ(where.size(), 2u);
    EXPECT_NE(PortIn(where, "stream: UDP port "), 0);
    const uint16_t rt_port = PortIn(where, "Qualisys RT on 127\\.0\\.0\\.1");
    ASSERT_NE(rt_port, 0);
    const nlohmann::json status = hub.Status();
    EXPECT_TRUE(status.contains("stream"));
    EXPECT_TRUE(status.contains("qtm_rt"));
    EXPECT_FALSE(status.contains("osc"));

    RtClient client(rt_port);
    ASSERT_TRUE(client.connected());
    EXPECT_EQ(client.Next().type, 1u);  // "QTM RT Interface connected"
    hub.StartCapture("fan_out");
    const RtPacket started = client.Next();
    EXPECT_EQ(started.type, 6u);
    EXPECT_EQ(started.body, std::string(1, 3));  // Capture Started
    hub.StopCapture();
    const RtPacket stopped = client.Next();
    EXPECT_EQ(stopped.type, 6u);
    EXPECT_EQ(stopped.body, std::string(1, 4));  // Capture Stopped
  }
  const nlohmann::json status = hub.Status();
  EXPECT_FALSE(status.contains("stream"));
  EXPECT_FALSE(status.contains("qtm_rt"));
}

TEST_F(StreamFanOutTest, BadStreamOptionsAreRefusedBeforeAnythingStarts) {
  streams_.osc_targets = "127.0.0.1:9000";
  streams_.osc_parts = "points,nonsense";
  EXPECT_THROW(streams_.Check(serve_), std::invalid_argument);
  streams_.osc_parts = "points";
  streams_.qtm_rt = "no port";
  EXPECT_THROW(streams_.Check(serve_), std::invalid_argument);
  streams_.qtm_rt.clear();
  EXPECT_NO_THROW(streams_.Check(serve_));
}

}  // namespace
}  // namespace mocap::service
