// darts_surfaces.cpp — the darts importer's surfaces: spheres, quads,
// triangles, OBJ meshes with their MTL materials, groups, and the point,
// spot and directional lights among them (darts_importer.h).
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scene/darts_importer.h"

namespace wp::darts_import {

namespace {

bool is_nonzero(glm::vec3 c) {
  return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f;
}

}  // namespace

void DartsImporter::parse_surface(const JsonCursor& j, const glm::mat4& parent) {
  j.expect_object();
  std::string type = j["type"].string();
  glm::mat4 xform = parent * (j.has("transform") ? parse_transform(j["transform"]) : glm::mat4(1.0f));
  if (type == "sphere") {
    j.allow_only({"type", "name", "radius", "transform", "material", "interior", "exterior"});
    float radius = j.has("radius") ? j["radius"].positive_number() : 1.0f;
    SceneSphere s;
    s.toWorld = xform * glm::scale(glm::mat4(1.0f), glm::vec3(radius));
    // Its bounds (centre +- the rows' lengths) must be finite too.
    const glm::mat3 rows = glm::transpose(glm::mat3(s.toWorld));
    const glm::vec3 centre(s.toWorld[3]), extent(glm::length(rows[0]), glm::length(rows[1]), glm::length(rows[2]));
    if (!is_finite(centre + extent) || !is_finite(centre - extent)) j.fail(std::string("sphere: ") + kPastFloatRange);
    s.material = material_of(j);
    if (scene_.materials[s.material].emission != WP_INVALID && !is_similarity(glm::mat3(s.toWorld)))
      j.fail("emissive spheres must keep their shape (uniform scale): an emissive ellipsoid cannot be sampled yet");
    scene_.spheres.push_back(s);
  } else if (type == "quad") {
    j.allow_only({"type", "name", "size", "transform", "material", "interior", "exterior"});
    glm::vec2 size(1.0f);
    if (j.has("size")) {
      JsonCursor sz = j["size"];
      if (sz.is_number()) size = glm::vec2(sz.number());
      else if (sz.is_array() && sz.size() == 2) size = glm::vec2(sz[size_t(0)].number(), sz[size_t(1)].number());
      else sz.fail("expected a number or [width, height]");
      if (!(size.x > 0.0f && size.y > 0.0f)) sz.fail("quad size must be positive (a zero-area quad cannot be rendered)");
    }
    uint32_t mat = material_of(j);
    glm::vec3 c[4] = {{-0.5f * size.x, -0.5f * size.y, 0}, {0.5f * size.x, -0.5f * size.y, 0},
                      {0.5f * size.x, 0.5f * size.y, 0}, {-0.5f * size.x, 0.5f * size.y, 0}};
    for (glm::vec3& p : c) p = glm::vec3(xform * glm::vec4(p, 1.0f));
    // The quad's front is its transformed +Z normal, as in darts; a mirroring
    // transform reverses the winding, so restore it.
    bool mirrored = glm::determinant(glm::mat3(xform)) < 0.0f;
    static const int kWinding[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 2, 1}, {0, 3, 2}}};
    static const glm::vec2 kCornerUv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // planar UVs over the quad
    for (const auto& t : kWinding[mirrored ? 1 : 0]) {
      SceneTriangleShading& sh = add_shading(add_triangle(j, c[t[0]], c[t[1]], c[t[2]], mat));
      sh.hasUvs = true;
      for (int k = 0; k < 3; ++k) sh.uv[k] = kCornerUv[t[k]];
    }
  } else if (type == "triangle") {
    j.allow_only({"type", "name", "positions", "normals", "uvs", "transform", "material", "interior", "exterior"});
    JsonCursor pos = j["positions"].expect_array();
    if (pos.size() != 3) pos.fail("expected 3 vertex positions, got " + std::to_string(pos.size()));
    glm::vec3 v[3];
    for (size_t i = 0; i < 3; ++i) v[i] = glm::vec3(xform * glm::vec4(pos[i].vec3(), 1.0f));
    SceneTriangle& tri = add_triangle(pos, v[0], v[1], v[2], material_of(j));
    if (j.has("normals")) {
      JsonCursor nrm = j["normals"].expect_array();
      if (nrm.size() != 3) nrm.fail("expected 3 vertex normals, got " + std::to_string(nrm.size()));
      glm::mat3 normalXform = normal_matrix(xform);
      SceneTriangleShading& sh = add_shading(tri);
      for (size_t i = 0; i < 3; ++i) {
        glm::vec3 n = normalXform * nrm[i].vec3();
        if (!(glm::length(n) > 0.0f)) nrm[i].fail("a vertex normal must not be zero");
        sh.n[i] = glm::normalize(n);
      }
      sh.hasNormals = true;
    }
    if (j.has("uvs")) {
      JsonCursor uvs = j["uvs"].expect_array();
      if (uvs.size() != 3) uvs.fail("expected 3 vertex UVs, got " + std::to_string(uvs.size()));
      SceneTriangleShading& sh = tri.shading == WP_INVALID ? add_shading(tri) : scene_.triangleShading[tri.shading];
      for (size_t i = 0; i < 3; ++i) {
        JsonCursor uv = uvs[i].expect_array();
        if (uv.size() != 2) uv.fail("expected [u, v]");
        sh.uv[i] = glm::vec2(uv[size_t(0)].number(), uv[size_t(1)].number());
      }
      sh.hasUvs = true;
    }
  } else if (type == "mesh") {
    j.allow_only({"type", "name", "filename", "transform", "material", "material prefix", "interior", "exterior"});
    load_mesh(j, xform);
  } else if (type == "point_light") {
    // wavepath extension (CS184's point lights): radiant intensity in W/sr.
    j.allow_only({"type", "name", "position", "intensity", "transform"});
    ScenePointLight l;
    l.position = glm::vec3(xform * glm::vec4(j.vec3_or("position", glm::vec3(0.0f)), 1.0f));
    if (!is_finite(l.position)) j.fail(std::string("point light: ") + kPastFloatRange);
    l.intensity = non_negative(j["intensity"]);
    scene_.pointLights.push_back(l);
  } else if (type == "spot_light" || type == "directional_light") {
    // wavepath extensions (glTF's KHR_lights_punctual): a spot's intensity
    // in W/sr within its cone, a directional light's irradiance in W/m^2.
    const bool spot = type == "spot_light";
    if (spot) j.allow_only({"type", "name", "position", "direction", "intensity", "inner_angle", "outer_angle", "transform"});
    else j.allow_only({"type", "name", "direction", "irradiance", "transform"});
    ScenePointLight l;
    l.kind = spot ? ScenePointLight::Kind::Spot : ScenePointLight::Kind::Directional;
    l.position = glm::vec3(xform * glm::vec4(j.vec3_or("position", glm::vec3(0.0f)), 1.0f));
    const glm::vec3 d = glm::vec3(xform * glm::vec4(j["direction"].vec3(), 0.0f));
    if (!(glm::length(d) > 0.0f) || !is_finite(d)) j["direction"].fail("the direction must be a nonzero vector");
    l.direction = glm::normalize(d);
    if (!is_finite(l.position)) j.fail(std::string("light: ") + kPastFloatRange);
    l.intensity = non_negative(j[spot ? "intensity" : "irradiance"]);
    if (spot) {
      const float inner = j.number_or("inner_angle", 0.0f), outer = j.number_or("outer_angle", 45.0f);
      if (!(inner >= 0.0f && inner < outer && outer <= 90.0f))
        j.fail("a spot light needs 0 <= inner_angle < outer_angle <= 90 (degrees)");
      l.cosInner = std::cos(glm::radians(inner));
      l.cosOuter = std::cos(glm::radians(outer));
    }
    scene_.pointLights.push_back(l);
  } else if (type == "group") {
    j.allow_only({"type", "name", "children", "transform"});
    JsonCursor children = j["children"].expect_array();
    for (size_t i = 0; i < children.size(); ++i) parse_surface(children[i], xform);
  } else {
    const std::vector<std::string> kinds = {"sphere", "quad", "triangle", "mesh", "group", "point_light", "spot_light", "directional_light"};
    std::string hint = did_you_mean(type, kinds);
    j["type"].fail("unknown surface type \"" + type + "\"" +
                   (hint.empty() ? " (expected sphere, quad, triangle, mesh, group, point_light, spot_light or directional_light)" : hint));
  }
}

bool DartsImporter::is_similarity(const glm::mat3& m) {
  float a = glm::length(m[0]), b = glm::length(m[1]), c = glm::length(m[2]);
  auto close = [](float x, float y) { return std::fabs(x - y) <= 1e-4f * std::max(x, y); };
  return close(a, b) && close(b, c) && std::fabs(glm::dot(m[0], m[1])) <= 1e-4f * a * b &&
         std::fabs(glm::dot(m[1], m[2])) <= 1e-4f * b * c && std::fabs(glm::dot(m[0], m[2])) <= 1e-4f * a * c;
}

SceneTriangle& DartsImporter::add_triangle(const JsonCursor& where, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
  if (!is_finite(a) || !is_finite(b) || !is_finite(c)) where.fail(std::string("triangle: ") + kPastFloatRange);
  if (glm::length(glm::cross(b - a, c - a)) == 0.0f) where.fail("triangle has zero area");
  SceneTriangle t;
  t.v[0] = a;
  t.v[1] = b;
  t.v[2] = c;
  t.material = material;
  scene_.triangles.push_back(t);
  return scene_.triangles.back();
}

// Per-vertex data for triangle t, which has none yet.
SceneTriangleShading& DartsImporter::add_shading(SceneTriangle& t) {
  t.shading = uint32_t(scene_.triangleShading.size());
  return scene_.triangleShading.emplace_back();
}

// The OBJ file of mesh surface j. A mesh placed many times (a grid of
// dragons) is parsed once.
const ObjFile& DartsImporter::mesh_of(const JsonCursor& j) {
  std::string path = resolve(j["filename"].string());
  auto cached = meshes_.find(path);
  if (cached == meshes_.end()) {
    try {
      cached = meshes_.emplace(path, load_obj(path)).first;
      for (const std::string& f : cached->second.files) scene_.inputFiles.push_back(f);
      // A file of no OBJ statements (not an OBJ at all: a typo in the name,
      // a path past the scene's folder) parses as an empty mesh; say so
      // rather than render an image without it.
      if (cached->second.mesh.triangle_count() == 0) {
        std::fprintf(stderr, "wavepath: warning: %s: no triangles (is it an OBJ file?), loaded by %s at %s\n", path.c_str(),
                     file_.c_str(), j["filename"].path().c_str());
      }
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) + " (loaded by " + file_ + " at " + j.path() + ")");
    }
  }
  return cached->second;
}

// The triangles the meshes among `surfaces` (groups included) will add, so
// that the triangle array is allocated once: 100 dragons are 10M triangles
// of 104 bytes, and growing the array by doubling copied it and faulted its
// pages in several times over. Surfaces that are not well formed are
// skipped here; parse_surface reports them.
size_t DartsImporter::mesh_triangles(const JsonCursor& surfaces) {
  size_t n = 0;
  for (size_t i = 0; i < surfaces.size(); ++i) {
    JsonCursor s = surfaces[i];
    if (!s.is_object() || !s.has("type") || !s["type"].is_string()) continue;
    std::string type = s["type"].string();
    if (type == "mesh" && s.has("filename") && s["filename"].is_string()) {
      n += mesh_of(s).mesh.triangle_count();
    } else if (type == "group" && s.has("children") && s["children"].is_array()) {
      n += mesh_triangles(s["children"]);
    }
  }
  return n;
}

void DartsImporter::load_mesh(const JsonCursor& j, const glm::mat4& xform) {
  std::string rel = j["filename"].string();
  const ObjFile& obj = mesh_of(j);
  const SceneMesh& mesh = obj.mesh;
  bool override = j.has("material");
  uint32_t fixed = override ? material_of(j) : 0;
  std::string prefix = j.has("material prefix") ? j["material prefix"].string() : "";
  std::vector<uint32_t> mtlToScene(obj.materials.size(), fixed);
  for (size_t i = 0; i < obj.materials.size() && !override; ++i) {
    const ObjMaterial& om = obj.materials[i];
    auto named = named_.find(prefix + om.name);
    if (named != named_.end()) {  // a scene material of that name overrides the MTL
      mtlToScene[i] = named->second;
      continue;
    }
    // Kd (or map_Kd) and Ke as a Lambertian that may emit; Ke without Kd a light.
    const bool light = is_nonzero(om.emission) && !is_nonzero(om.diffuse);
    MaterialParams m(light ? MAT_LIGHT : MAT_LAMBERTIAN, prefix + om.name, complaint_at(j));
    if (is_nonzero(om.emission)) m.texture("emit", add_texture(constant_texture(glm::max(om.emission, 0.0f))));
    if (light) {
    } else if (!om.diffuseMap.empty()) {
      m.texture("albedo", add_image_texture(scene_, om.diffuseMap, "map_Kd of " + om.name + ", loaded by " + file_ + " at " + j.path()));
    } else {
      m.texture("albedo", add_texture(constant_texture(glm::clamp(om.diffuse, 0.0f, 1.0f))));
    }
    mtlToScene[i] = wp::add_material(scene_, m);
  }
  if (!override)
    for (uint32_t& m : mtlToScene) m = with_media(j, m);
  if (!override && std::find(mesh.materials.begin(), mesh.materials.end(), WP_INVALID) != mesh.materials.end())
    j.fail("mesh " + rel + " has faces without a material: give the surface a \"material\"");
  add_mesh(scene_, mesh, xform, mtlToScene, override ? fixed : WP_INVALID,
           [&](const std::string& problem) { j.fail("mesh " + rel + ", " + problem); });
}

}  // namespace wp::darts_import
