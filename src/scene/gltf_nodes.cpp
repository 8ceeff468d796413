// gltf_nodes.cpp — the glTF importer's walk of the default scene's node
// tree: each node's transform, and what it places (gltf_importer.h).
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

#include "scene/gltf_importer.h"

namespace wp::gltf_import {

namespace {

// The most nodes a scene's tree may visit (a DAG can share subtrees, which
// multiplies what a walk visits).
constexpr size_t kMaxNodeVisits = 1u << 20;

}  // namespace

// ---- nodes ---------------------------------------------------------------

glm::mat4 GltfImporter::local_transform(const tinygltf::Node& n, const std::string& where) const {
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16) fail(where + "/matrix", "expected 16 numbers");
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = float(n.matrix[size_t(i)]);  // column-major, as glTF stores it
    return m;
  }
  glm::mat4 m(1.0f);
  if (!n.translation.empty()) {
    if (n.translation.size() != 3) fail(where + "/translation", "expected 3 numbers");
    m = glm::translate(m, glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
  }
  if (!n.rotation.empty()) {
    if (n.rotation.size() != 4) fail(where + "/rotation", "expected a quaternion of 4 numbers");
    glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));  // glTF: x, y, z, w
    const float len = glm::length(q);
    if (!(len > 0.0f) || !std::isfinite(len)) fail(where + "/rotation", "is not a rotation (its length is " + std::to_string(len) + ")");
    m = m * glm::mat4_cast(q / len);
  }
  if (!n.scale.empty()) {
    if (n.scale.size() != 3) fail(where + "/scale", "expected 3 numbers");
    m = glm::scale(m, glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
  }
  return m;
}

// Places node `index` and its subtree. `path` holds the nodes above it: a
// node met again on its own path is a cycle.
void GltfImporter::visit(int index, const glm::mat4& parent, const std::string& where, std::vector<int>& path) {
  if (index < 0 || index >= int(model_.nodes.size())) fail(where, "names node " + std::to_string(index) + ", which does not exist");
  if (std::find(path.begin(), path.end(), index) != path.end()) fail(where, "node " + std::to_string(index) + " is its own ancestor (a cycle)");
  if (++visits_ > kMaxNodeVisits) fail(where, "the node tree visits more than " + std::to_string(kMaxNodeVisits) + " nodes");
  const std::string at = "/nodes/" + std::to_string(index);
  const tinygltf::Node& n = model_.nodes[size_t(index)];
  const glm::mat4 toWorld = parent * local_transform(n, at);
  if (n.skin >= 0) unread_.insert("skins (meshes in their bind pose)");
  auto instancing = n.extensions.find("EXT_mesh_gpu_instancing");
  if (n.mesh >= 0 && instancing != n.extensions.end()) {
    add_gpu_instances(n.mesh, toWorld, instancing->second, at + "/extensions/EXT_mesh_gpu_instancing");
  } else if (n.mesh >= 0) {
    add_mesh_instance(n.mesh, toWorld, at + "/mesh");
  }
  if (n.camera >= 0) add_camera(n.camera, toWorld, at + "/camera");
  auto light = n.extensions.find("KHR_lights_punctual");
  if (light != n.extensions.end()) add_light(light->second, toWorld, at + "/extensions/KHR_lights_punctual");
  path.push_back(index);
  for (size_t c = 0; c < n.children.size(); ++c) visit(n.children[c], toWorld, at + "/children/" + std::to_string(c), path);
  path.pop_back();
}

}  // namespace wp::gltf_import
