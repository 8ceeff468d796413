// Partial renders and AOV layers on the Vulkan renderer (lavapipe in CI),
// with validation on: sample ranges and resumed renders against the whole
// render, within the documented bound, and the AOV layers of every way the
// kernels record them against the CPU reference.
#include "test_support.h"

#include <algorithm>
#include <memory>

#include "gpu/wavefront.h"
#include "render/partial.h"
#include "stats/compare.h"

namespace wp::test {
namespace {

class GpuPartial : public testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = std::make_unique<VulkanContext>("", true); }
  static void TearDownTestSuite() { ctx_.reset(); }
  void TearDown() override { EXPECT_EQ(ctx_->validation_messages(), 0u) << "Vulkan validation reported problems"; }

  static CompiledScene scene(const std::string& path, int size, int spp, uint32_t seed, std::vector<std::string> aovs,
                             const std::string& renderer) {
    Scene s = load_scene(source_path(path));
    s.camera.width = s.camera.height = size;
    RenderOptions o;
    o.spp = spp;
    o.seed = seed;
    o.aovs = std::move(aovs);
    return compile_scene(s, variant_options(o, renderer));
  }

  static uint32_t render(const CompiledScene& cs, ImageStats& image, SampleRange range, const std::string& variant = "gpu",
                         const PassHook& hook = {}) {
    WavefrontRenderer r(*ctx_, cs, kernel_variant(variant).settings);
    Progress quiet("", 0, false);
    return r.render(image, range, quiet, hook);
  }

  static std::unique_ptr<VulkanContext> ctx_;
};
std::unique_ptr<VulkanContext> GpuPartial::ctx_;

// The GPU adds a submission's samples in float before the host adds them to
// the image in double, and how many samples a submission takes depends on
// timing (at most 256). Two renders of the same samples grouped differently
// therefore differ by at most 2 * 256 * 2^-24 = 2^-15 of each sum (of
// non-negative terms): the bound docs/partial-renders.md guarantees.
constexpr double kGpuBound = 1.0 / 32768.0;

void expect_within(const ImageStats& a, const ImageStats& b, double bound, const char* what) {
  ASSERT_EQ(a.count, b.count) << what;
  double worst = 0.0;
  for (size_t i = 0; i < a.sum.size(); ++i) {
    if ((i % a.stride) >= ImageStats::kY + 1 && (i % a.stride) < a.stride) continue;  // AOVs can be negative: colour only
    double s = std::max(std::abs(a.sum[i]), std::abs(b.sum[i]));
    if (s > 0.0) worst = std::max(worst, std::abs(a.sum[i] - b.sum[i]) / s);
  }
  EXPECT_LE(worst, bound) << what;
}

TEST_F(GpuPartial, SplitsAndResumedRendersMatchTheWholeRenderWithinTheBound) {
  CompiledScene cs = scene("tests/data/features/materials.json", 40, 64, 3, {}, "gpu");
  ImageStats whole(cs.width, cs.height);
  ASSERT_EQ(render(cs, whole, {0, 64}), 64u);

  ImageStats merged(cs.width, cs.height);
  for (SampleRange r : {SampleRange{0, 16}, SampleRange{16, 40}, SampleRange{40, 64}}) {
    ImageStats part(cs.width, cs.height);
    ASSERT_EQ(render(cs, part, r), r.end);
    merged.add(part);
  }
  expect_within(merged, whole, kGpuBound, "0:16 + 16:40 + 40:64");

  // Stopped after its first submission, then continued.
  ImageStats resumed(cs.width, cs.height);
  uint32_t reached = render(cs, resumed, {0, 64}, "gpu", [](const ImageStats&, uint32_t) { return false; });
  ASSERT_GT(reached, 0u);
  ASSERT_LT(reached, 64u);
  ASSERT_EQ(render(cs, resumed, {reached, 64}), 64u);
  expect_within(resumed, whole, kGpuBound, "resumed");

  // The bound is not vacuous: one sample short is far outside it.
  ImageStats shorter(cs.width, cs.height);
  render(cs, shorter, {0, 63});
  shorter.count = whole.count;
  double worst = 0.0;
  for (size_t i = 0; i < whole.sum.size(); ++i)
    if (whole.sum[i] > 0.0) worst = std::max(worst, std::abs(shorter.sum[i] - whole.sum[i]) / whole.sum[i]);
  EXPECT_GT(worst, 100 * kGpuBound);
}

// An image in tiles (here a limit far below the device's, 333 pixels, so
// that a 40x40 render takes five, none a whole number of rows) is the
// untiled image to the bit: a pixel's random numbers come from its own
// index, and with one sample per submission both renders add the same float
// sums. So on the wavefront kernels and the megakernel, with AOV layers,
// with adaptive sampling (its pixel list split by tile), and stopped after
// a round and resumed.
TEST_F(GpuPartial, TiledRendersAreTheUntiledImage) {
  for (const char* variant : {"gpu", "gpu-mega"}) {
    for (bool adaptive : {false, true}) {
      Scene s = load_scene(source_path("tests/data/features/materials.json"));
      s.camera.width = s.camera.height = 40;
      RenderOptions o;
      o.spp = 12;
      o.seed = 5;
      o.aovs = {"albedo", "depth"};
      if (adaptive) o.adaptive = AdaptiveSampling{4, 0.05f};
      const CompiledScene cs = compile_scene(s, variant_options(o, variant));
      auto render_tiled = [&](uint32_t tilePixels, ImageStats& image, SampleRange range, const PassHook& hook = {}) {
        WavefrontSettings settings = kernel_variant(variant).settings;
        settings.targetSubmitSeconds = 0.0;  // one sample per submission
        settings.maxTilePixels = tilePixels;
        WavefrontRenderer r(*ctx_, cs, settings);
        Progress quiet("", 0, false);
        return r.render(image, range, quiet, hook);
      };
      const std::string what = std::string(variant) + (adaptive ? ", adaptive" : "");
      ImageStats untiled(cs.width, cs.height, image_layers(cs.aovs)), tiled = untiled, resumed = untiled;
      render_tiled(0, untiled, {0, 12});
      render_tiled(333, tiled, {0, 12});
      EXPECT_EQ(tiled.count, untiled.count) << what;
      EXPECT_EQ(tiled.sum, untiled.sum) << what;
      EXPECT_EQ(tiled.sumSq, untiled.sumSq) << what;
      if (adaptive) {
        EXPECT_LT(*std::min_element(untiled.count.begin(), untiled.count.end()), 12.0) << "no pixel converged early";
      }
      // Stopped after the first round of tiles, then the rest.
      const uint32_t reached = render_tiled(333, resumed, {0, 12}, [](const ImageStats&, uint32_t) { return false; });
      ASSERT_LT(reached, 12u) << what;
      render_tiled(333, resumed, {reached, 12});
      EXPECT_EQ(resumed.sum, untiled.sum) << what << ", resumed from sample " << reached;
    }
  }
}

// Every AOV layer, as the wavefront kernels (shade), the sorted shade kernels
// and the megakernel record it, estimates what the CPU reference's does; a
// 5 % bias planted in one layer is caught.
TEST_F(GpuPartial, AovLayersAgreeWithTheCpuReference) {
  const std::vector<std::string> aovs = {"albedo", "normal", "depth"};
  for (const char* path : {"tests/data/features/materials.json", "tests/data/features/textures.json"}) {
    ImageStats cpu(0, 0);
    {
      CompiledScene cs = scene(path, 48, 64, 2, aovs, "cpu");
      Progress quiet("", 0, false);
      cpu = render_cpu(cs, 0, quiet);
    }
    for (const char* variant : {"gpu", "gpu-sort", "gpu-mega"}) {
      CompiledScene cs = scene(path, 48, 64, 1, aovs, variant);
      ImageStats gpu(cs.width, cs.height, image_layers(cs.aovs));
      render(cs, gpu, {0, 64}, variant);
      for (const std::string& layer : aovs) {
        CompareResult r = compare_images(layer_as_color(gpu, layer), layer_as_color(cpu, layer));
        EXPECT_TRUE(r.passed()) << path << ", " << variant << ", " << layer << ": " << r.summary();
      }
      EXPECT_TRUE(compare_images(gpu, cpu).passed()) << path << ", " << variant << ": the colour, with AOVs recorded";
      ImageStats biased = layer_as_color(gpu, "albedo");
      plant_bias(biased, 1.05);
      EXPECT_FALSE(compare_images(biased, layer_as_color(cpu, "albedo")).passed()) << path << ", " << variant << ": planted bias";
    }
  }
}

}  // namespace
}  // namespace wp::test
