// Static files of the web console (see static_files.h).
#include "api/static_files.h"

#include <filesystem>
#include <system_error>

#include "util/plain_name.h"

namespace mocap::api {
namespace fs = std::filesystem;
namespace {

constexpr size_t kMaxPath = 512;
constexpr size_t kMaxSegments = 16;
constexpr size_t kMaxSegment = 128;  // characters of one segment

const char* ContentType(const std::string& name) {
  const size_t dot = name.rfind('.');
  if (dot == std::string::npos) return nullptr;
  const std::string ext = name.substr(dot + 1);
  if (ext == "html") return "text/html; charset=utf-8";
  if (ext == "js" || ext == "mjs") return "text/javascript; charset=utf-8";
  if (ext == "css") return "text/css; charset=utf-8";
  if (ext == "png") return "image/png";
  if (ext == "svg") return "image/svg+xml";
  if (ext == "ico") return "image/x-icon";
  return nullptr;
}

StaticFile NotFound(const std::string& reason) {
  StaticFile f;
  f.reason = reason;
  return f;
}

bool Inside(const fs::path& file, const fs::path& dir) {
  auto f = file.begin();
  for (auto d = dir.begin(); d != dir.end(); ++d, ++f)
    if (f == file.end() || *f != *d) return false;
  return true;
}

}  // namespace

StaticFile ResolveStaticFile(const std::vector<StaticMount>& mounts, const std::string& url_path) {
  if (url_path.empty() || url_path[0] != '/' || url_path.size() > kMaxPath) return NotFound("not a served path");
  const std::string path = url_path == "/" ? "/index.html" : url_path;
  const StaticMount* mount = nullptr;
  for (const StaticMount& m : mounts)
    if (path.compare(0, m.prefix.size(), m.prefix) == 0 && (!mount || m.prefix.size() > mount->prefix.size()))
      mount = &m;
  if (!mount) return NotFound("no such file: " + path);
  fs::path relative;
  size_t segments = 0;
  size_t start = mount->prefix.size();
  while (true) {
    const size_t end = path.find('/', start);
    const std::string segment = path.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!PlainName(segment, kMaxSegment) || ++segments > kMaxSegments) return NotFound("not a served path: " + path);
    relative /= segment;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  const char* type = ContentType(relative.filename().string());
  if (!type) return NotFound("not a served file type: " + path);
  std::error_code ec;
  const fs::path root = fs::canonical(mount->dir, ec);
  if (ec) return NotFound("no such file: " + path);
  const fs::path file = fs::canonical(root / relative, ec);
  if (ec || !Inside(file, root) || !fs::is_regular_file(file, ec)) return NotFound("no such file: " + path);
  StaticFile found;
  found.status = 200;
  found.path = file.string();
  found.content_type = type;
  return found;
}

std::vector<StaticMount> ConsoleMounts(const std::string& web_root, const std::string& three_dir) {
  std::vector<StaticMount> mounts;
  std::error_code ec;
  if (!web_root.empty() && fs::is_directory(web_root, ec)) mounts.push_back({"/", web_root});
  if (!three_dir.empty() && fs::is_directory(three_dir, ec)) mounts.push_back({"/vendor/three/", three_dir});
  return mounts;
}

}  // namespace mocap::api
