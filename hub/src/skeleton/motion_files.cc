// Writers for BVH, ASF/AMC and .mot (formats: motion_files.h).
#include "skeleton/motion_files.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mocap {
namespace {

constexpr double kDeg = 180.0 / M_PI;

std::string AxisUpper(int axis) { return std::string(1, static_cast<char>('X' + axis)); }

// The 3 rotation axes a BVH joint lists: its dofs, then the missing axes.
std::vector<int> BvhAxes(const SkeletonSegment& s) {
  std::vector<int> axes;
  for (const JointDof& d : s.dofs) axes.push_back(d.axis);
  for (int a = 0; a < 3; ++a) {
    bool present = false;
    for (int b : axes) present = present || b == a;
    if (!present) axes.push_back(a);
  }
  return axes;
}

std::string Num(double v) {
  std::ostringstream out;
  out.precision(9);
  out << (std::fabs(v) < 1e-12 ? 0.0 : v);
  return out.str();
}

std::string Vec(const Eigen::Vector3d& v) { return Num(v.x()) + " " + Num(v.y()) + " " + Num(v.z()); }

void Save(const std::string& text, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(path + ": cannot open for writing: " + std::strerror(errno));
  out << text;
  out.close();
  if (!out) throw std::runtime_error(path + ": write failed");
}

void BvhJoint(const Skeleton& skeleton, const std::vector<std::vector<int>>& children, int g, int depth,
              std::ostringstream& out) {
  const std::string pad(2 * depth, ' ');
  const SkeletonSegment& s = skeleton.segments[g];
  out << pad << (g == 0 ? "ROOT " : "JOINT ") << s.name << "\n" << pad << "{\n";
  out << pad << "  OFFSET " << Vec(g == 0 ? Eigen::Vector3d::Zero() : s.offset) << "\n";
  out << pad << "  CHANNELS " << (g == 0 ? 6 : 3);
  if (g == 0) out << " Xposition Yposition Zposition";
  for (int a : BvhAxes(s)) out << " " << AxisUpper(a) << "rotation";
  out << "\n";
  for (int c : children[g]) BvhJoint(skeleton, children, c, depth + 1, out);
  if (children[g].empty())
    out << pad << "  End Site\n" << pad << "  {\n" << pad << "    OFFSET " << Vec(s.end) << "\n" << pad << "  }\n";
  out << pad << "}\n";
}

// Values of segment g's BVH channels in the order BvhJoint lists them (the dofs' angles, then 0s).
void BvhValues(const Skeleton& skeleton, int g, const std::vector<double>& pose, std::ostringstream& out) {
  const size_t first = skeleton.FirstDof(g);
  const size_t n = skeleton.segments[g].dofs.size();
  for (size_t k = 0; k < 3; ++k) out << " " << Num(k < n ? pose[first + k] * kDeg : 0.0);
}

void BvhOrder(const std::vector<std::vector<int>>& children, int g, std::vector<int>* order) {
  order->push_back(g);
  for (int c : children[g]) BvhOrder(children, c, order);
}

std::string DofName(int axis) { return std::string("r") + static_cast<char>('x' + axis); }

std::string Limit(double v) { return Num(v); }

}  // namespace

std::vector<std::vector<double>> FilledPoses(const SkeletonMotion& motion) {
  if (!(motion.rate_hz > 0.0)) throw std::invalid_argument("motion: rate " + std::to_string(motion.rate_hz) + " Hz");
  std::vector<std::vector<double>> out = motion.poses;
  const std::vector<double>* last = nullptr;
  for (const auto& pose : motion.poses)
    if (!pose.empty()) {
      last = &pose;
      break;
    }
  if (!last) throw std::invalid_argument("motion: no frame has a solved pose");
  for (size_t f = 0; f < out.size(); ++f) {
    if (out[f].empty()) out[f] = *last;
    last = &out[f];
  }
  return out;
}

void WriteBvh(const Skeleton& skeleton, const SkeletonMotion& motion, const std::string& path) {
  const auto poses = FilledPoses(motion);
  const auto children = skeleton.Children();
  std::ostringstream out;
  out << "HIERARCHY\n";
  BvhJoint(skeleton, children, 0, 0, out);
  out << "MOTION\nFrames: " << poses.size() << "\nFrame Time: " << Num(1.0 / motion.rate_hz) << "\n";
  std::vector<int> order;
  BvhOrder(children, 0, &order);
  for (const auto& pose : poses) {
    out << Num(pose[0]) << " " << Num(pose[1]) << " " << Num(pose[2]);
    for (int g : order) BvhValues(skeleton, g, pose, out);
    out << "\n";
  }
  Save(out.str(), path);
}

void WriteAsf(const Skeleton& skeleton, const std::string& path) {
  const auto children = skeleton.Children();
  std::ostringstream out;
  out << "# mocap-hub skeleton (units: mm, degrees; +y up)\n:version 1.10\n:name mocap-hub\n:units\n"
         "  mass 1.0\n  length 1.0\n  angle deg\n:documentation\n"
         "  Bones rotate in the order of their dof line; lengths in millimetres.\n:root\n  order TX TY TZ";
  for (const JointDof& d : skeleton.segments[0].dofs) out << " R" << AxisUpper(d.axis);
  out << "\n  axis ";
  for (const JointDof& d : skeleton.segments[0].dofs) out << AxisUpper(d.axis);
  out << "\n  position 0 0 0\n  orientation 0 0 0\n:bonedata\n";
  int id = 1;
  std::ostringstream hierarchy;
  auto bone = [&](const std::string& name, const Eigen::Vector3d& vector, const std::vector<JointDof>& dofs) {
    const double length = vector.norm();
    const Eigen::Vector3d dir = length > 1e-9 ? Eigen::Vector3d(vector / length) : Eigen::Vector3d(0, 1, 0);
    out << "  begin\n    id " << id++ << "\n    name " << name << "\n    direction " << Vec(dir) << "\n    length "
        << Num(length) << "\n    axis 0 0 0 XYZ\n";
    if (!dofs.empty()) {
      out << "    dof";
      for (const JointDof& d : dofs) out << " " << DofName(d.axis);
      out << "\n    limits";
      for (size_t k = 0; k < dofs.size(); ++k)
        out << (k ? "\n           " : " ") << "(" << Limit(dofs[k].min_deg) << " " << Limit(dofs[k].max_deg) << ")";
      out << "\n";
    }
    out << "  end\n";
  };
  // Bones in tree order (parents first); each hierarchy line lists one parent's children.
  std::vector<int> order;
  BvhOrder(children, 0, &order);
  for (int g : order) {
    const SkeletonSegment& s = skeleton.segments[g];
    if (g != 0) {
      const Eigen::Vector3d reach = children[g].size() == 1 ? skeleton.segments[children[g][0]].offset
                                    : children[g].empty()   ? s.end
                                                            : Eigen::Vector3d::Zero();
      bone(s.name, reach, s.dofs);
    }
    if (children[g].empty()) continue;
    if (children[g].size() == 1 && g != 0) {
      hierarchy << "    " << s.name << " " << skeleton.segments[children[g][0]].name << "\n";
      continue;
    }
    hierarchy << "    " << (g == 0 ? std::string("root") : s.name);
    std::ostringstream connectors;
    for (int c : children[g]) {
      const std::string connector = s.name + "_" + skeleton.segments[c].name;
      bone(connector, skeleton.segments[c].offset, {});
      hierarchy << " " << connector;
      connectors << "    " << connector << " " << skeleton.segments[c].name << "\n";
    }
    hierarchy << "\n" << connectors.str();
  }
  out << ":hierarchy\n  begin\n" << hierarchy.str();
  out << "  end\n";
  Save(out.str(), path);
}

void WriteAmc(const Skeleton& skeleton, const SkeletonMotion& motion, const std::string& path) {
  const auto poses = FilledPoses(motion);
  const auto children = skeleton.Children();
  std::vector<int> order;
  BvhOrder(children, 0, &order);
  std::ostringstream out;
  out << "# mocap-hub motion, " << Num(motion.rate_hz) << " Hz\n:FULLY-SPECIFIED\n:DEGREES\n";
  for (size_t f = 0; f < poses.size(); ++f) {
    const auto& pose = poses[f];
    out << f + 1 << "\nroot " << Num(pose[0]) << " " << Num(pose[1]) << " " << Num(pose[2]);
    for (size_t k = 0; k < 3; ++k) out << " " << Num(pose[3 + k] * kDeg);
    out << "\n";
    for (int g : order) {
      if (g == 0) continue;
      out << skeleton.segments[g].name;
      const size_t first = skeleton.FirstDof(g);
      for (size_t k = 0; k < skeleton.segments[g].dofs.size(); ++k) out << " " << Num(pose[first + k] * kDeg);
      out << "\n";
    }
  }
  Save(out.str(), path);
}

void WriteMot(const Skeleton& skeleton, const SkeletonMotion& motion, const std::string& path) {
  const auto poses = FilledPoses(motion);
  const size_t n = skeleton.NumPoseParameters();
  std::ostringstream out;
  out << "skeleton angles\nversion=1\nnRows=" << poses.size() << "\nnColumns=" << n + 1
      << "\ninDegrees=yes\nendheader\ntime\t" << skeleton.segments[0].name << "_tx\t" << skeleton.segments[0].name
      << "_ty\t" << skeleton.segments[0].name << "_tz";
  for (const SkeletonSegment& s : skeleton.segments)
    for (const JointDof& d : s.dofs) out << "\t" << s.name << "_" << DofName(d.axis);
  out << "\n";
  for (size_t f = 0; f < poses.size(); ++f) {
    out << Num(static_cast<double>(f) / motion.rate_hz);
    for (size_t k = 0; k < n; ++k) out << "\t" << Num(k < 3 ? poses[f][k] / 1000.0 : poses[f][k] * kDeg);
    out << "\n";
  }
  Save(out.str(), path);
}

}  // namespace mocap

namespace mocap {
namespace {

constexpr size_t kMaxMotColumns = 10000;
constexpr size_t kMaxMotCells = 10000000;

std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

}  // namespace

MotTable ParseMot(const std::string& text, const std::string& source) {
  MotTable table;
  std::istringstream in(text);
  std::string line;
  size_t number = 0;
  bool header = true;
  size_t cells = 0;
  auto fail = [&](const std::string& reason) {
    throw std::runtime_error(source + ": line " + std::to_string(number) + ": " + reason);
  };
  while (std::getline(in, line)) {
    ++number;
    if (header) {
      if (line.rfind("inDegrees=", 0) == 0) table.in_degrees = line.find("yes") != std::string::npos;
      if (Fields(line) == std::vector<std::string>{"endheader"}) header = false;
      continue;
    }
    std::vector<std::string> fields = Fields(line);
    if (fields.empty()) continue;
    if (table.columns.empty()) {
      if (fields.size() > kMaxMotColumns) fail(std::to_string(fields.size()) + " columns (at most 10000)");
      table.columns = fields;
      continue;
    }
    if (fields.size() != table.columns.size())
      fail(std::to_string(fields.size()) + " values for " + std::to_string(table.columns.size()) + " columns");
    cells += fields.size();
    if (cells > kMaxMotCells) fail("more than 10^7 values");
    std::vector<double> row;
    for (const std::string& field : fields) {
      char* end = nullptr;
      const double v = std::strtod(field.c_str(), &end);
      if (end != field.c_str() + field.size() || !std::isfinite(v)) fail("\"" + field + "\" is not a finite number");
      row.push_back(v);
    }
    table.rows.push_back(std::move(row));
  }
  if (header) throw std::runtime_error(source + ": no endheader line");
  if (table.columns.empty()) throw std::runtime_error(source + ": no column names after endheader");
  if (!table.in_degrees)
    for (size_t c = 0; c < table.columns.size(); ++c) {
      const std::string& name = table.columns[c];
      if (name.size() > 3 && name[name.size() - 3] == '_' && name[name.size() - 2] == 'r')
        for (auto& row : table.rows) row[c] *= 180.0 / M_PI;
    }
  return table;
}

MotTable ReadMot(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return ParseMot(text.str(), path);
}

SkeletonMotion MotionFromMot(const Skeleton& skeleton, const MotTable& table, const std::string& source) {
  auto column = [&](const std::string& name) {
    for (size_t c = 0; c < table.columns.size(); ++c)
      if (table.columns[c] == name) return c;
    throw std::runtime_error(source + ": no column " + name);
  };
  std::vector<size_t> columns;
  const std::string& root = skeleton.segments[0].name;
  for (const char* t : {"_tx", "_ty", "_tz"}) columns.push_back(column(root + t));
  for (const SkeletonSegment& s : skeleton.segments)
    for (const JointDof& d : s.dofs) columns.push_back(column(s.name + "_" + DofName(d.axis)));
  const size_t time = column("time");
  SkeletonMotion motion;
  if (table.rows.size() >= 2) {
    const double dt = table.rows[1][time] - table.rows[0][time];
    if (dt > 0.0) motion.rate_hz = 1.0 / dt;
  }
  for (const auto& row : table.rows) {
    std::vector<double> pose(columns.size());
    for (size_t k = 0; k < columns.size(); ++k)
      pose[k] = k < 3 ? row[columns[k]] * 1000.0 : row[columns[k]] / kDeg;
    motion.poses.push_back(pose);
  }
  return motion;
}

}  // namespace mocap
