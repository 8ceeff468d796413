#include "job/scene_info.h"

#include <cstdarg>
#include <cstdio>

#include "gpu/wavefront.h"
#include "scene/kinds.h"

namespace wp {

namespace {

__attribute__((format(printf, 2, 3))) void appendf(std::string& text, const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    const size_t at = text.size();
    text.resize(at + size_t(n) + 1);
    std::vsnprintf(&text[at], size_t(n) + 1, format, again);
    text.resize(at + size_t(n));
  }
  va_end(again);
}

}  // namespace

RenderOptions info_options(const RenderOptions& base, const std::string& variant) {
  RenderOptions options = variant_options(base, variant);  // an unknown variant fails before any work
  options.photonsOnHost = true;  // the photon map it reports
  return options;
}

std::string scene_info(const std::string& path, const Scene& scene, const CompiledScene& cs, double loadSeconds) {
  std::string text;
  size_t gpuBytes = cs.gpu_bytes();
  // With instances: the bytes per triangle placed, and the build's rate over
  // the primitives its trees were built over.
  const size_t prims = scene.triangles.size() + scene.spheres.size() + cs.instancing.instancedTriangles;
  const size_t built = scene.triangles.size() + scene.spheres.size() + cs.instancing.instances + cs.instancing.uniqueTriangles;
  appendf(text, "scene        %s\n", path.c_str());
  appendf(text, "primitives   %zu triangles, %zu spheres, %zu materials, %u emitters\n", scene.triangles.size(),
              scene.spheres.size(), scene.materials.size(), cs.params.counts.x);
  appendf(text, "image        %dx%d, %d spp, %u max bounces\n", cs.width, cs.height, cs.spp, cs.params.image.z);
  appendf(text, "load         %.3f s (parsing and OBJ)\n", loadSeconds);
  bool wide = cs.bvhLayout == BvhLayout::Wide;
  appendf(text, "BVH          %s, %s, %zu nodes, depth %d, SAH cost %.2f, built in %.3f s (%.3g Mprims/s)\n",
              wide ? "8-wide compressed" : "binary", split_method_name(cs.bvhSplit), wide ? cs.wideNodes.size() : cs.nodes.size(),
              cs.bvhDepth, cs.bvh_sah_cost(), cs.bvhBuildSeconds, cs.bvhBuildSeconds > 0 ? built / cs.bvhBuildSeconds * 1e-6 : 0.0);
  appendf(text, "GPU scene    %.2f MiB (%.1f bytes per primitive, BVH included; instanced triangles counted as placed)\n", gpuBytes / 1048576.0,
              prims ? double(gpuBytes) / double(prims) : 0.0);
  const InstancingStats& inst = cs.instancing;
  if (inst.instances > 0) {
    // The BVH line above is the top level's tree.
    appendf(text, "instances    %zu instances of %zu mesh%s: %zu unique triangles place %zu (%.3g per unique one); top level %.2f MiB "
                "(its tree, %zu world triangles and the instances' placeholders and records), meshes' trees and triangles %.2f MiB\n",
                inst.instances, inst.meshes, inst.meshes == 1 ? "" : "es", inst.uniqueTriangles, inst.instancedTriangles,
                inst.uniqueTriangles ? double(inst.instancedTriangles) / double(inst.uniqueTriangles) : 0.0,
                inst.topLevelBytes / 1048576.0, scene.triangles.size(), inst.bottomLevelBytes / 1048576.0);
  }
  if (cs.params.mode.x == INTEGRATOR_PHOTONS) {
    const IntegratorSettings& in = scene.integrator;
    appendf(text, "photons      %u traced on the host in %.3f s, %zu records (%.2f MiB); the gather takes %s within %g\n", in.photons,
                cs.photonPassSeconds, cs.photons.size(), double(cs.photons.size() * sizeof(shader::Photon)) / 1048576.0,
                in.searchCount > 0 ? ("the " + std::to_string(in.searchCount) + " nearest").c_str() : "every photon", double(in.searchRadius));
  }
  // On a CPU device every branch a kernel has costs each path, taken or not:
  // what the scene uses is what its kernels pay for.
  appendf(text, "kinds        %s (compiled into the kernels)\n", kinds_description(cs.params.kinds).c_str());
  if (!scene.media.empty()) {
    appendf(text, "media       ");
    for (size_t i = 0; i < scene.media.size(); ++i) {
      const SceneMedium& m = scene.media[i];
      appendf(text, " %s (%s%s)%s", m.name.c_str(), kind_list(medium_kinds(), KIND_BIT(m.kind)).c_str(),
                  scene.cameraMedium == i ? ", the camera's" : "", i + 1 < scene.media.size() ? "," : "\n");
    }
    for (const SceneMedium& m : scene.media) {
      if (!m.grid) continue;
      const DensityGrid& g = *m.grid;
      const glm::ivec3 extent = g.indexMax - g.indexMin + 1;
      const glm::uvec3 cells = majorant_cells(m);
      appendf(text, "grid         %s: \"%s\" of %s, %dx%dx%d voxels (%llu active, %u leaves), largest density %g, %.2f MiB; "
                  "majorant grid %ux%ux%u\n",
                  m.name.c_str(), g.name.c_str(), g.file.c_str(), extent.x, extent.y, extent.z, (unsigned long long)g.activeVoxels,
                  g.leaves, g.maxDensity, double(g.words.size()) * 4.0 / (1 << 20), cells.x, cells.y, cells.z);
    }
  }
  // gpu-sort shades each class of materials with a kernel of its own kinds.
  appendf(text, "shade classes");
  for (size_t c = 0; c < cs.shadeClasses.size(); ++c) {
    const glm::uvec4 k = cs.shade_key_kinds(uint32_t(c) + 1);
    appendf(text, " %zu: %s / %s;", c, kind_list(material_kinds(), k.x, ", ").c_str(), kind_list(texture_kinds(), k.y, ", ").c_str());
  }
  appendf(text, " misses: textures %s (material / texture kinds of each gpu-sort shade kernel)\n",
              kind_list(texture_kinds(), cs.shade_key_kinds(SORT_KEY_MISS).y, ", ").c_str());
  return text;
}

}  // namespace wp
