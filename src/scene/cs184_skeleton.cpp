// cs184_skeleton.cpp — the two other readings of a CS184 scene's lights
// (importers.h): as the 3-2 skeleton builds the scene (--cs184 3-2), and
// physically (--consistent-lights). docs/scene-format.md, "Two skeletons",
// cites the course's lines.
#include <algorithm>
#include <cmath>
#include <map>

#include "scene/importers.h"
#include "scene/materials/material_module.h"
#include "util/error.h"

namespace wp {

namespace {

// The corner at `t` of the way from corner a to corner b of triangle `s`,
// with its shading (normals, UVs and the rest) interpolated alike.
struct Corner {
  glm::vec3 p;
  SceneTriangleShading s;  // only its corner 0 is meant
};

Corner corner(const SceneTriangle& tri, const SceneTriangleShading* sh, int a, int b, double t) {
  Corner c;
  const float f = float(t);
  c.p = glm::vec3(glm::dvec3(tri.v[a]) + (glm::dvec3(tri.v[b]) - glm::dvec3(tri.v[a])) * t);
  if (sh) {
    c.s = *sh;
    const glm::vec3 n = glm::mix(sh->n[a], sh->n[b], f);
    c.s.n[0] = glm::length(n) > 0.0f ? glm::normalize(n) : n;
    c.s.uv[0] = glm::mix(sh->uv[a], sh->uv[b], f);
    c.s.tangent[0] = glm::mix(sh->tangent[a], sh->tangent[b], f);
    c.s.color[0] = glm::mix(sh->color[a], sh->color[b], f);
    c.s.uv1[0] = glm::mix(sh->uv1[a], sh->uv1[b], f);
  }
  return c;
}

// Triangle `like` with the corners `c` (in its winding), or nothing where
// they enclose no area.
void add_piece(Scene& scene, const SceneTriangle& like, const Corner (&c)[3], std::vector<SceneTriangle>& out) {
  SceneTriangle t = like;
  for (int i = 0; i < 3; ++i) t.v[i] = c[i].p;
  if (glm::length(glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0])) == 0.0f) return;
  if (like.shading != WP_INVALID) {
    SceneTriangleShading s = c[0].s;
    for (int i = 1; i < 3; ++i) {
      s.n[i] = c[i].s.n[0], s.uv[i] = c[i].s.uv[0], s.tangent[i] = c[i].s.tangent[0];
      s.color[i] = c[i].s.color[0], s.uv1[i] = c[i].s.uv1[0];
    }
    scene.triangleShading.push_back(s);
    t.shading = uint32_t(scene.triangleShading.size() - 1);
  }
  out.push_back(t);
}

// Splits triangle `tri` along the line where the course's heights change
// sign: the pieces in front of the light (height > 0) into `front`, the
// rest into `behind`.
void split_at_light_plane(Scene& scene, const SceneTriangle& tri, const double (&h)[3], std::vector<SceneTriangle>& front,
                          std::vector<SceneTriangle>& behind) {
  const bool up[3] = {h[0] > 0.0, h[1] > 0.0, h[2] > 0.0};
  if (up[0] == up[1] && up[1] == up[2]) {
    (up[0] ? front : behind).push_back(tri);
    return;
  }
  // The corner alone on its side, k, and the other two in the winding's order.
  const int k = up[0] != up[1] && up[0] != up[2] ? 0 : up[1] != up[0] && up[1] != up[2] ? 1 : 2;
  const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
  const SceneTriangleShading* sh = tri.shading != WP_INVALID ? &scene.triangleShading[tri.shading] : nullptr;
  const SceneTriangleShading copy = sh ? *sh : SceneTriangleShading{};  // pushes below may move the original
  sh = sh ? &copy : nullptr;
  const Corner ck = corner(tri, sh, k, k, 0.0), c1 = corner(tri, sh, k1, k1, 0.0), c2 = corner(tri, sh, k2, k2, 0.0);
  const Corner p1 = corner(tri, sh, k, k1, h[k] / (h[k] - h[k1])), p2 = corner(tri, sh, k, k2, h[k] / (h[k] - h[k2]));
  std::vector<SceneTriangle>& alone = up[k] ? front : behind;
  std::vector<SceneTriangle>& pair = up[k] ? behind : front;
  add_piece(scene, tri, {ck, p1, p2}, alone);
  add_piece(scene, tri, {p1, c1, c2}, pair);
  add_piece(scene, tri, {p1, c2, p2}, pair);
}

}  // namespace

void use_cs184_3_2_skeleton(Scene& scene) {
  // The area lights' materials, each one's area (its two triangles), the
  // direction it faces and its scale (its largest coordinate, at least 1).
  struct Light {
    double area = 0.0;
    glm::vec3 facing{0.0f};
    float scale = 1.0f;
  };
  std::map<uint32_t, Light> lights;
  for (const SceneTriangle& t : scene.lightOnlyTriangles) {
    Light& l = lights[t.material];
    const glm::dvec3 n = glm::cross(glm::dvec3(t.v[1] - t.v[0]), glm::dvec3(t.v[2] - t.v[0]));
    l.area += 0.5 * glm::length(n);
    l.facing = glm::vec3(glm::normalize(n));
    for (const glm::vec3& v : t.v) l.scale = std::max(l.scale, std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z))));
  }
  // collada.cpp:879 gives every emissive mesh EmissionBSDF(radiance,
  // Vector3D(0)): its emission is the radiance times the cosine with a zero
  // direction. The mesh stays, black, absorbing what reaches it.
  for (uint32_t i = 0; i < scene.materials.size(); ++i)
    if (!lights.count(i)) scene.materials[i].emission = WP_INVALID;
  // gl_scene/scene.cpp:166 puts every light among the objects too, and
  // light.cpp:77-105 makes an area light two triangles facing its direction
  // with EmissionBSDF(radiance / area, direction).
  std::map<uint32_t, uint32_t> quadMaterial;
  for (const auto& [material, light] : lights) {
    const std::string name = scene.materials[material].name;
    const glm::vec3 radiance = scene.textures[scene.materials[material].emission].color;
    MaterialParams quad(MAT_LIGHT, name, [name](const std::string& problem) { throw InputError("the light quad of " + name + ": " + problem); });
    quad.texture("emit", add_texture(scene, constant_texture(radiance / float(light.area))));
    quad.flag("cosine", true);  // emission times the cosine (FEATURE_COSINE_EMISSION)
    quadMaterial[material] = add_material(scene, quad);
  }
  // The quad lies in its light's plane, and so, in floats, does a lamp mesh
  // placed within 5e-8 of it, as in the course's Cornell files: which of the
  // two a ray met would be rounding's choice, one on the CPU and another on
  // the GPU. The course decides in double, where the mesh lies a little in
  // front of the light or a little behind it (Cs184LightPlaneContact), and
  // its camera meets the nearer surface. So the quad goes back by
  // kCs184QuadSetBack of its scale, away from where it faces: behind the
  // end of every shadow ray aimed at its own light (which stops a few
  // hundred ulps short of the light's plane; in front, the quad would
  // shadow its own light), and behind the parts of the lamp that are in
  // front in the course; the parts the course has behind the light go
  // twice as far back, behind the quad.
  for (SceneTriangle t : scene.lightOnlyTriangles) {
    const Light& l = lights[t.material];
    t.material = quadMaterial[t.material];
    for (glm::vec3& v : t.v) v -= l.facing * float(kCs184QuadSetBack * l.scale);
    scene.triangles.push_back(t);
  }
  std::vector<SceneTriangle> added;
  for (const Cs184LightPlaneContact& c : scene.cs184LightPlaneContacts) {
    const Light& l = lights[scene.lightOnlyTriangles.at(c.light).material];
    std::vector<SceneTriangle> front, behind;
    split_at_light_plane(scene, scene.triangles.at(c.triangle), c.height, front, behind);
    for (SceneTriangle& t : behind)
      for (glm::vec3& v : t.v) v -= l.facing * float(2.0 * kCs184QuadSetBack * l.scale);
    front.insert(front.end(), behind.begin(), behind.end());
    if (front.empty()) continue;  // (a sliver: no piece encloses any area)
    scene.triangles[c.triangle] = front[0];
    added.insert(added.end(), front.begin() + 1, front.end());
  }
  scene.triangles.insert(scene.triangles.end(), added.begin(), added.end());
  scene.cs184Skeleton = 32;
}

void use_consistent_lights(Scene& scene) {
  scene.triangles.insert(scene.triangles.end(), scene.lightOnlyTriangles.begin(), scene.lightOnlyTriangles.end());
  scene.lightOnlyTriangles.clear();
  scene.cs184LightPlaneContacts.clear();  // (they name light-only triangles)
  scene.cs184Estimator = false;
  scene.integrator.kind = IntegratorKind::PathMis;
}

}  // namespace wp
