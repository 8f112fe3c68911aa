// The rule tables: the humanoid tree (left side; the right one mirrored) and where each marker
// of the known sets sits on it.
#include "skeleton/skeleton_template.h"

#include <map>
#include <stdexcept>

namespace mocap {
namespace {

struct DofRule {
  char axis;
  double min, max;
};

struct SegmentRule {
  const char* name;  // "Left" is replaced by "Right" for the mirrored copy
  const char* parent;
  Eigen::Vector3d offset;
  bool bone, reference_zero, sided;
  std::vector<DofRule> dofs;
  Eigen::Vector3d end;
};

// Rest pose: standing upright, arms hanging with the thumbs forward; x left, y up, z forward;
// the root at the middle of the two hip joints. Limits are generous: they stop solutions that no
// body reaches (a knee bending forwards), not ordinary ones.
const std::vector<SegmentRule>& SegmentRules() {
  static const std::vector<SegmentRule> rules = {
      {"Hips", "", {0, 0, 0}, false, true, false, {{'y', -180, 180}, {'x', -180, 180}, {'z', -180, 180}}, {0, 0, 0}},
      {"LeftUpLeg", "Hips", {90, 0, 0}, false, false, true, {{'x', -130, 45}, {'z', -40, 70}, {'y', -60, 60}}, {0, -420, 0}},
      {"LeftLeg", "LeftUpLeg", {0, -420, 0}, true, false, true, {{'x', -10, 160}}, {0, -410, 0}},
      {"LeftFoot", "LeftLeg", {0, -410, 0}, true, true, true, {{'x', -60, 60}, {'z', -45, 45}}, {0, -50, 140}},
      {"LeftToeBase", "LeftFoot", {0, -60, 130}, false, false, true, {{'x', -60, 60}}, {0, 0, 50}},
      {"Spine", "Hips", {0, 100, -30}, false, true, false, {{'x', -40, 90}, {'z', -45, 45}, {'y', -60, 60}}, {0, 200, 0}},
      {"Chest", "Spine", {0, 200, 0}, false, true, false, {{'x', -40, 60}, {'z', -40, 40}, {'y', -45, 45}}, {0, 250, 0}},
      {"Head", "Chest", {0, 250, 20}, false, true, false, {{'x', -80, 80}, {'z', -60, 60}, {'y', -90, 90}}, {0, 220, 0}},
      {"LeftShoulder", "Chest", {30, 200, 40}, false, false, true, {{'z', -25, 45}, {'y', -35, 35}}, {150, 0, 0}},
      {"LeftArm", "LeftShoulder", {150, 0, 0}, true, false, true, {{'z', -90, 180}, {'x', -150, 90}, {'y', -110, 110}}, {0, -290, 0}},
      {"LeftForeArm", "LeftArm", {0, -290, 0}, true, false, true, {{'x', -165, 10}, {'y', -120, 120}}, {0, -250, 0}},
      {"LeftHand", "LeftForeArm", {0, -250, 0}, true, true, true, {{'x', -90, 90}, {'z', -60, 60}}, {0, -180, 0}},
  };
  return rules;
}

struct MarkerRule {
  const char* key;      // the name without its side prefix (sided) or the whole name
  const char* segment;  // left-side segment name for sided markers
  Eigen::Vector3d offset;
  bool sided;
};

const std::vector<MarkerRule>& MarkerRules() {
  static const std::vector<MarkerRule> rules = {
      // Vicon / HDM05 41-marker set
      {"FWT", "Hips", {120, 90, 60}, true},
      {"BWT", "Hips", {50, 110, -110}, true},
      {"THI", "LeftUpLeg", {80, -220, 30}, true},
      {"KNE", "LeftUpLeg", {50, -420, 0}, true},
      {"SHN", "LeftLeg", {60, -200, 30}, true},
      {"ANK", "LeftLeg", {40, -410, 0}, true},
      {"HEE", "LeftFoot", {0, -50, -60}, true},
      {"TOE", "LeftFoot", {0, -40, 130}, true},
      {"MT5", "LeftFoot", {40, -50, 100}, true},
      {"TOT", "LeftToeBase", {0, 0, 60}, true},
      {"T10", "Spine", {0, 230, -110}, false},
      {"STRN", "Spine", {0, 260, 110}, false},
      {"C7", "Chest", {0, 250, -90}, false},
      {"CLAV", "Chest", {0, 200, 100}, false},
      {"BAC", "Chest", {80, 150, -120}, true},
      {"FHD", "Head", {50, 210, 90}, true},
      {"BHD", "Head", {50, 200, -90}, true},
      {"SHO", "LeftShoulder", {170, 40, 0}, true},
      {"UPA", "LeftArm", {50, -150, -20}, true},
      {"ELB", "LeftArm", {40, -290, 0}, true},
      {"FRM", "LeftForeArm", {40, -130, 0}, true},
      {"WRA", "LeftForeArm", {0, -250, 30}, true},
      {"WRB", "LeftForeArm", {0, -250, -30}, true},
      {"FIN", "LeftHand", {0, -80, 10}, true},
      // OpenSim gait sets (Gait2392, Hamner)
      {"ASIS", "Hips", {120, 90, 60}, true},
      {"V.Sacral", "Hips", {0, 110, -120}, false},
      {"Thigh.Upper", "LeftUpLeg", {90, -150, 0}, true},
      {"Thigh.Front", "LeftUpLeg", {70, -250, 60}, true},
      {"Thigh.Rear", "LeftUpLeg", {70, -250, -60}, true},
      {"Shank.Upper", "LeftLeg", {70, -120, 0}, true},
      {"Shank.Front", "LeftLeg", {50, -220, 60}, true},
      {"Shank.Rear", "LeftLeg", {50, -220, -60}, true},
      {"Heel", "LeftFoot", {0, -50, -60}, true},
      {"Midfoot.Sup", "LeftFoot", {0, -10, 50}, true},
      {"Midfoot.Lat", "LeftFoot", {40, -40, 60}, true},
      {"Toe.Tip", "LeftFoot", {0, -40, 180}, true},
      {"Toe.Lat", "LeftFoot", {40, -40, 130}, true},
      {"Toe.Med", "LeftFoot", {-25, -40, 130}, true},
      {"Sternum", "Chest", {0, 110, 110}, false},
      {"Acromium", "LeftShoulder", {170, 40, 0}, true},
      {"Bicep", "LeftArm", {30, -150, 40}, true},
      {"Elbow", "LeftArm", {40, -290, 0}, true},
      {"Wrist.Lat", "LeftForeArm", {0, -250, 30}, true},
      {"Wrist.Med", "LeftForeArm", {0, -250, -30}, true},
      {"Temple", "Head", {70, 180, 70}, true},
      {"Top.Head", "Head", {0, 250, 0}, false},
  };
  return rules;
}

std::string RightName(const std::string& left) {
  return left.rfind("Left", 0) == 0 ? "Right" + left.substr(4) : left;
}

Eigen::Vector3d Mirror(const Eigen::Vector3d& v) { return {-v.x(), v.y(), v.z()}; }

int AxisIndex(char axis) { return axis - 'x'; }

struct Placed {
  std::string name, segment;
  Eigen::Vector3d offset;
};

// The rule a name matches, with its side: exact unsided names first, then an "L"/"R" or
// "L."/"R." prefix followed by a sided key.
bool PlaceMarker(const std::string& name, Placed* placed) {
  for (const MarkerRule& rule : MarkerRules())
    if (!rule.sided && name == rule.key) {
      *placed = {name, rule.segment, rule.offset};
      return true;
    }
  if (name.size() < 2 || (name[0] != 'L' && name[0] != 'R')) return false;
  const bool right = name[0] == 'R';
  const std::string key = name.substr(name[1] == '.' ? 2 : 1);
  for (const MarkerRule& rule : MarkerRules())
    if (rule.sided && key == rule.key) {
      *placed = {name, right ? RightName(rule.segment) : rule.segment, right ? Mirror(rule.offset) : rule.offset};
      return true;
    }
  return false;
}

}  // namespace

Skeleton SkeletonTemplateFromNames(const std::vector<std::string>& names, std::vector<std::string>* unplaced) {
  unplaced->clear();
  std::vector<Placed> placed;
  std::map<std::string, int> markers_on;
  for (const std::string& name : names) {
    Placed p;
    if (PlaceMarker(name, &p)) {
      placed.push_back(p);
      ++markers_on[p.segment];
    } else {
      unplaced->push_back(name);
    }
  }
  // Every rule segment, both sides, in tree order (parents first).
  std::vector<SkeletonSegment> all;
  std::vector<std::string> parents;
  for (int side = 0; side < 2; ++side)
    for (const SegmentRule& rule : SegmentRules()) {
      if (side == 1 && !rule.sided) continue;
      SkeletonSegment s;
      s.name = side ? RightName(rule.name) : rule.name;
      s.offset = side ? Mirror(rule.offset) : rule.offset;
      s.end = side ? Mirror(rule.end) : rule.end;
      s.bone = rule.bone;
      s.reference_zero = rule.reference_zero;
      for (const DofRule& d : rule.dofs) {
        JointDof dof;
        dof.axis = AxisIndex(d.axis);
        // Mirroring x turns rotations about y and z the other way.
        const bool flip = side == 1 && dof.axis != 0;
        dof.min_deg = flip ? -d.max : d.min;
        dof.max_deg = flip ? -d.min : d.max;
        s.dofs.push_back(dof);
      }
      all.push_back(s);
      parents.push_back(side ? RightName(rule.parent) : rule.parent);
    }
  if (markers_on["Hips"] == 0) throw std::invalid_argument("marker set: no pelvis marker (e.g. LFWT, R.ASIS) is known");
  // One trunk segment when only one part carries markers: Spine's markers move to Chest.
  const bool split_trunk = markers_on["Spine"] > 0 && markers_on["Chest"] > 0;
  Eigen::Vector3d chest_in_spine = Eigen::Vector3d::Zero();
  for (const SkeletonSegment& s : all)
    if (s.name == "Chest") chest_in_spine = s.offset;
  if (!split_trunk)
    for (Placed& p : placed)
      if (p.segment == "Spine") {
        p.segment = "Chest";
        p.offset -= chest_in_spine;
        ++markers_on["Chest"];
      }
  // Keep the root and the segments with markers; a left-out segment's children hang from its
  // nearest kept ancestor.
  std::vector<bool> keep(all.size(), false);
  keep[0] = true;
  for (size_t i = 0; i < all.size(); ++i)
    if (markers_on[all[i].name] > 0 && !(all[i].name == "Spine" && !split_trunk)) keep[i] = true;
  auto index_of = [&](const std::string& name) {
    for (size_t i = 0; i < all.size(); ++i)
      if (all[i].name == name) return static_cast<int>(i);
    return -1;
  };
  Skeleton skeleton;
  std::map<std::string, int> kept_index;
  for (size_t i = 0; i < all.size(); ++i) {
    if (!keep[i]) continue;
    SkeletonSegment s = all[i];
    if (i > 0) {
      // Climb past left-out parents, adding their offsets.
      int p = index_of(parents[i]);
      while (p > 0 && !keep[p]) {
        s.offset += all[p].offset;
        s.bone = false;
        p = index_of(parents[p]);
      }
      s.parent = kept_index.at(all[p].name);
    }
    kept_index[s.name] = static_cast<int>(skeleton.segments.size());
    skeleton.segments.push_back(s);
  }
  for (const Placed& p : placed) {
    SkeletonMarker m;
    m.name = p.name;
    m.segment = kept_index.at(p.segment);
    m.offset = p.offset;
    skeleton.markers.push_back(m);
  }
  if (skeleton.segments.size() < 2) throw std::invalid_argument("marker set: markers on fewer than 2 segments");
  skeleton.Check();
  return skeleton;
}

}  // namespace mocap
