#include "scene/scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "scene/texture_image.h"
#include "scene/transform.h"
#include "util/error.h"

namespace wp {

const char* const kIntegratorNames =
    "normals, ao, path tracer mats, path tracer nee, path tracer mis, path tracer mixture, path tracer hemisphere or photon mapper";

std::optional<IntegratorKind> integrator_named(const std::string& name) {
  static const std::pair<const char*, IntegratorKind> kKinds[] = {
      {"path tracer mis", IntegratorKind::PathMis},   {"path tracer nee", IntegratorKind::PathNee},
      {"path tracer mats", IntegratorKind::PathMats}, {"path tracer mixture", IntegratorKind::PathMixture},
      {"path tracer hemisphere", IntegratorKind::PathHemisphere},
      {"normals", IntegratorKind::Normals},           {"ao", IntegratorKind::AmbientOcclusion},
      {"photon mapper", IntegratorKind::PhotonMapper}};
  for (const auto& [n, kind] : kKinds) {
    if (name == n) return kind;
  }
  return std::nullopt;
}

std::optional<SamplerKind> sampler_named(const std::string& name) {
  if (name == "independent") return SamplerKind::Independent;
  if (name == "cmj") return SamplerKind::Cmj;
  return std::nullopt;
}

SceneTexture constant_texture(glm::vec3 color) {
  SceneTexture t;
  t.kind = TEX_CONSTANT;
  t.color = color;
  return t;
}

uint32_t add_texture(Scene& scene, const SceneTexture& texture) {
  scene.textures.push_back(texture);
  return uint32_t(scene.textures.size() - 1);
}

uint32_t add_lambertian(Scene& scene, glm::vec3 albedo, const std::string& name) {
  SceneMaterial m;
  m.kind = MAT_LAMBERTIAN;
  m.name = name;
  m.albedo = add_texture(scene, constant_texture(albedo));
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

SceneTexture image_texture(Scene& scene, const std::string& path, const std::string& where) {
  LinearImage img;
  try {
    img = load_linear_image(path);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + (where.empty() ? "" : " (" + where + ")"));
  }
  SceneTexture t;
  t.kind = TEX_IMAGE;
  t.color = glm::vec3(1.0f);  // the image's factor
  t.image = uint32_t(scene.images.size());
  scene.images.push_back(std::move(img));
  scene.inputFiles.push_back(path);
  return t;
}

uint32_t add_image_texture(Scene& scene, const std::string& path, const std::string& where) {
  return add_texture(scene, image_texture(scene, path, where));
}

void set_resolution(Camera& camera, int width, int height) {
  if (camera.resizeKeepsFocalLength && camera.height > 0) {
    // tan(vfov / 2) is half the height over the focal length in pixels.
    double t = std::tan(glm::radians(double(camera.vfovDegrees)) * 0.5) * double(height) / double(camera.height);
    camera.vfovDegrees = float(glm::degrees(2.0 * std::atan(t)));
  }
  camera.width = width;
  camera.height = height;
}

void set_cell(Camera& c, int x, int y, int dx, int dy) {
  if (x < 0 || y < 0 || dx < 1 || dy < 1 || x + dx > c.width || y + dy > c.height)
    throw InputError("-p " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(dx) + " " + std::to_string(dy) +
                     ": the cell must lie inside the " + std::to_string(c.width) + "x" + std::to_string(c.height) + " frame");
  if (c.aspect <= 0.0f) c.aspect = float(c.width) / float(c.height);
  c.window = glm::vec4(float(x) / float(c.width), float(c.height - y - dy) / float(c.height), float(dx) / float(c.width),
                       float(dy) / float(c.height));
  c.width = dx;
  c.height = dy;
}

std::pair<glm::vec3, glm::vec3> scene_bounds(const Scene& scene) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& v : t.v) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  for (const SceneSphere& s : scene.spheres) {
    const glm::vec3 c(s.toWorld[3]);
    const float r = std::max({glm::length(glm::vec3(s.toWorld[0])), glm::length(glm::vec3(s.toWorld[1])), glm::length(glm::vec3(s.toWorld[2]))});
    lo = glm::min(lo, c - glm::vec3(r));
    hi = glm::max(hi, c + glm::vec3(r));
  }
  return {lo, hi};
}

Camera framing_camera(const Scene& scene) {
  const auto [lo, hi] = scene_bounds(scene);
  Camera c;
  c.width = 800;
  c.height = 600;
  c.vfovDegrees = 40.0f;
  if (!(lo.x <= hi.x)) return c;  // nothing to frame
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 1e-6f);
  const float halfFov = 0.5f * glm::radians(c.vfovDegrees);  // the vertical side is the narrower one
  const float distance = radius / std::sin(halfFov);
  const glm::vec3 back = glm::normalize(glm::vec3(0.0f, 0.35f, 1.0f));
  const glm::vec3 eye = centre + back * distance;
  c.toWorld = glm::inverse(glm::lookAt(eye, centre, glm::vec3(0.0f, 1.0f, 0.0f)));
  c.focusDistance = distance;
  return c;
}

void choose_camera(Scene& scene, const std::string& which) {
  const NamedCamera* found = nullptr;
  for (const NamedCamera& c : scene.cameras)
    if (c.name == which || std::to_string(c.index) == which) found = found ? found : &c;
  if (!found) {
    std::string names;
    for (const NamedCamera& c : scene.cameras) names += (names.empty() ? "" : ", ") + std::to_string(c.index) + " \"" + c.name + "\"";
    throw InputError("--camera " + which + ": " + scene.sourcePath + " has no such camera" +
                     (names.empty() ? " (it has none)" : " (it has " + names + ")"));
  }
  if (!found->problem.empty()) throw InputError(scene.sourcePath + ": " + found->problem);
  scene.camera = found->camera;
}

std::vector<glm::vec4> smooth_tangents(const SceneMesh& mesh, const std::vector<glm::vec2>& uvs) {
  const size_t n = mesh.positions.size();
  if (mesh.normals.size() != n || uvs.size() != n) return {};
  std::vector<glm::vec3> dpdu(n, glm::vec3(0.0f)), dpdv(n, glm::vec3(0.0f));
  for (size_t t = 0; t + 2 < mesh.positionIndices.size(); t += 3) {
    const uint32_t i[3] = {mesh.positionIndices[t], mesh.positionIndices[t + 1], mesh.positionIndices[t + 2]};
    const glm::vec3 e1 = mesh.positions[i[1]] - mesh.positions[i[0]], e2 = mesh.positions[i[2]] - mesh.positions[i[0]];
    const glm::vec2 d1 = uvs[i[1]] - uvs[i[0]], d2 = uvs[i[2]] - uvs[i[0]];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (det == 0.0f || !std::isfinite(det)) continue;
    // Weighted by the triangle's area over its UV area: larger triangles count more.
    const glm::vec3 u = (e1 * d2.y - e2 * d1.y) / det, v = (e2 * d1.x - e1 * d2.x) / det;
    if (!is_finite(u) || !is_finite(v)) continue;
    for (uint32_t k : i) {
      dpdu[k] += u;
      dpdv[k] += v;
    }
  }
  std::vector<glm::vec4> out(n, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  for (size_t k = 0; k < n; ++k) {
    const glm::vec3 normal = mesh.normals[k];
    const glm::vec3 t = dpdu[k] - normal * glm::dot(normal, dpdu[k]);
    const float len = glm::length(t);
    if (!(len > 0.0f) || !std::isfinite(len)) continue;
    out[k] = glm::vec4(t / len, glm::dot(glm::cross(normal, t), dpdv[k]) < 0.0f ? -1.0f : 1.0f);
  }
  return out;
}

void add_mesh(Scene& scene, const SceneMesh& mesh, const glm::mat4& toWorld, const std::vector<uint32_t>& slots,
              uint32_t unassigned, const std::function<void(const std::string&)>& fail) {
  const glm::mat3 normalXform = normal_matrix(toWorld);
  const glm::mat3 vectorXform(toWorld);
  // A mirroring transform turns the bitangent's handedness.
  const float handedness = glm::determinant(vectorXform) < 0.0f ? -1.0f : 1.0f;
  const bool vertexData = !mesh.tangents.empty() || !mesh.colors.empty() || !mesh.uvs1.empty();
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t slot = mesh.materials[t];
    const uint32_t material = slot == WP_INVALID ? unassigned : slot < slots.size() ? slots[slot] : WP_INVALID;
    if (material == WP_INVALID) fail("triangle " + std::to_string(t + 1) + " has no material");
    glm::vec3 v[3];
    for (size_t c = 0; c < 3; ++c) v[c] = glm::vec3(toWorld * glm::vec4(mesh.positions[mesh.positionIndices[3 * t + c]], 1.0f));
    if (!is_finite(v[0]) || !is_finite(v[1]) || !is_finite(v[2])) fail("triangle " + std::to_string(t + 1) + ": " + kPastFloatRange);
    // Degenerate triangles are common in scanned meshes; they can never be
    // hit, so they are dropped rather than rejected.
    if (glm::length(glm::cross(v[1] - v[0], v[2] - v[0])) == 0.0f) continue;
    SceneTriangle tri;
    for (int c = 0; c < 3; ++c) tri.v[c] = v[c];
    tri.material = material;
    // Smooth shading where every corner has a usable normal; UVs where every corner has one.
    SceneTriangleShading sh;
    sh.hasNormals = true;
    sh.hasUvs = true;
    for (size_t c = 0; c < 3; ++c) {
      const uint32_t ni = mesh.normalIndices[3 * t + c], ti = mesh.uvIndices[3 * t + c];
      glm::vec3 n = ni != WP_INVALID ? normalXform * mesh.normals[ni] : glm::vec3(0.0f);
      if (glm::length(n) > 0.0f) sh.n[c] = glm::normalize(n);
      else sh.hasNormals = false;
      if (ti != WP_INVALID) sh.uv[c] = mesh.uvs[ti];
      else sh.hasUvs = false;
    }
    if (vertexData) {
      sh.hasVertexData = true;
      sh.hasUv1 = !mesh.uvs1.empty();
      for (size_t c = 0; c < 3; ++c) {
        const uint32_t vi = mesh.positionIndices[3 * t + c];
        if (!mesh.tangents.empty()) {
          const glm::vec3 tw = vectorXform * glm::vec3(mesh.tangents[vi]);
          const float len = glm::length(tw);
          // A zero or broken tangent leaves the kernels to derive one from the UVs.
          if (len > 0.0f && std::isfinite(len)) sh.tangent[c] = glm::vec4(tw / len, mesh.tangents[vi].w < 0.0f ? -handedness : handedness);
        }
        if (!mesh.colors.empty()) sh.color[c] = mesh.colors[vi];
        if (!mesh.uvs1.empty()) sh.uv1[c] = mesh.uvs1[vi];
      }
    }
    if (sh.hasNormals || sh.hasUvs || sh.hasVertexData) {
      tri.shading = uint32_t(scene.triangleShading.size());
      scene.triangleShading.push_back(sh);
    }
    scene.triangles.push_back(tri);
  }
}

}  // namespace wp
