// darts_importer.h — the darts importer's class (importers.h's import_darts,
// darts_tests.h's test files), internal to it: included only by its parts,
// which define its member functions by concern:
//   import_darts.cpp      the document, its settings and the entry points
//   darts_materials.cpp   textures, the background and materials
//   darts_media.cpp       participating media and phase functions
//   darts_surfaces.cpp    surfaces (lights among them) and OBJ meshes
//   darts_test_files.cpp  darts' test files
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "scene/darts_tests.h"
#include "scene/json_cursor.h"
#include "scene/kinds.h"
#include "scene/materials/material_module.h"
#include "scene/obj_mesh.h"
#include "scene/scene.h"
#include "scene/transform.h"
#include "util/error.h"
#include "util/huge_pages.h"

namespace wp::darts_import {

class DartsImporter {
 public:
  explicit DartsImporter(std::string path) : file_(std::move(path)) {}

  // ---- the document (import_darts.cpp) ---------------------------------------

  void parse_document();
  static bool holds_tests(const nlohmann::json& doc);
  Scene load();

  // ---- test files (darts_test_files.cpp) -------------------------------------

  bool is_test_file();
  std::vector<DartsTest> load_tests();

 private:
  // (import_darts.cpp)
  glm::vec3 non_negative(const JsonCursor& j);
  std::string resolve(const std::string& rel) const;

  // ---- settings (import_darts.cpp) -------------------------------------------

  void parse_camera(const JsonCursor& j);
  void parse_sampler(const JsonCursor& j);
  void parse_accelerator(const JsonCursor& j);
  void parse_integrator(const JsonCursor& j);

  // ---- textures and materials (darts_materials.cpp) --------------------------

  uint32_t add_texture(const SceneTexture& t);
  void parse_mapping(const JsonCursor& j, SceneTexture& t);
  uint32_t texture_param(const JsonCursor& j, int depth = 0, glm::vec3* constant = nullptr);
  void parse_background(const JsonCursor& j);
  static Complaint complaint_at(const JsonCursor& j);
  uint32_t add_material(const JsonCursor& j, const std::string& name);
  void read_param(const JsonCursor& v, const ParamSpec& p, MaterialParams& params, const std::string& name);
  uint32_t material_part(const JsonCursor& j, const std::string& name);
  uint32_t material_of(const JsonCursor& surface);
  uint32_t interface_material();

  // ---- participating media (darts_media.cpp) ---------------------------------

  static bool is_phase_type(const std::string& type);
  float parse_phase(const JsonCursor& j);
  glm::vec3 coefficient(const JsonCursor& j, const char* key, glm::vec3 fallback);
  uint32_t add_medium(const JsonCursor& j, const std::string& name);
  void parse_media(const JsonCursor& j);
  uint32_t medium_of(const JsonCursor& j);
  uint32_t with_media(const JsonCursor& surface, uint32_t material);

  // ---- surfaces (darts_surfaces.cpp) -----------------------------------------

  void parse_surface(const JsonCursor& j, const glm::mat4& parent);
  static bool is_similarity(const glm::mat3& m);
  SceneTriangle& add_triangle(const JsonCursor& where, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material);
  SceneTriangleShading& add_shading(SceneTriangle& t);
  const ObjFile& mesh_of(const JsonCursor& j);
  size_t mesh_triangles(const JsonCursor& surfaces);
  void load_mesh(const JsonCursor& j, const glm::mat4& xform);

  // ---- test files (darts_test_files.cpp) -------------------------------------

  static void parse_sampling_options(const JsonCursor& j, DartsTest& t);
  static glm::vec3 unit_vector(const JsonCursor& j);
  void parse_test(const JsonCursor& j, DartsTest& t);
  void parse_test_surfaces(const JsonCursor& j, DartsTest& t, bool sampling);

  std::string file_;
  nlohmann::json doc_;
  Scene scene_;
  std::map<std::string, ObjFile> meshes_;  // parsed OBJ files by path
  std::map<std::string, uint32_t> named_;
  std::map<std::string, float> phases_;     // named phase functions: their g
  std::map<std::string, uint32_t> media_;   // named media
  std::set<std::string> unused_media_;      // named media no surface or camera names yet
  std::map<std::string, std::shared_ptr<const DensityGrid>> grids_;  // by file and grid name: each read once
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> bounding_;  // (material, interior, exterior): its copy bounding them
  uint32_t interface_ = WP_INVALID;         // the material of surfaces with "material": null
};

}  // namespace wp::darts_import
