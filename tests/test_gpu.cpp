// The Vulkan renderer (lavapipe in CI) with validation on: any validation
// message fails the test. Traversal against brute force, loop-budget safety,
// analytic scenes, and the GPU against the CPU reference, statistically.
#include "test_support.h"

#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <tuple>

#include "gpu/wavefront.h"
#include "render/photon_pass.h"
#include "scene/materials/material_module.h"
#include "scene/importers.h"
#include "scene/kinds.h"
#include "stats/compare.h"
#include "stats/darts_tests.h"
#include "util/error.h"

namespace wp::test {
namespace {

using namespace shader;

class Gpu : public testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = std::make_unique<VulkanContext>("", true); }
  static void TearDownTestSuite() { ctx_.reset(); }
  void TearDown() override { EXPECT_EQ(ctx_->validation_messages(), 0u) << "Vulkan validation reported problems"; }

  static ImageStats render(const CompiledScene& cs) {
    WavefrontRenderer r(*ctx_, cs);
    Progress quiet("", 0, false);
    return r.render(quiet);
  }
  static ImageStats render(const std::string& scenePath, RenderOptions o) {
    return render(compile_scene(load_scene(scenePath), o));
  }

  // The Cornell box at size x size.
  static Scene cornell_box(int size) {
    Scene scene = load_scene(source_path("scenes/cornell-box.json"));
    scene.camera.width = scene.camera.height = size;
    return scene;
  }

  // Renders `scenePath` at size x size on the GPU (with `gpuBias` planted) and
  // on the CPU with an independent seed, and compares them statistically.
  static CompareResult gpu_vs_cpu(const std::string& scenePath, int size, int spp, float gpuBias,
                                  std::optional<IntegratorKind> integrator = std::nullopt) {
    Scene scene = load_scene(scenePath);
    if (size > 0) scene.camera.width = scene.camera.height = size;
    RenderOptions go;
    go.integrator = integrator;
    go.spp = spp;
    go.seed = 1;
    RenderOptions co = go;
    co.seed = 2;
    ImageStats gpu = render(compile_scene(scene, go));
    plant_bias(gpu, gpuBias);
    Progress quiet("", 0, false);
    ImageStats cpu = render_cpu(compile_scene(scene, reference_options(co)), 0, quiet);
    return compare_images(gpu, cpu);
  }

  // `scene` with options `o` on the GPU (seed 1) against the CPU (seed 2).
  static CompareResult gpu_against_cpu(const Scene& scene, RenderOptions o) {
    o.seed = 1;
    ImageStats gpu = render(compile_scene(scene, o));
    o.seed = 2;
    Progress quiet("", 0, false);
    ImageStats cpu = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
    return compare_images(gpu, cpu);
  }

  // The Cornell box at 128x128, 64 spp: the GPU (with `bias` planted in
  // `region`) against the CPU with another seed.
  static CompareResult cornell_128(float bias, glm::uvec4 region, uint32_t seed, int size = 128) {
    Scene scene = cornell_box(size);
    RenderOptions a;
    a.spp = 64;
    a.seed = seed;
    RenderOptions b = a;
    b.seed = seed + 1000;
    ImageStats gpu = render(compile_scene(scene, a));
    plant_bias(gpu, bias, region);
    Progress quiet("", 0, false);
    ImageStats cpu = render_cpu(compile_scene(scene, reference_options(b)), 0, quiet);
    return compare_images(gpu, cpu);
  }

  static std::unique_ptr<VulkanContext> ctx_;
};
std::unique_ptr<VulkanContext> Gpu::ctx_;

// The kernels' closest hits against testing every primitive, for the wide
// walk with its stack in registers (as built) and in its indexed array (more
// stack slots than the registers hold, which only trees deeper than any real
// scene's need).
TEST_F(Gpu, ClosestHitsEqualBruteForceOnARealMesh) {
  Scene scene = bunny_with_spheres(AcceleratorSettings{4, SplitMethod::Sah});
  scene.camera.width = scene.camera.height = 64;  // 4096 path slots: rays go through in several chunks
  std::vector<ShadowRay> rays = random_rays(scene, 20000, 1234);
  std::vector<float> truth = brute_force_closest(scene, rays);
  // Coherent rays go one to an invocation, with workgroups interleaved on CPU
  // devices (dispatch_item, kernel.glsl): 20,000 rays leave the last
  // workgroup part full and the last row of the interleave short.
  struct Case {
    const char* name;
    bool indexedStack, clusteredBuild, coherent;
  };
  for (const Case& c : {Case{"register stack", false, false, false}, Case{"indexed stack", true, false, false},
                        Case{"clustered SAH build", false, true, false}, Case{"one ray per invocation", false, false, true}}) {
    SCOPED_TRACE(c.name);
    RenderOptions options;
    options.clusteredBuild = c.clusteredBuild;
    CompiledScene cs = compile_scene(scene, options);
    if (c.indexedStack) cs.params.accel.z = WIDE_REGISTER_STACK + 1u;
    WavefrontRenderer renderer(*ctx_, cs);
    uint64_t truncated = 0;
    std::vector<Hit> hits = renderer.cast_rays(rays, &truncated, nullptr, c.coherent);
    EXPECT_EQ(truncated, 0u);
    int mismatches = 0, hitCount = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      bool gpuHit = hits[i].prim != WP_INVALID;
      if (gpuHit != (truth[i] != WP_INF)) {
        ++mismatches;
        continue;
      }
      if (gpuHit) {
        ++hitCount;
        // The GPU compiler may fuse multiply-adds: allow a few ulps.
        EXPECT_NEAR(hits[i].t, truth[i], 1e-5f * truth[i] + 1e-6f) << "ray " << i;
      }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(hitCount, 4000);
  }
}

// Shadow rays (any hit, cast_shadow_rays) are blocked exactly where testing
// every primitive finds a hit before their tmax: each ray that hits is cut
// short of its hit or lengthened past it, alternately.
TEST_F(Gpu, ShadowRaysAreBlockedExactlyWhereBruteForceHitsBeforeTheirEnd) {
  Scene scene = bunny_with_spheres(AcceleratorSettings{4, SplitMethod::Sah});
  scene.camera.width = scene.camera.height = 64;  // 4096 path slots: rays go through in several chunks
  std::vector<ShadowRay> rays = random_rays(scene, 20000, 4321);
  const std::vector<float> closest = brute_force_closest(scene, rays);
  std::vector<bool> blocked(rays.size(), false);
  int blockedCount = 0, cutShort = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (closest[i] == WP_INF) continue;
    const bool shorten = i % 2 == 1;
    rays[i].tmax = closest[i] * (shorten ? 0.5f : 2.0f);
    blocked[i] = !shorten;
    blockedCount += !shorten;
    cutShort += shorten;
  }
  WavefrontRenderer renderer(*ctx_, compile_scene(scene, RenderOptions{}));
  // Incoherent rays share a subgroup's loop on CPU devices; coherent ones go
  // one to an invocation, their workgroups interleaved.
  for (bool coherent : {false, true}) {
    SCOPED_TRACE(coherent ? "coherent" : "incoherent");
    uint64_t truncated = 0;
    const std::vector<Hit> hits = renderer.cast_shadow_rays(rays, &truncated, nullptr, coherent);
    EXPECT_EQ(truncated, 0u);
    int mismatches = 0;
    for (size_t i = 0; i < rays.size(); ++i) mismatches += (hits[i].prim != WP_INVALID) != blocked[i];
    EXPECT_EQ(mismatches, 0);
  }
  EXPECT_GT(blockedCount, 2000);
  EXPECT_GT(cutShort, 2000);
}

// A stack of thin slivers in front of a target: a ray down the stack overlaps
// every sliver's box, so it visits every node and tests every sliver before it
// reaches the target.
Scene sliver_stack(int slivers) {
  Scene scene;
  scene.accelerator.maxLeafSize = 1;
  add_lambertian(scene, glm::vec3(0.5f));
  for (int i = 0; i < slivers; ++i) {
    float z = -float(i) * 1e-3f;
    // Close to the line y = x + 0.05: the box contains the axis, the sliver does not.
    scene.triangles.push_back(SceneTriangle{{{-1.0f, -0.95f, z}, {1.0f, 1.05f, z}, {1.0f, 1.06f, z}}, 0});
  }
  float zt = -float(slivers) * 1e-3f - 1.0f;
  scene.triangles.push_back(SceneTriangle{{{-2, -2, zt}, {2, -2, zt}, {0, 2, zt}}, 0});
  scene.camera.width = scene.camera.height = 8;
  return scene;
}

// The loop iterations one traversal takes, measured on the CPU by searching
// for the smallest step cap under which it completes.
uint32_t steps_needed(CompiledScene cs, const ShadowRay& ray) {
  uint32_t lo = 1, hi = 1u << 20;
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2;
    cs.params.counts.z = mid;
    SceneView view = cs.view();
    Hit h;
    if (view.trace_ray(ray.origin, ray.dir, ray.tmax, false, h) == TRACE_OK) hi = mid;
    else lo = mid + 1;
  }
  return lo;
}

std::vector<ShadowRay> down_the_stack() {
  std::vector<ShadowRay> rays;
  for (int i = 0; i < 64; ++i) {
    ShadowRay r{};
    r.origin = glm::vec3(0.001f * float(i % 8), -0.001f * float(i / 8), 1.0f);
    r.dir = glm::vec3(0, 0, -1);
    r.tmax = WP_INF;
    rays.push_back(r);
  }
  return rays;
}

// A sliver stack whose traversal in `layout` takes between `lo` and `hi` loop
// iterations: the two layouts take different numbers per sliver.
struct SliverCase {
  Scene scene;
  CompiledScene compiled;
  uint32_t steps;
};
SliverCase sliver_stack_taking(uint32_t lo, uint32_t hi, BvhLayout layout) {
  RenderOptions o;
  o.bvhLayout = layout;
  // Steps grow with the slivers, not quite linearly: bisect on their number.
  int fewest = 1000, most = 200000;
  while (fewest < most) {
    int slivers = fewest + (most - fewest) / 2;
    Scene scene = sliver_stack(slivers);
    CompiledScene cs = compile_scene(scene, o);
    uint32_t steps = steps_needed(cs, down_the_stack()[0]);
    if (steps > lo && steps < hi) return SliverCase{std::move(scene), std::move(cs), steps};
    if (steps <= lo) fewest = slivers + 1;
    else most = slivers;
  }
  return SliverCase{Scene{}, CompiledScene{}, 0};
}

// Just under the step cap, over 55,000 loop iterations in one invocation (real
// scenes need a few dozen): still inside lavapipe's 65,535 budget, so the GPU
// must find the target. Were the loops cut short, the rays would miss. (This
// test caught a nested leaf loop whose iterations lavapipe counted twice.)
TEST_F(Gpu, DeepTraversalWithinTheBudgetIsExact) {
  for (BvhLayout layout : {BvhLayout::Wide, BvhLayout::Binary}) {
    SliverCase c = sliver_stack_taking(55000, RenderOptions{}.traversalStepCap, layout);
    ASSERT_GT(c.steps, 0u) << "no sliver stack takes between 55,000 and the cap's steps";
    std::vector<ShadowRay> rays = down_the_stack();
    std::vector<float> truth = brute_force_closest(c.scene, rays);
    WavefrontRenderer renderer(*ctx_, c.compiled);
    uint64_t truncated = 0;
    std::vector<Hit> hits = renderer.cast_rays(rays, &truncated);
    EXPECT_EQ(truncated, 0u);
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_NE(truth[i], WP_INF);
      ASSERT_NE(hits[i].prim, WP_INVALID) << "ray " << i << ": the traversal stopped before the target";
      EXPECT_NEAR(hits[i].t, truth[i], 1e-5f * truth[i]);
    }
  }
}

// Several rays per invocation (trace_items.glsl) share lavapipe's budget,
// which both of its loops count. A workgroup of 64 invocations over 1,024
// rays: 16 to a lane, a share of (60,000 - 129) / 17 = 3,521 steps each.
// Rays just under it must come back exact from the multi-ray kernel itself,
// neither cut short silently nor redone one ray per invocation; rays over
// it (16 of them would overrun the budget) must be caught and redone.
TEST_F(Gpu, SeveralRaysPerInvocationShareTheBudgetExactly) {
  for (auto [lo, hi, fit] : {std::tuple<uint32_t, uint32_t, bool>{3000, 3400, true}, {4300, 4800, false}}) {
    SliverCase c = sliver_stack_taking(lo, hi, BvhLayout::Wide);
    ASSERT_GT(c.steps, 0u) << "no sliver stack takes between " << lo << " and " << hi << " steps";
    std::vector<ShadowRay> distinct = down_the_stack();
    std::vector<float> truth = brute_force_closest(c.scene, distinct);
    std::vector<ShadowRay> rays;
    for (int copy = 0; copy < 16; ++copy) rays.insert(rays.end(), distinct.begin(), distinct.end());
    // Rays per dispatch are at most the renderer's paths, one per pixel: all
    // 1,024 in one dispatch.
    Scene scene = c.scene;
    scene.camera.width = scene.camera.height = 32;
    RenderOptions wide;
    wide.bvhLayout = BvhLayout::Wide;
    WavefrontRenderer renderer(*ctx_, compile_scene(scene, wide), kernel_variant("gpu-multiray").settings);
    uint64_t truncated = 0;
    std::vector<Hit> hits = renderer.cast_rays(rays, &truncated);
    EXPECT_EQ(truncated, 0u) << c.steps << " steps";
    if (fit) {
      EXPECT_EQ(renderer.one_ray_reruns(), 0u) << c.steps << " steps: a ray outran its share, which is mis-counted";
    } else {
      EXPECT_GT(renderer.one_ray_reruns(), 0u) << c.steps << " steps: no ray outran its share, which is mis-counted";
    }
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_NE(hits[i].prim, WP_INVALID) << c.steps << " steps, ray " << i << ": the traversal stopped before the target";
      EXPECT_NEAR(hits[i].t, truth[i % distinct.size()], 1e-5f * truth[i % distinct.size()]);
    }
  }
}

// Past the step cap (which sits below lavapipe's budget) the kernels report
// truncation instead of silently returning a miss.
TEST_F(Gpu, TraversalPastTheCapIsReportedNotSilent) {
  for (BvhLayout layout : {BvhLayout::Wide, BvhLayout::Binary}) {
    SliverCase c = sliver_stack_taking(66000, 80000, layout);  // lavapipe would silently stop at 65,535
    ASSERT_GT(c.steps, 0u) << "no sliver stack takes between 66,000 and 80,000 steps";
    WavefrontRenderer renderer(*ctx_, c.compiled);
    uint64_t truncated = 0;
    std::vector<ShadowRay> rays = down_the_stack();
    renderer.cast_rays(rays, &truncated);
    EXPECT_EQ(truncated, rays.size());
  }
  RenderOptions tiny;
  tiny.traversalStepCap = 2;
  tiny.spp = 1;
  EXPECT_THROW(render(source_path("scenes/cornell-box.json"), tiny), RenderError);
}

// The megakernel traces all the rays of a path in one invocation, so on
// lavapipe each gets a share of its loop budget (here 3 traversals: 20,000
// steps each). A path whose camera ray needs more must fail the render, never
// come back as a silently truncated image; the wavefront kernels, one ray per
// invocation, render the same scene.
TEST_F(Gpu, MegakernelReportsRaysPastItsShareOfTheBudget) {
  SliverCase c = sliver_stack_taking(25000, 40000, BvhLayout::Wide);
  ASSERT_GT(c.steps, 0u);
  Scene scene = c.scene;
  scene.camera.toWorld = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 1.0f));  // looking down the stack
  scene.camera.vfovDegrees = 0.01f;
  scene.background = glm::vec3(1.0f);
  RenderOptions o;
  o.spp = 1;
  o.maxBounces = 1;
  CompiledScene cs = compile_scene(scene, o);
  Progress quiet("", 0, false);
  WavefrontRenderer wavefront(*ctx_, cs);
  EXPECT_NO_THROW(wavefront.render(quiet));
  // 16 rays per invocation give each ray a sixteenth of the cap: the camera
  // rays outrun it, and the renderer redoes the samples one ray per
  // invocation (render_samples) instead of failing.
  WavefrontRenderer multiRay(*ctx_, cs, kernel_variant("gpu-multiray").settings);
  EXPECT_NO_THROW(multiRay.render(quiet));
  WavefrontRenderer mega(*ctx_, cs, kernel_variant("gpu-mega").settings);
  if (ctx_->info().type != "cpu") {
    // A GPU has no loop budget: every ray of a path gets the whole cap, at
    // any depth (the H200 ran this test's lavapipe half and failed it).
    EXPECT_NO_THROW(mega.render(quiet));
    o.maxBounces = 200;
    EXPECT_NO_THROW(WavefrontRenderer(*ctx_, compile_scene(scene, o), kernel_variant("gpu-mega").settings));
    return;
  }
  try {
    mega.render(quiet);
    ADD_FAILURE() << "the megakernel rendered rays past its share of the loop budget";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("megakernel"), std::string::npos) << e.what();
  }
  // Too many bounces leave each ray too few steps: refused before any work.
  o.maxBounces = 200;
  CompiledScene deep = compile_scene(scene, o);
  EXPECT_THROW(WavefrontRenderer(*ctx_, deep, kernel_variant("gpu-mega").settings), RenderError);
}

// The regenerating megakernel (gpu-mega-bvh2-regen: an invocation renders
// four samples of its pixel, a lane beginning its next path as one ends)
// renders the plain megakernel's paths: the same sums to the bit, AOV
// layers (each path's first hit) and adaptive sampling's pixel lists
// included, with submissions of 1, 2, 4 and 3 samples, so waves of fewer
// samples than an invocation takes. A planted fault is caught: another seed.
TEST_F(Gpu, RegeneratingMegakernelRendersThePlainMegakernelsPaths) {
  for (bool adaptive : {false, true}) {
    SCOPED_TRACE(adaptive ? "adaptive" : "every pixel");
    Scene scene = cornell_box(24);
    RenderOptions o;
    o.spp = 10;
    o.aovs = {"albedo", "normal"};
    if (adaptive) o.adaptive = AdaptiveSampling{4, 0.05f};
    CompiledScene cs = compile_scene(scene, variant_options(o, "gpu-mega-bvh2"));
    WavefrontSettings plain = kernel_variant("gpu-mega-bvh2").settings;
    WavefrontSettings regen = kernel_variant("gpu-mega-bvh2-regen").settings;
    ASSERT_GT(regen.megakernelSamples, 1u);
    plain.targetSubmitSeconds = regen.targetSubmitSeconds = 1e9;
    Progress quiet("", 0, false);
    WavefrontRenderer a(*ctx_, cs, plain), b(*ctx_, cs, regen);
    ImageStats ia = a.render(quiet), ib = b.render(quiet);
    EXPECT_EQ(ia.sum, ib.sum);
    EXPECT_EQ(ia.sumSq, ib.sumSq);
    EXPECT_EQ(ia.count, ib.count);
    EXPECT_EQ(a.stage_times().closestHitRays, b.stage_times().closestHitRays);
    EXPECT_EQ(a.stage_times().shadowRays, b.stage_times().shadowRays);
    o.seed = 3;
    EXPECT_NE(WavefrontRenderer(*ctx_, compile_scene(scene, variant_options(o, "gpu-mega-bvh2")), regen).render(quiet).sum, ia.sum);
  }
  // On lavapipe, paths that four to an invocation would leave each ray too
  // little of the loop budget (64 bounces) are rendered fewer to one, not
  // refused.
  RenderOptions deep;
  deep.spp = 3;
  deep.maxBounces = 64;
  CompiledScene cs = compile_scene(cornell_box(16), variant_options(deep, "gpu-mega-bvh2"));
  WavefrontSettings plain = kernel_variant("gpu-mega-bvh2").settings;
  WavefrontSettings regen = kernel_variant("gpu-mega-bvh2-regen").settings;
  plain.targetSubmitSeconds = regen.targetSubmitSeconds = 1e9;
  Progress quiet("", 0, false);
  EXPECT_EQ(WavefrontRenderer(*ctx_, cs, plain).render(quiet).sum, WavefrontRenderer(*ctx_, cs, regen).render(quiet).sum);
}

// Shadow rays through media are tracked one an invocation
// (connect_through_media), whatever the rays an invocation of the tracing
// kernels (gpu-multiray's 16; gpu's on lavapipe for deep trees): the connect
// dispatch had been sized for 16 a lane, so 15 of 16 shadow rays through
// media were never traced (the media feature scene 95 % dark in
// scripts/check-agreement.sh).
TEST_F(Gpu, ShadowRaysThroughMediaAreAllTracedWhateverTheRaysALane) {
  Scene scene = load_scene(source_path("tests/data/features/media.json"));
  scene.camera.width = 48;
  scene.camera.height = 36;
  RenderOptions o;
  o.spp = 64;
  for (const char* variant : {"gpu-multiray", "gpu-multiray-fetch"}) {
    SCOPED_TRACE(variant);
    o.seed = 1;
    Progress quiet("", 0, false);
    ImageStats gpu = WavefrontRenderer(*ctx_, compile_scene(scene, variant_options(o, variant)), kernel_variant(variant).settings).render(quiet);
    o.seed = 2;
    ImageStats cpu = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
    const CompareResult r = compare_images(gpu, cpu);
    EXPECT_TRUE(r.passed()) << r.summary();
  }
}

TEST_F(Gpu, FurnaceBoxIsAnalytic) {
  expect_furnace_is_analytic([](const CompiledScene& cs) { return render(cs); });
}

TEST_F(Gpu, SphereUnderWhiteSkyIsExactlyHalf) {
  RenderOptions o;
  o.spp = 64;
  ImageStats img = render(source_path("tests/data/sphere-sky.json"), o);
  for (int y = 8; y < 16; ++y)
    for (int x = 8; x < 16; ++x) EXPECT_NEAR(img.mean(size_t(y * img.width + x)).x, 0.5, 1e-5) << x << "," << y;
  EXPECT_NEAR(img.mean(0).x, 1.0, 1e-6);
}

TEST_F(Gpu, CornellBoxAgreesWithTheCpuReference) {
  CompareResult r = gpu_vs_cpu(source_path("scenes/cornell-box.json"), 64, 256, 1.0f);
  EXPECT_TRUE(r.passed()) << r.summary();
  std::printf("%s\n", r.summary().c_str());
}

// The same comparison, shown once to fail: the GPU's radiance scaled by 3 %.
TEST_F(Gpu, ComparisonCatchesAPlantedBiasOfThreePercent) {
  CompareResult r = gpu_vs_cpu(source_path("scenes/cornell-box.json"), 64, 256, 1.03f);
  EXPECT_FALSE(r.passed()) << r.summary();
  EXPECT_NEAR(r.relativeBias, 0.03, 3.0 * r.relativeBiasCi95 + 1e-3);
  std::printf("%s\n", r.summary().c_str());
}

// Quads, triangles, an ellipsoid, a spherical light and a quad light.
TEST_F(Gpu, EveryPrimitiveAndLightKindAgreesWithTheCpuReference) {
  CompareResult r = gpu_vs_cpu(source_path("tests/data/quad-light.json"), 32, 512, 1.0f);
  EXPECT_TRUE(r.passed()) << r.summary();
  std::printf("%s\n", r.summary().c_str());
}

// The power of `wavepath compare`'s default settings, as issue 4 states it:
// on the Cornell box at 128x128 (64 spp each side) a 2 % bias over the whole
// image, and a 10 % bias in one 32x32 region, are detected, and with no bias
// the GPU and the CPU agree in at least 19 of 20 seeds. The biases are planted
// in the GPU's render (plant_bias: every sample of the region scaled).
TEST_F(Gpu, CompareDetectsATwoPercentGlobalBias) {
  CompareResult r = cornell_128(1.02f, glm::uvec4(0, 0, ~0u, ~0u), 1);
  EXPECT_FALSE(r.passed()) << r.summary();
  EXPECT_FALSE(r.meanTestPassed);
}

TEST_F(Gpu, CompareDetectsATenPercentBiasInA32x32Region) {
  CompareResult r = cornell_128(1.10f, glm::uvec4(48, 48, 80, 80), 1);
  EXPECT_FALSE(r.passed()) << r.summary();
  ASSERT_GT(r.failingTiles, 0u);
  for (const TileResult& t : r.tiles) {
    if (!t.failed) continue;
    bool overlaps = t.x0 < 80 && t.x1 > 48 && t.y0 < 80 && t.y1 > 48;
    EXPECT_TRUE(overlaps) << "tile x " << t.x0 << " y " << t.y0 << " failed outside the biased region";
  }
}

// (At 64x64: the comparison's levels do not depend on the image's size,
// and a quarter of the pixels keeps the suite's time.)
TEST_F(Gpu, CompareAgreesWithoutBiasAtLeast19TimesIn20) {
  int agree = 0;
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    CompareResult r = cornell_128(1.0f, glm::uvec4(0, 0, ~0u, ~0u), seed, 64);
    if (r.passed()) ++agree;
    else std::printf("seed %u: %s\n", seed, r.summary().c_str());
  }
  EXPECT_GE(agree, 19);
}

// Every kernel variant must agree with the CPU reference before it is trusted
// (and before the benchmark may time it).
TEST_F(Gpu, EveryKernelVariantAgreesWithTheCpuReference) {
  Scene scene = cornell_box(48);
  RenderOptions o;
  o.spp = 128;
  // Seeds 5 / 6 fell into the comparison's false-positive rate (one tile at
  // z = -3.9, 1 of 9) after the integrator began drawing more random numbers;
  // a 4096-spp comparison showed no bias (+0.15% +- 0.27%).
  o.seed = 7;
  Progress quiet("", 0, false);
  ImageStats cpu = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
  o.seed = 8;
  for (const KernelVariant& v : kernel_variants()) {
    CompiledScene cs = compile_scene(scene, variant_options(o, v.name));  // the variant's BVH layout and build
    WavefrontRenderer r(*ctx_, cs, v.settings);
    CompareResult result = compare_images(r.render(quiet), cpu);
    EXPECT_TRUE(result.passed()) << v.name << ": " << result.summary();
  }
  EXPECT_THROW(kernel_variant("gpu-wg7"), InputError);
}

// Instances (tests/data/gltf/instances.gltf: mirrored, scaled, sheared and
// nested placements, EXT_mesh_gpu_instancing): the kernels' walks through
// the two-level trees find the CPU walks' hits, instance included, for both
// layouts, several rays per invocation and one, the wide stack in registers
// and in its indexed array, nearest first and in octant order, an
// instance's root visited in the iteration that enters it or the next, the
// records read through the texture unit or by loads; and the
// kernel variants render the instanced scene as the CPU reference renders its
// flattened copy.
TEST_F(Gpu, InstancedHitsAreTheCpuWalksHits) {
  Scene scene = load_scene(source_path("tests/data/gltf/instances.gltf"));
  scene.camera.width = scene.camera.height = 48;
  Scene flat = scene;
  flatten_instances(flat);
  std::vector<ShadowRay> rays = random_rays(flat, 8000, 77);
  struct Case {
    const char* name;
    BvhLayout layout;
    bool indexedStack, coherent;
    WideChildOrder order = WideChildOrder::Auto;  // nearest first, in a scene with instances
    bool rootAtEntry = false;
    bool walkLoads = false;
    bool binaryFused = false;
    bool dynamicFetch = false;  // 16 rays a lane, their subgroup's blocks taken from a counter
  };
  for (const Case& c : {Case{"wide, register stack", BvhLayout::Wide, false, false}, Case{"wide, indexed stack", BvhLayout::Wide, true, false},
                        Case{"wide, one ray per invocation", BvhLayout::Wide, false, true},
                        Case{"wide, octant order", BvhLayout::Wide, false, false, WideChildOrder::Octant},
                        Case{"wide, an instance's root visited as it is entered", BvhLayout::Wide, false, false, WideChildOrder::Auto, true},
                        Case{"binary", BvhLayout::Binary, false, false},
                        Case{"wide, loads", BvhLayout::Wide, false, false, WideChildOrder::Auto, false, true},
                        Case{"binary, loads", BvhLayout::Binary, false, false, WideChildOrder::Auto, false, true},
                        Case{"binary, fused", BvhLayout::Binary, false, false, WideChildOrder::Auto, false, false, true},
                        Case{"wide, blocks of rays fetched", BvhLayout::Wide, false, false, WideChildOrder::Auto, false, false, false, true}}) {
    SCOPED_TRACE(c.name);
    RenderOptions options;
    options.bvhLayout = c.layout;
    options.wideChildOrder = c.order;
    options.rootAtEntry = c.rootAtEntry;
    options.binaryFused = c.binaryFused;
    CompiledScene cs = compile_scene(scene, options);
    if (c.indexedStack) cs.params.accel.z = WIDE_REGISTER_STACK + 1u;
    SceneView view = cs.view();
    WavefrontSettings settings;
    settings.walkLoads = c.walkLoads;
    if (c.dynamicFetch) {
      settings.raysPerInvocation = 16;
      settings.dynamicFetch = true;
    }
    WavefrontRenderer renderer(*ctx_, cs, settings);
    uint64_t truncated = 0;
    std::vector<Hit> hits = renderer.cast_rays(rays, &truncated, nullptr, c.coherent);
    EXPECT_EQ(truncated, 0u);
    int instanceHits = 0, differ = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      Hit h;
      ASSERT_EQ(view.trace_ray(rays[i].origin, rays[i].dir, rays[i].tmax, false, h), TRACE_OK);
      if (hits[i].prim != h.prim || hits[i].instance != h.instance) {
        ++differ;  // a ray through a shared edge may take either triangle
        continue;
      }
      if (h.prim == WP_INVALID) continue;
      instanceHits += h.instance != WP_INVALID ? 1 : 0;
      // The ray taken into an instance's space rounds differently where the
      // compiler fuses multiply-adds, which a grazing ray's t magnifies.
      const float tolerance = h.instance != WP_INVALID ? 1e-4f : 1e-5f;
      EXPECT_NEAR(hits[i].t, h.t, tolerance * h.t + 1e-6f) << "ray " << i;
    }
    EXPECT_LE(differ, 4);
    EXPECT_GT(instanceHits, 800);
  }
}

TEST_F(Gpu, InstancedScenesRenderAsTheirFlattenedCopies) {
  Scene scene = load_scene(source_path("tests/data/gltf/instances.gltf"));
  scene.camera.width = 48;
  scene.camera.height = 32;
  Scene flat = scene;
  flatten_instances(flat);
  RenderOptions o;
  o.spp = 64;
  o.seed = 3;
  Progress quiet("", 0, false);
  ImageStats cpu = render_cpu(compile_scene(flat, reference_options(o)), 0, quiet);
  o.seed = 4;
  for (const char* name : {"gpu", "gpu-octant", "gpu-enter-root", "gpu-bvh2", "gpu-mega", "gpu-sort"}) {
    CompiledScene cs = compile_scene(scene, variant_options(o, name));
    ASSERT_NE(cs.params.kinds.w & KIND_BIT(FEATURE_INSTANCES), 0u);
    WavefrontRenderer r(*ctx_, cs, kernel_variant(name).settings);
    CompareResult result = compare_images(r.render(quiet), cpu);
    EXPECT_TRUE(result.passed()) << name << ": " << result.summary();
  }
  // Each pebble placed by the next pebble's transform (an instance paired
  // with the wrong placement): the same places, other shapes and turns. The
  // comparison sees it.
  CompiledScene planted = compile_scene(scene, o);
  std::vector<Instance*> pebbles;
  for (Instance& i : planted.instances)
    if (i.mesh == planted.instances[0].mesh) pebbles.push_back(&i);
  ASSERT_GE(pebbles.size(), 3u);
  const Instance first = *pebbles[0];
  for (size_t k = 0; k < pebbles.size(); ++k) {
    const Instance& next = k + 1 < pebbles.size() ? *pebbles[k + 1] : first;
    Instance& p = *pebbles[k];
    p.toWorld0 = next.toWorld0, p.toWorld1 = next.toWorld1, p.toWorld2 = next.toWorld2;
    p.toObject0 = next.toObject0, p.toObject1 = next.toObject1, p.toObject2 = next.toObject2;
    p.flags = next.flags;
  }
  WavefrontRenderer r(*ctx_, planted);
  EXPECT_FALSE(compare_images(r.render(quiet), cpu).passed()) << "pebbles placed by each other's transforms go unseen";
}

// Per wave, generate and accumulate once, and per bounce pass one
// prepare-extend-shade-prepare-connect sequence, each timed by timestamps. A
// 24x24 image's wave holds all the samples of a submission: the first
// submission takes one sample, the second the other two.
TEST_F(Gpu, StageTimesCoverEveryDispatch) {
  RenderOptions o;
  o.spp = 3;
  o.maxBounces = 2;
  CompiledScene cs = compile_scene(load_scene(source_path("tests/data/furnace.json")), o);
  WavefrontRenderer r(*ctx_, cs);
  Progress quiet("", 0, false);
  r.render(quiet);
  const StageTimes& t = r.stage_times();
  ASSERT_EQ(t.submissions, 2u);
  const uint64_t waves = 2, passes = 3;
  const uint64_t expected[StageTimes::kStages] = {waves, waves * passes * 2, waves * passes, 0, waves * passes, waves * passes, waves, 0};
  for (int s = 0; s < StageTimes::kStages; ++s) {
    EXPECT_EQ(t.dispatches[s], expected[s]) << StageTimes::kNames[s];
    EXPECT_GE(t.seconds[s], 0.0) << StageTimes::kNames[s];
  }
  EXPECT_GT(t.seconds[StageTimes::kExtend], 0.0) << "extend took no time";
  EXPECT_LT(t.total(), 60.0);
}

// Uploads larger than the staging chunk go over in pieces, each at its offset;
// a chunk size that does not divide the data leaves a short last piece. (On
// lavapipe every buffer is mapped and upload() copies directly, so the staged
// path is called by name.)
TEST_F(Gpu, ChunkedUploadsArriveWhole) {
  std::vector<uint32_t> data(10007);
  for (size_t i = 0; i < data.size(); ++i) data[i] = uint32_t(i * 2654435761u);
  const size_t bytes = data.size() * sizeof(uint32_t);
  Buffer device(*ctx_, bytes, vk::BufferUsageFlagBits::eTransferDst | vk::BufferUsageFlagBits::eTransferSrc, false);
  Buffer readback(*ctx_, bytes, vk::BufferUsageFlagBits::eTransferDst, true);
  for (size_t chunk : {size_t(4096), size_t(1000), bytes, bytes * 2}) {
    std::memset(readback.mapped(), 0, bytes);
    ctx_->upload_staged(device, data.data(), bytes, chunk);
    ctx_->run_now([&](vk::CommandBuffer cb) { cb.copyBuffer(device.handle(), readback.handle(), vk::BufferCopy(0, 0, bytes)); });
    EXPECT_EQ(std::memcmp(readback.mapped(), data.data(), bytes), 0) << "chunks of " << chunk << " bytes";
  }
}

// A scene of the project's at most `size` pixels square, compiled with `o`.
CompiledScene compile_cropped(const char* path, int size, const RenderOptions& o) {
  Scene scene = load_scene(source_path(path));
  scene.camera.width = std::min(scene.camera.width, size);
  scene.camera.height = std::min(scene.camera.height, size);
  return compile_scene(scene, o);
}

// Two GPU renders of the same paths: each submission sums its samples in
// float and the number of samples per submission follows the clock, so sums
// agree to rounding, not bit for bit; a lost or repeated path would change a
// pixel by a whole sample. With `squares`, the sums of squares too.
void expect_sums_agree_to_rounding(const ImageStats& a, const ImageStats& b, const std::string& what, bool squares) {
  for (size_t k = 0; k < a.sum.size(); ++k) {
    ASSERT_NEAR(a.sum[k], b.sum[k], 1e-5 * std::max(1.0, std::abs(a.sum[k]))) << what << ", pixel " << k / 3;
    if (squares) {
      ASSERT_NEAR(a.sumSq[k], b.sumSq[k], 1e-5 * std::max(1.0, std::abs(a.sumSq[k]))) << what << ", pixel " << k / 3;
    }
  }
}

// The window's camera changes (update_params): a renderer whose view,
// lens and bounces were changed renders what a new renderer of that view
// renders; a change its kernels were not made for is refused.
TEST_F(Gpu, UpdatedParametersRenderAsANewRenderer) {
  RenderOptions o;
  o.spp = 4;
  o.maxBounces = 3;
  CompiledScene moved = compile_cropped("scenes/cornell-box.json", 48, o);
  Progress quiet("", 0, false);
  WavefrontRenderer renderer(*ctx_, moved);
  ImageStats before = renderer.render(quiet);
  Scene scene = load_scene(source_path("scenes/cornell-box.json"));
  scene.camera.width = scene.camera.height = 48;
  scene.camera.toWorld = glm::translate(glm::mat4(1.0f), glm::vec3(40.0f, -20.0f, 0.0f)) * scene.camera.toWorld;
  scene.camera.apertureRadius = 3.0f;
  scene.camera.focusDistance = 700.0f;
  RenderOptions deeper = o;
  deeper.maxBounces = 5;
  CompiledScene fresh = compile_scene(scene, deeper);
  set_camera_params(scene.camera, moved.params);
  moved.params.image.z = 5;
  renderer.update_params();
  ImageStats a = renderer.render(quiet), b = WavefrontRenderer(*ctx_, fresh).render(quiet);
  EXPECT_NE(before.sum, a.sum) << "the change reached the kernels";
  expect_sums_agree_to_rounding(a, b, "updated", true);
  moved.params.kinds.w ^= KIND_BIT(FEATURE_UNIFORM_HEMISPHERE);
  EXPECT_THROW(renderer.update_params(), RenderError);
}

// Sorting paths by material class (gpu-sort) changes which invocation, and
// which class's kernel, shades which path, never what a path computes: its
// random numbers come from (pixel, sample, seed) and it alone writes its
// state. So the image must be the same, as long as every class's kernel
// holds the kinds of its materials: on the feature scenes of many materials
// (spheres and rays that miss among them), of textures (a textured lamp too)
// and of an environment map, and on a deeper scene.
TEST_F(Gpu, SortingPathsByMaterialLeavesTheImageUnchanged) {
  for (const char* path : {"tests/data/features/materials.json", "tests/data/features/textures.json",
                           "tests/data/features/environment.json", "scenes/bunny-cornell-dof.json"}) {
    RenderOptions o;
    o.spp = 4;
    o.maxBounces = 3;
    CompiledScene cs = compile_cropped(path, 64, o);
    ASSERT_GE(cs.shadeClasses.size(), 3u) << path;
    Progress quiet("", 0, false);
    WavefrontSettings sortedUncompacted = kernel_variant("gpu-sort").settings;
    sortedUncompacted.compaction = false;  // the sort kernel then keeps every path's slot
    WavefrontRenderer plain(*ctx_, cs), sorted(*ctx_, cs, kernel_variant("gpu-sort").settings), uncompacted(*ctx_, cs, sortedUncompacted);
    ImageStats a = plain.render(quiet), b = sorted.render(quiet), c = uncompacted.render(quiet);
    EXPECT_EQ(a.count, b.count) << path;
    EXPECT_EQ(a.count, c.count) << path;
    // A path shaded by another class's kernel would change its pixel by far more than rounding.
    expect_sums_agree_to_rounding(a, b, path, true);
    expect_sums_agree_to_rounding(a, c, std::string(path) + ", uncompacted", false);
    EXPECT_EQ(sorted.stage_times().closestHitRays, plain.stage_times().closestHitRays) << path;
    EXPECT_EQ(sorted.stage_times().shadowRays, plain.stage_times().shadowRays) << path;
    // Per bounce pass: the extra prepare (counts to offsets) and the scatter.
    // A 64x64 image's submission is one wave, whatever its samples.
    const StageTimes& t = sorted.stage_times();
    const uint64_t waves = t.submissions;
    EXPECT_LT(waves, uint64_t(o.spp)) << path << ": samples not packed into waves";
    EXPECT_EQ(t.dispatches[StageTimes::kGenerate], waves) << path;
    EXPECT_EQ(t.dispatches[StageTimes::kSort], waves * uint64_t(o.maxBounces + 1)) << path;
    EXPECT_EQ(t.dispatches[StageTimes::kPrepare], 3 * waves * uint64_t(o.maxBounces + 1)) << path;
    EXPECT_EQ(plain.stage_times().dispatches[StageTimes::kSort], 0u) << path;
  }
}

// The SPIR-V specialized on the host (gpu/specialize.h) against the driver
// specializing it: the same paths, the same rays, the same sums to rounding.
TEST_F(Gpu, SpecializingTheSpirvLeavesTheImageUnchanged) {
  for (const char* path : {"tests/data/features/materials.json", "tests/data/features/layers.json"}) {
    RenderOptions o;
    o.spp = 4;
    o.maxBounces = 4;
    CompiledScene cs = compile_cropped(path, 48, o);
    Progress quiet("", 0, false);
    WavefrontSettings byDriver;
    byDriver.specializeSpirv = false;
    WavefrontRenderer specialized(*ctx_, cs), unspecialized(*ctx_, cs, byDriver);
    ImageStats a = specialized.render(quiet), b = unspecialized.render(quiet);
    ASSERT_EQ(a.count, b.count) << path;
    expect_sums_agree_to_rounding(a, b, path, false);
    EXPECT_EQ(specialized.stage_times().closestHitRays, unspecialized.stage_times().closestHitRays) << path;
    EXPECT_EQ(specialized.stage_times().shadowRays, unspecialized.stage_times().shadowRays) << path;
  }
}

// Rays traced: every variant traces the same paths, so the same rays,
// however it counts them (the queue sizes in prepare with compaction, per ray
// in extend without, per path in the megakernel). Every path casts its camera
// ray and at most one more per bounce; a shadow ray needs a vertex.
TEST_F(Gpu, EveryVariantCountsTheSameRays) {
  Scene scene = cornell_box(32);
  RenderOptions o;
  o.spp = 4;
  o.maxBounces = 3;
  CompiledScene cs = compile_scene(scene, o);
  const uint64_t paths = 32 * 32 * 4;
  Progress quiet("", 0, false);
  WavefrontRenderer plain(*ctx_, cs);
  plain.render(quiet);
  const StageTimes& base = plain.stage_times();
  EXPECT_GT(base.closestHitRays, paths);
  EXPECT_LE(base.closestHitRays, paths * uint64_t(o.maxBounces + 1));
  EXPECT_GT(base.shadowRays, 0u);
  EXPECT_LE(base.shadowRays, base.closestHitRays);
  for (const char* name : {"gpu-nocompact", "gpu-mega", "gpu-sort"}) {
    WavefrontRenderer r(*ctx_, cs, kernel_variant(name).settings);
    r.render(quiet);
    EXPECT_EQ(r.stage_times().closestHitRays, base.closestHitRays) << name;
    EXPECT_EQ(r.stage_times().shadowRays, base.shadowRays) << name;
  }
}

// No races: each pixel's samples depend only on (pixel, sample, seed).
// A device adds a submission's samples in float, and how many samples a
// submission takes follows its measured time (render_samples): two renders
// of one seed group them alike, and so are equal to the bit, only where the
// grouping is fixed, as here (one sample a submission). Timed, a loaded
// machine can group them otherwise, which once failed this test; such
// renders differ within the bound docs/partial-renders.md gives
// (GpuPartial.SplitsAndResumedRendersMatchTheWholeRenderWithinTheBound).
// Another seed's image differs: the equality can fail.
TEST_F(Gpu, SameSeedSameImageOtherSeedOtherImage) {
  Scene scene = cornell_box(32);
  RenderOptions o;
  o.spp = 8;
  WavefrontSettings fixed;
  fixed.targetSubmitSeconds = 0.0;
  auto render_fixed = [&](const CompiledScene& cs) {
    WavefrontRenderer r(*ctx_, cs, fixed);
    Progress quiet("", 0, false);
    return r.render(quiet);
  };
  ImageStats a = render_fixed(compile_scene(scene, o)), b = render_fixed(compile_scene(scene, o));
  o.seed = 9;
  ImageStats c = render_fixed(compile_scene(scene, o));
  EXPECT_EQ(a.sum, b.sum);
  EXPECT_NE(a.sum, c.sum);
}

// A small image's wave holds several samples (samples_per_wave), and the
// accumulate kernel adds each pixel's in order: the sums are those of one
// sample a wave to the bit, with AOV layers, with adaptive sampling's pixel
// lists, and where a submission's samples end in a part-full wave (100x100:
// 6 samples a wave). The submissions grow 1, 2, 4, ... samples alike in both
// (a target no submission reaches), so they group the samples alike; another
// seed's sums differ.
TEST_F(Gpu, SamplesPackedIntoWavesGiveTheSumsOfOneSampleAWave) {
  const struct { int size; bool adaptive; } cases[] = {{24, false}, {24, true}, {100, false}};
  for (const auto& [size, adaptive] : cases) {
    SCOPED_TRACE(std::to_string(size) + (adaptive ? ", adaptive" : ""));
    Scene scene = cornell_box(size);
    RenderOptions o;
    o.spp = 24;
    o.aovs = {"albedo", "normal"};
    if (adaptive) o.adaptive = AdaptiveSampling{8, 0.05f};
    CompiledScene cs = compile_scene(scene, o);
    WavefrontSettings packed;
    packed.targetSubmitSeconds = 1e9;
    WavefrontSettings single = packed;
    single.maxPathsPerWave = uint32_t(size * size);
    Progress quiet("", 0, false);
    ImageStats a = WavefrontRenderer(*ctx_, cs, packed).render(quiet);
    ImageStats b = WavefrontRenderer(*ctx_, cs, single).render(quiet);
    EXPECT_EQ(a.sum, b.sum);
    EXPECT_EQ(a.sumSq, b.sumSq);
    EXPECT_EQ(a.count, b.count);
    o.seed = 3;
    EXPECT_NE(WavefrontRenderer(*ctx_, compile_scene(scene, o), packed).render(quiet).sum, a.sum);
  }
}

// Every material, texture, light type and integrator of the course feature
// set, each on a small scene that exercises it: the GPU agrees with the CPU
// reference statistically (same shared code, independent seeds).
struct FeatureCase {
  const char* scene;  // under tests/data/features/
  std::optional<IntegratorKind> integrator;
  const char* what;
  int size = 0;  // rendered size x size, or 0: the scene's own
  void (*adjust)(Scene&) = nullptr;  // a reading of the scene a render option selects
  int spp = 64;  // per side: more where small bright reflections make the image's mean heavy-tailed
};

// A feature case's scene, as its options read it.
Scene feature_scene(const FeatureCase& c) {
  Scene s = load_scene(source_path(std::string("tests/data/features/") + c.scene));
  if (c.size > 0) s.camera.width = s.camera.height = c.size;
  if (c.adjust) c.adjust(s);
  return s;
}

const FeatureCase kFeatureCases[] = {
    {"materials.json", IntegratorKind::PathMis, "metal, mirror, glass, phong, blinn-phong, fresnel blend; quad, sphere and point lights (mis)"},
    {"materials.json", IntegratorKind::PathNee, "the same, path tracer nee"},
    {"materials.json", IntegratorKind::PathMats, "the same, path tracer mats"},
    {"materials.json", IntegratorKind::PathMixture, "the same, path tracer mixture"},
    {"materials.json", IntegratorKind::Normals, "normals"},
    {"materials.json", IntegratorKind::AmbientOcclusion, "ambient occlusion"},
    {"textures.json", std::nullopt, "image, marble and nested checker textures, uv and solid mappings, a checker-textured lamp"},
    {"smooth-mesh.json", std::nullopt, "OBJ with vertex normals and UVs (smooth shading)"},
    {"integrators.json", IntegratorKind::PathMixture, "mixture with rough metal, phong, quad and sphere lights"},
    {"integrators.json", IntegratorKind::PathMats, "mats with rough metal, phong, quad and sphere lights"},
    {"environment.json", IntegratorKind::PathMis, "HDR environment map, importance-sampled (mis)"},
    {"environment.json", IntegratorKind::PathMixture, "HDR environment map (mixture)"},
    {"integrators.json", IntegratorKind::PathHemisphere, "uniform hemisphere sampling (CS184 -H)"},
    {"camera.json", std::nullopt, "thin lens (aperture, focus distance), cmj sampler, 2:1 image"},
    {"microfacet.json", IntegratorKind::PathMis,
     "GGX: rough conductor and its smooth limit, rough and tinted dielectrics, metal-rough with a metallic-roughness "
     "texture, a blend with a transmissive lobe (mis)"},
    {"microfacet.json", IntegratorKind::PathMixture, "the GGX materials, path tracer mixture"},
    {"punctual.json", IntegratorKind::PathMis, "a spot light between its cones and a directional light (mis)"},
    {"dispersion.json", IntegratorKind::PathMis, "the spectral mode: glass dispersing each wavelength by its own index (mis)", 0,
     [](Scene& s) { s.integrator.spectral = true; }},
    {"materials.json", IntegratorKind::PathMis,
     "the spectral mode: coloured lobes and a fresnel blend (the uplift table for reflectances), a point light's falloff "
     "(the table for light) (mis)",
     0, [](Scene& s) { s.integrator.spectral = true; }},
    {"metals.json", IntegratorKind::PathMis, "measured metals by name, in RGB their spectra's projections (mis)"},
    {"microfacet.json", IntegratorKind::PathMats, "the GGX materials, path tracer mats"},
    {"layers.json", IntegratorKind::PathMis,
     "glTF's layers: clear coats (textured factor, own ior) over metal-rough, a sheen over metal-rough and under a coat, "
     "KHR_materials_specular's factor and colour, constant and textured, a thin film of textured thickness "
     "(KHR_materials_iridescence), an anisotropic metal (KHR_materials_anisotropy) (mis)",
     0, nullptr, 256},
    {"layers.json", IntegratorKind::PathMixture, "glTF's layers, path tracer mixture", 0, nullptr, 256},
    {"volume.json", IntegratorKind::PathMis,
     "KHR_materials_volume: smooth and rough glass refracting into absorbing volumes, one under a clear coat, one of "
     "scattering particles (KHR_materials_volume_scatter), and a thin-walled pane (mis)"},
    {"translucent.json", IntegratorKind::PathMis,
     "KHR_materials_diffuse_transmission: backlit leaf and paper of textured factor and colour, a wax ball transmitting "
     "diffusely into an absorbing volume, a shade mixing it with specular transmission, under a sun and a light behind (mis)"},
    {"dispersion.json", IntegratorKind::PathMis,
     "KHR_materials_dispersion: a smooth flint ball splitting the glowing checker board behind it into its colours, a "
     "rough tinted one (mis)"},
    {"../gltf/surface.glb", IntegratorKind::PathMis,
     "glTF surfaces: normal maps (given and derived tangents), vertex colours, a second UV set with clamped and mirrored "
     "wrapping, MASK and BLEND alpha, a one-sided wall, thin-walled transmission",
     40},
    {"../collada/lights.dae", std::nullopt,
     "CS184: its estimator, point light without falloff, directional and ambient (hemisphere) lights, microfacet gold, "
     "refraction",
     32},
    {"../collada/cornell.dae", std::nullopt,
     "CS184 3-2's scene: the lamp mesh black, the area light a visible quad of cosine emission seen in the mirror ball",
     40, use_cs184_3_2_skeleton},
    {"media.json", IntegratorKind::PathMis,
     "participating media: the camera in a thin haze, a chromatic forward-scattering smoke with null particles behind an "
     "interface, a milky medium inside a water ball, a vacuum bubble (mis)"},
    {"media.json", IntegratorKind::PathNee, "participating media, path tracer nee"},
    {"media.json", IntegratorKind::PathMats, "participating media, path tracer mats"},
    {"media-grid.json", IntegratorKind::PathMis,
     "grid media (NanoVDB): a chromatic plume behind an interface, and the same grid rotated under one majorant, in a "
     "haze (mis)"},
    {"media-grid.json", IntegratorKind::PathNee, "grid media, path tracer nee"},
    {"media-grid.json", IntegratorKind::PathMats, "grid media, path tracer mats"},
    {"photons.json", IntegratorKind::PhotonMapper,
     "the photon mapper: caustics of a glass ball and a mirror ball on a diffuse floor under a sphere light, k-nearest gather"},
    {"../gltf/instances.gltf", IntegratorKind::PathMis,
     "instances: meshes placed by several glTF nodes (mirrored, stretched, sheared, nested) and by EXT_mesh_gpu_instancing, "
     "one-sided and normal-mapped, lit by emissive quads placed twice (mis)",
     40},
    {"../gltf/translucent.glb", IntegratorKind::PathMis,
     "KHR_materials_diffuse_transmission laid out as the Khronos DiffuseTransmissionTest: backlit panes of rising factor, "
     "colour factor, factor texture (alpha) and colour texture (sRGB)",
     40},
    {"../gltf/layers.glb", IntegratorKind::PathMis,
     "glTF's clear coat (textured, its own normal map), sheen (textured colour and roughness), specular (textured), thin "
     "film, anisotropy and a dispersive volume under a sun",
     40},
};

// CS184's scenes (tests/data/collada): the course's estimator (lights no
// ray meets, emissive meshes only the camera sees, both-sided emission, its
// Russian roulette, the environment in its layout seen from the camera
// alone), -H, its hemisphere and falloff-free point lights, and the
// physical reading.
TEST_F(Gpu, Cs184ScenesAgreeWithTheCpuReference) {
  struct Cs184Case {
    const char* scene;
    std::optional<IntegratorKind> integrator;
    bool consistent, environment;
    const char* what;
  };
  const Cs184Case cases[] = {
      {"cornell.dae", std::nullopt, false, false, "the course's estimator: area light, lamp mesh, mirror and glass balls"},
      {"cornell.dae", IntegratorKind::PathHemisphere, false, false, "-H"},
      {"lights.dae", std::nullopt, false, true, "point, directional and ambient lights, microfacet gold, refraction, a CS184 environment map"},
      {"cornell.dae", std::nullopt, true, false, "--consistent-lights"},
      // One light kind alone, as CS184's CBempty.dae has a lone <point>: the
      // kernels compile only that kind. The no-falloff flag and the ambient
      // light's zenith once lived in PointLight.direction, which the kernels
      // loaded only where spot or directional lights were compiled, so the
      // lone point light fell off as 1/d^2 (CBempty 43 % dark) and the lone
      // ambient light shone from below (types.glsl, LIGHTS_READING_DIRECTION).
      {"lone-point.dae", std::nullopt, false, false, "a lone point light (no falloff)"},
      {"lone-point.dae", std::nullopt, true, false, "a lone point light, --consistent-lights"},
      {"lone-ambient.dae", std::nullopt, false, false, "a lone ambient light"},
  };
  for (const Cs184Case& c : cases) {
    Scene scene = load_scene(source_path(std::string("tests/data/collada/") + c.scene));
    if (c.consistent) use_consistent_lights(scene);
    if (c.environment) scene.environment = add_image_texture(scene, source_path("tests/data/features/sky.hdr"), "test");
    scene.camera.width = 40;  // the whole frame, small
    scene.camera.height = 30;
    RenderOptions o;
    o.integrator = c.integrator;
    o.spp = 64;
    o.maxBounces = 5;
    CompareResult r = gpu_against_cpu(scene, o);
    EXPECT_TRUE(r.passed()) << c.what << ": " << r.summary();
    EXPECT_GT(r.meanB, 0.01) << c.what << ": lit";
  }
}

TEST_F(Gpu, EveryFeatureAgreesWithTheCpuReference) {
  for (const FeatureCase& c : kFeatureCases) {
    RenderOptions o;
    o.integrator = c.integrator;
    o.spp = c.spp;
    CompareResult r = gpu_against_cpu(feature_scene(c), o);
    EXPECT_TRUE(r.passed()) << c.what << ": " << r.summary();
  }
}

// glTF models (tests/data/gltf/, scripts/make-gltf-test-assets.py): a node
// tree of metal-rough boxes, an emissive panel and a point light; a binary
// model with base colour and metallic-roughness textures under the white sky.
TEST_F(Gpu, GltfModelsAgreeWithTheCpuReference) {
  for (const char* model : {"box-room.gltf", "textured.glb"}) {
    CompareResult r = gpu_vs_cpu(source_path(std::string("tests/data/gltf/") + model), 40, 128, 1.0f);
    EXPECT_TRUE(r.passed()) << model << ": " << r.summary();
  }
}

// Every kind of every table in kinds.glsl is used by a feature case, and
// its code is needed: with the kind's bit cleared from the scene's masks (as
// a forgotten bit would), the kernels render an image the CPU reference
// disagrees with, in the first case that uses it or a later one. (With the masks as compiled, EveryFeatureAgreesWithTheCpuReference
// shows agreement.) A kind added to a table without a feature scene that
// uses it fails here.
TEST_F(Gpu, EveryKindIsUsedByAFeatureSceneAndCompilingItOutIsCaught) {
  struct Table {
    const std::vector<KindInfo>* kinds;
    int mask;  // its component of SceneParams.kinds
    const char* what;
  };
  const Table tables[] = {{&material_kinds(), 0, "material"}, {&texture_kinds(), 1, "texture"}, {&light_kinds(), 2, "light"},
                          {&feature_kinds(), 3, "feature"}};
  // Kinds whose absence no comparison can see: the code of a light material
  // (one comparison: it scatters nothing) and of a constant texture (what
  // every lookup ends in) is never compiled out; without CMJ or uniform
  // hemisphere sampling the kernels sample independently or by the BSDF,
  // unbiased too (Scene.KindMasksNameWhatTheSceneUses checks those bits).
  auto unobservable = [](int mask, uint32_t id) {
    return (mask == 0 && id == MAT_LIGHT) || (mask == 1 && id == TEX_CONSTANT) ||
           (mask == 3 && (id == FEATURE_CMJ || id == FEATURE_UNIFORM_HEMISPHERE));
  };
  Progress quiet("", 0, false);
  // Each feature case compiled once (for the GPU) and its CPU reference
  // rendered on first use.
  auto options = [](size_t c, uint32_t seed) {
    RenderOptions o;
    o.spp = 128;  // the fresnel blend covers a few pixels of its scene
    o.seed = seed;
    o.integrator = kFeatureCases[c].integrator;
    return o;
  };
  auto scene_of = [](size_t c) { return feature_scene(kFeatureCases[c]); };
  std::vector<CompiledScene> compiled;
  for (size_t c = 0; c < std::size(kFeatureCases); ++c) compiled.push_back(compile_scene(scene_of(c), options(c, 1)));
  std::map<size_t, ImageStats> cpu;
  for (const Table& t : tables) {
    for (const KindInfo& k : *t.kinds) {
      // The scenes that use it, in order, until one shows its absence.
      bool used = false, caught = false;
      std::string unnoticed;
      for (size_t c = 0; c < compiled.size() && !caught; ++c) {
        if (!(compiled[c].params.kinds[t.mask] & KIND_BIT(k.id))) continue;
        used = true;
        if (unobservable(t.mask, k.id)) break;
        if (!cpu.count(c)) cpu[c] = render_cpu(compile_scene(scene_of(c), reference_options(options(c, 2))), 0, quiet);
        CompiledScene cs = compiled[c];
        cs.params.kinds[t.mask] &= ~KIND_BIT(k.id);
        CompareResult r = compare_images(render(cs), cpu[c]);
        caught = !r.passed();
        unnoticed += std::string("\n  ") + kFeatureCases[c].scene + ": " + r.summary();
      }
      ASSERT_TRUE(used) << "no feature scene uses " << t.what << " kind " << k.name;
      EXPECT_TRUE(caught || unobservable(t.mask, k.id)) << t.what << " kind " << k.name
                                                        << " compiled out of the feature scenes that use it went unnoticed:" << unnoticed;
    }
  }
}

// A slab of chromatic medium with null particles, lit through its
// interface by a sun and a sphere light, over a floor, and a chromatic
// plume of grid medium against a white sky: the kernels agree with the CPU
// reference (delta tracking of paths, ratio tracking of shadow rays), and
// the comparison sees coefficients 5 % off on the GPU.
TEST_F(Gpu, MediaAgreeWithTheCpuReferenceAndAPlantedSigmaErrorIsCaught) {
  for (const char* file : {"tests/data/media-slab.json", "tests/data/media-grid-plume.json"}) {
    Scene scene = load_scene(source_path(file));
    RenderOptions o;
    o.spp = 256;
    CompareResult r = gpu_against_cpu(scene, o);
    EXPECT_TRUE(r.passed()) << file << ": " << r.summary();
    Progress quiet("", 0, false);
    RenderOptions co = o;
    co.seed = 2;
    ImageStats cpu = render_cpu(compile_scene(scene, reference_options(co)), 0, quiet);
    for (SceneMedium& m : scene.media) {
      m.sigmaA *= 1.05f;
      m.sigmaS *= 1.05f;
    }
    o.seed = 1;
    CompareResult planted = compare_images(render(compile_scene(scene, o)), cpu);
    EXPECT_FALSE(planted.passed()) << file << ": sigma 5 % off went unnoticed: " << planted.summary();
  }
}

// The photons kernel traces the host's photons (the code is shared): photon
// by photon the same records, to rounding. A GPU may fuse multiply-adds, so
// now and then a photon's Russian roulette or a grazing hit goes the other
// way; every other photon's records agree. Traced with another seed, they
// do not. In RGB and in the spectral mode (each photon's wavelengths, and
// its power stored in RGB).
TEST_F(Gpu, PhotonsTracedByTheKernelsAreTheHostsToRounding) {
  for (bool spectral : {false, true}) {
    SCOPED_TRACE(spectral ? "spectral" : "RGB");
    RenderOptions options;
    options.spectral = spectral;
    CompiledScene cs = compile_scene(load_scene(source_path("tests/data/features/photons.json")), options);
    cs.photonCount = 30000;  // several batches of the renderer's path slots
    const std::vector<shader::Photon> host = trace_photons(cs);
    WavefrontRenderer renderer(*ctx_, cs);
    auto by_photon = [](const std::vector<shader::Photon>& records) {
      std::map<uint32_t, std::vector<shader::Photon>> m;
      uint32_t last = 0;
      for (const shader::Photon& p : records) {
        EXPECT_GE(p.axis, last) << "records out of photon order";
        last = p.axis;
        m[p.axis].push_back(p);
      }
      return m;
    };
    auto same = [](const std::vector<shader::Photon>& a, const std::vector<shader::Photon>& b) {
      if (a.size() != b.size()) return false;
      for (size_t i = 0; i < a.size(); ++i) {
        if (glm::length(a[i].position - b[i].position) > 1e-3f) return false;
        if (glm::length(a[i].power - b[i].power) > 1e-4f * glm::length(a[i].power)) return false;
      }
      return true;
    };
    const auto hostPhotons = by_photon(host);
    ASSERT_GT(hostPhotons.size(), 1000u);
    auto agreeing = [&](uint32_t seed) {
      const auto gpuPhotons = by_photon(renderer.trace_photons(cs.photonCount, seed));
      size_t agree = 0;
      for (const auto& [photon, records] : hostPhotons) {
        auto found = gpuPhotons.find(photon);
        agree += found != gpuPhotons.end() && same(records, found->second);
      }
      return double(agree) / double(hostPhotons.size());
    };
    const double sameSeed = agreeing(cs.photonSeed), otherSeed = agreeing(cs.photonSeed + 1);
    std::printf("photons whose records agree: %.4f (seed + 1: %.4f)\n", sameSeed, otherSeed);
    EXPECT_GE(sameSeed, 0.995);
    EXPECT_LT(otherSeed, 0.05) << "photons of another seed agreed";
  }
}

// A photon map the kernels traced (RenderOptions::photonsOnHost false,
// PhotonPass::Kernels, which lavapipe would leave to the host) renders the
// image the host's map does; the same comparison sees a map whose photons
// are 5 % too strong. The CPU reference refuses a scene whose map was left
// to a GPU.
TEST_F(Gpu, APhotonMapTracedByTheKernelsRendersAsTheHostsMap) {
  Scene scene = load_scene(source_path("tests/data/features/photons.json"));
  RenderOptions o;
  o.spp = 64;
  o.seed = 1;
  o.photonsOnHost = false;
  CompiledScene onDevice = compile_scene(scene, o);
  ASSERT_TRUE(onDevice.photonMapLeftToDevice);
  ASSERT_TRUE(onDevice.photons.empty());
  WavefrontSettings kernels;
  kernels.photonPass = PhotonPass::Kernels;
  Progress quiet("", 0, false);
  ImageStats gpu = WavefrontRenderer(*ctx_, onDevice, kernels).render(quiet);
  EXPECT_THROW(render_cpu(onDevice, 0, quiet), RenderError);
  o.seed = 2;
  CompiledScene host = compile_scene(scene, reference_options(o));
  CompareResult r = compare_images(gpu, render_cpu(host, 0, quiet));
  EXPECT_TRUE(r.passed()) << r.summary();
  for (shader::Photon& p : host.photons) p.power *= 1.05f;
  CompareResult planted = compare_images(gpu, render_cpu(host, 0, quiet));
  EXPECT_FALSE(planted.passed()) << "photons 5 % too strong went unnoticed: " << planted.summary();
}

// The same comparison has the power to see a 5% bias planted on the GPU in
// the feature scene.
TEST_F(Gpu, FeatureComparisonCatchesAPlantedBias) {
  CompareResult r = gpu_vs_cpu(source_path("tests/data/features/materials.json"), 0, 64, 1.05f, IntegratorKind::PathMis);
  EXPECT_FALSE(r.passed()) << "a 5% bias went unnoticed: " << r.summary();
}

// The GLSL texture code against its C++ compilation, query by query: the
// kernels and the CPU reference must see the same textures. Constants agree
// exactly. Checker and image lookups agree to rounding: a GPU compiler may
// fuse multiply-adds (the Vulkan spec allows it), which moves a bilinear
// weight by an ulp of the texel coordinate (measured: 0 on lavapipe, 1.2e-7
// on an H100); a checker cell picked wrongly, or a texel off by one, differs by far
// more. Marble, built on sin and seven octaves of noise, within 1e-5 (the
// GPU's sin may differ from the C library's in the last bits; measured: 6e-8
// on lavapipe, 2.4e-6 on an H100).
TEST_F(Gpu, TextureLookupsMatchTheCpuCode) {
  Scene scene = load_scene(source_path("tests/data/features/textures.json"));
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  ShaderMath m;
  uint32_t state = 2024;
  std::vector<WavefrontRenderer::TextureQuery> queries;
  for (uint32_t t = 0; t < cs.textures.size(); ++t) {
    if ((cs.textures[t].info.x & TEX_TYPE_MASK) == TEX_FRESNEL) continue;
    for (int k = 0; k < 2000; ++k) {
      glm::vec2 uv(m.rng_next(state) * 4.0f - 2.0f, m.rng_next(state) * 4.0f - 2.0f);
      glm::vec3 p(m.rng_next(state) * 6.0f - 3.0f, m.rng_next(state) * 6.0f - 3.0f, m.rng_next(state) * 6.0f - 3.0f);
      queries.push_back({t, uv, p});
    }
  }
  WavefrontRenderer renderer(*ctx_, cs);
  std::vector<glm::vec3> gpu = renderer.eval_textures(queries);
  ASSERT_EQ(gpu.size(), queries.size());
  float worst[4] = {};  // by texture type: constant, checker, marble, image
  for (size_t i = 0; i < queries.size(); ++i) {
    glm::vec3 cpu = view.texture_eval(queries[i].texture, glm::vec4(queries[i].uv, queries[i].uv), queries[i].p);
    float err = glm::max(glm::abs(cpu.x - gpu[i].x), glm::max(glm::abs(cpu.y - gpu[i].y), glm::abs(cpu.z - gpu[i].z)));
    uint32_t type = cs.textures[queries[i].texture].info.x & TEX_TYPE_MASK;
    ASSERT_LT(type, 4u);
    worst[type] = std::max(worst[type], err);
  }
  EXPECT_EQ(worst[TEX_CONSTANT], 0.0f) << "constant";
  EXPECT_LE(worst[TEX_CHECKER], 1e-4f) << "checker";
  EXPECT_LE(worst[TEX_IMAGE], 1e-4f) << "image";
  EXPECT_LE(worst[TEX_MARBLE], 1e-5f) << "marble";
  std::printf("worst differences: checker %g, image %g, marble %g\n", worst[TEX_CHECKER], worst[TEX_IMAGE], worst[TEX_MARBLE]);
}

// Adaptive sampling on the GPU makes the CPU reference's decisions (the same
// samples reach the same confidence intervals; measured: 96% of pixels stop
// at the same count, the rest differ where float rounding sent a path another
// way) and estimates the same image.
TEST_F(Gpu, AdaptiveSamplingMatchesTheCpuReference) {
  Scene scene = load_scene(source_path("tests/data/features/integrators.json"));
  RenderOptions o = adaptive_options(256);
  o.seed = 5;
  CompiledScene cs = compile_scene(scene, o);
  ImageStats gpu = render(cs);
  Progress quiet("", 0, false);
  ImageStats cpuSame = render_cpu(cs, 0, quiet);
  size_t sameCount = 0;
  double gpuTotal = 0.0;
  for (size_t p = 0; p < gpu.pixels(); ++p) {
    sameCount += gpu.count[p] == cpuSame.count[p];
    gpuTotal += gpu.count[p];
  }
  EXPECT_GE(double(sameCount), 0.9 * double(gpu.pixels()));
  EXPECT_LT(gpuTotal, 0.9 * 256.0 * double(gpu.pixels())) << "adaptive sampling saved nothing";
  o.seed = 6;
  ImageStats cpu = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
  CompareResult r = compare_images(gpu, cpu);
  EXPECT_TRUE(r.passed()) << r.summary();
}

// Several light samples per vertex on the GPU (shadow rays of one path added
// with float atomics) against the CPU reference.
TEST_F(Gpu, SeveralLightSamplesPerVertexMatchTheCpuReference) {
  ASSERT_TRUE(ctx_->info().floatAtomicAdd) << "lavapipe and the H100 both have VK_EXT_shader_atomic_float";
  RenderOptions o;
  o.spp = 64;
  o.lightSamples = 4;
  CompareResult r = gpu_against_cpu(load_scene(source_path("tests/data/features/materials.json")), o);
  EXPECT_TRUE(r.passed()) << r.summary();
}

// The balance heuristic (darts "power": 1) on the GPU against the CPU.
TEST_F(Gpu, BalanceHeuristicMatchesTheCpuReference) {
  Scene scene = load_scene(source_path("tests/data/features/integrators.json"));
  scene.integrator.misPower = 1.0f;
  RenderOptions o;
  o.spp = 64;
  CompareResult r = gpu_against_cpu(scene, o);
  EXPECT_TRUE(r.passed()) << r.summary();
}

// darts' test files run through probe.comp: they pass on the kernels, and,
// drawing the same random numbers, their histograms and pdfs are the CPU
// reference's (a direction may land in the next cell where float rounding
// differs).
TEST(GpuDarts, TestFilesRunOnTheKernelsAsOnTheCpuReference) {
  const std::string tests = R"({"type": "tests", "tests": [
    {"type": "sample material", "name": "phong", "material": {"type": "phong", "exponent": 9}, "normal": [0.2, 0, 1],
     "image size": [48, 24], "spp": 100},
    {"type": "scatter material", "name": "metal", "material": {"type": "metal", "roughness": 0.3}, "normal": [0, 0, 1],
     "image size": [48, 24], "spp": 100},
    {"type": "sample surface", "name": "group", "image size": [48, 24], "spp": 100, "surfaces": {"type": "group", "children": [
      {"type": "sphere", "transform": {"translate": [0, 0, 3]}, "material": {"type": "diffuse_light", "emit": 1}},
      {"type": "triangle", "positions": [[-1, -1, -1], [1, -1, -1], [0, 1, -1]], "material": {"type": "lambertian"}}]}},
    {"type": "intersection", "surface": {"type": "sphere", "material": {"type": "lambertian"}},
     "ray": {"origin": [0, 0, 5], "direction": [0, 0, -2]}, "t": 2, "p": [0, 0, 1], "gn": [0, 0, 1], "sn": [0, 0, 1]}]})";
  std::map<bool, std::string> dir;
  for (bool cpu : {false, true}) {
    dir[cpu] = scratch_path(cpu ? "cpu" : "gpu");
    std::filesystem::create_directories(dir[cpu]);
    std::ofstream(dir[cpu] + "/tests.json") << tests;
    DartsTestOptions o;
    o.cpu = cpu;
    for (const DartsTestResult& r : run_darts_tests(dir[cpu] + "/tests.json", o, nullptr))
      EXPECT_TRUE(r.passed) << (cpu ? "cpu " : "gpu ") << r.name << ": " << r.message;
  }
  for (const char* image : {"phong-sampled.exr", "phong-pdf.exr", "metal-sampled.exr", "group-sampled.exr", "group-pdf.exr"}) {
    int w = 0, h = 0;
    std::vector<float> a = read_exr_red_channel(dir[false] + "/" + image, w, h), b = read_exr_red_channel(dir[true] + "/" + image, w, h);
    ASSERT_EQ(a.size(), b.size()) << image;
    ASSERT_FALSE(a.empty()) << image;
    double total = 0.0, differs = 0.0;
    for (size_t p = 0; p < a.size(); ++p) {
      total += b[p];
      differs += std::fabs(a[p] - b[p]);
    }
    EXPECT_LT(differs, 1e-3 * total) << image;
  }
}

// The histogram image holds every sample a test draws, as darts' does,
// whatever share of them the chi-square takes: for a quad, a triangle and a
// sphere whose pdfs cap the chi-square at 12-70 % of the 819200 samples, the
// histogram integrates over the sphere to what the pdf integrates to, on
// the kernels and on the CPU reference. (The surfaces keep away from the
// poles, where darts' float weights make single samples count 1e8 times:
// direction_test.cpp.)
TEST(GpuDarts, HistogramImagesHoldEverySampleWhateverTheChiSquareTakes) {
  const std::string tests = R"({"type": "tests", "tests": [
    {"type": "sample surface", "name": "quad", "image size": [64, 32], "spp": 400,
     "surface": {"type": "quad", "size": [1.2, 1.2], "transform": {"o": [0.9, 0.2, 0.3], "x": [0, 1, 0], "y": [0, 0, 1], "z": [1, 0, 0]},
                 "material": {"type": "diffuse_light", "emit": 1}}},
    {"type": "sample surface", "name": "triangle", "image size": [64, 32], "spp": 400,
     "surface": {"type": "triangle", "positions": [[-0.6, 0.9, -0.5], [0.7, 1.0, -0.4], [-0.4, 0.8, 0.6]],
                 "material": {"type": "diffuse_light", "emit": 1}}},
    {"type": "sample surface", "name": "sphere", "image size": [64, 32], "spp": 400,
     "surface": {"type": "sphere", "radius": 0.6, "transform": {"o": [-1.2, -0.5, 0.2]},
                 "material": {"type": "diffuse_light", "emit": 1}}}]})";
  for (bool cpu : {false, true}) {
    const std::string dir = scratch_path(cpu ? "histogram-cpu" : "histogram-gpu");
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/tests.json") << tests;
    DartsTestOptions o;
    o.cpu = cpu;
    char* said = nullptr;
    size_t saidSize = 0;
    FILE* log = open_memstream(&said, &saidSize);
    for (const DartsTestResult& r : run_darts_tests(dir + "/tests.json", o, log))
      EXPECT_TRUE(r.passed) << (cpu ? "cpu " : "gpu ") << r.name << ": " << r.message;
    std::fclose(log);
    const std::string text(said, saidSize);
    std::free(said);
    // Each chi-square capped, so that the test means something.
    size_t capped = 0;
    for (size_t at = text.find("chi-square of the first "); at != std::string::npos; at = text.find("chi-square of the first ", at + 1))
      capped += std::stoull(text.substr(at + 24)) < 819200;
    EXPECT_EQ(capped, 3u) << text;
    for (const char* name : {"quad", "triangle", "sphere"}) {
      // Integrals over the sphere, cell by cell (64x32 cells drawn 4x4 pixels each).
      double integral[2] = {0.0, 0.0};
      for (int k = 0; k < 2; ++k) {
        int w = 0, h = 0;
        std::vector<float> v = read_exr_red_channel(dir + "/" + name + (k == 0 ? "-sampled.exr" : "-pdf.exr"), w, h);
        ASSERT_EQ(w, 256) << name;
        for (int y = 0; y < 32; ++y) {
          const double solidAngle = (std::cos(y * M_PI / 32) - std::cos((y + 1) * M_PI / 32)) * 2.0 * M_PI / 64;
          for (int x = 0; x < 64; ++x) integral[k] += double(v[size_t(4 * y) * size_t(w) + size_t(4 * x)]) * solidAngle;
        }
      }
      EXPECT_NEAR(integral[0], integral[1], 0.01) << (cpu ? "cpu " : "gpu ") << name << ": histogram against pdf";
    }
  }
}

// The variant is settled before the scene is compiled, for the device that
// rendering will open: here lavapipe, the only device CI has.
TEST(GpuVariants, TheDefaultIsResolvedForTheDeviceBeforeCompiling) {
  EXPECT_EQ(resolve_variant("gpu-bvh2", ""), "gpu-bvh2");  // named: no device asked
  EXPECT_THROW(resolve_variant("gpu-bhv2", ""), InputError);
  const std::string chosen = resolve_variant("", "");
  EXPECT_EQ(chosen, default_variant(VulkanContext::selected_device("")).name);
  EXPECT_EQ(variant_options(RenderOptions{}, chosen).bvhLayout, kernel_variant(chosen).bvhLayout);
}

}  // namespace
}  // namespace wp::test
