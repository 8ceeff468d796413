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

namespace {
const std::pair<const char*, IntegratorKind> kIntegratorKinds[] = {
    {"path tracer mis", IntegratorKind::PathMis},   {"path tracer nee", IntegratorKind::PathNee},
    {"path tracer mats", IntegratorKind::PathMats}, {"path tracer mixture", IntegratorKind::PathMixture},
    {"path tracer hemisphere", IntegratorKind::PathHemisphere},
    {"normals", IntegratorKind::Normals},           {"ao", IntegratorKind::AmbientOcclusion},
    {"photon mapper", IntegratorKind::PhotonMapper}};
}  // namespace

std::optional<IntegratorKind> integrator_named(const std::string& name) {
  for (const auto& [n, kind] : kIntegratorKinds) {
    if (name == n) return kind;
  }
  return std::nullopt;
}

std::string integrator_kind_name(IntegratorKind kind) {
  for (const auto& [n, k] : kIntegratorKinds) {
    if (k == kind) return n;
  }
  return "";
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

shader::Material SceneMaterial::blank_material_record() {
  // No textures, no parts; the kind's extra slots zero (its module fills
  // those it uses).
  shader::Material m{};
  m.info = glm::uvec4(MAT_LAMBERTIAN, WP_INVALID, WP_INVALID, WP_INVALID);
  m.children = glm::uvec4(WP_INVALID);
  m.media = glm::uvec4(WP_INVALID, WP_INVALID, 0u, 0u);
  return m;
}

uint32_t add_texture(Scene& scene, const SceneTexture& texture) {
  scene.textures.push_back(texture);
  return uint32_t(scene.textures.size() - 1);
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

std::pair<glm::vec3, glm::vec3> placed_bounds(glm::vec3 lo, glm::vec3 hi, const glm::mat4& toWorld) {
  glm::vec3 wlo(INFINITY), whi(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const glm::vec3 w(toWorld * glm::vec4(p, 1.0f));
    wlo = glm::min(wlo, w);
    whi = glm::max(whi, w);
  }
  return {wlo, whi};
}

std::pair<glm::vec3, glm::vec3> scene_bounds(const Scene& scene) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& v : t.v) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  for (const SceneInstance& i : scene.instances) {
    const SceneInstancedMesh& m = scene.instancedMeshes[i.mesh];
    const auto [wlo, whi] = placed_bounds(m.lo, m.hi, i.toWorld);
    lo = glm::min(lo, wlo);
    hi = glm::max(hi, whi);
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

namespace {

// How a mesh's vertices, normals and tangents are placed in world space:
// positions by the transform, normals by its inverse transpose and tangents
// by its linear part, each normalized; a mirroring transform turns the
// bitangent's handedness. surfaces.glsl places an instance's surface the
// same way, so that an instance and its flattened copy look alike.
struct Placement {
  glm::mat4 toWorld;
  glm::mat3 normalXform;
  glm::mat3 vectorXform;
  float handedness;
  explicit Placement(const glm::mat4& m)
      : toWorld(m), normalXform(normal_matrix(m)), vectorXform(m), handedness(glm::determinant(glm::mat3(m)) < 0.0f ? -1.0f : 1.0f) {}
  glm::vec3 point(glm::vec3 p) const { return glm::vec3(toWorld * glm::vec4(p, 1.0f)); }
  // The unit normal, or zero where there is none.
  glm::vec3 normal(glm::vec3 n) const {
    n = normalXform * n;
    return glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f);
  }
  // The unit tangent and handedness, or zero: a zero or broken tangent
  // leaves the kernels to derive one from the UVs.
  glm::vec4 tangent(glm::vec4 t) const {
    const glm::vec3 tw = vectorXform * glm::vec3(t);
    const float len = glm::length(tw);
    if (!(len > 0.0f && std::isfinite(len))) return glm::vec4(0.0f);
    return glm::vec4(tw / len, t.w < 0.0f ? -handedness : handedness);
  }
};

void append_mesh(std::vector<SceneTriangle>& triangles, std::vector<SceneTriangleShading>& shading, const SceneMesh& mesh,
                 const Placement& place, const std::vector<uint32_t>& slots, uint32_t unassigned,
                 const std::function<void(const std::string&)>& fail) {
  const bool vertexData = !mesh.tangents.empty() || !mesh.colors.empty() || !mesh.uvs1.empty();
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t slot = mesh.materials[t];
    const uint32_t material = slot == WP_INVALID ? unassigned : slot < slots.size() ? slots[slot] : WP_INVALID;
    if (material == WP_INVALID) fail("triangle " + std::to_string(t + 1) + " has no material");
    glm::vec3 v[3];
    for (size_t c = 0; c < 3; ++c) v[c] = place.point(mesh.positions[mesh.positionIndices[3 * t + c]]);
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
      sh.n[c] = ni != WP_INVALID ? place.normal(mesh.normals[ni]) : glm::vec3(0.0f);
      if (sh.n[c] == glm::vec3(0.0f)) sh.hasNormals = false;
      if (ti != WP_INVALID) sh.uv[c] = mesh.uvs[ti];
      else sh.hasUvs = false;
    }
    if (vertexData) {
      sh.hasVertexData = true;
      sh.hasUv1 = !mesh.uvs1.empty();
      for (size_t c = 0; c < 3; ++c) {
        const uint32_t vi = mesh.positionIndices[3 * t + c];
        if (!mesh.tangents.empty()) sh.tangent[c] = place.tangent(mesh.tangents[vi]);
        if (!mesh.colors.empty()) sh.color[c] = mesh.colors[vi];
        if (!mesh.uvs1.empty()) sh.uv1[c] = mesh.uvs1[vi];
      }
    }
    if (sh.hasNormals || sh.hasUvs || sh.hasVertexData) {
      tri.shading = uint32_t(shading.size());
      shading.push_back(sh);
    }
    triangles.push_back(tri);
  }
}

// Places a triangle of an instanced mesh in world space, as append_mesh
// would have placed the triangle it came from, but for one rule instances
// follow (glTF's: the determinant of the transform decides the winding): a
// mirroring transform keeps the mesh's front side its front, by turning the
// order of the corners, which would otherwise turn it.
void place_instanced_triangle(Scene& scene, const SceneInstancedMesh& mesh, const SceneTriangle& t, const Placement& place) {
  SceneTriangle w = t;
  const int corner[3] = {0, place.handedness < 0.0f ? 2 : 1, place.handedness < 0.0f ? 1 : 2};
  for (int c = 0; c < 3; ++c) w.v[c] = place.point(t.v[corner[c]]);
  if (glm::length(glm::cross(w.v[1] - w.v[0], w.v[2] - w.v[0])) == 0.0f) return;
  if (t.shading != WP_INVALID) {
    const SceneTriangleShading& in = mesh.shading[t.shading];
    SceneTriangleShading sh = in;
    for (int c = 0; c < 3; ++c) {
      const int k = corner[c];
      sh.n[c] = sh.hasNormals ? place.normal(in.n[k]) : in.n[k];
      sh.uv[c] = in.uv[k];
      sh.tangent[c] = sh.hasVertexData ? place.tangent(in.tangent[k]) : in.tangent[k];
      sh.color[c] = in.color[k];
      sh.uv1[c] = in.uv1[k];
    }
    w.shading = uint32_t(scene.triangleShading.size());
    scene.triangleShading.push_back(sh);
  }
  scene.triangles.push_back(w);
}

}  // namespace

void add_mesh(Scene& scene, const SceneMesh& mesh, const glm::mat4& toWorld, const std::vector<uint32_t>& slots,
              uint32_t unassigned, const std::function<void(const std::string&)>& fail) {
  append_mesh(scene.triangles, scene.triangleShading, mesh, Placement(toWorld), slots, unassigned, fail);
}

uint32_t add_instanced_mesh(Scene& scene) {
  scene.instancedMeshes.emplace_back();
  return uint32_t(scene.instancedMeshes.size() - 1);
}

void add_to_instanced_mesh(Scene& scene, uint32_t into, const SceneMesh& mesh, const std::vector<uint32_t>& slots,
                           uint32_t unassigned, const std::function<void(const std::string&)>& fail) {
  SceneInstancedMesh& m = scene.instancedMeshes.at(into);
  const size_t first = m.triangles.size();
  append_mesh(m.triangles, m.shading, mesh, Placement(glm::mat4(1.0f)), slots, unassigned, fail);
  for (size_t t = first; t < m.triangles.size(); ++t)
    for (const glm::vec3& v : m.triangles[t].v) {
      m.lo = glm::min(m.lo, v);
      m.hi = glm::max(m.hi, v);
    }
}

void add_instance(Scene& scene, uint32_t mesh, const glm::mat4& toWorld, const std::function<void(const std::string&)>& fail) {
  const SceneInstancedMesh& m = scene.instancedMeshes.at(mesh);
  if (m.triangles.empty()) return;
  const float det = glm::determinant(glm::mat3(toWorld));
  if (!std::isfinite(det)) fail(kPastFloatRange);
  if (det == 0.0f) return;
  const auto [lo, hi] = placed_bounds(m.lo, m.hi, toWorld);
  if (!is_finite(lo) || !is_finite(hi)) fail(kPastFloatRange);
  scene.instances.push_back(SceneInstance{mesh, toWorld});
}

bool material_emits(const Scene& scene, uint32_t material) {
  const uint32_t e = scene.materials.at(material).emission;
  if (e == WP_INVALID) return false;
  const SceneTexture& t = scene.textures.at(e);
  return !(t.kind == TEX_CONSTANT && t.color == glm::vec3(0.0f));
}

bool default_sky_wanted(const Scene& scene) {
  // Each emitting material's brightest channel anywhere and mean
  // illuminance (a texture's factor times its texels' brightest and mean).
  std::vector<double> peak(scene.materials.size(), 0.0), mean(scene.materials.size(), 0.0);
  for (uint32_t m = 0; m < scene.materials.size(); ++m) {
    if (!material_emits(scene, m)) continue;
    const SceneTexture& t = scene.textures[scene.materials[m].emission];
    glm::dvec3 hi(t.color), sum(t.color);
    if (t.kind == TEX_IMAGE && t.image < scene.images.size() && !scene.images[t.image].pixels.empty()) {
      const LinearImage& image = scene.images[t.image];
      glm::dvec3 texelHi(0.0), texelSum(0.0);
      for (const glm::vec3& p : image.pixels) texelHi = glm::max(texelHi, glm::dvec3(p)), texelSum += glm::dvec3(p);
      hi *= texelHi;
      sum *= texelSum / double(image.pixels.size());
    }
    peak[m] = std::max({hi.x, hi.y, hi.z});
    const glm::vec3 s(sum);
    mean[m] = double(LUMINANCE_R * s.x + LUMINANCE_G * s.y + LUMINANCE_B * s.z);  // sampling.glsl's illuminance
  }
  // What those brighter than the sky emit (a side's radiance times its area,
  // over pi), against what the sky of radiance 1 pours onto the box.
  double power = 0.0;
  for (const SceneTriangle& t : scene.triangles)
    if (t.material < peak.size() && peak[t.material] > 1.0)
      power += mean[t.material] * 0.5 * glm::length(glm::cross(glm::dvec3(t.v[1] - t.v[0]), glm::dvec3(t.v[2] - t.v[0])));
  const auto [lo, hi] = scene_bounds(scene);
  const glm::dvec3 d = glm::max(glm::dvec3(hi) - glm::dvec3(lo), glm::dvec3(0.0));
  const double boxArea = 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
  return !(power > 0.0 && power >= kEmittersLightTheScene * boxArea);
}

// Flattens the instances of the meshes `keep` refuses into world triangles,
// and keeps the rest (dropping meshes no instance places).
static void flatten_unless(Scene& scene, const std::function<bool(size_t mesh, size_t uses)>& keep) {
  std::vector<size_t> uses(scene.instancedMeshes.size(), 0);
  for (const SceneInstance& i : scene.instances) ++uses[i.mesh];
  std::vector<uint32_t> kept(scene.instancedMeshes.size(), WP_INVALID);
  std::vector<SceneInstancedMesh> meshes;
  for (size_t m = 0; m < scene.instancedMeshes.size(); ++m) {
    if (uses[m] > 0 && keep(m, uses[m])) {
      kept[m] = uint32_t(meshes.size());
      meshes.push_back(std::move(scene.instancedMeshes[m]));
    }
  }
  std::vector<SceneInstance> instances;
  for (const SceneInstance& i : scene.instances) {
    if (kept[i.mesh] != WP_INVALID) {
      instances.push_back(SceneInstance{kept[i.mesh], i.toWorld});
      continue;
    }
    const SceneInstancedMesh& mesh = scene.instancedMeshes[i.mesh];
    const Placement place(i.toWorld);
    for (const SceneTriangle& t : mesh.triangles) place_instanced_triangle(scene, mesh, t, place);
  }
  scene.instancedMeshes = std::move(meshes);
  scene.instances = std::move(instances);
}

void settle_instances(Scene& scene) {
  flatten_unless(scene, [&](size_t m, size_t uses) {
    const std::vector<SceneTriangle>& triangles = scene.instancedMeshes[m].triangles;
    return uses >= 2 && std::none_of(triangles.begin(), triangles.end(), [&](const SceneTriangle& t) { return material_emits(scene, t.material); });
  });
}

void flatten_instances(Scene& scene) {
  flatten_unless(scene, [](size_t, size_t) { return false; });
}

size_t instanced_triangle_count(const Scene& scene) {
  size_t n = 0;
  for (const SceneInstance& i : scene.instances) n += scene.instancedMeshes[i.mesh].triangles.size();
  return n;
}

}  // namespace wp
