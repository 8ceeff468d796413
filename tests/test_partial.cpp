// Partial renders on the CPU reference: sample ranges that merge exactly,
// the partial EXR that carries them, the merge's refusals, resuming, the
// render's identity, and the AOV layers' conventions.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>

#include "render/partial.h"
#include "stats/compare.h"
#include "test_support.h"
#include "util/error.h"

namespace wp::test {
namespace {

Progress quiet() {
  return Progress("", 0, false);
}

CompiledScene small_scene(const std::string& path, int spp, std::vector<std::string> aovs = {}, uint32_t seed = 0,
                          AdaptiveSampling adaptive = {}) {
  RenderOptions o;
  o.spp = spp;
  o.seed = seed;
  o.aovs = std::move(aovs);
  o.adaptive = adaptive;
  Scene scene = load_scene(path);
  scene.camera.width = 32;
  scene.camera.height = 24;
  return compile_scene(scene, reference_options(o));
}

ImageStats render_range(const CompiledScene& cs, SampleRange range) {
  ImageStats image(cs.width, cs.height, image_layers(cs.aovs));
  Progress p = quiet();
  EXPECT_EQ(render_cpu(cs, 0, image, range, p), range.end);
  return image;
}

// Writes `image` as the partial file of samples `ranges` of the render of `cs`.
std::string write_part(const std::string& name, const ImageStats& image, const CompiledScene& cs, const std::string& ranges,
                       const std::string& sceneHash = "0123456789abcdef") {
  RenderRecord r;
  r.sceneHash = sceneHash;
  r.settings = render_settings(cs);
  r.samples = ranges;
  r.status = "complete";
  r.renderer = "the CPU reference";
  r.version = wavepath_version();
  std::string path = scratch_path(name);
  write_exr(path, image, r, true);
  return path;
}

void expect_sums_near(const ImageStats& a, const ImageStats& b, double relative) {
  ASSERT_EQ(a.sum.size(), b.sum.size());
  for (size_t p = 0; p < a.pixels(); ++p) ASSERT_EQ(a.count[p], b.count[p]) << "pixel " << p;
  for (size_t i = 0; i < a.sum.size(); ++i) {
    ASSERT_NEAR(a.sum[i], b.sum[i], relative * std::max(std::abs(a.sum[i]), 1e-30)) << "channel " << i % a.stride << " of pixel " << i / a.stride;
    ASSERT_NEAR(a.sumSq[i], b.sumSq[i], relative * std::max(std::abs(a.sumSq[i]), 1e-30));
  }
}

TEST(Partial, SampleRangesParseAndRefuseWhatIsNotARange) {
  std::vector<SampleRange> r = parse_sample_ranges("0:16,16:40,100:101", "test");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[1].begin, 16u);
  EXPECT_EQ(r[1].end, 40u);
  EXPECT_EQ(format_sample_ranges(r), "0:16,16:40,100:101");
  for (const char* bad : {"", "5", "4:4", "9:3", "1:2:3", "a:b", "-1:4", "0:16,", "0:99999999999"})
    EXPECT_THROW(parse_sample_ranges(bad, "test"), InputError) << bad;
  std::vector<SampleRange> missing = missing_ranges({{4, 8}, {8, 10}, {12, 20}}, 24);
  EXPECT_EQ(format_sample_ranges(missing), "0:4,10:12,20:24");
}

// The partial EXR keeps every channel's sums bit for bit, AOV layers
// included, and the render record in its header.
TEST(Partial, TheExrKeepsEverySumBitForBitAndTheRecord) {
  ImageStats image(7, 5, image_layers({"normal", "albedo", "depth"}));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  for (double& v : image.sum) v = u(rng) * 1e-7;  // values with all 52 mantissa bits in use
  for (double& v : image.sumSq) v = std::abs(u(rng));
  for (double& v : image.count) v = double(rng() % 1000);
  RenderRecord r{"feedface01234567", "spp=8; seed=1", "0:3,5:8", "interrupted by SIGINT", "llvmpipe", wavepath_version()};
  std::string path = scratch_path("round.exr");
  write_exr(path, image, r, true);
  RenderRecord back;
  ImageStats read = read_exr(path, &back);
  EXPECT_TRUE(back.exactSums);
  EXPECT_EQ(back.sceneHash, r.sceneHash);
  EXPECT_EQ(back.settings, r.settings);
  EXPECT_EQ(back.samples, r.samples);
  EXPECT_EQ(back.status, r.status);
  EXPECT_EQ(back.renderer, r.renderer);
  EXPECT_EQ(back.version, r.version);
  ASSERT_EQ(read.aov_names(), (std::vector<std::string>{"albedo", "normal", "depth"}));
  EXPECT_EQ(std::memcmp(read.sum.data(), image.sum.data(), image.sum.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(read.sumSq.data(), image.sumSq.data(), image.sumSq.size() * sizeof(double)), 0);
  EXPECT_EQ(read.count, image.count);
}

// Any split of 0:N merges to the render of 0:N: on the CPU each pixel adds
// its samples in order in double precision, so the merged sums differ from
// the whole render's only in how the parts' sums associate (well inside
// 1e-12 of the sums; docs/partial-renders.md).
TEST(Partial, CpuSplitsMergeToTheWholeRender) {
  CompiledScene cs = small_scene(source_path("tests/data/features/materials.json"), 64, {"albedo", "depth"});
  ImageStats whole = render_range(cs, {0, 64});
  std::vector<PartialFile> parts;
  for (SampleRange r : {SampleRange{16, 40}, SampleRange{0, 16}, SampleRange{40, 64}}) {
    std::string name = "part" + std::to_string(r.begin) + ".exr";
    parts.push_back(read_partial(write_part(name, render_range(cs, r), cs, format_sample_ranges({r}))));
  }
  PartialFile merged = merge_partials(parts, false);
  EXPECT_EQ(merged.record.samples, "0:64");
  EXPECT_EQ(merged.record.status, "complete");
  expect_sums_near(merged.image, whole, 1e-12);
  // The bound is not vacuous: one sample more or less is far outside it.
  ImageStats shorter = render_range(cs, {0, 63});
  for (size_t i = 0; i < whole.pixels(); ++i) shorter.count[i] = whole.count[i];
  bool outside = false;
  for (size_t i = 0; i < whole.sum.size() && !outside; ++i) outside = std::abs(shorter.sum[i] - whole.sum[i]) > 1e-12 * std::abs(whole.sum[i]);
  EXPECT_TRUE(outside);
}

TEST(Partial, MergeRefusesGapsOverlapsOtherScenesAndOtherSettings) {
  const std::string scene = source_path("tests/data/quad-light.json");
  CompiledScene cs = small_scene(scene, 8);
  CompiledScene otherSeed = small_scene(scene, 8, {}, 5);
  ImageStats a = render_range(cs, {0, 4}), b = render_range(cs, {4, 8});
  PartialFile pa = read_partial(write_part("a.exr", a, cs, "0:4"));
  PartialFile pb = read_partial(write_part("b.exr", b, cs, "4:8"));
  auto refused = [](const std::vector<PartialFile>& parts, const std::string& text, bool allowGaps = false) {
    try {
      merge_partials(parts, allowGaps);
      ADD_FAILURE() << "merged, expected a refusal naming \"" << text << "\"";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  EXPECT_NO_THROW(merge_partials({pb, pa}, false));
  refused({pa}, "leave out samples 4:8");
  refused({pa, pa}, "overlaps");
  refused({pa, read_partial(write_part("c.exr", render_range(cs, {2, 8}), cs, "2:8"))}, "overlaps");
  refused({pa, read_partial(write_part("d.exr", b, cs, "4:8", "ffffffffffffffff"))}, "another scene");
  refused({pa, read_partial(write_part("e.exr", render_range(otherSeed, {4, 8}), otherSeed, "4:8"))}, "seed 5 vs 0");
  // With --allow-gaps a gap is merged and recorded as missing.
  PartialFile gappy = merge_partials({pa}, true);
  EXPECT_EQ(gappy.record.status, "partial: samples 4:8 missing");
  // A file that is no partial render is refused by name: one without a
  // render record, and a plain render's, which lacks the exact sums.
  std::string plain = scratch_path("plain.exr");
  write_exr(plain, a);
  EXPECT_THROW(read_partial(plain), InputError);
  RenderRecord record = pa.record;
  write_exr(plain, a, record, false);
  try {
    read_partial(plain);
    ADD_FAILURE() << "a file without the exact sums was read as a partial render";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lacks the exact sums"), std::string::npos) << e.what();
  }
}

// A render stopped between passes and continued from what it held is the
// uninterrupted render, bit for bit (each pixel adds its samples in order).
TEST(Partial, CpuResumeEqualsAnUninterruptedRender) {
  for (bool adaptive : {false, true}) {
    AdaptiveSampling a;
    if (adaptive) a = AdaptiveSampling{8, 0.05f};
    CompiledScene cs = small_scene(source_path("tests/data/features/materials.json"), 48, {"normal"}, 0, a);
    ImageStats whole = render_range(cs, {0, 48});
    ImageStats image(cs.width, cs.height, image_layers(cs.aovs));
    Progress p = quiet();
    int passes = 0;
    uint32_t reached = render_cpu(cs, 0, image, {0, 48}, p, [&](const ImageStats&, uint32_t) { return ++passes < 2; });
    ASSERT_LT(reached, 48u) << "stopped after two passes";
    if (adaptive) {
      EXPECT_EQ(reached % 8u, 0u) << "adaptive renders stop at batch ends";
    }
    // Through the partial file, as --checkpoint and --resume do.
    PartialFile checkpoint = read_partial(write_part("ck.exr", image, cs, format_sample_ranges({{0, reached}})));
    EXPECT_EQ(render_cpu(cs, 0, checkpoint.image, {reached, 48}, p), 48u);
    EXPECT_EQ(checkpoint.image.count, whole.count) << (adaptive ? "adaptive" : "fixed");
    EXPECT_EQ(checkpoint.image.sum, whole.sum) << (adaptive ? "adaptive" : "fixed");
    EXPECT_EQ(checkpoint.image.sumSq, whole.sumSq) << (adaptive ? "adaptive" : "fixed");
  }
}

// The identity hashes every file the scene loads: the scene file, an OBJ,
// its MTL and an image texture each change it.
TEST(Partial, TheSceneHashCoversEveryFileTheSceneLoads) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(scratch_path("scene")).parent_path() / "copy";
  fs::create_directories(dir);
  for (const char* f : {"furnace.json", "furnace-box.obj", "furnace-box.mtl"}) fs::copy_file(source_path(std::string("tests/data/") + f), dir / f);
  fs::copy_file(source_path("tests/data/features/tiles.png"), dir / "tiles.png");
  // An image texture the MTL names.
  {
    std::ofstream mtl(dir / "furnace-box.mtl", std::ios::app);
    mtl << "\nnewmtl textured\nKd 1 1 1\nmap_Kd tiles.png\n";
  }
  const std::string scene = (dir / "furnace.json").string();
  Scene loaded = load_scene(scene);
  ASSERT_EQ(loaded.inputFiles.size(), 4u) << "scene, OBJ, MTL, image";
  const std::string base = scene_content_hash(loaded);
  EXPECT_EQ(scene_content_hash(load_scene(scene)), base) << "the same files, the same hash";
  for (const char* f : {"furnace.json", "furnace-box.obj", "furnace-box.mtl", "tiles.png"}) {
    fs::path p = dir / f;
    std::string original;
    {
      std::ifstream in(p, std::ios::binary);
      original.assign(std::istreambuf_iterator<char>(in), {});
    }
    {
      std::ofstream out(p, std::ios::binary | std::ios::app);
      out << (std::string(f).find(".png") != std::string::npos ? "" : "\n");
      if (std::string(f).find(".png") != std::string::npos) out << '\0';  // trailing bytes after IEND
    }
    EXPECT_NE(scene_content_hash(loaded), base) << f << " changed";
    std::ofstream restore(p, std::ios::binary | std::ios::trunc);
    restore << original;
  }
}

// The AOV conventions (layers.glsl), on a grey Lambertian sphere under a
// white sky: the first hit's albedo and camera-facing normal, the distance
// to it, coverage 1; the sky's clamped radiance, no normal and coverage 0
// where the ray escapes.
TEST(Partial, AovLayersFollowOpenImageDenoiseConventions) {
  RenderOptions o;
  o.spp = 16;
  o.aovs = {"albedo", "normal", "depth"};
  ImageStats image = render_reference(source_path("tests/data/sphere-sky.json"), o, 16);
  const ImageLayer* albedo = image.layer("albedo");
  const ImageLayer* normal = image.layer("normal");
  const ImageLayer* depth = image.layer("depth");
  ASSERT_TRUE(albedo && normal && depth);
  auto mean = [&](size_t pixel, const ImageLayer* l, size_t c) { return image.sum[pixel * image.stride + l->first + c] / image.count[pixel]; };
  // The four pixels about the image's centre see the sphere's front, whose
  // distance is 3.7 on the axis and 3.704 at 1.25 degrees off it.
  for (size_t pixel : {size_t(11 * 24 + 11), size_t(11 * 24 + 12), size_t(12 * 24 + 11), size_t(12 * 24 + 12)}) {
    for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(mean(pixel, albedo, c), 0.5, 1e-6);
    EXPECT_NEAR(mean(pixel, normal, 2), 1.0, 0.01);
    EXPECT_NEAR(mean(pixel, depth, 1), 1.0, 0.0);
    EXPECT_GT(mean(pixel, depth, 0), 3.699);
    EXPECT_LT(mean(pixel, depth, 0), 3.705);
  }
  // The corner sees the white sky.
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_EQ(mean(0, albedo, c), 1.0);
    EXPECT_EQ(mean(0, normal, c), 0.0);
  }
  EXPECT_EQ(mean(0, depth, 0), 0.0);
  EXPECT_EQ(mean(0, depth, 1), 0.0);
}

}  // namespace
}  // namespace wp::test
