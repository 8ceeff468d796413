// obj_mesh.h — Wavefront OBJ (+ MTL) through tinyobjloader, validated: every
// index is checked before use, so a malformed file is an error, never a crash.
// The mesh comes out as the importers' common SceneMesh, its material slots
// being the MTL's materials.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "scene/scene.h"

namespace wp {

struct ObjMaterial {
  std::string name;
  glm::vec3 diffuse{0.0f};   // Kd
  glm::vec3 emission{0.0f};  // Ke
  std::string diffuseMap;    // map_Kd, resolved against the OBJ's folder ("" if none)
};

struct ObjFile {
  SceneMesh mesh;                       // its material slots index `materials`
  std::vector<ObjMaterial> materials;
  std::vector<std::string> files;       // the OBJ and the material libraries read with it
};

// Throws InputError naming the file (and line, where tinyobjloader gives one).
ObjFile load_obj(const std::string& path);

}  // namespace wp
