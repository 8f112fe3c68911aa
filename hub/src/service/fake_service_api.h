// A ServiceApi that records what the router asked for and answers with what it was given, for
// the router's test and fuzzer (no loop, no nodes).
#pragma once

#include <string>
#include <vector>

#include "service/api_error.h"
#include "service/service_api.h"

namespace mocap::service {

class FakeServiceApi : public ServiceApi {
 public:
  std::vector<std::string> calls;
  CameraSettings last_settings;
  uint32_t last_node = 0;
  uint32_t last_number = 0;
  bool last_thresholded = false;
  std::string last_name;
  WandingOptions last_wanding;
  WorldFrameRequest last_world;
  bool last_flag = false;
  nlohmann::json last_request;
  uint32_t known_node = 1;  // other ids answer 404, as the service does

  nlohmann::json Status() override { return Call("status"); }
  nlohmann::json Nodes() override { return Call("nodes"); }
  nlohmann::json Node(uint32_t id) override { return Call("node", id); }
  nlohmann::json Configure(uint32_t id, const CameraSettings& s) override {
    last_settings = s;
    return Call("configure", id);
  }
  nlohmann::json Identify(uint32_t id, uint32_t ms) override {
    last_number = ms;
    return Call("identify", id);
  }
  std::vector<uint8_t> PreviewPng(uint32_t id, bool thresholded, uint32_t downscale) override {
    last_thresholded = thresholded;
    last_number = downscale;
    Call("preview", id);
    return {0x89, 'P', 'N', 'G'};
  }
  nlohmann::json AutoMask(int frames) override {
    last_number = static_cast<uint32_t>(frames);
    return Call("automask");
  }
  nlohmann::json ClearMasks() override { return Call("clearmasks"); }
  nlohmann::json StartCapture(const std::string& name) override {
    last_name = name;
    return Call("start");
  }
  nlohmann::json StopCapture() override { return Call("stop"); }
  nlohmann::json Sessions() override { return Call("sessions"); }
  nlohmann::json Session(const std::string& name) override {
    last_name = name;
    return Call("session");
  }
  std::string SessionFile(const std::string& name, const std::string& file) override {
    last_name = name + "/" + file;
    Call("sessionfile");
    return "/sessions/" + name + "/" + file;
  }
  nlohmann::json DeleteSession(const std::string& name) override {
    last_name = name;
    return Call("deletesession");
  }
  nlohmann::json RenameSession(const std::string& name, const std::string& new_name) override {
    last_name = name + ">" + new_name;
    return Call("renamesession");
  }
  nlohmann::json AnnotateSession(const std::string& name, const std::string& notes) override {
    last_name = name + ":" + notes;
    return Call("annotatesession");
  }
  nlohmann::json Calibration() override { return Call("calibration"); }
  nlohmann::json Blobs() override { return Call("blobs"); }
  nlohmann::json StartWanding(const WandingOptions& options) override {
    last_wanding = options;
    return Call("wandstart");
  }
  nlohmann::json Wanding() override { return Call("wanding"); }
  nlohmann::json StopWanding(bool solve) override {
    last_flag = solve;
    return Call("wandstop");
  }
  nlohmann::json SolveWanding(const std::string& refine_intrinsics) override {
    last_name = refine_intrinsics;
    return Call("wandsolve");
  }
  nlohmann::json ApplyWandCalibration(bool save) override {
    last_flag = save;
    return Call("wandapply");
  }
  nlohmann::json ApplyMonitorSolve(uint32_t camera_id, bool save) override {
    last_number = camera_id;
    last_flag = save;
    return Call("monitorapply");
  }
  nlohmann::json SetWorldFrame(const WorldFrameRequest& request) override {
    last_world = request;
    return Call("world");
  }
  nlohmann::json ProcessSession(const std::string& name, const nlohmann::json& request) override {
    last_name = name;
    last_request = request;
    return Call("process");
  }
  nlohmann::json Processing() override { return Call("processing"); }
  std::string ProcessedFile(const std::string& name, const std::string& recipe, const std::string& file) override {
    calls.push_back("processedfile");
    return "/sessions/" + name + "/processed/" + recipe + "/" + file;
  }
  nlohmann::json ProcessedEdits(const std::string& name, const std::string& recipe) override {
    last_name = name + "/" + recipe;
    return Call("edits");
  }
  nlohmann::json PutProcessedEdits(const std::string& name, const std::string& recipe, const nlohmann::json& log) override {
    last_name = name + "/" + recipe;
    last_request = log;
    return Call("putedits");
  }

 private:
  nlohmann::json Call(const std::string& what, uint32_t node = 0) {
    calls.push_back(what);
    if (node) {
      last_node = node;
      if (node != known_node) throw ApiError(404, "no node " + std::to_string(node));
    }
    return {{"called", what}};
  }
};

}  // namespace mocap::service
