#include "render/photon_pass.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>

#include "render/compile_parts.h"
#include "render/shader_cpp.h"
#include "util/error.h"

namespace wp {

std::vector<shader::Photon> trace_photons(const CompiledScene& cs) {
  shader::SceneView view = cs.view();  // read-only: shared by the threads
  // Each photon's records in its own list, so that the order does not depend
  // on how the threads share the work; a block of photons at a time.
  constexpr uint32_t kBlock = 1u << 14;
  const uint32_t count = cs.photonCount;
  std::vector<std::vector<shader::Photon>> records(std::min(count, kBlock));
  std::vector<shader::Photon> out;
  std::atomic<uint32_t> truncated{0};
  for (uint32_t first = 0; first < count; first += kBlock) {
    const uint32_t n = std::min(kBlock, count - first);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 256), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        records[i].clear();
        shader::SceneView::PhotonPath path = view.photon_emit(first + i, count, cs.photonSeed);
        shader::Photon ph;
        while (path.alive != 0u) {
          const uint32_t status = view.photon_bounce(path, ph);
          if (status & PHOTON_STORED) {
            ph.axis = first + i;
            records[i].push_back(ph);
          }
          if (status & PHOTON_TRUNCATED) truncated.fetch_add(1, std::memory_order_relaxed);
        }
      }
    });
    for (uint32_t i = 0; i < n; ++i) out.insert(out.end(), records[i].begin(), records[i].end());
  }
  if (truncated > 0)
    throw RenderError(std::to_string(truncated.load()) + " photon(s) outran the traversal step cap; the photon map would be wrong");
  return out;
}

std::vector<shader::Photon> balance_photons(const std::vector<shader::Photon>& records) {
  PhotonMap map;
  for (const shader::Photon& ph : records) map.add(ph.position, ph.power, ph.from);
  map.build();
  return pack_photon_map(map);
}

std::vector<shader::Photon> pack_photon_map(const PhotonMap& map) {
  std::vector<shader::Photon> out(map.size());
  for (uint32_t i = 0; i < map.size(); ++i) {
    const PhotonMap::Photon& p = map.photon(i);
    out[i] = shader::Photon{p.position, map.axis(i), p.power, p.from};
  }
  return out;
}

// What the photon mapper refuses: light no photon carries (the background,
// an environment map, lights at infinity, CS184's point lights that do not
// fall off) and media, which its photons do not cross yet.
static void check_photon_mapper_scene(const Scene& scene, bool media) {
  const std::string at = scene.sourcePath + ": the photon mapper ";
  if (media) throw InputError(at + "does not trace photons through participating media; use a path tracer");
  if (scene.environment != WP_INVALID || scene.background != glm::vec3(0.0f))
    throw InputError(at + "carries light from emitters only, and this scene's background or environment lights it too: "
                          "make the background black (\"background\": 0) or use a path tracer");
  for (const ScenePointLight& l : scene.pointLights) {
    if (l.kind == ScenePointLight::Kind::Directional || l.kind == ScenePointLight::Kind::Hemisphere)
      throw InputError(at + "emits photons from area, sphere, point and spot lights; this scene has a light at infinity");
    if (!l.falloff) throw InputError(at + "needs point lights that fall off with distance (CS184's do not)");
  }
}

void compile_photons(const Scene& scene, const RenderOptions& options, CompiledScene& out) {
  check_photon_mapper_scene(scene, scene_has_media(scene));
  shader::SceneParams& p = out.params;
  const IntegratorSettings& s = scene.integrator;
  p.photons = glm::uvec4(0u, s.searchCount, glm::floatBitsToUint(s.searchRadius * s.searchRadius), 0u);
  out.photonCount = s.photons;
  out.photonSeed = s.photonSeed;
  out.photonMapLeftToDevice = !options.photonsOnHost;
  if (options.photonsOnHost) {
    const auto start = std::chrono::steady_clock::now();
    out.photons = balance_photons(trace_photons(out));
    p.photons.x = uint32_t(out.photons.size());
    out.photonPassSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

}  // namespace wp
