// collada_lights.cpp — the COLLADA reader's lights: CS184's point,
// directional, ambient and area lights, and its spot lights that give no
// light (collada_reader.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scene/collada_reader.h"

namespace wp::collada_import {

// ---- lights ---------------------------------------------------------------------

glm::vec3 ColladaReader::point(const glm::dmat4& m, glm::dvec3 p) const { return glm::vec3(glm::dvec3(m * glm::dvec4(p, 1.0))); }

// A light as light_info.cpp and the gl_scene lights place it: the CGL
// technique wins over technique_common; its first element is the kind.
void ColladaReader::read_light(pugi::xml_node light, const glm::dmat4& m) {
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

}  // namespace wp::collada_import
