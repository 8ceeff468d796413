// import_collada.cpp — Berkeley CS184's COLLADA scenes (.dae), read as the
// course's pathtracer reads them (its src/scene/collada/collada.cpp and
// src/application/application.cpp; docs/scene-format.md, "CS184", cites
// each rule): the up axis, the node tree, polygon meshes with the course's
// recomputed vertex normals, its CGL spheres, lights and materials, and its
// camera rule. Anything else in the node tree is refused by name.
#include <pugixml.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <unordered_map>

#include "scene/materials/material_module.h"
#include "scene/cs184_normals.h"
#include "scene/importers.h"
#include "util/error.h"
#include "util/files.h"

namespace wp {

namespace {

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

  Scene read() {
    auto bytes = read_file_bytes(path_);
    if (!bytes) throw InputError(path_ + ": cannot read scene file");
    text_.assign(bytes->begin(), bytes->end());
    pugi::xml_parse_result parsed = doc_.load_buffer(text_.data(), text_.size(), pugi::parse_default);
    if (!parsed) throw InputError(path_ + ":" + position(size_t(parsed.offset)) + ": malformed XML: " + parsed.description());
    pugi::xml_node root = doc_.document_element();
    if (std::string(root.name()) != "COLLADA") fail(root, "not a COLLADA document (the root element is <" + std::string(root.name()) + ">)");
    index_ids(root);
    scene_.sourcePath = path_;
    read_up_axis(root);
    pugi::xml_node instance = root.child("scene").child("instance_visual_scene");
    if (!instance) fail(root, "no <scene><instance_visual_scene> names the scene to render");
    pugi::xml_node visual = resolve(instance, "url", "visual_scene");
    std::vector<Placed> placed;
    for (pugi::xml_node node : visual.children("node")) read_node(node, upAxis_, placed, 0);
    for (pugi::xml_node other : visual.children())
      if (std::string(other.name()) != "node" && !ignorable(other)) unsupported(other);
    build(placed);
    return std::move(scene_);
  }

 private:
  // ---- places and errors ----------------------------------------------------

  std::string position(size_t offset) const {
    offset = std::min(offset, text_.size());
    size_t line = 1 + size_t(std::count(text_.begin(), text_.begin() + std::ptrdiff_t(offset), '\n'));
    size_t lineStart = text_.rfind('\n', offset == 0 ? std::string::npos : offset - 1);
    size_t column = offset - (lineStart == std::string::npos ? 0 : lineStart + 1) + 1;
    return std::to_string(line) + ":" + std::to_string(column);
  }
  // The place of an element: where its start tag opens.
  std::string where(pugi::xml_node n) const {
    ptrdiff_t offset = n.offset_debug();
    return position(offset > 0 ? size_t(offset - 1) : 0);
  }
  [[noreturn]] void fail(pugi::xml_node at, const std::string& what) const {
    throw InputError(path_ + ":" + where(at) + ": " + what);
  }
  [[noreturn]] void unsupported(pugi::xml_node n) const {
    fail(n, "<" + std::string(n.name()) + "> is not supported here (docs/scene-format.md lists what wavepath reads of COLLADA)");
  }
  // Elements that carry nothing to render: metadata, and other applications' extras.
  static bool ignorable(pugi::xml_node n) {
    const std::string name = n.name();
    return n.type() != pugi::node_element || name == "asset" || name == "extra";
  }

  pugi::xml_node required(pugi::xml_node parent, const char* name) const {
    pugi::xml_node c = parent.child(name);
    if (!c) fail(parent, "<" + std::string(parent.name()) + "> has no <" + name + ">");
    return c;
  }

  // ---- references ------------------------------------------------------------

  void index_ids(pugi::xml_node root) {
    std::vector<pugi::xml_node> stack{root};  // no recursion: files may nest deeply
    while (!stack.empty()) {
      pugi::xml_node e = stack.back();
      stack.pop_back();
      if (pugi::xml_attribute id = e.attribute("id")) {
        if (!ids_.emplace(id.value(), e).second) fail(e, "a second element with id \"" + std::string(id.value()) + "\"");
      }
      for (pugi::xml_node c : e.children())
        if (c.type() == pugi::node_element) stack.push_back(c);
    }
  }

  // The element that attribute `attr` of `from` names ("#id"), which must be a <kind>.
  pugi::xml_node resolve(pugi::xml_node from, const char* attr, const char* kind) const {
    pugi::xml_attribute a = from.attribute(attr);
    if (!a) fail(from, "<" + std::string(from.name()) + "> has no " + attr + " attribute");
    const std::string ref = a.value();
    if (ref.size() < 2 || ref[0] != '#') fail(from, std::string(attr) + " \"" + ref + "\" is not a reference into this file (#id)");
    auto it = ids_.find(ref.substr(1));
    if (it == ids_.end()) fail(from, std::string(attr) + " \"" + ref + "\" names no element of this file");
    if (std::string(it->second.name()) != kind)
      fail(from, std::string(attr) + " \"" + ref + "\" names a <" + it->second.name() + ">, not a <" + kind + ">");
    return it->second;
  }

  // ---- numbers ---------------------------------------------------------------

  // Exactly `count` numbers of the element's text (count 0: all there are).
  template <typename T>
  std::vector<T> numbers(pugi::xml_node e, size_t count, const char* what) const {
    const char* s = e.child_value();
    std::vector<T> out;
    if (count > 0) out.reserve(std::min(count, kMaxArray));
    const std::string problem = read_numbers(s, s + std::strlen(s), kMaxArray, out);
    if (!problem.empty()) fail(e, std::string(what) + ": " + problem);
    if (count > 0 && out.size() != count)
      fail(e, std::string(what) + ": " + std::to_string(out.size()) + " numbers where " + std::to_string(count) + " belong");
    return out;
  }
  double number(pugi::xml_node e, const char* what) const { return numbers<double>(e, 1, what)[0]; }
  glm::dvec3 color(pugi::xml_node e, const char* what) const {
    // A colour is three numbers; a fourth (alpha) is allowed and not read, as in the course.
    std::vector<double> v = numbers<double>(e, 0, what);
    if (v.size() != 3 && v.size() != 4) fail(e, std::string(what) + ": expected 3 numbers (RGB), got " + std::to_string(v.size()));
    return {v[0], v[1], v[2]};
  }
  size_t count_attribute(pugi::xml_node e, const char* name) const {
    pugi::xml_attribute a = e.attribute(name);
    if (!a) fail(e, "<" + std::string(e.name()) + "> has no " + name + " attribute");
    const std::string s = a.value();
    size_t v = 0;
    auto [next, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || next != s.data() + s.size()) fail(e, std::string(name) + " \"" + s + "\" is not a count");
    if (v > kMaxArray) fail(e, std::string(name) + " " + s + " is past what wavepath reads");
    return v;
  }

  // ---- the document ----------------------------------------------------------

  // <asset><up_axis>: Z_UP scenes turn (x, y, z) into (-x, z, y), X_UP ones
  // into (y, x, -z), at the root (collada.cpp). Without <asset> the scene is
  // taken as Y_UP, as there; an <asset> without <up_axis> is an error there.
  void read_up_axis(pugi::xml_node root) {
    pugi::xml_node asset = root.child("asset");
    if (!asset) return;
    pugi::xml_node up = asset.child("up_axis");
    if (!up) fail(asset, "<asset> has no <up_axis> (the course's reader requires one)");
    std::string axis = up.child_value();
    axis.erase(0, axis.find_first_not_of(" \t\r\n"));
    axis.erase(axis.find_last_not_of(" \t\r\n") + 1);
    glm::dmat4 m(1.0);
    if (axis == "Z_UP") {
      m[0][0] = -1.0;
      m[1][1] = 0.0, m[2][1] = 1.0;
      m[1][2] = 1.0, m[2][2] = 0.0;
    } else if (axis == "X_UP") {
      m[0][0] = 0.0, m[1][0] = 1.0;
      m[0][1] = 1.0, m[1][1] = 0.0;
      m[2][2] = -1.0;
    } else if (axis != "Y_UP") {
      fail(up, "up_axis \"" + axis + "\" is not X_UP, Y_UP or Z_UP");
    }
    upAxis_ = m;
  }

  // A node's transform: its transform elements multiplied in document order,
  // as COLLADA defines (the course's reader has bugs here: docs/scene-format.md).
  glm::dmat4 node_transform(pugi::xml_node node) const {
    glm::dmat4 m(1.0);
    for (pugi::xml_node e : node.children()) {
      const std::string name = e.name();
      if (name == "matrix") {
        // The course reads 16 numbers with a stream, which reads a missing
        // one as 0; one of its own scenes (CBgems.dae) relies on that.
        std::vector<double> v = numbers<double>(e, 0, "<matrix>");
        if (v.size() != 16) {
          std::fprintf(stderr, "wavepath: note: %s:%s: <matrix> has %zu numbers, not 16; the missing ones read as 0, as the course reads them\n",
                       path_.c_str(), where(e).c_str(), v.size());
          v.resize(16, 0.0);
        }
        glm::dmat4 t;
        for (int r = 0; r < 4; ++r)
          for (int c = 0; c < 4; ++c) t[c][r] = v[size_t(r * 4 + c)];  // row-major in the file
        m = m * t;
      } else if (name == "translate") {
        std::vector<double> v = numbers<double>(e, 3, "<translate>");
        glm::dmat4 t(1.0);
        t[3] = glm::dvec4(v[0], v[1], v[2], 1.0);
        m = m * t;
      } else if (name == "scale") {
        std::vector<double> v = numbers<double>(e, 3, "<scale>");
        m = m * glm::dmat4(glm::dvec4(v[0], 0, 0, 0), glm::dvec4(0, v[1], 0, 0), glm::dvec4(0, 0, v[2], 0), glm::dvec4(0, 0, 0, 1));
      } else if (name == "rotate") {
        std::vector<double> v = numbers<double>(e, 4, "<rotate>");
        glm::dvec3 axis(v[0], v[1], v[2]);
        if (glm::length(axis) == 0.0) fail(e, "<rotate>: the axis is zero");
        axis = glm::normalize(axis);
        const double a = glm::radians(v[3]), c = std::cos(a), s = std::sin(a);
        glm::dmat3 r = glm::dmat3(c) + s * glm::dmat3(glm::dvec3(0, axis.z, -axis.y), glm::dvec3(-axis.z, 0, axis.x),
                                                      glm::dvec3(axis.y, -axis.x, 0)) +
                       (1.0 - c) * glm::outerProduct(axis, axis);
        m = m * glm::dmat4(r);
      } else if (name == "lookat") {
        std::vector<double> v = numbers<double>(e, 9, "<lookat>");
        glm::dvec3 eye(v[0], v[1], v[2]), at(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
        glm::dvec3 back = eye - at;
        if (glm::length(back) == 0.0 || glm::length(glm::cross(up, back)) == 0.0) fail(e, "<lookat>: the eye, target and up do not make a frame");
        back = glm::normalize(back);
        glm::dvec3 right = glm::normalize(glm::cross(up, back));
        m = m * glm::dmat4(glm::dvec4(right, 0), glm::dvec4(glm::cross(back, right), 0), glm::dvec4(back, 0), glm::dvec4(eye, 1));
      } else if (name == "skew") {
        unsupported(e);
      }
    }
    return m;
  }

  // Walks a node and its children (post-order, as the course's parser adds
  // nodes: a child's instances before its parent's), collecting instances.
  void read_node(pugi::xml_node node, const glm::dmat4& parent, std::vector<Placed>& placed, int depth) {
    if (depth > kMaxNodeDepth) fail(node, "nodes nest more than " + std::to_string(kMaxNodeDepth) + " deep");
    // Shared subtrees (instance_node) multiply: bound the nodes visited.
    if (++nodesVisited_ > kMaxNodesVisited) fail(node, "the node tree visits more than " + std::to_string(kMaxNodesVisited) + " nodes");
    ancestors_.push_back(node);
    const glm::dmat4 toWorld = parent * node_transform(node);
    for (pugi::xml_node child : node.children("node")) read_node(child, toWorld, placed, depth + 1);
    for (pugi::xml_node e : node.children()) {
      const std::string name = e.name();
      if (name == "instance_camera" || name == "instance_light" || name == "instance_geometry") {
        placed.push_back({e, toWorld});
      } else if (name == "instance_node") {
        pugi::xml_node target = resolve(e, "url", "node");
        if (std::find(ancestors_.begin(), ancestors_.end(), target) != ancestors_.end())
          fail(e, "url \"" + std::string(e.attribute("url").value()) + "\" instances a node that contains this one");
        read_node(target, toWorld, placed, depth + 1);
      } else if (!(name == "node" || name == "matrix" || name == "translate" || name == "scale" || name == "rotate" ||
                   name == "lookat" || ignorable(e))) {
        unsupported(e);
      }
    }
    ancestors_.pop_back();
  }

  // ---- materials ---------------------------------------------------------------

  // The technique of profile CGL among an element's <extra>s, or null.
  static pugi::xml_node cgl_technique(pugi::xml_node e) {
    for (pugi::xml_node extra : e.children("extra"))
      for (pugi::xml_node t : extra.children("technique"))
        if (std::string(t.attribute("profile").value()) == "CGL") return t;
    return {};
  }

  uint32_t constant(glm::dvec3 c) { return add_texture(scene_, constant_texture(glm::vec3(c))); }

  // A material's BSDF as the course builds it (collada.cpp, parse_material):
  // the last BSDF element of the effect's CGL technique, or else profile
  // COMMON's diffuse colour, or else 0.5 grey.
  uint32_t material(pugi::xml_node mat) {
    auto known = materials_.find(mat.internal_object());
    if (known != materials_.end()) return known->second;
    pugi::xml_node effect = resolve(required(mat, "instance_effect"), "url", "effect");
    const std::string name = mat.attribute("name") ? mat.attribute("name").value() : mat.attribute("id").value();
    // The course's BSDFs in wavepath's kinds and their parameters' names.
    std::optional<MaterialParams> m;
    for (pugi::xml_node b : cgl_technique(effect).children()) {
      if (b.type() != pugi::node_element) continue;
      const std::string type = b.name();
      const auto at = [this](pugi::xml_node n) { return Complaint([this, n](const std::string& problem) { fail(n, problem); }); };
      if (type == "emission") {
        m.emplace(MAT_LIGHT, name, at(b));
        m->texture("emit", constant(color(required(b, "radiance"), "<radiance>")), at(b.child("radiance")));
      } else if (type == "mirror") {
        m.emplace(MAT_METAL, name, at(b));  // roughness 0: a mirror tinted by the reflectance
        m->texture("albedo", constant(color(required(b, "reflectance"), "<reflectance>")), at(b.child("reflectance")));
      } else if (type == "microfacet") {
        m.emplace(MAT_BECKMANN_CONDUCTOR, name, at(b));
        m->number("alpha", float(number(required(b, "alpha"), "<alpha>")), at(b.child("alpha")));
        m->colour("eta", glm::vec3(color(required(b, "eta"), "<eta>")), at(b.child("eta")));
        m->colour("k", glm::vec3(color(required(b, "k"), "<k>")), at(b.child("k")));
        m->choice("shadowing", "cs184");  // the 3-2 skeleton's shadowing term
      } else if (type == "glass" || type == "refraction") {
        m.emplace(MAT_CS184_GLASS, name, at(b));
        m->texture("transmittance", constant(color(required(b, "transmittance"), "<transmittance>")), at(b.child("transmittance")));
        if (type == "glass") m->colour("reflectance", glm::vec3(color(required(b, "reflectance"), "<reflectance>")), at(b.child("reflectance")));
        number(required(b, "roughness"), "<roughness>");  // read, not used: both BSDFs are smooth in the course
        const double ior = number(required(b, "ior"), "<ior>");
        if (!(ior > 0.0 && ior < 100.0)) fail(b.child("ior"), "ior must lie between 0 and 100");
        m->number("ior", float(ior), at(b.child("ior")));
        m->flag("refraction_only", type == "refraction");
      } else {
        unsupported(b);
      }
    }
    if (!m) {
      // profile_COMMON: the technique of sid "common"; its shading model's diffuse colour.
      glm::dvec3 diffuse(0.5);
      for (pugi::xml_node t : effect.child("profile_COMMON").children("technique")) {
        for (pugi::xml_node model : t.children()) {
          const std::string shading = model.name();
          if (shading != "phong" && shading != "lambert" && shading != "blinn") continue;
          pugi::xml_node d = model.child("diffuse");
          if (!d) continue;
          if (d.child("texture")) fail(d, "a diffuse <texture> is not supported (colours only)");
          if (pugi::xml_node c = d.child("color")) diffuse = color(c, "<color>");
        }
      }
      m.emplace(MAT_LAMBERTIAN, name, [this, effect](const std::string& problem) { fail(effect, problem); });
      m->texture("albedo", constant(diffuse));
    }
    const uint32_t id = add_material(scene_, *m);
    materials_.emplace(mat.internal_object(), id);
    return id;
  }

  uint32_t default_material() {
    if (defaultMaterial_ == WP_INVALID) defaultMaterial_ = add_lambertian(scene_, glm::vec3(0.5f), "default (0.5 grey)");
    return defaultMaterial_;
  }

  // The material bound to `symbol` by an instance's <bind_material>; with no
  // binding at all, the course's 0.5 grey.
  uint32_t bound_material(pugi::xml_node instance, const std::string& symbol) {
    pugi::xml_node common = instance.child("bind_material").child("technique_common");
    pugi::xml_node first;
    for (pugi::xml_node im : common.children("instance_material")) {
      if (!first) first = im;
      if (symbol.empty() || symbol == im.attribute("symbol").value()) return material(resolve(im, "target", "material"));
    }
    if (!first) return default_material();
    fail(instance, "no <instance_material> binds the material symbol \"" + symbol + "\"");
  }

  // ---- geometry ------------------------------------------------------------------

  struct Source {
    std::vector<double> values;
    size_t stride = 0;
  };

  Source source(pugi::xml_node src, size_t defaultStride) const {
    pugi::xml_node arr = src.child("float_array");
    if (!arr) fail(src, "<source> has no <float_array> (other arrays are not read)");
    Source s;
    s.values = numbers<double>(arr, count_attribute(arr, "count"), "<float_array>");
    s.stride = defaultStride;
    if (pugi::xml_node acc = src.child("technique_common").child("accessor")) {
      if (acc.attribute("stride")) s.stride = count_attribute(acc, "stride");
      if (s.stride < defaultStride) fail(acc, "stride " + std::to_string(s.stride) + " is below the " + std::to_string(defaultStride) + " values each element needs");
    }
    return s;
  }

  // Reads a mesh's polygons into world-space triangles with the course's
  // vertex normals (computed over the whole mesh, as its half-edge mesh is).
  void read_mesh(pugi::xml_node instance, pugi::xml_node mesh, const glm::dmat4& toWorld) {
    std::map<std::string, pugi::xml_node> sources;
    for (pugi::xml_node s : mesh.children("source")) sources[s.attribute("id").value()] = s;
    pugi::xml_node vertices = required(mesh, "vertices");
    pugi::xml_node positionInput;
    for (pugi::xml_node in : vertices.children("input"))
      if (std::string(in.attribute("semantic").value()) == "POSITION") positionInput = in;
    if (!positionInput) fail(vertices, "<vertices> has no POSITION input");
    Source positions = source(resolve(positionInput, "source", "source"), 3);
    const size_t numPositions = positions.values.size() / positions.stride;

    std::vector<glm::vec3> world(numPositions);
    for (size_t i = 0; i < numPositions; ++i) {
      const double* p = &positions.values[i * positions.stride];
      glm::dvec4 w = toWorld * glm::dvec4(p[0], p[1], p[2], 1.0);
      world[i] = glm::vec3(glm::dvec3(w) / w.w);
      if (!is_finite(world[i])) fail(positionInput, std::string("position ") + std::to_string(i) + ": " + kPastFloatRange);
    }
    Polygons polys;
    for (pugi::xml_node prim : mesh.children()) {
      const std::string kind = prim.name();
      if (kind == "source" || kind == "vertices" || ignorable(prim)) continue;
      if (kind != "polylist" && kind != "triangles" && kind != "polygons") unsupported(prim);
      read_primitive(instance, prim, vertices, numPositions, polys);
    }
    const std::vector<std::vector<uint32_t>>& polygons = polys.vertices;
    // The course's vertex normals, or (where its half-edge mesh would refuse
    // the polygons) the same sums around each vertex without its walk.
    std::optional<std::vector<glm::vec3>> normals = cs184_vertex_normals(polygons, world);
    if (!normals) {
      normals.emplace(world.size(), glm::vec3(0.0f));
      for (const auto& poly : polygons)
        for (size_t i = 0; i < poly.size(); ++i) {
          const glm::vec3 pi = world[poly[i]], pj = world[poly[(i + 1) % poly.size()]], pk = world[poly[(i + 2) % poly.size()]];
          (*normals)[poly[i]] += glm::cross(pj - pi, pk - pi);
        }
      for (glm::vec3& n : *normals)
        if (glm::length(n) > 0.0f) n = glm::normalize(n);
    }
    SceneMesh out;
    out.positions = std::move(world);
    out.normals = std::move(*normals);
    out.uvs = std::move(polys.uvValues);
    std::vector<uint32_t> slots;
    for (size_t p = 0; p < polygons.size(); ++p) {
      const auto& poly = polygons[p];
      const auto& uv = polys.uvs[p];
      for (size_t i = 1; i + 1 < poly.size(); ++i) {  // a fan: the course's polygons are convex
        for (size_t c : {size_t(0), i, i + 1}) {
          out.positionIndices.push_back(poly[c]);
          out.normalIndices.push_back(poly[c]);
          out.uvIndices.push_back(uv.empty() ? WP_INVALID : uv[c]);
        }
        out.materials.push_back(polys.material[p]);
      }
    }
    for (uint32_t m = 0; m < scene_.materials.size(); ++m) slots.push_back(m);
    if (scene_.triangles.size() + out.materials.size() > kMaxTriangles)
      fail(instance, "the scene would hold more than " + std::to_string(kMaxTriangles) + " triangles");
    if (!out.materials.empty()) {
      const size_t first = scene_.triangles.size();
      add_mesh(scene_, out, glm::mat4(1.0f), slots, WP_INVALID,
               [&](const std::string& what) { fail(instance, what); });
      find_light_plane_contacts(first, out.positions, positions, toWorld);
    }
  }

  // The triangles from `first` on (one mesh's, at `world`) that lie in an
  // area light's plane, with their corners' heights above it as the course
  // computes them: the positions parsed as floats (collada.cpp:631-640),
  // placed in double (gl_scene/mesh.cpp:31). Near the light, wavepath's own
  // float positions lose the difference (the course's lamps lie within 5e-8
  // of their light's plane); the heights keep it.
  void find_light_plane_contacts(size_t first, const std::vector<glm::vec3>& world, const Source& positions, const glm::dmat4& toWorld) {
    // A float world position's vertex, built on the first contact (+ 0.0f: the
    // placement turns -0 into +0).
    const auto key = [](glm::vec3 v) { return std::array<float, 3>{v.x + 0.0f, v.y + 0.0f, v.z + 0.0f}; };
    std::map<std::array<float, 3>, size_t> vertexOf;
    for (size_t t = first; t < scene_.triangles.size(); ++t) {
      const SceneTriangle& tri = scene_.triangles[t];
      for (const LightPlane& plane : lightPlanes_) {
        bool in = true;
        for (const glm::vec3& v : tri.v) {
          const glm::dvec3 p(v);
          in = in && std::fabs(glm::dot(p - plane.origin, plane.facing)) <= plane.near;
        }
        const glm::dvec3 lo = glm::min(glm::dvec3(tri.v[0]), glm::min(glm::dvec3(tri.v[1]), glm::dvec3(tri.v[2])));
        const glm::dvec3 hi = glm::max(glm::dvec3(tri.v[0]), glm::max(glm::dvec3(tri.v[1]), glm::dvec3(tri.v[2])));
        if (!in || glm::any(glm::lessThan(hi, plane.lo)) || glm::any(glm::greaterThan(lo, plane.hi))) continue;
        if (vertexOf.empty())
          for (size_t i = 0; i < world.size(); ++i) vertexOf.emplace(key(world[i]), i);
        Cs184LightPlaneContact contact{uint32_t(t), plane.firstTriangle, {}};
        for (int c = 0; c < 3; ++c) {
          const double* local = &positions.values[vertexOf.at(key(tri.v[c])) * positions.stride];
          const glm::dvec4 w = toWorld * glm::dvec4(double(float(local[0])), double(float(local[1])), double(float(local[2])), 1.0);
          contact.height[c] = glm::dot(glm::dvec3(w) / w.w - plane.origin, plane.facing);
        }
        scene_.cs184LightPlaneContacts.push_back(contact);
        break;
      }
    }
  }

  // A mesh's polygons: each one's position indices, UV indices (into
  // uvValues; empty without UVs) and material.
  struct Polygons {
    std::vector<std::vector<uint32_t>> vertices, uvs;
    std::vector<uint32_t> material;
    std::vector<glm::vec2> uvValues;
  };

  void read_primitive(pugi::xml_node instance, pugi::xml_node prim, pugi::xml_node vertices, size_t numPositions, Polygons& out) {
    const std::string kind = prim.name();
    const size_t count = count_attribute(prim, "count");
    size_t stride = 0, vertexOffset = SIZE_MAX, uvOffset = SIZE_MAX, uvBase = out.uvValues.size(), numUvs = 0;
    for (pugi::xml_node in : prim.children("input")) {
      const size_t offset = count_attribute(in, "offset");
      stride = std::max(stride, offset + 1);
      const std::string semantic = in.attribute("semantic").value();
      if (semantic == "VERTEX") {
        if (resolve(in, "source", "vertices") != vertices) fail(in, "VERTEX names another mesh's <vertices>");
        vertexOffset = offset;
      } else if (semantic == "TEXCOORD" && uvOffset == SIZE_MAX) {
        // The first UV set, as OBJ's (v up); the course's materials read none.
        Source uv = source(resolve(in, "source", "source"), 2);
        numUvs = uv.values.size() / uv.stride;
        for (size_t i = 0; i < numUvs; ++i) out.uvValues.emplace_back(uv.values[i * uv.stride], uv.values[i * uv.stride + 1]);
        uvOffset = offset;
      } else {
        resolve(in, "source", "source");  // NORMAL and others: checked, not read (the course recomputes normals)
      }
    }
    if (vertexOffset == SIZE_MAX) fail(prim, "<" + kind + "> has no VERTEX input");
    const uint32_t mat = bound_material(instance, prim.attribute("material").value());
    std::vector<size_t> sides;
    std::vector<pugi::xml_node> lists;
    if (kind == "polylist") {
      sides = numbers<size_t>(required(prim, "vcount"), count, "<vcount>");
      lists.push_back(required(prim, "p"));
    } else if (kind == "triangles") {
      sides.assign(count, 3);
      lists.push_back(required(prim, "p"));
    } else {  // polygons: one <p> per polygon
      if (prim.child("ph")) unsupported(prim.child("ph"));
      for (pugi::xml_node p : prim.children("p")) lists.push_back(p);
      if (lists.size() != count) fail(prim, "count " + std::to_string(count) + " but " + std::to_string(lists.size()) + " <p> elements");
    }
    size_t total = 0;
    for (size_t s : sides) {
      if (s < 3) fail(prim, "a polygon of " + std::to_string(s) + " vertices (at least 3 make one)");
      if (s > kMaxPolygonSides) fail(prim, "a polygon of " + std::to_string(s) + " vertices");
      total += s;
      if (total > kMaxArray / stride) fail(prim, "more than " + std::to_string(kMaxArray) + " indices");
    }
    size_t polygon = 0;
    for (pugi::xml_node list : lists) {
      const size_t expected = kind == "polygons" ? 0 : total * stride;
      std::vector<size_t> idx = numbers<size_t>(list, expected, "<p>");
      if (kind == "polygons") {
        if (idx.size() % stride != 0 || idx.size() / stride < 3 || idx.size() / stride > kMaxPolygonSides)
          fail(list, "a polygon needs 3 to " + std::to_string(kMaxPolygonSides) + " vertices of " + std::to_string(stride) + " indices each");
        sides.push_back(idx.size() / stride);
      }
      size_t at = 0;
      for (; polygon < sides.size(); ++polygon) {
        if (at == idx.size()) break;
        std::vector<uint32_t> poly, uvs;
        for (size_t v = 0; v < sides[polygon]; ++v, at += stride) {
          const size_t i = idx[at + vertexOffset];
          if (i >= numPositions) fail(list, "vertex index " + std::to_string(i) + " past the " + std::to_string(numPositions) + " positions");
          poly.push_back(uint32_t(i));
          if (uvOffset == SIZE_MAX) continue;
          const size_t t = idx[at + uvOffset];
          if (t >= numUvs) fail(list, "UV index " + std::to_string(t) + " past the " + std::to_string(numUvs) + " UVs");
          uvs.push_back(uint32_t(uvBase + t));
        }
        out.vertices.push_back(std::move(poly));
        out.uvs.push_back(std::move(uvs));
        out.material.push_back(mat);
      }
    }
  }

  // ---- lights ---------------------------------------------------------------------

  glm::vec3 point(const glm::dmat4& m, glm::dvec3 p) const { return glm::vec3(glm::dvec3(m * glm::dvec4(p, 1.0))); }

  // A light as light_info.cpp and the gl_scene lights place it: the CGL
  // technique wins over technique_common; its first element is the kind.
  void read_light(pugi::xml_node light, const glm::dmat4& m) {
    pugi::xml_node technique = cgl_technique(light);
    if (!technique) technique = light.child("technique_common");
    if (!technique) fail(light, "<light> has neither a CGL technique nor <technique_common>");
    pugi::xml_node kind = technique.find_child([](pugi::xml_node n) { return n.type() == pugi::node_element; });
    if (!kind) fail(technique, "the light's technique names no kind of light");
    const std::string type = kind.name();
    const glm::vec3 c = glm::vec3(color(required(kind, "color"), "<color>"));
    if (type == "point" || type == "spot") {
      for (const char* a : {"constant_attenuation", "linear_attenuation", "quadratic_attenuation"}) number(required(kind, a), a);
      if (type == "spot") {
        number(required(kind, "falloff_angle"), "falloff_angle");
        number(required(kind, "falloff_exponent"), "falloff_exponent");
        // The skeleton's SpotLight returns no light: kept so, and said.
        std::fprintf(stderr, "wavepath: note: %s:%s: CS184's spot lights give no light (light.cpp), nor does this one\n",
                     path_.c_str(), where(kind).c_str());
        return;
      }
      ScenePointLight l;
      l.kind = ScenePointLight::Kind::Point;
      l.position = point(m, {0, 0, 0});
      l.intensity = c;
      l.falloff = false;  // the course's point light gives its colour at any distance
      scene_.pointLights.push_back(l);
    } else if (type == "directional") {
      // The light arrives from m (0, 0, -1) as a point, translation included (directional_light.h).
      glm::dvec3 from = glm::dvec3(m * glm::dvec4(0, 0, -1, 1));
      if (glm::length(from) == 0.0) fail(kind, "the directional light's direction is zero");
      ScenePointLight l;
      l.kind = ScenePointLight::Kind::Directional;
      l.direction = -glm::vec3(glm::normalize(from));
      l.intensity = c;
      scene_.pointLights.push_back(l);
    } else if (type == "ambient") {
      ScenePointLight l;  // the course's infinite hemisphere light: radiance from above +Y
      l.kind = ScenePointLight::Kind::Hemisphere;
      l.direction = glm::vec3(0, 1, 0);
      l.intensity = c;
      scene_.pointLights.push_back(l);
    } else if (type == "area") {
      // A one-sided parallelogram at m (0, 0, 0), facing m (0, 0, -1), with
      // sides m (-1, 0, 0) and m (0, 1, 0) (area_light.h), no geometry.
      const glm::dvec3 o = glm::dvec3(m * glm::dvec4(0, 0, 0, 1));
      const glm::dvec3 facing = glm::dvec3(m * glm::dvec4(0, 0, -1, 1)) - o;
      const glm::dvec3 dx = glm::dvec3(m * glm::dvec4(-1, 0, 0, 0)), dy = glm::dvec3(m * glm::dvec4(0, 1, 0, 0));
      if (glm::length(glm::cross(dx, dy)) == 0.0 || glm::length(facing) == 0.0) fail(kind, "the area light's transform flattens it");
      MaterialParams em(MAT_LIGHT, light.attribute("id").value(), [this, kind](const std::string& problem) { fail(kind, problem); });
      em.texture("emit", constant(glm::dvec3(c)));
      const uint32_t mat = add_material(scene_, em);
      glm::dvec3 q[4] = {o - 0.5 * dx - 0.5 * dy, o + 0.5 * dx - 0.5 * dy, o + 0.5 * dx + 0.5 * dy, o - 0.5 * dx + 0.5 * dy};
      const bool flip = glm::dot(glm::cross(dx, dy), facing) < 0.0;  // the front (cross of the sides) must face `facing`
      LightPlane plane{o, glm::normalize(facing), glm::dvec3(INFINITY), glm::dvec3(-INFINITY), 1.0, uint32_t(scene_.lightOnlyTriangles.size())};
      for (const glm::dvec3& c : q) plane.near = std::max(plane.near, std::max(std::fabs(c.x), std::max(std::fabs(c.y), std::fabs(c.z))));
      plane.near *= 2.5 * kCs184QuadSetBack;  // past where the 3-2 skeleton's quad is put, behind the plane
      for (const glm::dvec3& c : q) plane.lo = glm::min(plane.lo, c - plane.near), plane.hi = glm::max(plane.hi, c + plane.near);
      lightPlanes_.push_back(plane);
      for (int t = 0; t < 2; ++t) {
        SceneTriangle tri;
        glm::dvec3 a = q[0], b = q[t + 1], d = q[t + 2];
        if (flip) std::swap(b, d);
        tri.v[0] = glm::vec3(a), tri.v[1] = glm::vec3(b), tri.v[2] = glm::vec3(d);
        tri.material = mat;
        scene_.lightOnlyTriangles.push_back(tri);
      }
    } else {
      unsupported(kind);
    }
  }

  // ---- the scene ---------------------------------------------------------------------

  void build(const std::vector<Placed>& placed) {
    pugi::xml_node cameraNode;
    glm::dmat4 cameraToWorld(1.0);
    Bounds bounds;
    // The lights first, so that each mesh is read knowing the area lights' planes.
    for (const Placed& p : placed)
      if (std::string(p.instance.name()) == "instance_light") read_light(resolve(p.instance, "url", "light"), p.toWorld);
    for (const Placed& p : placed) {
      const std::string kind = p.instance.name();
      if (kind == "instance_camera") {
        cameraNode = resolve(p.instance, "url", "camera");  // the last one wins, as in the course
        cameraToWorld = p.toWorld;
      } else if (kind == "instance_light") {
        continue;
      } else {
        pugi::xml_node geometry = resolve(p.instance, "url", "geometry");
        if (pugi::xml_node mesh = geometry.child("mesh")) {
          const size_t before = scene_.triangles.size();
          read_mesh(p.instance, mesh, p.toWorld);
          for (size_t t = before; t < scene_.triangles.size(); ++t)
            for (const glm::vec3& v : scene_.triangles[t].v) bounds.grow(glm::dvec3(v));
        } else if (pugi::xml_node sphere = cgl_technique(geometry).child("sphere")) {
          const glm::dvec4 hc = p.toWorld * glm::dvec4(0, 0, 0, 1);
          const glm::dvec3 c = glm::dvec3(hc) / hc.w;
          const double r = number(required(sphere, "radius"), "<radius>") * glm::length(glm::dvec3(p.toWorld[0]));
          if (!(r > 0.0) || !std::isfinite(r)) fail(sphere, "the sphere's radius (times the node's scale) must be positive");
          SceneSphere s;
          s.toWorld = glm::mat4(glm::translate(glm::dmat4(1.0), c) * glm::scale(glm::dmat4(1.0), glm::dvec3(r)));
          s.material = bound_material(p.instance, "");
          scene_.spheres.push_back(s);
          bounds.grow(c - glm::dvec3(r));
          bounds.grow(c + glm::dvec3(r));
        } else {
          fail(geometry, "the geometry is neither a <mesh> nor a CGL <sphere>");
        }
      }
    }
    place_camera(cameraNode, cameraToWorld, bounds);
    scene_.cs184Estimator = true;
    scene_.cs184LatLong = true;
    scene_.eightBitCurve = EightBitCurve::Cs184;
    scene_.cs184Skeleton = 31;
    scene_.integrator.kind = IntegratorKind::PathNee;
    scene_.integrator.maxBounces = 1;  // the course's -m default
    scene_.samplesPerPixel = 1;
  }

  struct Bounds {
    glm::dvec3 lo{INFINITY}, hi{-INFINITY};
    void grow(glm::dvec3 p) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    bool empty() const { return !(lo.x <= hi.x); }
  };

  // The course's camera: xfov and yfov (50 and 35 where absent; yfov from
  // the aspect ratio when only that is given), fitted to 800x600 by widening
  // the narrower field (camera.cpp, configure); then an orbit camera placed by
  // application.cpp: looking at the centre of the objects' bounding box from
  // 1.5 times its diagonal, along the direction the camera node's transform
  // gives the point (0, 0, -1) (translation included), up +Y.
  void place_camera(pugi::xml_node camera, const glm::dmat4& toWorld, const Bounds& bounds) {
    double hFov = 50.0, vFov = 35.0;
    glm::dvec3 dir(0.0, 0.0, 1.0);
    if (camera) {
      pugi::xml_node optics = required(camera, "optics");
      pugi::xml_node common = required(optics, "technique_common");
      pugi::xml_node persp = common.child("perspective");
      if (!persp) {
        if (pugi::xml_node ortho = common.child("orthographic")) unsupported(ortho);
        fail(common, "the camera has no <perspective>");
      }
      pugi::xml_node xfov = persp.child("xfov"), yfov = persp.child("yfov");
      if (xfov) hFov = number(xfov, "<xfov>");
      if (yfov) vFov = number(yfov, "<yfov>");
      if (!yfov) {
        pugi::xml_node aspect = persp.child("aspect_ratio");
        if (!aspect) fail(persp, "<perspective> has neither <yfov> nor <aspect_ratio>");
        const double ar = number(aspect, "<aspect_ratio>");
        if (!(ar > 0.0)) fail(aspect, "the aspect ratio must be positive");
        vFov = 2.0 * glm::degrees(std::atan(std::tan(glm::radians(0.5 * hFov)) / ar));
      }
      if (!(hFov > 0.0 && hFov < 180.0 && vFov > 0.0 && vFov < 180.0)) fail(persp, "fields of view must lie between 0 and 180 degrees");
      dir = glm::dvec3(toWorld * glm::dvec4(0, 0, -1, 1));
      if (!(glm::length(dir) > 0.0)) fail(camera, "the camera node's transform takes (0, 0, -1) to the origin: no direction");
      dir = glm::normalize(dir);
    }
    const int w = 800, h = 600;
    const double ar1 = std::tan(glm::radians(hFov) / 2) / std::tan(glm::radians(vFov) / 2), ar = double(w) / h;
    if (ar1 > ar) vFov = 2.0 * glm::degrees(std::atan(std::tan(glm::radians(hFov) / 2) / ar));
    Camera cam;
    cam.width = w;
    cam.height = h;
    cam.vfovDegrees = float(vFov);
    cam.resizeKeepsFocalLength = true;
    if (!bounds.empty()) {
      const glm::dvec3 target = 0.5 * (bounds.lo + bounds.hi);
      const double r = 1.5 * glm::length(bounds.hi - bounds.lo);
      double phi = std::acos(std::clamp(dir.y, -1.0, 1.0));
      const double theta = std::atan2(dir.x, dir.z);
      if (std::sin(phi) == 0.0) phi += 1e-5;  // EPS_F, as camera.cpp nudges the poles
      const glm::dvec3 toCamera(r * std::sin(phi) * std::sin(theta), r * std::cos(phi), r * std::sin(phi) * std::cos(theta));
      const glm::dvec3 up(0.0, std::sin(phi) > 0.0 ? 1.0 : -1.0, 0.0);
      const glm::dvec3 x = glm::normalize(glm::cross(up, toCamera));
      const glm::dvec3 y = glm::normalize(glm::cross(toCamera, x));
      cam.toWorld = glm::mat4(glm::dmat4(glm::dvec4(x, 0), glm::dvec4(y, 0), glm::dvec4(glm::normalize(toCamera), 0),
                                         glm::dvec4(target + toCamera, 1)));
    }
    scene_.camera = cam;
  }

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

}  // namespace

Scene import_collada(const std::string& path) {
  return ColladaReader(path).read();
}

std::vector<double> read_cs184_camera_settings(const std::string& path) {
  auto bytes = read_file_bytes(path);
  if (!bytes) throw InputError(path + ": cannot read the camera settings file");
  std::vector<double> v;
  const char* s = reinterpret_cast<const char*>(bytes->data());
  const std::string problem = read_numbers(s, s + bytes->size(), 30, v);
  if (!problem.empty()) throw InputError(path + ": " + problem + " (a CS184 camera settings file holds 30)");
  if (v.size() != 30) throw InputError(path + ": " + std::to_string(v.size()) + " numbers, where a CS184 camera settings file holds 30");
  return v;
}

void apply_cs184_camera_settings(const std::vector<double>& v, Camera& camera, const std::string& where) {
  // hFov vFov ar nClip fClip / pos target / phi theta r minR maxR / c2w (9,
  // row by row) / screenW screenH screenDist / focalDistance lensRadius.
  const double hFov = v[0], vFov = v[1];
  if (!(hFov > 0.0 && hFov < 180.0 && vFov > 0.0 && vFov < 180.0))
    throw InputError(where + ": the fields of view (" + std::to_string(hFov) + ", " + std::to_string(vFov) + ") must lie between 0 and 180 degrees");
  glm::dmat3 c2w;
  for (int i = 0; i < 9; ++i) c2w[i % 3][i / 3] = v[size_t(16 + i)];  // row i / 3, column i % 3
  if (std::abs(glm::determinant(c2w)) < 1e-6) throw InputError(where + ": the camera's orientation matrix is singular");
  camera.toWorld = glm::mat4(glm::dmat4(glm::dvec4(c2w[0], 0), glm::dvec4(c2w[1], 0), glm::dvec4(c2w[2], 0), glm::dvec4(v[5], v[6], v[7], 1)));
  camera.vfovDegrees = float(vFov);
  camera.aspect = float(std::tan(glm::radians(hFov) / 2) / std::tan(glm::radians(vFov) / 2));
}

void apply_cs184_camera_settings(const std::string& path, Camera& camera) {
  apply_cs184_camera_settings(read_cs184_camera_settings(path), camera, path);
}

}  // namespace wp
