// collada_reader.h — the COLLADA reader's class (importers.h's
// import_collada), internal to it: included only by its parts, which define
// its member functions by concern:
//   import_collada.cpp     the document, its node tree, the scene, the entry
//                          point
//   collada_materials.cpp  materials and their bindings
//   collada_geometry.cpp   meshes and their primitives
//   collada_lights.cpp     lights
//   collada_camera.cpp     the camera, and CS184's camera settings files
#pragma once

#include <pugixml.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "scene/materials/material_module.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/files.h"

namespace wp::collada_import {

// Sizes past which a count is taken for corruption, not a scene.
constexpr size_t kMaxArray = size_t(1) << 28;
constexpr size_t kMaxPolygonSides = 1u << 16;
constexpr int kMaxNodeDepth = 256;
constexpr size_t kMaxNodesVisited = size_t(1) << 20;
constexpr size_t kMaxTriangles = size_t(1) << 26;

// Appends the whitespace-separated numbers of [s, end) to `out`, at most
// `limit` of them. Returns the problem ("" for none): text that is not a
// number, a float that is not finite, or one number past the limit.
template <typename T>
std::string read_numbers(const char* s, const char* end, size_t limit, std::vector<T>& out) {
  for (;;) {
    while (s < end && std::isspace(static_cast<unsigned char>(*s))) ++s;
    if (s == end) return "";
    T v{};
    if (*s == '+') ++s;  // from_chars refuses a leading plus
    auto [next, ec] = std::from_chars(s, end, v);
    if (ec != std::errc() || (next < end && !std::isspace(static_cast<unsigned char>(*next)))) {
      // The word that is not a number, shortened, its unprintable bytes shown as '?' (a binary file's).
      std::string word;
      for (const char* c = s; c < end && word.size() < 20 && !std::isspace(static_cast<unsigned char>(*c)); ++c)
        word += std::isprint(static_cast<unsigned char>(*c)) ? *c : '?';
      return "\"" + word + "\" is not a number";
    }
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(v)) return "a number is not finite";
    }
    out.push_back(v);
    if (out.size() > limit) return "more than " + std::to_string(limit) + " numbers";
    s = next;
  }
}

// What a node instances, in the order the course's parser meets them.
struct Placed {
  pugi::xml_node instance;  // instance_camera, instance_light or instance_geometry
  glm::dmat4 toWorld;
};

class ColladaReader {
 public:
  explicit ColladaReader(const std::string& path) : path_(path) {}

  Scene read();

 private:
  // ---- places and errors (import_collada.cpp) --------------------------------

  std::string position(size_t offset) const;
  std::string where(pugi::xml_node n) const;
  [[noreturn]] void fail(pugi::xml_node at, const std::string& what) const;
  [[noreturn]] void unsupported(pugi::xml_node n) const;
  static bool ignorable(pugi::xml_node n);
  pugi::xml_node required(pugi::xml_node parent, const char* name) const;

  // ---- references (import_collada.cpp) ---------------------------------------

  void index_ids(pugi::xml_node root);
  pugi::xml_node resolve(pugi::xml_node from, const char* attr, const char* kind) const;

  // ---- numbers (import_collada.cpp; numbers below) ---------------------------

  template <typename T>
  std::vector<T> numbers(pugi::xml_node e, size_t count, const char* what) const;
  double number(pugi::xml_node e, const char* what) const;
  glm::dvec3 color(pugi::xml_node e, const char* what) const;
  size_t count_attribute(pugi::xml_node e, const char* name) const;

  // ---- the document (import_collada.cpp) -------------------------------------

  void read_up_axis(pugi::xml_node root);
  glm::dmat4 node_transform(pugi::xml_node node) const;
  void read_node(pugi::xml_node node, const glm::dmat4& parent, std::vector<Placed>& placed, int depth);

  // ---- materials (collada_materials.cpp) -------------------------------------

  static pugi::xml_node cgl_technique(pugi::xml_node e);
  uint32_t constant(glm::dvec3 c);
  uint32_t material(pugi::xml_node mat);
  uint32_t default_material();
  uint32_t bound_material(pugi::xml_node instance, const std::string& symbol);

  // ---- geometry (collada_geometry.cpp) ---------------------------------------

  struct Source {
    std::vector<double> values;
    size_t stride = 0;
  };

  // A mesh's polygons: each one's position indices, UV indices (into
  // uvValues; empty without UVs) and material.
  struct Polygons {
    std::vector<std::vector<uint32_t>> vertices, uvs;
    std::vector<uint32_t> material;
    std::vector<glm::vec2> uvValues;
  };

  Source source(pugi::xml_node src, size_t defaultStride) const;
  void read_mesh(pugi::xml_node instance, pugi::xml_node mesh, const glm::dmat4& toWorld);
  void find_light_plane_contacts(size_t first, const std::vector<glm::vec3>& world, const Source& positions, const glm::dmat4& toWorld);
  void read_primitive(pugi::xml_node instance, pugi::xml_node prim, pugi::xml_node vertices, size_t numPositions, Polygons& out);

  // ---- lights (collada_lights.cpp) -------------------------------------------

  glm::vec3 point(const glm::dmat4& m, glm::dvec3 p) const;
  void read_light(pugi::xml_node light, const glm::dmat4& m);

  // ---- the scene (import_collada.cpp) and its camera (collada_camera.cpp) ----

  struct Bounds {
    glm::dvec3 lo{INFINITY}, hi{-INFINITY};
    void grow(glm::dvec3 p) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    bool empty() const { return !(lo.x <= hi.x); }
  };

  void build(const std::vector<Placed>& placed);
  void place_camera(pugi::xml_node camera, const glm::dmat4& toWorld, const Bounds& bounds);

  std::string path_;
  std::string text_;
  pugi::xml_document doc_;
  std::unordered_map<std::string, pugi::xml_node> ids_;
  std::unordered_map<pugi::xml_node_struct*, uint32_t> materials_;
  uint32_t defaultMaterial_ = WP_INVALID;
  glm::dmat4 upAxis_{1.0};
  // The CGL area lights' planes, as the course places them: where meshes
  // may lie in them (find_light_plane_contacts).
  struct LightPlane {
    glm::dvec3 origin, facing;  // facing: a unit vector
    glm::dvec3 lo, hi;          // the light's box, widened by `near`
    double near;                // how far from the plane a triangle lies in it
    uint32_t firstTriangle;     // in Scene::lightOnlyTriangles
  };
  std::vector<LightPlane> lightPlanes_;
  std::vector<pugi::xml_node> ancestors_;  // of the node being read (instance_node cycles)
  size_t nodesVisited_ = 0;
  Scene scene_;
};

// Exactly `count` numbers of the element's text (count 0: all there are).
template <typename T>
std::vector<T> ColladaReader::numbers(pugi::xml_node e, size_t count, const char* what) const {
  const char* s = e.child_value();
  std::vector<T> out;
  if (count > 0) out.reserve(std::min(count, kMaxArray));
  const std::string problem = read_numbers(s, s + std::strlen(s), kMaxArray, out);
  if (!problem.empty()) fail(e, std::string(what) + ": " + problem);
  if (count > 0 && out.size() != count)
    fail(e, std::string(what) + ": " + std::to_string(out.size()) + " numbers where " + std::to_string(count) + " belong");
  return out;
}

}  // namespace wp::collada_import
