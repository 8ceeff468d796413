// obj_mesh.h — Wavefront OBJ (+ MTL) through tinyobjloader, validated: every
// index is checked before use, so a malformed file is an error, never a crash.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace wp {

struct ObjMaterial {
  std::string name;
  glm::vec3 diffuse{0.0f};   // Kd
  glm::vec3 emission{0.0f};  // Ke
  std::string diffuseMap;    // map_Kd, resolved against the OBJ's folder ("" if none)
};

struct ObjMesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;       // three per triangle, into positions
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> texcoords;
  std::vector<int> normalIndices;      // three per triangle, into normals, or -1
  std::vector<int> texcoordIndices;    // three per triangle, into texcoords, or -1
  std::vector<int> triangleMaterials;  // one per triangle, into materials, or -1
  std::vector<ObjMaterial> materials;
};

// Throws InputError naming the file (and line, where tinyobjloader gives one).
ObjMesh load_obj(const std::string& path);

}  // namespace wp
