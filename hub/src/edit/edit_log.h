// The edit log: a JSON list of operations applied in order to a processed result (edit_apply.h),
// never to the file in place. It is what the console shows, what undo shortens and what a
// replay re-applies. Format (docs/editor.md):
//   {"format": "mocap-edits", "version": 1, "operations": [
//     {"op": "fill", "marker": "LKNE", "method": "spline", "from": 120, "to": 180},
//     {"op": "swap", "markers": ["LKNE", "RKNE"], "from": 300, "to": 420}, ...]}
// Frame fields are the take's frame numbers (Time x rate: Frame# - 1 in the hub's own TRC files),
// inclusive. Reading refuses
// anything it does not know (field, value and rule named) and bounds every size.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edit/edited_take.h"

namespace mocap::edit {

enum class EditKind { kFill, kSwap, kSplit, kJoin, kRename, kDelete, kSpikes };

const char* EditKindName(EditKind kind);

struct EditOperation {
  EditKind kind = EditKind::kFill;
  // fill, split, join, rename, delete: the column acted on; swap: the first of the two.
  std::string marker;
  // swap: the second column; join: the column merged into `marker`; split, rename: the new name.
  std::string other;
  // fill: donors; spikes: the columns looked at (empty: all).
  std::vector<std::string> markers;
  FillMethod method = FillMethod::kSpline;  // fill
  int context = 10;                          // fill (spline)
  int max_gap = 0;                           // fill
  bool has_range = false;                    // fill, swap, delete, spikes: [from, to], else the take
  uint64_t from = 0, to = 0;
  uint64_t frame = 0;                        // split: the first frame of the new column
  double threshold = 8.0;                    // spikes: robust z-score of the acceleration
  bool remove = false;                       // spikes: make the spikes gaps (else only report)
};

struct EditLog {
  std::vector<EditOperation> operations;
};

constexpr size_t kMaxOperations = 100000;
constexpr size_t kMaxEditLogBytes = 64u << 20;

// Throws std::invalid_argument "<source>: operation N (op): field 'F' <rule>".
EditLog EditLogFromJson(const nlohmann::json& doc, const std::string& source);
EditLog ParseEditLog(const std::string& text, const std::string& source);
// Reads a file (at most kMaxEditLogBytes); std::runtime_error when it cannot be read.
EditLog ReadEditLog(const std::string& path);
nlohmann::json EditLogToJson(const EditLog& log);
nlohmann::json OperationToJson(const EditOperation& op);

}  // namespace mocap::edit
