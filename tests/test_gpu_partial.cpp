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
#include "util/fault.h"

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

// Faults, injected as WAVEPATH_FAULT injects them (util/fault.h), with
// one sample per submission so that renders add the same float sums.
class GpuFaults : public GpuPartial {
 protected:
  void TearDown() override {
    fault::inject(nullptr);
    GpuPartial::TearDown();
  }
  static WavefrontSettings one_sample_a_submission() {
    WavefrontSettings s = kernel_variant("gpu").settings;
    s.targetSubmitSeconds = 0.0;
    return s;
  }
  static uint32_t render_on(const VulkanContext& ctx, const CompiledScene& cs, const WavefrontSettings& s, ImageStats& image,
                            SampleRange range) {
    WavefrontRenderer r(ctx, cs, s);
    Progress quiet("", 0, false);
    return r.render(image, range, quiet);
  }
  using GpuPartial::render;
  // Renders `range` on a context of its own, which the fault `spec` loses;
  // returns the DeviceLost.
  static DeviceLost render_until_lost(const char* spec, const CompiledScene& cs, const WavefrontSettings& s, ImageStats& image,
                                      SampleRange range) {
    VulkanContext doomed("", true);
    fault::inject(spec);
    try {
      render_on(doomed, cs, s, image, range);
    } catch (const DeviceLost& lost) {
      fault::inject(nullptr);
      EXPECT_EQ(doomed.validation_messages(), 0u);
      return lost;
    }
    fault::inject(nullptr);
    ADD_FAILURE() << spec << " lost no device";
    return DeviceLost("none");
  }
};

// A device lost at the 8th submission of a render in five tiles (a round
// of samples is five submissions) in its second round: its image holds the
// first round alone, since a round's sums reach the image once every tile
// has them. Resumed from there, the render is the uninterrupted one to the
// bit; resumed a sample late it is not.
TEST_F(GpuFaults, ALostDeviceKeepsTheRoundsItFinishedAndResumesToTheSameSums) {
  CompiledScene cs = scene("tests/data/features/materials.json", 40, 12, 5, {"albedo"}, "gpu");
  WavefrontSettings s = one_sample_a_submission();
  s.maxTilePixels = 333;
  ImageStats whole(cs.width, cs.height, image_layers(cs.aovs)), image = whole;
  DeviceLost lost = render_until_lost("device-lost@submit:8", cs, s, image, {0, 12});
  EXPECT_TRUE(lost.intact);
  EXPECT_EQ(lost.reached, 1u);
  EXPECT_EQ(*std::min_element(image.count.begin(), image.count.end()), 1.0);
  EXPECT_EQ(*std::max_element(image.count.begin(), image.count.end()), 1.0);
  WavefrontRenderer r(*ctx_, cs, s);
  Progress quiet("", 0, false);
  r.render(whole, {0, 12}, quiet);
  ImageStats late = image;
  r.render(image, {lost.reached, 12}, quiet);
  EXPECT_EQ(image.sum, whole.sum);
  EXPECT_EQ(image.sumSq, whole.sumSq);
  r.render(late, {lost.reached + 1, 12}, quiet);
  EXPECT_NE(late.sum, whole.sum) << "planted: a sample left out";
}

// Under adaptive sampling a pixel's batch takes several submissions: a
// device lost part-way through one leaves samples that no partial file can
// record, and says so.
TEST_F(GpuFaults, ALostDeviceInAnAdaptiveBatchSaysItsImageIsNotWhole) {
  Scene sc = load_scene(source_path("tests/data/features/materials.json"));
  sc.camera.width = sc.camera.height = 16;
  RenderOptions o;
  o.spp = 12;
  o.adaptive = AdaptiveSampling{4, 0.05f};
  const CompiledScene cs = compile_scene(sc, variant_options(o, "gpu"));
  ImageStats image(cs.width, cs.height);
  DeviceLost lost = render_until_lost("device-lost@submit:6", cs, one_sample_a_submission(), image, {0, 12});
  EXPECT_EQ(lost.reached, 4u);
  EXPECT_FALSE(lost.intact);
}

// Out of device memory for the image's buffers, the renderer renders in
// smaller tiles (with no more path slots than a tile's pixels), says so in
// one line, and makes the untiled image to the bit (as do tiles of one row
// with as many path slots); where even one row does not fit, it refuses,
// naming the memory needed and the device's.
TEST_F(GpuFaults, OutOfDeviceMemoryRendersInSmallerTilesTheSameImage) {
  CompiledScene cs = scene("tests/data/features/materials.json", 40, 4, 5, {}, "gpu");
  const WavefrontSettings s = one_sample_a_submission();
  WavefrontSettings oneRow = s;
  oneRow.maxTilePixels = oneRow.maxPathsPerWave = uint32_t(cs.width);
  ImageStats untiled(cs.width, cs.height), rows = untiled, tiled = untiled;
  render_on(*ctx_, cs, s, untiled, {0, 4});
  fault::inject("oom@bytes:1099511627776");  // counted, never short
  uint64_t row = 0;
  {
    WavefrontRenderer r(*ctx_, cs, oneRow);
    row = fault::device_memory_held();
    Progress quiet("", 0, false);
    r.render(rows, {0, 4}, quiet);
  }
  // Room for tiles of about two rows, the scene's buffers being small.
  fault::inject(("oom@bytes:" + std::to_string(2 * row)).c_str());
  testing::internal::CaptureStderr();
  render_on(*ctx_, cs, s, tiled, {0, 4});
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("out of device memory for tiles of 1600 pixels"), std::string::npos) << said;
  EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
  EXPECT_EQ(rows.sum, untiled.sum);
  EXPECT_EQ(tiled.sum, untiled.sum);
  EXPECT_EQ(tiled.sumSq, untiled.sumSq);

  fault::inject(("oom@bytes:" + std::to_string(row - 1)).c_str());
  try {
    WavefrontRenderer r(*ctx_, cs, s);
    ADD_FAILURE() << "a device without room for one row's tile renders";
  } catch (const RenderError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("even tiles of one row (40 pixels) need"), std::string::npos) << what;
    EXPECT_NE(what.find("WAVEPATH_FAULT gives it"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace wp::test
