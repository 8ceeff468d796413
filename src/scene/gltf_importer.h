// gltf_importer.h — the glTF importer's class (importers.h's import_gltf),
// internal to it: included only by its parts, which define its member
// functions by concern:
//   import_gltf.cpp          loading the model (sandboxed), its extensions,
//                            the entry point
//   gltf_nodes.cpp           the node tree
//   gltf_meshes.cpp          meshes, their primitives and instances
//   gltf_materials.cpp       materials and their extensions
//   gltf_textures.cpp        textures, samplers and images
//   gltf_cameras_lights.cpp  cameras and KHR_lights_punctual lights
#pragma once

#include <tiny_gltf.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/kinds.h"
#include "scene/materials/material_module.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/files.h"

namespace wp::gltf_import {

namespace fs = std::filesystem;

// The material extensions the importer reads (gltf_materials.cpp).
const std::set<std::string>& material_extensions();

// The files a model may read: those inside its folder.
struct Sandbox {
  fs::path root;  // canonical
  std::vector<std::string> read;
  std::string refused;  // the first path refused, for the error message

  bool inside(const std::string& path);  // import_gltf.cpp
};

class GltfImporter {
 public:
  explicit GltfImporter(const std::string& path) : path_(path) {}

  Scene run();

 private:
  // ---- the model (import_gltf.cpp) -------------------------------------------

  [[noreturn]] void fail(const std::string& where, const std::string& what) const;
  void load_model();
  void check_what_tinygltf_passes(const std::vector<unsigned char>& bytes, bool binary) const;
  static std::string first_line(const std::string& s);
  void check_extensions();

  // ---- nodes (gltf_nodes.cpp) ------------------------------------------------

  glm::mat4 local_transform(const tinygltf::Node& n, const std::string& where) const;
  void visit(int index, const glm::mat4& parent, const std::string& where, std::vector<int>& path);

  // ---- meshes (gltf_meshes.cpp) ----------------------------------------------

  // A primitive of a mesh, as read from the file.
  struct Primitive {
    SceneMesh mesh;
    uint32_t material;
    std::string where;  // its JSON path
  };

  void add_mesh_instance(int meshIndex, const glm::mat4& toWorld, const std::string& where);
  void add_gpu_instances(int meshIndex, const glm::mat4& toWorld, const tinygltf::Value& ext, const std::string& where);
  uint32_t instanced_mesh_of(int meshIndex, const std::string& where);
  std::vector<Primitive> primitives_of(int meshIndex, const std::string& where);

  // ---- materials (gltf_materials.cpp) ----------------------------------------

  uint32_t material_for(int index, const std::string& where);
  Complaint complaint(const std::string& where) const;
  int uv_set_needing_tangents(uint32_t m) const;
  // Material g's extension `name` (checked to be an object; its path in
  // `where`), or null where g has none.
  const tinygltf::Value* material_extension(const tinygltf::Material& g, const char* name, const std::string& at, std::string& where) const;
  float extension_number(const tinygltf::Value& ext, const char* key, float fallback, float lo, float hi, const std::string& at) const;
  glm::vec3 extension_color(const tinygltf::Value& ext, const char* key, glm::vec3 fallback, float hi, const std::string& at) const;
  static std::string number_text(float v);
  uint32_t extension_texture(const tinygltf::Value& ext, const char* key, glm::vec4 factor, ColorEncoding encoding, const std::string& at,
                             bool normal = false);
  void read_specular(const tinygltf::Material& g, const std::string& at, MaterialParams& m);
  bool read_volume(const tinygltf::Material& g, const std::string& at, MaterialParams& m) const;
  void read_iridescence(const tinygltf::Material& g, const std::string& at, MaterialParams& m);
  void read_anisotropy(const tinygltf::Material& g, const std::string& at, MaterialParams& m);
  std::optional<MaterialParams> sheen_layer(const tinygltf::Material& g, const std::string& at, const std::string& name);
  std::optional<MaterialParams> clearcoat_layer(const tinygltf::Material& g, const std::string& at, const std::string& name, uint32_t& normalMap);
  glm::vec3 factor3(const std::vector<double>& v, glm::vec3 fallback, const std::string& where) const;
  float unit(double v, const std::string& where) const;

  // ---- textures (gltf_textures.cpp) ------------------------------------------

  // What a material says of one of its textures (glTF's textureInfo, and
  // the normal texture's, which adds a scale).
  struct TextureRef {
    int index;
    int texCoord;
    const tinygltf::ExtensionMap& extensions;
    template <typename Info>
    explicit TextureRef(const Info& info) : index(info.index), texCoord(info.texCoord), extensions(info.extensions) {}
  };

  uint32_t texture_times(const TextureRef& info, glm::vec4 factor, ColorEncoding encoding, const std::string& where);
  uint32_t wrap_mode(int mode, const std::string& where) const;
  glm::mat4 uv_transform(const tinygltf::Value& t, const std::string& where) const;
  uint32_t decoded_image(int index, ColorEncoding encoding);

  // ---- cameras and lights (gltf_cameras_lights.cpp) --------------------------

  void add_camera(int index, const glm::mat4& toWorld, const std::string& where);
  void add_light(const tinygltf::Value& ext, const glm::mat4& toWorld, const std::string& where);
  void default_camera();

  std::string path_;
  Sandbox sandbox_;
  tinygltf::Model model_;
  Scene scene_;
  size_t visits_ = 0;
  uint32_t defaultMaterial_ = WP_INVALID;
  std::map<int, uint32_t> materials_;
  std::map<int, uint32_t> instancedMeshes_;  // glTF mesh -> Scene::instancedMeshes
  std::map<std::pair<int, ColorEncoding>, uint32_t> images_;
  std::set<std::string> unread_;  // features of the model wavepath renders without, for one warning
};

}  // namespace wp::gltf_import
