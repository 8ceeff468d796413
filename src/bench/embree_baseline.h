// embree_baseline.h — Embree 3 as the CPU baseline of the benchmarks: the same
// rays traced with rtcIntersect1 (shadow rays: rtcOccluded1) on all cores,
// and its BVH build on the same triangles. Optional: built when CMake finds
// Embree (Debian libembree-dev).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shader/types.h"
#include "scene/scene.h"

namespace wp {

bool embree_available();

struct EmbreeRun {
  double buildSeconds = 0.0;
  double traceSeconds = 0.0;
  std::vector<float> t;  // hit distance per ray, WP_INF on a miss
};

class EmbreeScene {
 public:
  // Triangles, flat or placed by instances; throws RenderError for spheres.
  explicit EmbreeScene(const Scene& scene);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  double build_seconds() const { return buildSeconds_; }  // rtcCommitScene alone
  // Closest hits of the rays, on all cores; returns the seconds spent tracing.
  double trace(const std::vector<shader::ShadowRay>& rays, std::vector<float>* t) const;
  // Whether each ray's segment is blocked (rtcOccluded1), on all cores;
  // returns the seconds spent tracing.
  double occluded(const std::vector<shader::ShadowRay>& rays, std::vector<uint8_t>* blocked) const;

 private:
  void* device_ = nullptr;
  void* scene_ = nullptr;
  double buildSeconds_ = 0.0;
};

// Seconds Embree takes to build its BVHs over the scene's triangles from
// scratch (new scenes, rtcCommitScene at the default build quality, all
// cores). Triangles only: throws RenderError otherwise.
double embree_build_seconds(const Scene& scene);

}  // namespace wp
