// The statistical image comparison on synthetic images whose truth is known:
// it must accept independent estimates of one image, and reject a small
// planted bias (globally, or in one region).
#include "test_support.h"

#include <random>

#include "stats/compare.h"
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
