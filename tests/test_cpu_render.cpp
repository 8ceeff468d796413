// The CPU reference renderer on scenes whose answer is known exactly.
#include "test_support.h"

#include "util/error.h"

namespace wp::test {
namespace {

// Inside a closed box whose walls have albedo 0.5 and emit 0.5, paths of at
// most D bounces see exactly 1 - 0.5^(D+1), for every integrator.
TEST(CpuReference, FurnaceBoxIsAnalyticForEveryIntegratorAndDepth) {
  for (int bounces : {0, 2, 64}) {
    for (IntegratorKind kind : {IntegratorKind::PathMis, IntegratorKind::PathNee, IntegratorKind::PathMats}) {
      Scene scene = load_scene(source_path("tests/data/furnace.json"));
      scene.integrator.kind = kind;
      RenderOptions o;
      o.maxBounces = bounces;
      o.spp = 32;
      CompiledScene cs = compile_scene(scene, o);
      Progress quiet("", 0, false);
      ImageStats img = render_cpu(cs, 0, quiet);
      std::string what = "bounces " + std::to_string(bounces) + ", integrator " + std::to_string(int(kind));
      expect_mean(img, 1.0 - std::pow(0.5, bounces + 1), what.c_str());
    }
  }
}

// A convex diffuse sphere (albedo 0.5) under a white sky: every ray leaving it
// escapes, so it shows exactly 0.5. A self-intersection would darken it.
TEST(CpuReference, SphereUnderWhiteSkyIsExactlyHalf) {
  ImageStats img = render_reference(source_path("tests/data/sphere-sky.json"), RenderOptions{}, 64);
  double sum = 0.0;
  int n = 0;
  for (int y = 8; y < 16; ++y)
    for (int x = 8; x < 16; ++x) {
      glm::dvec3 m = img.mean(size_t(y * img.width + x));
      sum += m.x + m.y + m.z;
      n += 3;
      EXPECT_NEAR(m.x, 0.5, 1e-5) << x << "," << y;  // no variance: every path gives 0.5
    }
  EXPECT_NEAR(sum / n, 0.5, 1e-6);
  glm::dvec3 corner = img.mean(0);
  EXPECT_NEAR(corner.x, 1.0, 1e-6);  // the sky itself
}

TEST(CpuReference, TruncatedTraversalIsAnErrorNotAnImage) {
  RenderOptions o;
  o.traversalStepCap = 2;
  EXPECT_THROW(render_reference(source_path("scenes/cornell-box.json"), o, 1), RenderError);
}

}  // namespace
}  // namespace wp::test
