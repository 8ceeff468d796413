// gltf_meshes.cpp — the glTF importer's meshes: their primitives' vertex
// attributes and indices, and their instances, EXT_mesh_gpu_instancing's
// included (gltf_importer.h).
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <limits>

#include "scene/gltf_importer.h"

namespace wp::gltf_import {

namespace {

// The most instances a file may place (nodes and EXT_mesh_gpu_instancing's
// together): each costs the GPU 160 bytes.
constexpr size_t kMaxInstances = size_t(1) << 24;

}  // namespace

// ---- meshes --------------------------------------------------------------

// Every node that places a mesh makes an instance of it; settle_instances
// flattens the meshes that gain nothing from instancing (placed once).
void GltfImporter::add_mesh_instance(int meshIndex, const glm::mat4& toWorld, const std::string& where) {
  if (scene_.instances.size() >= kMaxInstances) fail(where, "the scene places more than " + std::to_string(kMaxInstances) + " instances");
  add_instance(scene_, instanced_mesh_of(meshIndex, where), toWorld, [&](const std::string& problem) { fail(where, problem); });
}

// EXT_mesh_gpu_instancing: the node places its mesh once per element of
// its attribute accessors, each placement the node's transform times the
// element's translation, rotation and scale (the extension's
// specification, "Instancing").
void GltfImporter::add_gpu_instances(int meshIndex, const glm::mat4& toWorld, const tinygltf::Value& ext, const std::string& where) {
  if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject()) fail(where, "has no attributes object");
  const tinygltf::Value& attributes = ext.Get("attributes");
  AccessorReader reader(model_, path_);
  std::vector<glm::vec4> columns[3];
  const char* const kNames[3] = {"TRANSLATION", "ROTATION", "SCALE"};
  size_t count = std::numeric_limits<size_t>::max();
  for (int a = 0; a < 3; ++a) {
    if (!attributes.Has(kNames[a])) continue;
    const tinygltf::Value& index = attributes.Get(kNames[a]);
    const std::string at = where + "/attributes/" + kNames[a];
    if (!index.IsInt()) fail(at, "must be an accessor index");
    columns[a] = reader.read(index.GetNumberAsInt(), {a == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3}, at, count);
    count = columns[a].size();
  }
  if (count == std::numeric_limits<size_t>::max()) fail(where + "/attributes", "has none of TRANSLATION, ROTATION and SCALE");
  if (scene_.instances.size() + count > kMaxInstances) fail(where, "the scene places more than " + std::to_string(kMaxInstances) + " instances");
  const uint32_t mesh = instanced_mesh_of(meshIndex, where);
  for (size_t i = 0; i < count; ++i) {
    const std::string at = where + "/attributes (instance " + std::to_string(i) + ")";
    glm::mat4 m(1.0f);
    if (!columns[0].empty()) m = glm::translate(m, glm::vec3(columns[0][i]));
    if (!columns[1].empty()) {
      const glm::vec4 r = columns[1][i];
      glm::quat q(r.w, r.x, r.y, r.z);
      const float len = glm::length(q);
      if (!(len > 0.0f) || !std::isfinite(len)) fail(at, "its ROTATION is not a rotation (its length is " + std::to_string(len) + ")");
      m = m * glm::mat4_cast(q / len);
    }
    if (!columns[2].empty()) m = glm::scale(m, glm::vec3(columns[2][i]));
    add_instance(scene_, mesh, toWorld * m, [&](const std::string& problem) { fail(at, problem); });
  }
}

// The instanced mesh (Scene::instancedMeshes) of glTF mesh `meshIndex`,
// made on first use from all its primitives.
uint32_t GltfImporter::instanced_mesh_of(int meshIndex, const std::string& where) {
  auto found = instancedMeshes_.find(meshIndex);
  if (found != instancedMeshes_.end()) return found->second;
  const std::vector<Primitive> primitives = primitives_of(meshIndex, where);
  const uint32_t index = add_instanced_mesh(scene_);
  for (const Primitive& p : primitives)
    add_to_instanced_mesh(scene_, index, p.mesh, {p.material}, WP_INVALID, [&](const std::string& problem) { fail(p.where, problem); });
  instancedMeshes_[meshIndex] = index;
  return index;
}

// A mesh's primitives, read once (instanced_mesh_of keeps what they hold).
std::vector<GltfImporter::Primitive> GltfImporter::primitives_of(int meshIndex, const std::string& where) {
  if (meshIndex < 0 || meshIndex >= int(model_.meshes.size())) fail(where, "names mesh " + std::to_string(meshIndex) + ", which does not exist");
  std::vector<Primitive> out;
  const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
  const std::string at = "/meshes/" + std::to_string(meshIndex);
  AccessorReader reader(model_, path_);
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string pat = at + "/primitives/" + std::to_string(p);
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
      static const char* const kModes[] = {"points", "lines", "line loops", "line strips", "triangles", "triangle strips", "triangle fans"};
      const std::string mode = prim.mode >= 0 && prim.mode <= 6 ? kModes[prim.mode] : "mode " + std::to_string(prim.mode);
      fail(pat + "/mode", "wavepath renders triangles only, not " + mode);
    }
    if (!prim.targets.empty()) unread_.insert("morph targets");
    auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) fail(pat + "/attributes", "has no POSITION");
    SceneMesh m;
    for (const glm::vec4& v : reader.read(pos->second, {TINYGLTF_TYPE_VEC3}, pat + "/attributes/POSITION")) {
      glm::vec3 q(v);
      if (!is_finite(q)) fail(pat + "/attributes/POSITION", "holds a position that is not a finite number");
      m.positions.push_back(q);
    }
    const size_t vertices = m.positions.size();
    auto normal = prim.attributes.find("NORMAL");
    if (normal != prim.attributes.end())
      for (const glm::vec4& v : reader.read(normal->second, {TINYGLTF_TYPE_VEC3}, pat + "/attributes/NORMAL", vertices))
        m.normals.push_back(glm::vec3(v));
    for (int set = 0; set < 2; ++set) {
      auto uv = prim.attributes.find("TEXCOORD_" + std::to_string(set));
      if (uv == prim.attributes.end()) continue;
      std::vector<glm::vec2>& uvs = set == 0 ? m.uvs : m.uvs1;
      for (const glm::vec4& v : reader.read(uv->second, {TINYGLTF_TYPE_VEC2}, pat + "/attributes/TEXCOORD_" + std::to_string(set), vertices))
        uvs.push_back(glm::vec2(v.x, 1.0f - v.y));  // glTF's v runs down the image; wavepath's up
    }
    auto tangent = prim.attributes.find("TANGENT");
    if (tangent != prim.attributes.end())
      for (const glm::vec4& v : reader.read(tangent->second, {TINYGLTF_TYPE_VEC4}, pat + "/attributes/TANGENT", vertices)) {
        // A tangent that is not a finite direction is derived from the UVs instead.
        const bool usable = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
        m.tangents.push_back(usable ? v : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
      }
    auto color = prim.attributes.find("COLOR_0");
    if (color != prim.attributes.end()) {
      const std::vector<glm::vec4> colors = reader.read(color->second, {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, pat + "/attributes/COLOR_0", vertices);
      const bool rgb = model_.accessors[size_t(color->second)].type == TINYGLTF_TYPE_VEC3;  // read() checked the index
      for (const glm::vec4& v : colors) {
        const glm::vec4 c(v.x, v.y, v.z, rgb ? 1.0f : v.w);
        if (!(glm::all(glm::greaterThanEqual(c, glm::vec4(0.0f))) && glm::all(glm::lessThanEqual(c, glm::vec4(1.0f)))))
          fail(pat + "/attributes/COLOR_0", "holds a colour outside [0, 1]");
        m.colors.push_back(c);
      }
    }
    std::vector<uint32_t> corners;
    if (prim.indices >= 0) {
      corners = reader.indices(prim.indices, pat + "/indices", vertices);
    } else {
      corners.resize(vertices);
      for (size_t i = 0; i < vertices; ++i) corners[i] = uint32_t(i);
    }
    if (corners.size() % 3 != 0) fail(prim.indices >= 0 ? pat + "/indices" : pat + "/attributes/POSITION", "holds " + std::to_string(corners.size()) + " corners, not a whole number of triangles");
    m.positionIndices = corners;
    m.normalIndices = m.normals.empty() ? std::vector<uint32_t>(corners.size(), WP_INVALID) : corners;
    m.uvIndices = m.uvs.empty() ? std::vector<uint32_t>(corners.size(), WP_INVALID) : corners;
    m.materials.assign(corners.size() / 3, 0u);
    const uint32_t material = material_for(prim.material, pat + "/material");
    // A normal map or anisotropy without TANGENT: smooth tangents from its UV set.
    const int uvSet = uv_set_needing_tangents(material);
    if (uvSet >= 0 && m.tangents.empty()) m.tangents = smooth_tangents(m, uvSet == 1 ? m.uvs1 : m.uvs);
    out.push_back(Primitive{std::move(m), material, pat});
  }
  return out;
}

}  // namespace wp::gltf_import
