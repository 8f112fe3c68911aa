// The web console's static files (hub/web: HTML, ES modules, CSS) and the Debian-packaged
// libraries it imports (three.js from libjs-three), looked up from a request's path as a pure
// function of the path and the file system: which file, of which type, or why not.
//
// Only plain names are served: every path segment is letters, digits, '.', '-' or '_', not
// starting with '.', under a known extension; the file found must be a regular file whose real
// path (links resolved) lies inside its mount's real directory, so neither "..", nor an encoded
// slash, nor a link can reach anything else. "/" is "/index.html".
//
// Error policy: nothing throws; a path that is not served gets status 404 with a reason.
#pragma once

#include <string>
#include <vector>

namespace mocap::api {

struct StaticMount {
  std::string prefix;  // URL prefix, starting and ending with '/': "/", "/vendor/three/"
  std::string dir;     // the directory it maps to
};

struct StaticFile {
  int status = 404;          // 200: path and content_type are set; else reason says why not
  std::string path;
  std::string content_type;
  std::string reason;
};

// The longest prefix among `mounts` that starts `url_path` decides where to look.
StaticFile ResolveStaticFile(const std::vector<StaticMount>& mounts, const std::string& url_path);

// The console's mounts: the web root at "/" and three.js at "/vendor/three/" (each only when
// its directory exists).
std::vector<StaticMount> ConsoleMounts(const std::string& web_root, const std::string& three_dir);

}  // namespace mocap::api
