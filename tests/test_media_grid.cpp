// Grid media (darts' "nanovdb"; media.glsl, src/scene/nanovdb_grid.cpp) on
// the CPU reference: the density a lookup returns against NanoVDB's own
// sampler, the majorant grid against every lookup, free flights and
// transmittance through a density ramp against their closed forms (each
// shown to catch a planted error), and the reader's refusals of bad files.
// Grids are written by NanoVDB's builder (src/tools/volume_shapes.h); the
// GPU's agreement is in test_gpu.cpp.
#include "test_support.h"

#include <gtest/gtest-spi.h>

#include <fstream>
#include <random>

#include "tools/volume_shapes.h"

#include <nanovdb/util/SampleFromVoxels.h>  // after NanoVDB.h, which it needs

namespace wp::test {
namespace {

std::string write_grid(const std::string& name, const nanovdb::GridHandle<>& handle) {
  const std::string path = scratch_path(name);
  nanovdb::io::writeGrid(path, handle);
  return path;
}

// A scene whose camera sits in the grid medium `medium` (a JSON object),
// which the tests take apart.
CompiledScene grid_scene(const std::string& medium) {
  Scene s = load_scene(write_scene("grid.json", R"({
    "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "resolution": [4, 4], "medium": "grid" },
    "media": [ )" + medium + R"( ],
    "surfaces": [ { "type": "sphere", "radius": 0.1, "material": { "type": "diffuse_light", "emit": 1 } } ]
  })"));
  return compile_scene(s, RenderOptions{});
}

// Density a + b x over voxels [0, n)^3 of size 1: inside [0, n - 1]^3 a
// lookup returns it exactly, and along a ray o + t d its optical depth is
// sigma (a + b o.x) t + sigma b d.x t^2 / 2.
struct Ramp {
  int n = 32;
  float a = 0.3f, b = 0.05f;
  double depth(glm::vec3 o, glm::vec3 d, double sigma, double t) const {
    return sigma * ((a + b * o.x) * t + b * d.x * t * t / 2.0);
  }
};

std::string ramp_medium(const std::string& path, const std::string& extra = "", float sigmaS = 1.5f) {
  return R"({ "type": "nanovdb", "name": "grid", "filename": ")" + path + R"(", "sigma_a": 0, "sigma_s": )" + std::to_string(sigmaS) +
         extra + " }";
}

TEST(GridMedia, LookupsAgreeWithNanoVdbsOwnTrilinearSampler) {
  const auto handle = volumes::plume(32);
  CompiledScene cs = grid_scene(ramp_medium(write_grid("plume.nvdb", handle)));
  shader::SceneView v = cs.view();
  const shader::Medium m = v.load_medium(1);
  auto acc = v.grid_accessor(m);
  const auto* grid = handle.grid<float>();
  ASSERT_NE(grid, nullptr);
  nanovdb::SampleFromVoxels<nanovdb::FloatGrid::TreeType, 1, false> sampler(grid->tree());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int nonzero = 0;
  for (int i = 0; i < 4000; ++i) {
    // Scene points over the plume's box (it is one unit tall, 2/3 wide).
    const glm::vec3 p(u(rng) * 0.8f - 0.4f, u(rng) * 1.1f - 0.05f, u(rng) * 0.8f - 0.4f);
    const glm::vec3 q = v.xform_point(m.toIndex0, m.toIndex1, m.toIndex2, p);
    const nanovdb::Vec3f qi = grid->worldToIndexF(nanovdb::Vec3f(p.x, p.y, p.z));
    ASSERT_NEAR(q.x, qi[0], 1e-3f);
    const float expected = std::max(0.0f, sampler(qi));
    EXPECT_NEAR(v.grid_density(acc, q), expected, 1e-5f + 1e-5f * expected) << "at " << p.x << " " << p.y << " " << p.z;
    nonzero += expected > 0.0f;
  }
  EXPECT_GT(nonzero, 400);
}

// No lookup exceeds the majorant of its cell, with any cell count.
TEST(GridMedia, TheMajorantGridBoundsEveryLookup) {
  const std::string path = write_grid("plume.nvdb", volumes::plume(40));
  for (const char* cells : {"", R"(, "majorant grid": 1)", R"(, "majorant grid": 7)", R"(, "majorant grid": 64)"}) {
    CompiledScene cs = grid_scene(ramp_medium(path, cells));
    shader::SceneView v = cs.view();
    const shader::Medium m = v.load_medium(1);
    auto acc = v.grid_accessor(m);
    const glm::vec3 lo(m.boundsLo.x, m.boundsLo.y, m.boundsLo.z), hi(m.boundsHi.x, m.boundsHi.y, m.boundsHi.z);
    const glm::uvec3 n(m.info.w & 1023u, (m.info.w >> 10u) & 1023u, (m.info.w >> 20u) & 1023u);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int tight = 0;
    for (int i = 0; i < 20000; ++i) {
      const glm::vec3 q = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
      const glm::uvec3 c = glm::min(glm::uvec3((q - lo) / (hi - lo) * glm::vec3(n)), n - 1u);
      const float majorant = glm::uintBitsToFloat(cs.volumeWords[m.info.z + c.x + n.x * (c.y + n.y * c.z)]);
      const float d = v.grid_density(acc, q);
      ASSERT_LE(d, majorant) << "cells '" << cells << "' at " << q.x << " " << q.y << " " << q.z;
      tight += d > 0.5f * majorant;
    }
    EXPECT_GT(tight, 0) << cells;
  }
}

// Delta tracking's real collisions through the ramp, along an oblique ray
// that crosses many majorant cells, follow sigma(t) exp(-tau(t)): a
// chi-square test of the collision distances and the share that gets
// through, with one majorant for the grid and with the default cells. A
// majorant 30 % low is caught, and so is one cell's majorant left out.
TEST(GridMedia, DeltaTrackingSamplesTheRampsFreeFlightDensity) {
  const Ramp ramp;
  const std::string path = write_grid("ramp.nvdb", volumes::ramp(ramp.n, ramp.a, ramp.b));
  const double sigma = 0.15;  // a few percent get through
  const glm::vec3 o(1.5f, 2.0f, 3.0f), d = glm::normalize(glm::vec3(0.8f, 0.36f, 0.48f));
  const float tmax = 26.0f;  // stays within [0, n - 1]^3
  auto run = [&](const std::string& cells, const std::function<void(shader::Medium&, CompiledScene&)>& plant) {
    CompiledScene cs = grid_scene(ramp_medium(path, cells, float(sigma)));
    shader::SceneView v = cs.view();
    shader::Medium m = v.load_medium(1);
    plant(m, cs);
    v = cs.view();
    const int bins = 40, n = 200000;
    std::vector<double> obs(bins + 1, 0.0), expc(bins + 1, 0.0);
    uint32_t rng = 1234;
    for (int i = 0; i < n; ++i) {
      shader::Spectrum throughput(1.0f);
      float t;
      const uint32_t event = v.medium_free_flight(m, v.medium_coefficients(m, glm::vec4(0.0f)), o, d, tmax, rng, throughput, t);
      obs[event == MEDIUM_EVENT_SCATTER ? std::min(int(t / tmax * bins), bins - 1) : bins] += 1.0;
    }
    for (int b = 0; b < bins; ++b) {
      const double t0 = double(tmax) * b / bins, t1 = double(tmax) * (b + 1) / bins;
      expc[b] = n * (std::exp(-ramp.depth(o, d, sigma, t0)) - std::exp(-ramp.depth(o, d, sigma, t1)));
    }
    expc[bins] = n * std::exp(-ramp.depth(o, d, sigma, tmax));
    return chi2_test(obs, expc, n);
  };
  auto none = [](shader::Medium&, CompiledScene&) {};
  for (const char* cells : {R"(, "majorant grid": 1)", ""}) {
    Chi2Result r = run(cells, none);
    EXPECT_TRUE(r.problem.empty()) << r.problem;
    EXPECT_GT(r.pValue, 0.001) << "cells '" << cells << "': chi2 " << r.statistic << " with " << r.dof << " dof";
  }
  EXPECT_LT(run("", [](shader::Medium& m, CompiledScene&) { m.sigmaS.w *= 0.7f; }).pValue, 1e-6);
  EXPECT_LT(run(R"(, "majorant grid": 4)", [](shader::Medium& m, CompiledScene& cs) {
              cs.volumeWords[m.info.z + 1 + 4 * (1 + 4 * 1)] = glm::floatBitsToUint(0.0f);  // a cell the ray crosses
            }).pValue,
            1e-6);
}

// Ratio tracking's transmittance through the ramp, for chromatic
// coefficients, matches exp(-tau) in each channel within 5 standard errors;
// coefficients 5 % off are caught.
TEST(GridMedia, RatioTrackingMatchesTheRampsTransmittance) {
  const Ramp ramp;
  const std::string path = write_grid("ramp.nvdb", volumes::ramp(ramp.n, ramp.a, ramp.b));
  const glm::vec3 sa(0.2f, 0.4f, 0.1f), ss(0.3f, 0.5f, 0.9f);
  const std::string medium = R"({ "type": "nanovdb", "name": "grid", "filename": ")" + path +
                             R"(", "sigma_a": [0.2, 0.4, 0.1], "sigma_s": [0.3, 0.5, 0.9] })";
  CompiledScene cs = grid_scene(medium);
  shader::SceneView v = cs.view();
  const glm::vec3 o(2.0f, 20.0f, 4.0f), d = glm::normalize(glm::vec3(0.5f, -0.3f, 0.6f));
  const float tmax = 18.0f;
  auto estimate = [&](float scale) {
    shader::Medium m = v.load_medium(1);
    m.sigmaA *= glm::vec4(glm::vec3(scale), 1.0f);
    m.sigmaS *= glm::vec4(glm::vec3(scale), 1.0f);
    const int n = 100000;
    glm::dvec3 sum(0.0), sum2(0.0);
    uint32_t rng = 99;
    // A direction of any length: tmax scales with it.
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 tr(glm::vec3(v.medium_transmittance(m, v.medium_coefficients(m, glm::vec4(0.0f)), o, d * 2.0f, tmax / 2.0f, rng)));
      sum += tr;
      sum2 += tr * tr;
    }
    const glm::dvec3 mean = sum / double(n);
    return std::make_pair(mean, glm::sqrt((sum2 / double(n) - mean * mean) / double(n)));
  };
  auto check = [&](float scale) {
    const auto [mean, se] = estimate(scale);
    for (int c = 0; c < 3; ++c) {
      const double expected = std::exp(-ramp.depth(o, d, sa[c] + ss[c], tmax));
      EXPECT_NEAR(mean[c], expected, 5.0 * se[c]) << "channel " << c;
    }
  };
  check(1.0f);
  EXPECT_NONFATAL_FAILURE(check(1.05f), "channel");
}

TEST(GridMedia, DartsNanovdbMediaAreReadAsTheCourseDefinesThem) {
  const std::string path = write_grid("ramp.nvdb", volumes::ramp(8, 1.0f, 0.0f, 0.5));
  Scene s = load_scene(write_scene("s.json", R"({
    "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "resolution": [4, 4], "medium": "smoke" },
    "media": [ { "type": "nanovdb", "name": "smoke", "filename": ")" + path + R"(", "transform": { "translate": [1, 2, 3] },
                 "phase function": { "type": "henyey-greenstein", "g": 0.4 } } ],
    "surfaces": [ { "type": "sphere", "radius": 0.1, "material": { "type": "diffuse_light", "emit": 1 } } ]
  })"));
  ASSERT_EQ(s.media.size(), 1u);
  const SceneMedium& m = s.media[0];
  EXPECT_EQ(m.kind, MEDIUM_NANOVDB);
  // darts' defaults (src/media/nanovdb_medium.cpp:29-30) and gridname "density".
  EXPECT_EQ(m.sigmaA, glm::vec3(0.2f));
  EXPECT_EQ(m.sigmaS, glm::vec3(0.8f));
  EXPECT_FLOAT_EQ(m.g, 0.4f);
  ASSERT_NE(m.grid, nullptr);
  EXPECT_EQ(m.grid->name, "density");
  EXPECT_EQ(m.grid->indexMin, glm::ivec3(0));
  EXPECT_EQ(m.grid->indexMax, glm::ivec3(7));
  EXPECT_FLOAT_EQ(m.grid->maxDensity, 1.0f);
  // The transform places the grid: the scene point (1, 2, 3) + world (0.5,
  // 0.5, 0.5) is index point (1, 1, 1).
  CompiledScene cs = compile_scene(s, RenderOptions{});
  const shader::Medium pm = cs.view().load_medium(1);
  const glm::vec3 q = cs.view().xform_point(pm.toIndex0, pm.toIndex1, pm.toIndex2, glm::vec3(1.5f, 2.5f, 3.5f));
  EXPECT_NEAR(glm::length(q - glm::vec3(1.0f)), 0.0f, 1e-5f);
  EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(FEATURE_MEDIA_GRID));
}

TEST(GridMedia, BadGridsAreRefusedInOneLine) {
  auto scene = [](const std::string& file, const std::string& extra = "") {
    return R"({ "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "medium": "m" },
      "media": [ { "type": "nanovdb", "name": "m", "filename": ")" + file + "\"" + extra + R"( } ],
      "surfaces": [ { "type": "sphere", "radius": 1, "material": { "type": "lambertian" } } ] })";
  };
  expect_error(scene(scratch_path("missing.nvdb")), {"missing.nvdb", "cannot open", "/media/0"});
  const std::string good = write_grid("good.nvdb", volumes::ramp(8, 1.0f, 0.1f));
  expect_error(scene(good, R"(, "gridname": "densty")"), {"no grid named \"densty\"", "did you mean \"density\""});
  expect_error(scene(write_grid("ls.nvdb", volumes::level_set_sphere(6)), R"(, "gridname": "surface")"), {"is a level set, not a fog volume"});
  expect_error(scene(write_grid("v.nvdb", volumes::velocity(8)), R"(, "gridname": "velocity")"), {"holds Vec3f values", "float grid"});
  expect_error(scene(good, R"(, "majorant grid": 0)"), {"majorant grid", "whole number"});
  expect_error(scene(good, R"(, "sigma_s": -1)"), {"sigma_s", "not negative"});
  // Damaged copies of the good file.
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto damaged = [&](const std::string& name, const std::function<void(std::string&)>& damage) {
    std::string b = bytes;
    damage(b);
    const std::string path = scratch_path(name);
    std::ofstream(path, std::ios::binary) << b;
    return path;
  };
  expect_error(scene(damaged("trunc.nvdb", [](std::string& b) { b.resize(b.size() / 2); })), {"truncated"});
  expect_error(scene(damaged("head.nvdb", [](std::string& b) { b.resize(10); })), {"truncated", "header"});
  expect_error(scene(damaged("magic.nvdb", [](std::string& b) { b[0] = 'X'; })), {"not a NanoVDB file"});
  expect_error(scene(damaged("zip.nvdb", [](std::string& b) { b[14] = 1; })), {"compressed (ZIP)"});
  expect_error(scene(damaged("version.nvdb", [](std::string& b) { b[11] = char(b[11] + 2); })), {"wavepath reads the format of NanoVDB 32"});
  // The root's tile count (the grid's bytes start after the header, the
  // record and the name; the root follows the grid and tree headers).
  expect_error(scene(damaged("tiles.nvdb", [](std::string& b) {
                 const size_t grid = 16 + 176 + std::string("density").size() + 1;
                 uint64_t rootOffset;
                 std::memcpy(&rootOffset, b.data() + grid + 672 + 24, 8);
                 const uint32_t tiles = 1000;
                 std::memcpy(b.data() + grid + 672 + rootOffset + 24, &tiles, 4);
               })),
               {"1000 tiles"});
}

}  // namespace
}  // namespace wp::test
