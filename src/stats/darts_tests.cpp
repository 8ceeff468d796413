#include "stats/darts_tests.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>

#include "bvh/photon_map.h"
#include "gpu/wavefront.h"
#include "render/compiled_scene.h"
#include "render/shader_cpp.h"
#include "scene/darts_tests.h"
#include "stats/direction_test.h"
#include "image/image_file.h"
#include "util/error.h"
#include "util/progress.h"

namespace wp {

namespace {

using shader::Hit;
using shader::ShadowRay;

// A test failed: its message is printed and the others still run.
struct TestFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The family-wise level of the chi-square verdicts of one file.
constexpr double kChi2Level = 0.01;

// Answers probes on the GPU (through probe.comp) or on the CPU reference.
class Prober {
 public:
  Prober(const CompiledScene& scene, const DartsTestOptions& a, const VulkanContext* ctx) : scene_(scene), view_(scene.view()), threads_(a.threads) {
    if (ctx) gpu_ = std::make_unique<WavefrontRenderer>(*ctx, scene, kernel_variant("gpu").settings);
  }

  std::vector<Hit> run(const std::vector<ShadowRay>& queries) {
    std::vector<Hit> out;
    if (gpu_) {
      out = gpu_->run_probes(queries);
    } else {
      out.resize(queries.size());
      tbb::task_arena arena(threads_ > 0 ? threads_ : tbb::task_arena::automatic);
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, queries.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
          for (size_t i = r.begin(); i != r.end(); ++i) out[i] = view_.run_probe(queries[i]);
        });
      });
    }
    for (size_t i = 0; i < queries.size(); ++i)
      if ((queries[i].path >> PROBE_KIND_SHIFT) == PROBE_INTERSECT && out[i].prim == PROBE_TRUNCATED)
        throw RenderError("a probe ray needed more than " + std::to_string(scene_.params.counts.z) + " BVH traversal steps");
    return out;
  }

 private:
  const CompiledScene& scene_;
  shader::SceneView view_;
  int threads_;
  std::unique_ptr<WavefrontRenderer> gpu_;
};

// Four random numbers of sample i: a stream of its own, so that the result
// does not depend on how the samples are batched.
glm::vec4 random4(uint64_t i, uint32_t seed) {
  shader::ShaderMath m;
  uint32_t state = m.rng_seed(uint32_t(i), uint32_t(i >> 32), seed);
  glm::vec4 u;
  for (int k = 0; k < 4; ++k) u[k] = m.rng_next(state);
  return u;
}

uint32_t probe_path(uint32_t kind, uint32_t index) {
  return (kind << PROBE_KIND_SHIFT) | index;
}

std::string output_path(const std::string& file, const std::string& name, const char* suffix) {
  return (std::filesystem::path(file).parent_path() / (name + suffix)).string();
}

// darts' group: a child uniformly, then (here) a point on it in proportion
// to area; the emitter table is rebuilt with those probabilities.
void pick_children_uniformly(CompiledScene& cs, const DartsTest& t) {
  shader::SceneView view = cs.view();
  std::vector<double> area(cs.emitters.size()), childArea(t.childMaterials.size(), 0.0);
  std::vector<size_t> child(cs.emitters.size());
  for (size_t e = 0; e < cs.emitters.size(); ++e) {
    const uint32_t prim = cs.emitters[e].prim;
    uint32_t material;
    if (prim & HIT_SPHERE_BIT) {
      const shader::Sphere& s = cs.spheres[prim & ~HIT_SPHERE_BIT];
      material = s.material;
      area[e] = s.area;
    } else {
      const shader::Triangle& tri = cs.triangles[prim];
      material = tri.material & TRIANGLE_MATERIAL_MASK;
      area[e] = view.triangle_area(tri);
    }
    child[e] = size_t(std::find(t.childMaterials.begin(), t.childMaterials.end(), material) - t.childMaterials.begin());
    childArea[child[e]] += area[e];
  }
  std::vector<double> weights(cs.emitters.size());
  for (size_t e = 0; e < weights.size(); ++e) weights[e] = area[e] / childArea[child[e]] / double(t.childMaterials.size());
  std::vector<shader::Emitter> table = build_alias_table(weights);
  for (size_t e = 0; e < table.size(); ++e) table[e].prim = cs.emitters[e].prim;
  cs.emitters = table;
}

class TestRunner {
 public:
  TestRunner(const std::string& file, const DartsTestOptions& a, const VulkanContext* ctx, int chi2Tests, FILE* log)
      : file_(file), args_(a), ctx_(ctx), level_(sidak(kChi2Level, std::max(chi2Tests, 1))), log_(log) {}

  // Runs test t; throws TestFailure with darts' message (or ours) if it fails.
  void run(const DartsTest& t) {
    if (t.kind == DartsTestKind::PhotonMap) return photon_map(t);
    RenderOptions options;
    options.seed = args_.seed;
    CompiledScene cs = compile_scene(t.scene, options);
    if (t.kind == DartsTestKind::SampleSurface) {
      if (cs.params.counts.x == 0 || t.childMaterials.empty()) throw TestFailure("there is no surface to sample");
      pick_children_uniformly(cs, t);
    }
    Prober prober(cs, args_, ctx_);
    if (t.kind == DartsTestKind::Intersection) return intersect(t, prober);
    sample(t, prober);
  }

 private:
  // The queries of samples [first, first + n) of a sampling test.
  std::vector<ShadowRay> sample_queries(const DartsTest& t, uint64_t first, size_t n) const {
    std::vector<ShadowRay> q(n);
    for (size_t i = 0; i < n; ++i) {
      glm::vec4 u = random4(first + i, args_.seed);
      q[i].origin = glm::vec3(u);
      q[i].tmax = u.w;
      if (t.kind == DartsTestKind::SampleSurface) {
        q[i].contribution = glm::vec4(0.0f);  // darts samples surfaces as seen from the origin
        q[i].path = probe_path(PROBE_SURFACE_SAMPLE, 0);
      } else {
        q[i].dir = -t.incoming;
        q[i].contribution = glm::vec4(t.normal, 0.0f);
        q[i].path = probe_path(PROBE_MATERIAL_SAMPLE, t.material);
      }
    }
    return q;
  }

  std::vector<float> pdf_at(const DartsTest& t, Prober& prober, const std::vector<glm::vec3>& dirs) const {
    // The planted error (tests only): a tilted normal, a moved viewpoint.
    const float e = args_.plantedPdfError;
    const glm::vec3 tilt = glm::normalize(glm::abs(t.normal.x) < 0.9f ? glm::cross(t.normal, glm::vec3(1, 0, 0)) : glm::cross(t.normal, glm::vec3(0, 1, 0)));
    const glm::vec3 normal = glm::normalize(t.normal * std::cos(e) + tilt * std::sin(e));
    std::vector<ShadowRay> q(dirs.size());
    for (size_t i = 0; i < dirs.size(); ++i) {
      if (t.kind == DartsTestKind::SampleSurface) {
        q[i].dir = dirs[i];
        q[i].contribution = glm::vec4(e, 0.0f, 0.0f, 0.0f);
        q[i].path = probe_path(PROBE_SURFACE_PDF, 0);
      } else {
        q[i].origin = dirs[i];
        q[i].dir = -t.incoming;
        q[i].contribution = glm::vec4(normal, 0.0f);
        q[i].path = probe_path(PROBE_MATERIAL_PDF, t.material);
      }
    }
    std::vector<Hit> answers = prober.run(q);
    std::vector<float> pdf(answers.size());
    for (size_t i = 0; i < answers.size(); ++i) pdf[i] = answers[i].t;
    return pdf;
  }

  // darts' PhotonMapTest: photons spread uniformly over the unit disk
  // placed by the test's transform, each carrying 1/N of the power; over the
  // image's unit square, the disk's pdf (super-sampled per pixel) and the
  // photon map's density estimate at each pixel's centre (the k nearest, or
  // a fixed radius, over the disc they fill) must integrate to the same
  // value within 0.01, as darts checks. Runs on the host, as darts does.
  void photon_map(const DartsTest& t) {
    const uint64_t total = t.samplesPerPixel * uint64_t(t.imageSize.x) * uint64_t(t.imageSize.y);
    shader::ShaderMath m;
    const float power = (1.0f + args_.plantedPdfError) / float(total);
    PhotonMap map;
    map.reserve(total);
    for (uint64_t i = 0; i < total; ++i) {
      const glm::vec2 d = m.square_to_disk_concentric(glm::vec2(random4(i, args_.seed)));
      map.add(glm::vec3(t.transform * glm::vec4(d, 0.0f, 1.0f)), glm::vec3(power));
    }
    map.build();
    const glm::mat4 toDisk = glm::inverse(t.transform);
    const double det = std::abs(double(glm::determinant(t.transform)));
    const size_t pixels = size_t(t.imageSize.x) * size_t(t.imageSize.y);
    std::vector<double> pdf(pixels), density(pixels);
    const uint32_t ss = t.superSamples;
    const float r2 = t.searchRadius * t.searchRadius;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t p = r.begin(); p != r.end(); ++p) {
        const double x = double(p % size_t(t.imageSize.x)), y = double(p / size_t(t.imageSize.x));
        double sum = 0.0;
        for (uint32_t sx = 0; sx < ss; ++sx)
          for (uint32_t sy = 0; sy < ss; ++sy) {
            const glm::vec2 at((x + (sx + 0.5) / ss) / t.imageSize.x, (y + (sy + 0.5) / ss) / t.imageSize.y);
            const glm::vec2 onDisk(toDisk * glm::vec4(at, 0.0f, 1.0f));
            sum += double(m.square_to_disk_concentric_pdf(onDisk)) / det;
          }
        pdf[p] = sum / (double(ss) * ss);
        const glm::vec3 q((x + 0.5) / t.imageSize.x, (y + 0.5) / t.imageSize.y, 0.0f);
        const PhotonMap::Gathered g = t.searchCount > 0 ? map.gather_nearest(q, r2, size_t(t.searchCount)) : map.gather_within(q, r2);
        density[p] = double(m.illuminance(g.power)) / double(g.area);
      }
    });
    double integral = 0.0, densityIntegral = 0.0;
    for (size_t p = 0; p < pixels; ++p) integral += pdf[p], densityIntegral += density[p];
    integral /= double(pixels);
    densityIntegral /= double(pixels);
    const double exposure = heatmap_exposure(pdf);
    write_pair(t.name, "pdf", pdf, exposure, t);
    write_pair(t.name, "photon-density", density, exposure, t);
    char msg[160];
    std::snprintf(msg, sizeof msg, "Integrals of analytic PDF: %g, and photon density: %g should match.", integral, densityIntegral);
    if (std::fabs(integral - densityIntegral) > 0.01) throw TestFailure(msg);
    say(msg);
  }

  void write_pair(const std::string& name, const char* what, const std::vector<double>& values, double exposure, const DartsTest& t) const {
    write_image(output_path(file_, name, (std::string("-") + what + ".png").c_str()), heatmap_image(values, t.imageSize, t.upSamples, exposure),
                EightBitCurve::DartsSrgb);
    write_image(output_path(file_, name, (std::string("-") + what + ".exr").c_str()), graymap_image(values, t.imageSize, t.upSamples));
  }

  void sample(const DartsTest& t, Prober& prober) {
    const bool material = t.kind != DartsTestKind::SampleSurface;
    const bool hasPdfImage = t.kind != DartsTestKind::ScatterMaterial;  // darts' scatter tests have no pdf
    const uint64_t total = t.samplesPerPixel * uint64_t(t.imageSize.x) * uint64_t(t.imageSize.y);
    DirectionHistogram histogram(t.imageSize, total);
    bool anyDelta = false, anyBelow = false;
    const glm::vec3 n = t.normal;
    auto add_samples = [&](uint64_t first, size_t count) {
      for (const Hit& h : prober.run(sample_queries(t, first, count))) {
        glm::vec3 wi(h.t, h.u, h.v);
        if (h.prim & PROBE_DELTA) anyDelta = true;
        // darts counts directions below the surface as failures of opaque materials.
        bool below = material && glm::dot(wi, n) < -1e-4f;
        anyBelow = anyBelow || ((h.prim & PROBE_VALID) && below);
        if ((h.prim & PROBE_VALID) && !below) histogram.add(wi);
        else histogram.add_invalid();
      }
    };
    // A first batch says whether a delta lobe samples (no density to
    // integrate); the pdf then says how many samples its chi-square may
    // take, and the histogram keeps its counts at that point.
    const size_t firstBatch = size_t(std::min<uint64_t>(total, 1024));
    add_samples(0, firstBatch);
    std::optional<PdfGrid> pdf;
    uint64_t chi2Samples = 0;
    const bool terminal = log_ && Progress::stderr_is_terminal();  // the course's files take a minute or two a test
    if (!anyDelta) {
      const uint64_t points = uint64_t(t.imageSize.x) * uint64_t(t.imageSize.y) * t.superSamples * t.superSamples;
      Progress pdfProgress("pdf points", points, terminal);
      uint64_t counted = 0;  // the refining pass's points come on top: the line stops at 100 %
      pdf = integrate_pdf(t.imageSize, t.superSamples, [&](const std::vector<glm::vec3>& dirs) {
        const uint64_t add = std::min<uint64_t>(dirs.size(), points - counted);
        counted += add;
        pdfProgress.add(add);
        return pdf_at(t, prober, dirs);
      });
      pdfProgress.finish();
      chi2Samples = std::max<uint64_t>(firstBatch, std::min(total, chi2_sample_budget(*pdf)));
      histogram.keep_counts_after(chi2Samples);
    }
    Progress progress("samples", total, terminal);
    progress.add(firstBatch);
    for (uint64_t first = firstBatch; first < total;) {
      uint64_t end = std::min(total, first + (1u << 20));
      if (first < chi2Samples && chi2Samples < end) end = chi2Samples;  // a batch ends where the chi-square's samples do
      add_samples(first, size_t(end - first));
      progress.add(end - first);
      first = end;
    }
    progress.finish();

    // One exposure for both heat maps, the histogram's, as in the course's
    // reference images (*-pdf-ref.png is as bright as *-sampled-ref.png).
    const double exposure = heatmap_exposure(histogram.density());
    if (pdf && hasPdfImage) write_pair(t.name, "pdf", pdf->mean, exposure, t);
    write_pair(t.name, "sampled", histogram.density(), exposure, t);

    // darts' checks and messages, in its order.
    if (hasPdfImage) {
      if (!pdf) throw TestFailure("is_specular is set. It should not be.");
      std::string integral = "Integral of PDF (should be close to 1): " + std::to_string(pdf->integral);
      if (pdf->integral > 1.01 || pdf->integral < 0.90) throw TestFailure(integral);
      say(integral);
    }
    const uint64_t percent = histogram.valid() * 100 / total;
    std::string valid = std::to_string(percent) + "% of the scattered directions were valid (this should be close to 100%)";
    if (percent > 100 || percent < 90) throw TestFailure(valid);
    say(valid);
    if (histogram.non_finite())
      throw TestFailure("Some directions/PDFs contained invalid values (NaN or infinity). This should not happen.");
    if (anyBelow) throw TestFailure("Some generated directions were below the hemisphere.");

    // Beyond darts: the histogram against the pdf.
    if (!pdf || anyDelta) {
      say("chi-square: skipped (a delta lobe has no density to test against)");
      return;
    }
    const uint64_t used = histogram.kept_samples();
    const std::vector<double>& counts = histogram.kept_counts();
    if (used < 10000) {
      say("chi-square: not applicable (the pdf's integrals over the cells are too uncertain to test even 10000 samples)");
      return;
    }
    Chi2Result r = direction_chi2(counts, *pdf, used);
    char line[320];
    std::snprintf(line, sizeof line, "chi-square of the first %llu samples: %.1f with %d degrees of freedom, p = %.3g (fails below %.3g)",
                  static_cast<unsigned long long>(used), r.statistic, r.dof, r.pValue, level_);
    if (!r.problem.empty()) throw TestFailure(std::string(line) + ": " + r.problem);
    if (r.pValue < level_) throw TestFailure(std::string(line) + ": the samples do not follow the pdf");
    say(line);
  }

  void intersect(const DartsTest& t, Prober& prober) {
    std::vector<ShadowRay> q(4);
    for (uint32_t i = 0; i < 4; ++i) {
      q[i].origin = t.rayOrigin;
      q[i].dir = t.rayDirection;
      q[i].tmax = WP_INF;
      q[i].path = probe_path(PROBE_INTERSECT, 0);
      q[i].media = i;  // PROBE_ANSWER_HIT, _POINT, _GEOMETRIC_NORMAL, _SHADING_NORMAL
    }
    std::vector<Hit> a = prober.run(q);
    const bool hit = a[PROBE_ANSWER_HIT].prim != WP_INVALID;
    if (!hit) {
      if (t.shouldHit) throw TestFailure("Intersection incorrect! Ray should hit surface.");
      say("the ray misses, as it should");
      return;
    }
    if (!t.shouldHit) throw TestFailure("Intersection incorrect! Ray should not hit the surface.");
    auto vec = [](const Hit& h) { return glm::vec3(h.t, h.u, h.v); };
    auto check = [&](const char* what, glm::vec3 want, glm::vec3 got) {
      glm::vec3 d = glm::abs(want - got);
      if (std::max(d.x, std::max(d.y, d.z)) > t.threshold) {
        char msg[256];
        std::snprintf(msg, sizeof msg, "%s incorrect! Should be (%g, %g, %g) but got (%g, %g, %g)", what, want.x, want.y, want.z, got.x,
                      got.y, got.z);
        throw TestFailure(msg);
      }
    };
    const float tHit = a[PROBE_ANSWER_HIT].t;
    if (std::fabs(tHit - t.t) > t.threshold)
      throw TestFailure("Intersection distance incorrect! Should be " + std::to_string(t.t) + " but got " + std::to_string(tHit));
    check("Intersection point", t.p, vec(a[PROBE_ANSWER_POINT]));
    check("Geometric normal", t.gn, vec(a[PROBE_ANSWER_GEOMETRIC_NORMAL]));
    check("Shading normal", t.sn, vec(a[PROBE_ANSWER_SHADING_NORMAL]));
    say("hit at t = " + std::to_string(tHit) + ", as it should");
  }

  std::string file_;
  const DartsTestOptions& args_;
  const VulkanContext* ctx_;
  double level_;
  FILE* log_;

  void say(const std::string& line) const {
    if (log_) std::fprintf(log_, "%s\n", line.c_str());
  }
};

}  // namespace

std::vector<DartsTestResult> run_darts_tests(const std::string& file, const DartsTestOptions& a, FILE* log) {
  std::vector<DartsTest> tests = import_darts_tests(file);
  // The tests write their images beside the file, as darts does: say so
  // before a minute of sampling, not after.
  require_output_directory(file);
  int chi2Tests = 0;
  for (const DartsTest& t : tests) chi2Tests += t.kind != DartsTestKind::Intersection && t.kind != DartsTestKind::PhotonMap;
  std::unique_ptr<VulkanContext> ctx;
  if (!a.cpu) ctx = std::make_unique<VulkanContext>(a.device, a.validation || VulkanContext::validation_requested_by_environment());
  TestRunner runner(file, a, ctx.get(), chi2Tests, log);
  std::vector<DartsTestResult> results;
  for (const DartsTest& t : tests) {
    DartsTestResult r;
    r.name = t.name;
    r.where = t.where;
    if (log) {
      const char* on = ctx ? ctx->info().name.c_str() : "the CPU reference";
      std::fprintf(log, "---------------------------------------------------------------------------\n");
      if (t.kind == DartsTestKind::Intersection && t.loadError.empty()) std::fprintf(log, "Testing surface intersection (%s) on %s\n", t.where.c_str(), on);
      else std::fprintf(log, "Running test for \"%s\" (%s) on %s\n", t.name.c_str(), t.where.c_str(), on);
      std::fflush(log);
    }
    if (!t.loadError.empty()) {
      r.unreadable = true;
      r.message = t.loadError;
    } else {
      try {
        runner.run(t);
        r.passed = true;
      } catch (const TestFailure& e) {
        r.message = e.what();
      }
    }
    results.push_back(r);
  }
  if (ctx && ctx->validation_messages() > 0)
    throw RenderError(std::to_string(ctx->validation_messages()) + " Vulkan validation message(s) reported");
  return results;
}

}  // namespace wp
