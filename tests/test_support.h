// test_support.h — helpers shared by the tests: paths to test data, scene
// construction, and the chi-square test of directions against a pdf
// (stats/chi2.h has the test itself).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include <filesystem>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "cpu/reference.h"
#include "image/exr.h"
#include "render/compiled_scene.h"
#include "render/shader_cpp.h"
#include "scene/materials/material_module.h"
#include "scene/load_scene.h"
#include "stats/chi2.h"
#include "util/error.h"

namespace wp::test {

inline std::string source_path(const std::string& rel) {
  return std::string(WAVEPATH_SOURCE_DIR) + "/" + rel;
}

// The folder for the files test `t` writes. ctest runs each test as its own
// process, two at a time, so every test gets its own folder (test name and
// process id): a shared name in TempDir() raced between tests. The folder is
// removed when the test passes and kept when it fails (test_support.cpp).
inline std::filesystem::path scratch_dir(const testing::TestInfo& t) {
  return std::filesystem::path(testing::TempDir()) /
         ("wavepath-" + std::to_string(::getpid()) + "-" + t.test_suite_name() + "." + t.name());
}

// A path for a file the current test writes, in its scratch folder.
inline std::string scratch_path(const std::string& name) {
  std::filesystem::path dir = scratch_dir(*testing::UnitTest::GetInstance()->current_test_info());
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

inline std::string write_scene(const std::string& name, const std::string& text) {
  std::string path = scratch_path(name);
  std::ofstream(path) << text;
  return path;
}

// Loads `text`, written as `file`, and expects an InputError naming the file
// in one line that contains every part.
inline void expect_error(const std::string& text, std::initializer_list<const char*> parts, const std::string& file = "bad.json") {
  std::string path = write_scene(file, text);
  try {
    load_scene(path);
    ADD_FAILURE() << "no error for: " << text;
  } catch (const InputError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    for (const char* p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
  }
}

// The red channel of an EXR (a render's or a plain RGB image's).
inline std::vector<float> read_exr_red_channel(const std::string& path, int& w, int& h) {
  try {
    ExrReader exr(path);
    w = exr.width();
    h = exr.height();
    std::vector<float> red(size_t(w) * size_t(h));
    exr.read(0, h, {{"R", red.data()}}, {ExrType::Float});
    return red;
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
    return {};
  }
}

// Histogram of directions over (cos theta, phi) cells of equal solid angle,
// against the pdf integrated over each cell by a k x k midpoint rule
// (k = integrationRes; raise it for peaked pdfs).
struct DirectionalChi2 {
  int thetaRes = 32;
  int phiRes = 64;
  int integrationRes = 4;
  bool refineEdges = false;
  std::vector<double> observed, expected;

  // Cells are uniform in azimuth around `pole` and in s = 1 - ((1 - z) / 2)^(1 /
  // polarPower), z the cosine to the pole: power 1 makes them equal in solid
  // angle; a higher power crowds them towards the pole, where a narrow lobe
  // centred on it needs them.
  glm::vec3 pole{0.0f, 0.0f, 1.0f};
  int polarPower = 1;

  void frame(glm::vec3& t, glm::vec3& b) const {
    if (pole == glm::vec3(0.0f, 0.0f, 1.0f)) {
      t = glm::vec3(1.0f, 0.0f, 0.0f);
      b = glm::vec3(0.0f, 1.0f, 0.0f);
    } else {
      shader::ShaderMath{}.make_frame(pole, t, b);
    }
  }

  int cell(glm::vec3 w) const {
    glm::vec3 t, b;
    frame(t, b);
    glm::dvec3 d(w);
    double x = glm::dot(d, glm::dvec3(t)), y = glm::dot(d, glm::dvec3(b)), z = std::clamp(glm::dot(d, glm::dvec3(pole)), -1.0, 1.0);
    // 1 - z from the transverse part, which keeps its precision near the pole.
    double oneMinusZ = z > 0.0 ? (x * x + y * y) / (1.0 + z) : 1.0 - z;
    double s = 1.0 - std::pow(std::min(oneMinusZ * 0.5, 1.0), 1.0 / polarPower);
    int i = std::min(thetaRes - 1, int(s * thetaRes));
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += 2.0 * M_PI;
    int j = std::min(phiRes - 1, int(phi / (2.0 * M_PI) * phiRes));
    return i * phiRes + j;
  }

  // sample() returns a direction and sets ok=false on failure (not counted).
  Chi2Result run(int n, const std::function<glm::vec3(glm::vec2, bool&)>& sample,
                 const std::function<double(glm::vec3)>& pdf, uint32_t seed) {
    observed.assign(size_t(thetaRes * phiRes), 0.0);
    expected.assign(size_t(thetaRes * phiRes), 0.0);
    uint32_t state = seed;
    shader::ShaderMath m;
    Chi2Result bad;
    for (int s = 0; s < n; ++s) {
      glm::vec2 u(m.rng_next(state), m.rng_next(state));
      bool ok = true;
      glm::vec3 w = sample(u, ok);
      if (!ok) continue;
      if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z) || std::fabs(glm::length(w) - 1.0f) > 1e-3f) {
        bad.problem = "a sample is not a finite unit vector";
        return bad;
      }
      observed[size_t(cell(w))] += 1.0;
    }
    double ds = 1.0 / thetaRes, dphi = 2.0 * M_PI / phiRes;
    glm::vec3 ft, fb;
    frame(ft, fb);
    // Midpoint rule over a k x k grid of the cell; returns the mean pdf and
    // whether the pdf jumps inside the cell (an edge of its support, or a step).
    auto integrate = [&](int i, int j, int k, bool& jumps) {
      double sum = 0.0, lo = INFINITY, hi = 0.0;
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
          double s = (i + (a + 0.5) / k) * ds;
          double z = 1.0 - 2.0 * std::pow(1.0 - s, polarPower);
          double dzds = 2.0 * polarPower * std::pow(1.0 - s, polarPower - 1);
          double phi = (j + (b + 0.5) / k) * dphi;
          double r = std::sqrt(std::max(0.0, 1.0 - z * z));
          glm::dvec3 w = glm::dvec3(ft) * (r * std::cos(phi)) + glm::dvec3(fb) * (r * std::sin(phi)) + glm::dvec3(pole) * z;
          double p = pdf(glm::vec3(glm::normalize(w))) * dzds;
          sum += p;
          lo = std::min(lo, p);
          hi = std::max(hi, p);
        }
      jumps = hi > 1.5 * lo;
      return sum / (k * k);
    };
    std::vector<char> jumpy(expected.size(), 0);
    for (int i = 0; i < thetaRes; ++i)
      for (int j = 0; j < phiRes; ++j) {
        bool jumps = false;
        expected[size_t(i * phiRes + j)] = integrate(i, j, integrationRes, jumps) * ds * dphi * n;
        jumpy[size_t(i * phiRes + j)] = jumps;
      }
    // Densities with sharp edges (emitters seen from a point) need a much finer
    // rule where the edges run: in cells where the pdf jumps, and next to
    // cells that jump or differ sharply (an edge may clip a cell between the
    // coarse rule's points).
    if (refineEdges) {
      std::vector<double> coarse = expected;
      for (int i = 0; i < thetaRes; ++i)
        for (int j = 0; j < phiRes; ++j) {
          bool near = false;
          for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj) {
              int ii = i + di, jj = (j + dj + phiRes) % phiRes;
              if (ii < 0 || ii >= thetaRes) continue;
              double a = coarse[size_t(i * phiRes + j)], b = coarse[size_t(ii * phiRes + jj)];
              if (jumpy[size_t(ii * phiRes + jj)] || std::max(a, b) > 1.5 * std::min(a, b)) near = true;
            }
          bool jumps = false;
          if (near) expected[size_t(i * phiRes + j)] = integrate(i, j, integrationRes * 16, jumps) * ds * dphi * n;
        }
    }
    return chi2_test(observed, expected, n);
  }
};

// Normal and incident direction pairs for BSDF tests: normal incidence,
// oblique, grazing, around normals that are not +Z.
struct BsdfGeometry {
  glm::vec3 n;
  glm::vec3 wo;
};
inline const BsdfGeometry kBsdfGeometries[] = {
    {{0, 0, 1}, {0, 0, 1}},
    {{0, 0, 1}, {0.6f, 0.0f, 0.8f}},
    {{0.48f, -0.6f, 0.64f}, {0.9f, 0.1f, 0.1f}},
};

// Chi-square over `grid`'s cells of n directions bsdf_sample draws from
// `sampled` at wo against the pdf `claimed` reports (the same BSDF, unless a
// test plants an error). Samples the BSDF absorbs are not counted; the
// expected counts are the pdf's integrals, which then sum to less than n.
// `keep`, where given, restricts both to the directions it accepts (one of
// two narrow peaks, which one grid cannot resolve together).
inline Chi2Result bsdf_chi2(DirectionalChi2& grid, int n, const shader::ShaderMath::Bsdf& sampled,
                            const shader::ShaderMath::Bsdf& claimed, glm::vec3 wo, uint32_t seed,
                            const std::function<bool(glm::vec3)>& keep = nullptr) {
  shader::ShaderMath m;
  uint32_t extra = m.rng_seed(seed, 1u, 2u);  // a stream unrelated to the harness's
  return grid.run(
      n,
      [&](glm::vec2 u, bool& ok) {
        glm::vec4 u4(u.x, u.y, m.rng_next(extra), m.rng_next(extra));
        glm::vec3 wi;
        float pdf;
        bool isDelta;
        glm::vec3 w = m.bsdf_sample(sampled, wo, u4, wi, pdf, isDelta);
        ok = pdf > 0.0f && !isDelta && (w.x > 0.0f || w.y > 0.0f || w.z > 0.0f) && (!keep || keep(wi));
        return wi;
      },
      [&](glm::vec3 wi) { return !keep || keep(wi) ? double(m.bsdf_pdf(claimed, wo, wi)) : 0.0; }, seed);
}

// The bunny (28.6k triangles, scaled to about 10 units) with a few spheres,
// one of them an ellipsoid, some overlapping the mesh.
Scene bunny_with_spheres(const AcceleratorSettings& accel);

// Rays through the scene's bounds: origins around and inside the box,
// directions uniform; a quarter aimed at surface points so many of them hit.
std::vector<shader::ShadowRay> random_rays(const Scene& scene, int count, uint32_t seed);

// Closest hit by testing every primitive: t, or WP_INF on a miss; one per ray,
// computed on all cores.
std::vector<float> brute_force_closest(const Scene& scene, const std::vector<shader::ShadowRay>& rays);



inline ImageStats render_reference(const std::string& scenePath, RenderOptions options, int spp = -1) {
  options.spp = spp;
  CompiledScene cs = compile_scene(load_scene(scenePath), reference_options(options));
  Progress quiet("", 0, false);
  return render_cpu(cs, 0, quiet);
}

// Mean over all pixels and channels, and a bound on its standard error: the
// channels of one sample are correlated, so their errors add (not in quadrature).
inline std::pair<double, double> image_mean(const ImageStats& img) {
  glm::dvec3 sum(0.0), var(0.0);
  for (size_t p = 0; p < img.pixels(); ++p) {
    sum += img.mean(p);
    var += img.variance(p) / std::max(img.count[p], 1.0);
  }
  double n = double(img.pixels());
  return {(sum.x + sum.y + sum.z) / (3.0 * n), (std::sqrt(var.x) + std::sqrt(var.y) + std::sqrt(var.z)) / (3.0 * n)};
}

// The image mean must be within 4 standard errors (and 1 %) of `expected`.
inline void expect_mean(const ImageStats& img, double expected, const char* what) {
  auto [mean, se] = image_mean(img);
  double err = std::fabs(mean - expected);
  EXPECT_TRUE(err < 4.0 * se + 1e-4 && err < 0.01 * expected)
      << what << ": mean " << mean << " +- " << se << ", expected " << expected;
  EXPECT_EQ(img.nonFinite, 0u) << what;
}


// Inside a closed box whose walls have albedo 0.5 and emit 0.5, paths of at
// most D bounces see exactly 1 - 0.5^(D+1), for every integrator. Runs that
// check with `render` for several depths and each integrator.
// CS184's adaptive sampling as its pathtracer defaults it: batches of 32,
// tolerance 5%, at most `spp` samples.
inline RenderOptions adaptive_options(int spp) {
  RenderOptions o;
  o.spp = spp;
  o.adaptive.batch = 32;
  o.adaptive.tolerance = 0.05f;
  return o;
}

inline void expect_furnace_is_analytic(const std::function<ImageStats(const CompiledScene&)>& render) {
  // Not "path tracer nee": at the box's edges, light samples on the adjacent
  // wall carry cos * cos / d^2 without bound, so NEE alone has infinite variance
  // here and the 4-sigma check is meaningless (seen: one sample of ~2000 in a
  // pixel). MIS tames exactly that; NEE is checked against the CPU and against
  // MIS on scenes without such edges.
  for (int bounces : {0, 2, 64}) {
    for (IntegratorKind kind : {IntegratorKind::PathMis, IntegratorKind::PathMats, IntegratorKind::PathMixture,
                                IntegratorKind::PathHemisphere}) {
      Scene scene = load_scene(source_path("tests/data/furnace.json"));
      scene.integrator.kind = kind;
      RenderOptions o;
      o.maxBounces = bounces;
      o.spp = 32;
      ImageStats img = render(compile_scene(scene, o));
      std::string what = "bounces " + std::to_string(bounces) + ", integrator " + std::to_string(int(kind));
      expect_mean(img, 1.0 - std::pow(0.5, bounces + 1), what.c_str());
    }
  }
}

// Single-scattering GGX with F = 1, computed here without the shared code:
// E(mu) = integral over wi of D G2 / (4 cos_o), taken over the microfacet
// normals h instead (d wi = 4 |wo.h| d h) and there in the variable s that
// GGX's D cos(h) makes uniform (tan^2 = alpha^2 s / (1 - s)), so that narrow
// lobes are resolved as well as wide ones: E = integral over s and phi of
// G2 |wo.h| / (cos_o cos_h) / (2 pi), where wi lies above the surface.
inline double ggx_albedo(double alpha, double cosO) {
  auto lambda = [&](double c) {
    double t2 = (1.0 - c * c) / (c * c);
    return 0.5 * (std::sqrt(1.0 + alpha * alpha * t2) - 1.0);
  };
  glm::dvec3 wo(std::sqrt(1.0 - cosO * cosO), 0.0, cosO);
  const int ns = 4000, nphi = 2000;
  double sum = 0.0;
  for (int i = 0; i < ns; ++i) {
    double s = (i + 0.5) / ns;
    double cosH = std::sqrt((1.0 - s) / (1.0 + (alpha * alpha - 1.0) * s));
    double sinH = std::sqrt(std::max(0.0, 1.0 - cosH * cosH));
    for (int j = 0; j < nphi; ++j) {
      double phi = (j + 0.5) / nphi * 2.0 * M_PI;
      glm::dvec3 h(sinH * std::cos(phi), sinH * std::sin(phi), cosH);
      double woH = glm::dot(wo, h);
      if (woH <= 0.0) continue;
      glm::dvec3 wi = 2.0 * woH * h - wo;
      if (wi.z <= 0.0) continue;
      sum += woH / (cosO * cosH) / (1.0 + lambda(cosO) + lambda(wi.z));
    }
  }
  return sum / (double(ns) * nphi);
}

}  // namespace wp::test
