// libFuzzer entry for the OBJ reader: any bytes parse or throw runtime_error naming the source;
// every face index of a parsed mesh names a vertex.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "registration/obj_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mocap::ObjMesh mesh = mocap::ParseObj(text, "fuzz");
    for (const std::vector<int>& face : mesh.faces) {
      if (face.size() < 3 || face.size() > mocap::kMaxObjFaceCorners) __builtin_trap();
      for (int index : face)
        if (index < 0 || static_cast<size_t>(index) >= mesh.vertices.size()) __builtin_trap();
    }
  } catch (const std::runtime_error& error) {
    if (std::string(error.what()).rfind("fuzz: ", 0) != 0) __builtin_trap();
  }
  return 0;
}
