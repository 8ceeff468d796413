// The CPU reference renderer on scenes whose answer is known exactly.
#include "test_support.h"

#include <gtest/gtest-spi.h>

#include "util/error.h"

namespace wp::test {
namespace {

TEST(CpuReference, FurnaceBoxIsAnalyticForEveryIntegratorAndDepth) {
  expect_furnace_is_analytic([](const CompiledScene& cs) {
    Progress quiet("", 0, false);
    return render_cpu(cs, 0, quiet);
  });
}

// The analytic check itself must notice a 2 % error: plant one in the
// integrator's radiance and expect the mean test to fail.
TEST(CpuReference, FurnaceCheckCatchesAPlantedBiasOfTwoPercent) {
  Scene scene = load_scene(source_path("tests/data/furnace.json"));
  RenderOptions o;
  o.maxBounces = 2;
  o.spp = 32;
  o.plantedBias = 1.02f;
  Progress quiet("", 0, false);
  ImageStats img = render_cpu(compile_scene(scene, o), 0, quiet);
  EXPECT_NONFATAL_FAILURE(expect_mean(img, 0.875, "planted"), "planted");
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
