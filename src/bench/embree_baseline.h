// embree_baseline.h — the same rays traced by Embree 3 (rtcIntersect1 on all
// cores), as the CPU baseline of the ray-casting benchmark. Optional: built
// when CMake finds Embree (Debian libembree-dev).
#pragma once

#include <string>
#include <vector>

#include "render/shader_cpp.h"
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
  explicit EmbreeScene(const Scene& scene);  // triangles only; throws RenderError otherwise
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  double build_seconds() const { return buildSeconds_; }
  // Closest hits of the rays, on all cores; returns the seconds spent tracing.
  double trace(const std::vector<shader::ShadowRay>& rays, std::vector<float>* t) const;

 private:
  void* device_ = nullptr;
  void* scene_ = nullptr;
  double buildSeconds_ = 0.0;
};

}  // namespace wp
