// Applying an edit log (edit_log.h) to a take, in order. Each operation either applies whole or
// throws std::invalid_argument "operation N (op): <reason>" (a marker that is not in the take at
// that point, a name already taken, a join whose columns overlap, ...): the take then holds the
// operations before it. What each did is reported, one line per operation, and the spikes found.
//   swap    exchanges two columns over the range (samples and fill marks);
//   split   moves a column's samples from `frame` on into a new column `name`;
//   join    moves `other`'s samples into `marker`'s gaps and removes `other` (refused where both
//           hold a sample in one frame);
//   rename  renames a column (refused onto a name in use);
//   delete  gaps over the range, or the whole column without one;
//   spikes  finds spikes (spikes.h) and, with remove, makes them gaps.
#pragma once

#include <string>
#include <vector>

#include "edit/edit_log.h"
#include "edit/edited_take.h"
#include "edit/spikes.h"

namespace mocap::edit {

struct EditReport {
  std::vector<std::string> lines;  // one per operation
  struct NamedSpike {
    std::string marker;
    uint64_t frame = 0;
    double accel_mm_per_frame2 = 0.0, limit_mm_per_frame2 = 0.0;
    bool removed = false;
  };
  std::vector<NamedSpike> spikes;
};

// The take's frame numbers must increase (std::invalid_argument otherwise).
EditReport ApplyEdits(const EditLog& log, EditedTake* take);
// One operation (index: its 0-based place in the log, for messages).
void ApplyEdit(const EditOperation& op, size_t index, EditedTake* take, EditReport* report);

}  // namespace mocap::edit
