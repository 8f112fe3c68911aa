// The trajectory editor's side of a recipe's results (SESSION/processed/RECIPE/): its edit log
// (edits.json, edit/edit_log.h) and the edited outputs it makes from the results' marker file,
// never over it: markers.trc -> edited.trc, markers.c3d -> edited.c3d (C3D residuals mark filled
// samples), and edited.filled.tsv (edit/edit_output.h). GET and PUT
// /api/sessions/NAME/processed/RECIPE/edits call these (api_router.h); undo in the console is a
// PUT of the log without its last operation. Files, no sockets: tested on a temporary directory.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace mocap::service {

// {"edits": the saved log (an empty one when none), "input": the marker file edited,
//  "outputs": the edited files present}. ApiError 404 when the results hold no marker file.
nlohmann::json ReadProcessedEdits(const std::filesystem::path& dir);

// Checks `log`, applies it to the marker file and only then saves it and writes the outputs:
// {"edits", "input", "outputs", "operations": one line each, "spikes": [...],
//  "filled": [{"marker", "first_frame", "last_frame", "method"}]}. ApiError 400 naming the
// operation, field and rule when the log is refused or an operation cannot apply (nothing is
// written then), 404 as above.
nlohmann::json WriteProcessedEdits(const std::filesystem::path& dir, const nlohmann::json& log);

}  // namespace mocap::service
