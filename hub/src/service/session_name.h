// The one rule for a session's name and for the names of its files, shared by the captures
// (which make and serve them) and the API's router (which refuses any other before the service
// sees it): nothing that could leave the sessions directory.
#pragma once

#include <string>

namespace mocap::service {

// Letters, digits, '.', '-', '_'; 1-64 characters, not starting with '.'.
bool ValidSessionName(const std::string& name);

}  // namespace mocap::service
