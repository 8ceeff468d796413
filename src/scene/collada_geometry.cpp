// collada_geometry.cpp — the COLLADA reader's geometry: polygon meshes
// with the course's vertex normals, their sources and primitives, and the
// triangles that lie in an area light's plane (collada_reader.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>

#include "scene/collada_reader.h"
#include "scene/cs184_normals.h"

namespace wp::collada_import {

// ---- geometry ------------------------------------------------------------------

ColladaReader::Source ColladaReader::source(pugi::xml_node src, size_t defaultStride) const {
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
void ColladaReader::read_mesh(pugi::xml_node instance, pugi::xml_node mesh, const glm::dmat4& toWorld) {
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
void ColladaReader::find_light_plane_contacts(size_t first, const std::vector<glm::vec3>& world, const Source& positions, const glm::dmat4& toWorld) {
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

void ColladaReader::read_primitive(pugi::xml_node instance, pugi::xml_node prim, pugi::xml_node vertices, size_t numPositions, Polygons& out) {
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

}  // namespace wp::collada_import
