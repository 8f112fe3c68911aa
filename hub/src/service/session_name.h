// The one rule for a session's name and for the names of its files, shared by the captures
// (which make and serve them) and the API's router (which refuses any other before the service
// sees it): a plain name (util/plain_name.h), so nothing outside the sessions directory.
#pragma once

#include <string>

#include "util/plain_name.h"

namespace mocap::service {

// Letters, digits, '.', '-', '_'; 1-64 characters, not starting with '.'.
inline bool ValidSessionName(const std::string& name) { return PlainName(name, 64); }

}  // namespace mocap::service
