// Wavefront OBJ reading and writing (see obj_mesh.h).
#include "registration/obj_mesh.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <Eigen/Geometry>

#include "util/regular_file.h"

namespace mocap {
namespace {

class LineParser {
 public:
  LineParser(const std::string& source, size_t line_number, const char* begin, const char* end)
      : source_(source), line_(line_number), p_(begin), end_(end) {}

  [[noreturn]] void Fail(const std::string& reason) const {
    throw std::runtime_error(source_ + ": line " + std::to_string(line_) + ": " + reason);
  }
  void SkipSpace() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r')) ++p_;
  }
  bool AtEnd() {
    SkipSpace();
    return p_ >= end_;
  }
  // The next whitespace-separated word.
  std::string Word() {
    SkipSpace();
    const char* start = p_;
    while (p_ < end_ && *p_ != ' ' && *p_ != '\t' && *p_ != '\r') ++p_;
    return std::string(start, p_);
  }
  double Number(const char* what) {
    const std::string word = Word();
    if (word.empty()) Fail(std::string("missing ") + what);
    char* stop = nullptr;
    errno = 0;
    const double value = std::strtod(word.c_str(), &stop);
    if (stop != word.c_str() + word.size() || !std::isfinite(value) || errno == ERANGE)
      Fail(std::string(what) + " '" + word + "' is not a finite number");
    return value;
  }

 private:
  const std::string& source_;
  size_t line_;
  const char* p_;
  const char* end_;
};

// A face corner's vertex index (the part before the first '/'), 1-based or negative.
int CornerIndex(LineParser& parser, const std::string& corner, size_t vertex_count) {
  const std::string index_text = corner.substr(0, corner.find('/'));
  char* stop = nullptr;
  errno = 0;
  const long long index = std::strtoll(index_text.c_str(), &stop, 10);
  if (index_text.empty() || stop != index_text.c_str() + index_text.size() || errno == ERANGE)
    parser.Fail("face corner '" + corner + "' does not start with a vertex index");
  const long long resolved = index < 0 ? static_cast<long long>(vertex_count) + index : index - 1;
  if (index == 0 || resolved < 0 || resolved >= static_cast<long long>(vertex_count))
    parser.Fail("face corner '" + corner + "' names vertex " + std::to_string(index) + " of " +
                std::to_string(vertex_count) + " read so far");
  return static_cast<int>(resolved);
}

}  // namespace

ObjMesh ParseObj(const std::string& text, const std::string& source) {
  ObjMesh mesh;
  size_t line_number = 0;
  size_t start = 0;
  while (start < text.size()) {
    size_t stop = text.find('\n', start);
    if (stop == std::string::npos) stop = text.size();
    ++line_number;
    LineParser line(source, line_number, text.data() + start, text.data() + stop);
    start = stop + 1;
    const std::string keyword = line.Word();
    if (keyword == "v") {
      Eigen::Vector3d vertex;
      for (int a = 0; a < 3; ++a) vertex[a] = line.Number("vertex coordinate");
      mesh.vertices.push_back(vertex);
    } else if (keyword == "f") {
      std::vector<int> face;
      while (!line.AtEnd()) {
        if (face.size() >= kMaxObjFaceCorners)
          line.Fail("a face of more than " + std::to_string(kMaxObjFaceCorners) + " corners");
        face.push_back(CornerIndex(line, line.Word(), mesh.vertices.size()));
      }
      if (face.size() < 3) line.Fail("a face needs at least 3 corners, this one has " + std::to_string(face.size()));
      mesh.faces.push_back(std::move(face));
    }
  }
  if (mesh.vertices.empty()) throw std::runtime_error(source + ": no vertices ('v x y z' lines)");
  return mesh;
}

ObjMesh ReadObj(const std::string& path) {
  return ParseObj(ReadRegularFile(path, kMaxObjFileBytes, "an OBJ mesh"), path);
}

std::vector<Eigen::Vector3d> VertexNormals(const std::vector<Eigen::Vector3d>& vertices,
                                           const std::vector<std::vector<int>>& faces) {
  std::vector<Eigen::Vector3d> normals(vertices.size(), Eigen::Vector3d::Zero());
  for (const std::vector<int>& face : faces) {
    Eigen::Vector3d area = Eigen::Vector3d::Zero();  // twice the area times the unit normal
    for (size_t i = 0; i < face.size(); ++i)
      area += vertices[static_cast<size_t>(face[i])].cross(vertices[static_cast<size_t>(face[(i + 1) % face.size()])]);
    for (int index : face) normals[static_cast<size_t>(index)] += area;
  }
  for (Eigen::Vector3d& n : normals) {
    const double length = n.norm();
    n = length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
  }
  return normals;
}

void WriteObj(const ObjMesh& mesh, const std::string& path, const std::vector<Eigen::Vector3d>* vertices) {
  const std::vector<Eigen::Vector3d>& points = vertices != nullptr ? *vertices : mesh.vertices;
  if (points.size() != mesh.vertices.size())
    throw std::invalid_argument("WriteObj: " + std::to_string(points.size()) + " vertices for a mesh of " +
                                std::to_string(mesh.vertices.size()));
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) throw std::runtime_error(path + ": cannot open for writing");
  for (const Eigen::Vector3d& p : points) std::fprintf(file, "v %.6f %.6f %.6f\n", p.x(), p.y(), p.z());
  for (const std::vector<int>& face : mesh.faces) {
    std::fputc('f', file);
    for (int index : face) std::fprintf(file, " %d", index + 1);
    std::fputc('\n', file);
  }
  const bool failed = std::ferror(file) != 0;
  if (std::fclose(file) != 0 || failed) throw std::runtime_error(path + ": write failed");
}

}  // namespace mocap
