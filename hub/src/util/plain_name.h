// A plain name: one that, taken from a request, cannot leave the directory it is looked up in
// and names nothing hidden: letters, digits, '.', '-', '_', 1..max_size characters, not starting
// with '.' (so no separator, no "." or ".."). The captures' session names and the web console's
// path segments both use this rule.
#pragma once

#include <cstddef>
#include <string>

namespace mocap {

inline bool PlainName(const std::string& name, size_t max_size) {
  if (name.empty() || name.size() > max_size || name[0] == '.') return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '-' || c == '_';
    if (!ok) return false;
  }
  return true;
}

}  // namespace mocap
