// import_collada.cpp — Berkeley CS184's COLLADA scenes (.dae), read as the
// course's pathtracer reads them (its src/scene/collada/collada.cpp and
// src/application/application.cpp; docs/scene-format.md, "CS184", cites
// each rule): the up axis, the node tree, polygon meshes with the course's
// recomputed vertex normals, its CGL spheres, lights and materials, and its
// camera rule. Anything else in the node tree is refused by name.
//
// This file reads the document, its node tree and the scene they make; the
// reader's class is in collada_reader.h, and its other parts are
// collada_materials.cpp, collada_geometry.cpp, collada_lights.cpp and
// collada_camera.cpp (with CS184's camera settings files).
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "scene/collada_reader.h"
#include "scene/importers.h"

namespace wp {

namespace collada_import {

Scene ColladaReader::read() {
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

// ---- places and errors ----------------------------------------------------

std::string ColladaReader::position(size_t offset) const {
  offset = std::min(offset, text_.size());
  size_t line = 1 + size_t(std::count(text_.begin(), text_.begin() + std::ptrdiff_t(offset), '\n'));
  size_t lineStart = text_.rfind('\n', offset == 0 ? std::string::npos : offset - 1);
  size_t column = offset - (lineStart == std::string::npos ? 0 : lineStart + 1) + 1;
  return std::to_string(line) + ":" + std::to_string(column);
}

// The place of an element: where its start tag opens.
std::string ColladaReader::where(pugi::xml_node n) const {
  ptrdiff_t offset = n.offset_debug();
  return position(offset > 0 ? size_t(offset - 1) : 0);
}

void ColladaReader::fail(pugi::xml_node at, const std::string& what) const {
  throw InputError(path_ + ":" + where(at) + ": " + what);
}

void ColladaReader::unsupported(pugi::xml_node n) const {
  fail(n, "<" + std::string(n.name()) + "> is not supported here (docs/scene-format.md lists what wavepath reads of COLLADA)");
}

// Elements that carry nothing to render: metadata, and other applications' extras.
bool ColladaReader::ignorable(pugi::xml_node n) {
  const std::string name = n.name();
  return n.type() != pugi::node_element || name == "asset" || name == "extra";
}

pugi::xml_node ColladaReader::required(pugi::xml_node parent, const char* name) const {
  pugi::xml_node c = parent.child(name);
  if (!c) fail(parent, "<" + std::string(parent.name()) + "> has no <" + name + ">");
  return c;
}

// ---- references ------------------------------------------------------------

void ColladaReader::index_ids(pugi::xml_node root) {
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
pugi::xml_node ColladaReader::resolve(pugi::xml_node from, const char* attr, const char* kind) const {
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

double ColladaReader::number(pugi::xml_node e, const char* what) const { return numbers<double>(e, 1, what)[0]; }

glm::dvec3 ColladaReader::color(pugi::xml_node e, const char* what) const {
  // A colour is three numbers; a fourth (alpha) is allowed and not read, as in the course.
  std::vector<double> v = numbers<double>(e, 0, what);
  if (v.size() != 3 && v.size() != 4) fail(e, std::string(what) + ": expected 3 numbers (RGB), got " + std::to_string(v.size()));
  return {v[0], v[1], v[2]};
}

size_t ColladaReader::count_attribute(pugi::xml_node e, const char* name) const {
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
void ColladaReader::read_up_axis(pugi::xml_node root) {
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
glm::dmat4 ColladaReader::node_transform(pugi::xml_node node) const {
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
void ColladaReader::read_node(pugi::xml_node node, const glm::dmat4& parent, std::vector<Placed>& placed, int depth) {
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

// ---- the scene ---------------------------------------------------------------------

void ColladaReader::build(const std::vector<Placed>& placed) {
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

}  // namespace collada_import

using collada_import::ColladaReader;

Scene import_collada(const std::string& path) {
  return ColladaReader(path).read();
}

}  // namespace wp
