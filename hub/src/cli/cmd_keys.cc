// `keys new|rotate|retire|list`: the installation's wire keys (wire/key_file.h), one file per
// node in a keys directory: the hub reads the directory (serve --keys DIR), each node gets a copy
// of its own file (node config `key_file`). Keys come from libsodium's CSPRNG; files are written
// atomically with mode 0600 and never printed. Rotation is a change-over in two steps: `rotate`
// puts a new key first and keeps the old one (both sides accept both; the node signs with the
// new one once it has the file, and the hub follows it), `retire` drops the old key.
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "wire/key_file.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

struct KeysArgs {
  std::vector<uint32_t> nodes;
  std::string dir;
  int key_id = 1;
  bool force = false;
  bool json = false;
};

std::string PathOf(const KeysArgs& a, uint32_t node) { return (fs::path(a.dir) / wire::KeyFileName(node)).string(); }

std::string Ids(const wire::KeyFile& f) {
  std::string ids;
  for (const auto& k : f.keys) ids += (ids.empty() ? "" : ", ") + std::to_string(k.id);
  return ids;
}

void EnsurePrivateDirectory(const std::string& dir) {
  std::error_code ec;
  if (fs::create_directories(dir, ec)) {
    fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace, ec);
  }
  if (!fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create the keys directory");
}

void RunNew(const KeysArgs& a) {
  if (a.key_id < 1 || a.key_id > 255) throw UsageError("--key-id must be 1..255");
  EnsurePrivateDirectory(a.dir);
  for (uint32_t node : a.nodes) {
    const std::string path = PathOf(a, node);
    if (fs::exists(path) && !a.force)
      throw std::runtime_error(path + " exists (rotate it with `keys rotate`, or --force to replace it)");
    wire::KeyFile f;
    f.node_id = node;
    f.keys.push_back({static_cast<uint8_t>(a.key_id), wire::GenerateKey()});
    wire::WriteKeyFile(path, f);
    std::printf("%s: node %u, key %d\n", path.c_str(), node, a.key_id);
  }
}

void RunRotate(const KeysArgs& a) {
  for (uint32_t node : a.nodes) {
    const std::string path = PathOf(a, node);
    wire::KeyFile f = wire::ReadKeyFile(path);
    if (f.keys.size() >= wire::kMaxKeysPerFile)
      throw std::runtime_error(path + ": a change-over is under way (keys " + Ids(f) + "); `keys retire` it first");
    const uint8_t id = static_cast<uint8_t>(f.keys.front().id % 255 + 1);
    f.keys.insert(f.keys.begin(), {id, wire::GenerateKey()});
    wire::WriteKeyFile(path, f);
    std::printf("%s: node %u, keys %s (%u signs once the node has this file; copy it to the node)\n", path.c_str(),
                node, Ids(f).c_str(), id);
  }
}

void RunRetire(const KeysArgs& a) {
  for (uint32_t node : a.nodes) {
    const std::string path = PathOf(a, node);
    wire::KeyFile f = wire::ReadKeyFile(path);
    if (f.keys.size() > 1) {
      f.keys.resize(1);
      wire::WriteKeyFile(path, f);
    }
    std::printf("%s: node %u, key %s\n", path.c_str(), node, Ids(f).c_str());
  }
}

void RunList(const KeysArgs& a) {
  nlohmann::json out = nlohmann::json::array();
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(a.dir))
    if (e.path().extension() == ".key") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& p : files) {
    try {
      const wire::KeyFile f = wire::ReadKeyFile(p.string());
      nlohmann::json ids = nlohmann::json::array();
      for (const auto& k : f.keys) ids.push_back(k.id);
      out.push_back({{"file", p.string()}, {"node", f.node_id}, {"key_ids", ids}, {"signing_key_id", f.keys[0].id}});
      if (!a.json)
        std::printf("%s: node %u, keys %s%s\n", p.c_str(), f.node_id, Ids(f).c_str(),
                    f.keys.size() > 1 ? " (change-over: the first signs)" : "");
    } catch (const std::exception& e) {
      out.push_back({{"file", p.string()}, {"error", e.what()}});
      if (!a.json) std::printf("%s: UNUSABLE: %s\n", p.c_str(), e.what());
    }
  }
  if (a.json) std::printf("%s\n", out.dump(2).c_str());
}

CLI::App* AddNodesArgument(CLI::App* command, KeysArgs& a) {
  command->add_option("NODE_ID", a.nodes, "Node ids (1..4095)")->required()->check(CLI::Range(1, 4095));
  return command;
}

}  // namespace

void AddKeysCommands(CLI::App& app) {
  CLI::App& group = CommandGroup(app, "keys");
  auto args = std::make_shared<KeysArgs>();

  CLI::App* make = AddNodesArgument(group.add_subcommand("new", "Generate a wire key file per node (mode 0600)"), *args);
  make->add_option("--out", args->dir, "Keys directory (created with mode 0700)")->required();
  make->add_option("--key-id", args->key_id, "Key id of the new key (1..255)")->capture_default_str();
  make->add_flag("--force", args->force, "Replace an existing key file");
  make->callback([args] { RunNew(*args); });

  CLI::App* rotate =
      AddNodesArgument(group.add_subcommand("rotate", "Start a change-over: a new key first, the old one kept"), *args);
  rotate->add_option("--dir", args->dir, "Keys directory")->required()->check(CLI::ExistingDirectory);
  rotate->callback([args] { RunRotate(*args); });

  CLI::App* retire =
      AddNodesArgument(group.add_subcommand("retire", "End a change-over: keep only the first (new) key"), *args);
  retire->add_option("--dir", args->dir, "Keys directory")->required()->check(CLI::ExistingDirectory);
  retire->callback([args] { RunRetire(*args); });

  CLI::App* list = group.add_subcommand("list", "Node and key ids of every key file (never the keys)");
  list->add_option("--dir", args->dir, "Keys directory")->required()->check(CLI::ExistingDirectory);
  list->add_flag("--json", args->json, "One JSON array on stdout");
  list->callback([args] { RunList(*args); });
}

}  // namespace mocap
