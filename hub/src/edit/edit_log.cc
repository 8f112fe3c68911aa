// Edit logs from and to JSON (see edit_log.h).
#include "edit/edit_log.h"

#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "util/regular_file.h"

namespace mocap::edit {
namespace {

constexpr size_t kMaxNameBytes = 255;  // a C3D label's bound
constexpr uint64_t kMaxFrame = uint64_t{1} << 53;  // exact in a JSON number read as double

const std::map<std::string, EditKind> kKinds = {{"fill", EditKind::kFill},     {"swap", EditKind::kSwap},
                                                {"split", EditKind::kSplit},   {"join", EditKind::kJoin},
                                                {"rename", EditKind::kRename}, {"delete", EditKind::kDelete},
                                                {"spikes", EditKind::kSpikes}};
const std::map<std::string, FillMethod> kMethods = {{"spline", FillMethod::kSpline},
                                                    {"linear", FillMethod::kLinear},
                                                    {"pattern", FillMethod::kPattern},
                                                    {"rigid", FillMethod::kRigid},
                                                    {"relational", FillMethod::kRelational}};
// The fields each kind takes besides "op".
const std::map<EditKind, std::set<std::string>> kFields = {
    {EditKind::kFill, {"marker", "method", "donors", "context", "max_gap", "from", "to"}},
    {EditKind::kSwap, {"markers", "from", "to"}},
    {EditKind::kSplit, {"marker", "frame", "name"}},
    {EditKind::kJoin, {"marker", "other"}},
    {EditKind::kRename, {"marker", "name"}},
    {EditKind::kDelete, {"marker", "from", "to"}},
    {EditKind::kSpikes, {"markers", "threshold", "remove", "from", "to"}}};

template <typename Map>
std::string Keys(const Map& map) {
  std::string out;
  for (const auto& item : map) out += (out.empty() ? "" : ", ") + item.first;
  return out;
}

std::string Keys(const std::set<std::string>& set) {
  std::string out;
  for (const std::string& s : set) out += (out.empty() ? "" : ", ") + s;
  return out;
}

class OperationReader {
 public:
  OperationReader(const nlohmann::json& j, std::string where) : j_(j), where_(std::move(where)) {}

  [[noreturn]] void Refuse(const std::string& field, const std::string& rule) const {
    throw std::invalid_argument(where_ + ": field '" + field + "' " + rule);
  }
  const nlohmann::json* Field(const char* name) const {
    const auto it = j_.find(name);
    return it == j_.end() ? nullptr : &*it;
  }
  const nlohmann::json& Required(const char* name) const {
    const nlohmann::json* j = Field(name);
    if (!j) Refuse(name, "is missing");
    return *j;
  }
  std::string NameOf(const char* field, const nlohmann::json& j) const {
    if (!j.is_string()) Refuse(field, "must be a marker name (a string)");
    const std::string s = j.get<std::string>();
    if (s.empty() || s.size() > kMaxNameBytes)
      Refuse(field, "must be a marker name of 1-" + std::to_string(kMaxNameBytes) + " bytes");
    for (unsigned char c : s)
      if (c < 0x20 || c == 0x7f) Refuse(field, "'" + s.substr(0, 64) + "' holds a control character (tab, newline...)");
    return s;
  }
  std::string Name(const char* field) const { return NameOf(field, Required(field)); }
  std::vector<std::string> Names(const char* field, size_t min, size_t max) const {
    std::vector<std::string> out;
    const nlohmann::json* j = Field(field);
    if (!j) {
      if (min > 0) Refuse(field, "is missing");
      return out;
    }
    if (!j->is_array() || j->size() < min || j->size() > max)
      Refuse(field, "must be a list of " + std::to_string(min) + "-" + std::to_string(max) + " marker names");
    for (const nlohmann::json& name : *j) out.push_back(NameOf(field, name));
    return out;
  }
  uint64_t Frame(const char* field) const {
    const nlohmann::json& j = Required(field);
    if (!j.is_number_unsigned() || j.get<uint64_t>() > kMaxFrame)
      Refuse(field, "must be a frame number (a whole number 0-2^53)");
    return j.get<uint64_t>();
  }
  void Int(const char* field, int* value, int low, int high) const {
    const nlohmann::json* j = Field(field);
    if (!j) return;
    if (!j->is_number_integer() || j->get<long long>() < low || j->get<long long>() > high)
      Refuse(field, "must be a whole number " + std::to_string(low) + "-" + std::to_string(high));
    *value = j->get<int>();
  }
  void Number(const char* field, double* value, double low, double high) const {
    const nlohmann::json* j = Field(field);
    if (!j) return;
    if (!j->is_number() || !std::isfinite(j->get<double>()) || j->get<double>() < low || j->get<double>() > high)
      Refuse(field, "must be a number " + std::to_string(static_cast<int>(low)) + "-" + std::to_string(static_cast<int>(high)));
    *value = j->get<double>();
  }
  void Bool(const char* field, bool* value) const {
    const nlohmann::json* j = Field(field);
    if (!j) return;
    if (!j->is_boolean()) Refuse(field, "must be true or false");
    *value = j->get<bool>();
  }
  void Range(EditOperation* op) const {
    const bool from = Field("from") != nullptr, to = Field("to") != nullptr;
    if (from != to) Refuse(from ? "to" : "from", "is missing (a range takes both 'from' and 'to')");
    if (!from) return;
    op->has_range = true;
    op->from = Frame("from");
    op->to = Frame("to");
    if (op->to < op->from) Refuse("to", std::to_string(op->to) + " is before 'from' " + std::to_string(op->from));
  }

 private:
  const nlohmann::json& j_;
  std::string where_;
};

EditOperation OperationFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw std::invalid_argument(where + ": an operation is a JSON object");
  const auto op_field = j.find("op");
  if (op_field == j.end() || !op_field->is_string() || !kKinds.count(op_field->get<std::string>()))
    throw std::invalid_argument(where + ": field 'op' must be one of " + Keys(kKinds));
  EditOperation op;
  op.kind = kKinds.at(op_field->get<std::string>());
  const OperationReader read(j, where + " (" + op_field->get<std::string>() + ")");
  const std::set<std::string>& fields = kFields.at(op.kind);
  for (const auto& item : j.items())
    if (item.key() != "op" && !fields.count(item.key()))
      read.Refuse(item.key().substr(0, 64), "is not a field of this operation (" + Keys(fields) + ")");
  switch (op.kind) {
    case EditKind::kFill: {
      op.marker = read.Name("marker");
      const nlohmann::json& method = read.Required("method");
      if (!method.is_string() || !kMethods.count(method.get<std::string>()))
        read.Refuse("method", "must be one of " + Keys(kMethods));
      op.method = kMethods.at(method.get<std::string>());
      op.markers = read.Names("donors", 0, 64);
      read.Int("context", &op.context, 2, 1000);
      read.Int("max_gap", &op.max_gap, 0, 1 << 30);
      read.Range(&op);
      break;
    }
    case EditKind::kSwap: {
      const std::vector<std::string> pair = read.Names("markers", 2, 2);
      if (pair[0] == pair[1]) read.Refuse("markers", "names '" + pair[0] + "' twice");
      op.marker = pair[0];
      op.other = pair[1];
      read.Range(&op);
      break;
    }
    case EditKind::kSplit:
      op.marker = read.Name("marker");
      op.frame = read.Frame("frame");
      op.other = read.Name("name");
      break;
    case EditKind::kJoin:
      op.marker = read.Name("marker");
      op.other = read.Name("other");
      if (op.other == op.marker) read.Refuse("other", "is the marker itself");
      break;
    case EditKind::kRename:
      op.marker = read.Name("marker");
      op.other = read.Name("name");
      break;
    case EditKind::kDelete:
      op.marker = read.Name("marker");
      read.Range(&op);
      break;
    case EditKind::kSpikes:
      op.markers = read.Names("markers", 0, 100000);
      read.Number("threshold", &op.threshold, 2.0, 1000.0);
      read.Bool("remove", &op.remove);
      read.Range(&op);
      break;
  }
  return op;
}

}  // namespace

const char* EditKindName(EditKind kind) {
  for (const auto& item : kKinds)
    if (item.second == kind) return item.first.c_str();
  return "?";
}

EditLog EditLogFromJson(const nlohmann::json& doc, const std::string& source) {
  if (!doc.is_object()) throw std::invalid_argument(source + ": an edit log is a JSON object");
  for (const auto& item : doc.items())
    if (item.key() != "format" && item.key() != "version" && item.key() != "operations")
      throw std::invalid_argument(source + ": field '" + item.key().substr(0, 64) +
                                  "' is not an edit log field (format, version, operations)");
  if (doc.value("format", nlohmann::json()) != "mocap-edits")
    throw std::invalid_argument(source + ": field 'format' must be \"mocap-edits\"");
  if (doc.value("version", nlohmann::json()) != 1)
    throw std::invalid_argument(source + ": field 'version' must be 1 (the version this hub reads)");
  const auto ops = doc.find("operations");
  if (ops == doc.end() || !ops->is_array())
    throw std::invalid_argument(source + ": field 'operations' must be a list (empty for no edits)");
  if (ops->size() > kMaxOperations)
    throw std::invalid_argument(source + ": field 'operations' holds " + std::to_string(ops->size()) +
                                " operations; at most " + std::to_string(kMaxOperations));
  EditLog log;
  for (size_t i = 0; i < ops->size(); ++i)
    log.operations.push_back(OperationFromJson((*ops)[i], source + ": operation " + std::to_string(i + 1)));
  return log;
}

EditLog ParseEditLog(const std::string& text, const std::string& source) {
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded()) throw std::invalid_argument(source + ": not JSON");
  return EditLogFromJson(doc, source);
}

EditLog ReadEditLog(const std::string& path) {
  return ParseEditLog(ReadRegularFile(path, kMaxEditLogBytes, "an edit log"), path);
}

nlohmann::json OperationToJson(const EditOperation& op) {
  nlohmann::json j = {{"op", EditKindName(op.kind)}};
  switch (op.kind) {
    case EditKind::kFill:
      j["marker"] = op.marker;
      j["method"] = FillMethodName(op.method);
      if (!op.markers.empty()) j["donors"] = op.markers;
      j["context"] = op.context;
      j["max_gap"] = op.max_gap;
      break;
    case EditKind::kSwap:
      j["markers"] = {op.marker, op.other};
      break;
    case EditKind::kSplit:
      j["marker"] = op.marker;
      j["frame"] = op.frame;
      j["name"] = op.other;
      break;
    case EditKind::kJoin:
      j["marker"] = op.marker;
      j["other"] = op.other;
      break;
    case EditKind::kRename:
      j["marker"] = op.marker;
      j["name"] = op.other;
      break;
    case EditKind::kDelete:
      j["marker"] = op.marker;
      break;
    case EditKind::kSpikes:
      if (!op.markers.empty()) j["markers"] = op.markers;
      j["threshold"] = op.threshold;
      j["remove"] = op.remove;
      break;
  }
  if (op.has_range) {
    j["from"] = op.from;
    j["to"] = op.to;
  }
  return j;
}

nlohmann::json EditLogToJson(const EditLog& log) {
  nlohmann::json ops = nlohmann::json::array();
  for (const EditOperation& op : log.operations) ops.push_back(OperationToJson(op));
  return {{"format", "mocap-edits"}, {"version", 1}, {"operations", ops}};
}

}  // namespace mocap::edit
