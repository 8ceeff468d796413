// The traversal benchmarks' ray sets (ray_sets.h).
#include "bench/ray_sets.h"

#include <tbb/parallel_for.h>

#include "render/shader_cpp.h"

namespace wp::bench {

// Camera rays through every pixel, then from every hit one cosine-distributed
// bounce and one shadow ray to a point that next-event estimation picks on
// an emitter (where it lies above the surface), leaving the surface as the
// path tracer would.
RaySets make_rays(const CompiledScene& cs) {
  shader::SceneView view = cs.view();
  RaySets sets;
  size_t pixels = size_t(cs.width) * size_t(cs.height);
  sets.primary.resize(pixels);
  for (size_t p = 0; p < pixels; ++p) {
    shader::PathState ps;
    view.path_begin(ps, uint32_t(p), 0);
    sets.primary[p] = shader::ShadowRay{ps.origin, WP_INF, ps.dir, uint32_t(p), glm::vec4(0.0f), 0u};
  }
  std::vector<shader::Hit> hits(pixels);
  tbb::parallel_for(size_t(0), pixels, [&](size_t p) {
    view.trace_ray(sets.primary[p].origin, sets.primary[p].dir, sets.primary[p].tmax, false, hits[p]);
  });
  sets.primaryHits.assign(pixels, WP_INF);
  for (size_t p = 0; p < pixels; ++p) {
    if (hits[p].prim == WP_INVALID) continue;
    sets.primaryHits[p] = hits[p].t;
    const shader::ShadowRay& r = sets.primary[p];
    shader::SceneView::SurfaceHit s = view.surface_at(r.origin, r.dir, hits[p]);
    glm::vec3 n = glm::dot(s.ng, r.dir) < 0.0f ? s.ng : -s.ng;
    uint32_t rng = view.rng_seed(uint32_t(p), 1u, 7u);
    glm::vec3 t, b;
    view.make_frame(n, t, b);
    glm::vec3 d = view.frame_to_world(view.square_to_cosine_hemisphere(glm::vec2(view.rng_next(rng), view.rng_next(rng))), t, b, n);
    sets.bounce.push_back(shader::ShadowRay{view.offset_ray(s.p, n), WP_INF, d, uint32_t(p), glm::vec4(0.0f), 0u});
    shader::SceneView::LightSample ls;
    const glm::vec3 uLight(view.rng_next(rng), view.rng_next(rng), view.rng_next(rng));
    if (view.sample_emitter(s.p, uLight, ls) && ls.pdf > 0.0f && glm::dot(ls.wi, n) > 0.0f) {
      shader::ShadowRay sr{};
      sr.path = uint32_t(p);
      view.aim_shadow_ray(s.p, n, ls, sr.origin, sr.dir, sr.tmax);
      sets.shadow.push_back(sr);
    }
  }
  return sets;
}

}  // namespace wp::bench
