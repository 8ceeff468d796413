// The statistical image comparison on synthetic images whose truth is known:
// it must accept independent estimates of one image, and reject a small
// planted bias (globally, or in one region).
#include "test_support.h"

#include <random>

#include "stats/compare.h"
#include "stats/reference_diff.h"
#include "util/error.h"

namespace wp::test {
namespace {

// A synthetic render: each pixel's samples are drawn from an exponential
// distribution (heavy-ish tail, like path tracing) around a smooth image. As in
// a path tracer, one draw sets all three channels, so they are correlated.
ImageStats synthetic(int w, int h, int spp, uint32_t seed, double bias, int biasX0 = 0, int biasX1 = 1 << 30) {
  ImageStats img(w, h);
  std::mt19937 rng(seed);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t p = size_t(y * w + x);
      double truth = 0.2 + 0.6 * (x + y) / double(w + h);
      double b = (x >= biasX0 && x < biasX1 && y >= biasX0 && y < biasX1) ? bias : 1.0;
      std::exponential_distribution<double> dist(1.0 / (truth * b));
      for (int s = 0; s < spp; ++s) {
        double draw = dist(rng);
        for (int c = 0; c < 3; ++c) {
          double v = draw * (c == 0 ? 1.0 : 0.7 - 0.2 * c);
          img.sum[p * img.stride + size_t(c)] += v;
          img.sumSq[p * img.stride + size_t(c)] += v * v;
        }
        img.count[p] += 1.0;
      }
    }
  return img;
}

TEST(Compare, IndependentEstimatesAgreeAtLeast19TimesIn20) {
  int passes = 0;
  for (uint32_t seed = 0; seed < 20; ++seed) {
    CompareResult r = compare_images(synthetic(64, 64, 64, 2 * seed + 1, 1.0), synthetic(64, 64, 64, 2 * seed + 2, 1.0));
    passes += r.passed();
  }
  EXPECT_GE(passes, 19);
}

TEST(Compare, CatchesAPlantedGlobalBiasOfTwoPercent) {
  CompareResult r = compare_images(synthetic(64, 64, 64, 1, 1.02), synthetic(64, 64, 64, 2, 1.0));
  EXPECT_FALSE(r.passed()) << r.summary();
  EXPECT_FALSE(r.meanTestPassed);
  EXPECT_NEAR(r.relativeBias, 0.02, 3 * r.relativeBiasCi95);
}

TEST(Compare, CatchesAStrongLocalBias) {
  // Doubling a 16x16 region of a 64x64 image: many pixels fail the Welch test.
  CompareResult r = compare_images(synthetic(64, 64, 256, 3, 2.0, 16, 32), synthetic(64, 64, 256, 4, 1.0));
  EXPECT_FALSE(r.pixelTestPassed) << r.summary();
}

// A pixel a million times darker than the image whose variance floats
// cannot hold (both sides' variance 0) is not a disagreement; a pixel as
// bright as the image with the same difference is.
TEST(Compare, PixelsFarDarkerThanTheImageAreNeverSignificant) {
  ImageStats a = synthetic(32, 32, 16, 1, 1.0), b = synthetic(32, 32, 16, 2, 1.0);
  auto set = [](ImageStats& img, size_t p, double v) {
    for (int c = 0; c < 3; ++c) {
      img.sum[img.stride * p + size_t(c)] = v * img.count[p];
      img.sumSq[img.stride * p + size_t(c)] = v * v * img.count[p];  // no variance
    }
  };
  for (size_t p = 0; p < 40; ++p) {
    set(a, p, 3e-24);
    set(b, p, 4e-28);
  }
  EXPECT_TRUE(compare_images(a, b).passed()) << compare_images(a, b).summary();
  for (size_t p = 0; p < 40; ++p) {
    set(a, p, 1.0);
    set(b, p, 1.1);
  }
  EXPECT_FALSE(compare_images(a, b).pixelTestPassed);
}

// compare --reference: the measures on images whose truth is known.
TEST(ReferenceDiff, MeasuresRatiosBlocksAndLeavesOutWhatItIsTold) {
  LinearImage ref;
  ref.width = 64;
  ref.height = 32;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) ref.pixels.push_back(glm::vec3(0.2f + 0.01f * float(x % 7), 0.3f, 0.1f + 0.002f * float(y)));
  LinearImage image = ref;
  for (glm::vec3& p : image.pixels) p *= glm::vec3(1.1f, 1.0f, 1.0f);
  ReferenceDiff d = diff_against_reference(image, ref);
  EXPECT_NEAR(d.ratio.x, 1.1, 1e-6);
  EXPECT_NEAR(d.ratio.y, 1.0, 1e-6);
  EXPECT_EQ(d.blocks, 8u);  // 4 x 2 blocks of 16x16
  EXPECT_GT(d.meanError, 0.02);
  EXPECT_GT(d.blockMedian, 0.02);
  // One row of wild values, left out; a watermark, masked; clipped pixels and their blocks.
  image = ref;
  for (int x = 0; x < 64; ++x) image.pixels[size_t(x)] = glm::vec3(1000.0f);
  ReferenceDiffSettings s;
  s.excludeTop = 1;
  d = diff_against_reference(image, ref, s);
  EXPECT_NEAR(d.meanError, 0.0, 1e-9);
  EXPECT_EQ(d.blocks, 4u);  // the top row of blocks is no longer whole
  image = ref;
  for (int y = 27; y < 32; ++y)
    for (int x = 0; x < 48; ++x) image.pixels[size_t(y) * 64 + size_t(x)] = glm::vec3(10.0f);
  s = ReferenceDiffSettings{};
  s.mask = glm::ivec4(0, 27, 48, 32);
  EXPECT_NEAR(diff_against_reference(image, ref, s).meanError, 0.0, 1e-9);
  image = ref;
  image.pixels[100] = glm::vec3(1.0f);
  s = ReferenceDiffSettings{};
  s.clipped = 1.0f;
  d = diff_against_reference(image, ref, s);
  EXPECT_NEAR(d.meanError, 0.0, 1e-9);
  EXPECT_EQ(d.blocks, 7u);
  EXPECT_THROW(diff_against_reference(LinearImage{}, ref), InputError);
}

TEST(Compare, RejectsImagesOfDifferentSizes) {
  EXPECT_THROW(compare_images(ImageStats(4, 4), ImageStats(4, 5)), InputError);
}

TEST(Compare, ExrRoundTripKeepsTheStatistics) {
  ImageStats a = synthetic(16, 8, 32, 9, 1.0);
  std::string path = scratch_path("roundtrip.exr");
  write_exr(path, a);
  ImageStats b = read_exr(path);
  ASSERT_EQ(b.width, 16);
  ASSERT_EQ(b.height, 8);
  for (size_t p = 0; p < a.pixels(); ++p) {
    EXPECT_EQ(b.count[p], a.count[p]);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(b.mean(p)[c], a.mean(p)[c], 1e-6 * a.mean(p)[c]);
      EXPECT_NEAR(b.variance(p)[c], a.variance(p)[c], 1e-4 * a.variance(p)[c]);
    }
  }
  EXPECT_TRUE(compare_images(a, b).passed());
  EXPECT_THROW(read_exr(scratch_path("missing.exr")), InputError);
}

}  // namespace
}  // namespace wp::test
