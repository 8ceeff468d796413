// The CPU reference renderer on scenes whose answer is known exactly.
#include "test_support.h"

#include <gtest/gtest-spi.h>

#include "stats/compare.h"
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

// MIS, NEE alone, BSDF sampling alone and the one-sample mixture estimate the
// same image (the scene has no point lights, which only NEE can reach, and
// lights large enough for BSDF sampling alone to find them at 256 spp).
TEST(CpuRender, AllPathTracersAgreeOnOneScene) {
  Scene scene = load_scene(source_path("tests/data/features/integrators.json"));
  auto render = [&](IntegratorKind kind, uint32_t seed) {
    RenderOptions o;
    o.integrator = kind;
    o.spp = 256;
    o.seed = seed;
    Progress quiet("", 0, false);
    return render_cpu(compile_scene(scene, o), 0, quiet);
  };
  ImageStats mis = render(IntegratorKind::PathMis, 1);
  for (auto [kind, name] : {std::pair{IntegratorKind::PathNee, "nee"}, std::pair{IntegratorKind::PathMats, "mats"},
                            std::pair{IntegratorKind::PathMixture, "mixture"}}) {
    CompareResult r = compare_images(render(kind, 2), mis);
    EXPECT_TRUE(r.passed()) << name << " vs mis: " << r.summary();
  }
  // A planted 4% bias in one of them is seen.
  RenderOptions o;
  o.integrator = IntegratorKind::PathNee;
  o.spp = 256;
  o.seed = 3;
  o.plantedBias = 1.04f;
  Progress quiet("", 0, false);
  EXPECT_FALSE(compare_images(render_cpu(compile_scene(scene, o), 0, quiet), mis).passed());
}

}  // namespace
}  // namespace wp::test
