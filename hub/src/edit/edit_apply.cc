// The edit operations (see edit_apply.h).
#include "edit/edit_apply.h"

#include <stdexcept>

#include "edit/gap_fill.h"

namespace mocap::edit {
namespace {

class Operation {
 public:
  Operation(const EditOperation& op, size_t index, EditedTake* take)
      : op_(op), take_(*take), where_("operation " + std::to_string(index + 1) + " (" + EditKindName(op.kind) + ")") {}

  [[noreturn]] void Refuse(const std::string& reason) const { throw std::invalid_argument(where_ + ": " + reason); }

  size_t Column(const std::string& name) const {
    const long c = take_.Find(name);
    if (c < 0) Refuse("marker '" + name + "' is not in the take");
    return static_cast<size_t>(c);
  }
  void NameFree(const std::string& name) const {
    if (take_.Find(name) >= 0) Refuse("name '" + name + "' is already a marker of the take");
  }
  // Frame indices of the operation's range, or of the whole take; empty when none fall in it.
  bool Range(size_t* first, size_t* last) const {
    const size_t frames = take_.markers.NumFrames();
    if (frames == 0) return false;
    if (!op_.has_range) {
      *first = 0, *last = frames - 1;
      return true;
    }
    *first = take_.IndexAtOrAfter(op_.from);
    const size_t end = take_.IndexAtOrAfter(op_.to + 1);
    if (end == 0 || *first >= end) return false;
    *last = end - 1;
    return true;
  }
  std::string RangeText() const {
    return op_.has_range ? " frames " + std::to_string(op_.from) + "-" + std::to_string(op_.to) : "";
  }

 private:
  const EditOperation& op_;
  EditedTake& take_;
  std::string where_;
};

std::string Fill(const EditOperation& op, const Operation& o, EditedTake* take) {
  const size_t marker = o.Column(op.marker);
  FillOptions options;
  options.method = op.method;
  options.context = op.context;
  options.max_gap = op.max_gap;
  for (const std::string& donor : op.markers) options.donors.push_back(o.Column(donor));
  try {
    options.Check();
  } catch (const std::invalid_argument& e) {
    o.Refuse(e.what());
  }
  for (size_t donor : options.donors)
    if (donor == marker) o.Refuse("donor '" + op.marker + "' is the marker filled");
  size_t first = 0, last = 0;
  FillResult r;
  if (o.Range(&first, &last)) r = FillGaps(take, marker, first, last, options);
  return "fill " + op.marker + " (" + FillMethodName(op.method) + ")" + o.RangeText() + ": " +
         std::to_string(r.gaps_filled) + " of " + std::to_string(r.gaps_seen) + " gaps filled, " +
         std::to_string(r.samples_filled) + " samples filled, " + std::to_string(r.samples_left) + " left";
}

std::string Swap(const EditOperation& op, const Operation& o, EditedTake* take) {
  const size_t a = o.Column(op.marker), b = o.Column(op.other);
  size_t first = 0, last = 0, swapped = 0;
  if (o.Range(&first, &last))
    for (size_t f = first; f <= last; ++f, ++swapped) {
      const Eigen::Vector3d pa = take->markers.At(f, a);
      const uint8_t ma = take->Mark(f, a);
      take->Set(f, a, take->markers.At(f, b), take->Mark(f, b));
      take->Set(f, b, pa, ma);
    }
  return "swap " + op.marker + " and " + op.other + o.RangeText() + ": " + std::to_string(swapped) + " frames";
}

std::string Split(const EditOperation& op, const Operation& o, EditedTake* take) {
  const size_t marker = o.Column(op.marker);
  o.NameFree(op.other);
  take->AddColumn(op.other);
  const size_t added = take->markers.NumMarkers() - 1;
  size_t moved = 0;
  for (size_t f = take->IndexAtOrAfter(op.frame); f < take->markers.NumFrames(); ++f) {
    if (!take->markers.Has(f, marker)) continue;
    take->Set(f, added, take->markers.At(f, marker), take->Mark(f, marker));
    take->Clear(f, marker);
    ++moved;
  }
  return "split " + op.marker + " at frame " + std::to_string(op.frame) + " into " + op.other + ": " +
         std::to_string(moved) + " samples moved";
}

std::string Join(const EditOperation& op, const Operation& o, EditedTake* take) {
  const size_t marker = o.Column(op.marker), other = o.Column(op.other);
  size_t overlap = 0, first_overlap = 0;
  for (size_t f = 0; f < take->markers.NumFrames(); ++f)
    if (take->markers.Has(f, marker) && take->markers.Has(f, other) && overlap++ == 0) first_overlap = f;
  if (overlap > 0)
    o.Refuse("'" + op.marker + "' and '" + op.other + "' both hold samples in " + std::to_string(overlap) +
             " frames, the first " + std::to_string(take->markers.frame_numbers[first_overlap]) +
             " (delete or split one of them there first)");
  size_t moved = 0;
  for (size_t f = 0; f < take->markers.NumFrames(); ++f) {
    if (!take->markers.Has(f, other)) continue;
    take->Set(f, marker, take->markers.At(f, other), take->Mark(f, other));
    ++moved;
  }
  take->RemoveColumn(other);
  return "join " + op.other + " into " + op.marker + ": " + std::to_string(moved) + " samples moved";
}

std::string Rename(const EditOperation& op, const Operation& o, EditedTake* take) {
  const size_t marker = o.Column(op.marker);
  if (op.other == op.marker) return "rename " + op.marker + ": unchanged";
  o.NameFree(op.other);
  take->markers.names[marker] = op.other;
  return "rename " + op.marker + " to " + op.other;
}

std::string Delete(const EditOperation& op, const Operation& o, EditedTake* take) {
  const size_t marker = o.Column(op.marker);
  if (!op.has_range) {
    take->RemoveColumn(marker);
    return "delete " + op.marker + ": column removed";
  }
  size_t first = 0, last = 0, cleared = 0;
  if (o.Range(&first, &last))
    for (size_t f = first; f <= last; ++f)
      if (take->markers.Has(f, marker)) take->Clear(f, marker), ++cleared;
  return "delete " + op.marker + o.RangeText() + ": " + std::to_string(cleared) + " samples";
}

std::string Spikes(const EditOperation& op, const Operation& o, EditedTake* take, EditReport* report) {
  std::vector<size_t> columns;
  for (const std::string& name : op.markers) columns.push_back(o.Column(name));
  if (op.markers.empty())
    for (size_t m = 0; m < take->markers.NumMarkers(); ++m) columns.push_back(m);
  size_t first = 0, last = 0, found = 0;
  if (o.Range(&first, &last)) {
    // Every marker judged on the take as it was: removing one spike must not move another's limit.
    std::vector<Spike> all;
    for (size_t m : columns) {
      const std::vector<Spike> spikes = FindSpikes(*take, m, first, last, op.threshold);
      all.insert(all.end(), spikes.begin(), spikes.end());
    }
    for (const Spike& s : all) {
      report->spikes.push_back({take->markers.names[s.marker], take->markers.frame_numbers[s.frame_index],
                                s.accel_mm_per_frame2, s.limit_mm_per_frame2, op.remove});
      if (op.remove) take->Clear(s.frame_index, s.marker);
    }
    found = all.size();
  }
  return "spikes" + o.RangeText() + ": " + std::to_string(found) + (op.remove ? " removed" : " found");
}

}  // namespace

void ApplyEdit(const EditOperation& op, size_t index, EditedTake* take, EditReport* report) {
  const Operation o(op, index, take);
  std::string line;
  switch (op.kind) {
    case EditKind::kFill: line = Fill(op, o, take); break;
    case EditKind::kSwap: line = Swap(op, o, take); break;
    case EditKind::kSplit: line = Split(op, o, take); break;
    case EditKind::kJoin: line = Join(op, o, take); break;
    case EditKind::kRename: line = Rename(op, o, take); break;
    case EditKind::kDelete: line = Delete(op, o, take); break;
    case EditKind::kSpikes: line = Spikes(op, o, take, report); break;
  }
  report->lines.push_back(line);
}

EditReport ApplyEdits(const EditLog& log, EditedTake* take) {
  const std::vector<uint64_t>& numbers = take->markers.frame_numbers;
  for (size_t f = 1; f < numbers.size(); ++f)
    if (numbers[f] <= numbers[f - 1])
      throw std::invalid_argument("the take's frame numbers must increase (frame " + std::to_string(numbers[f]) +
                                  " follows " + std::to_string(numbers[f - 1]) + ")");
  if (take->marks.size() != take->markers.points.size()) throw std::invalid_argument("the take's fill marks do not match its points");
  EditReport report;
  for (size_t i = 0; i < log.operations.size(); ++i) ApplyEdit(log.operations[i], i, take, &report);
  return report;
}

}  // namespace mocap::edit
