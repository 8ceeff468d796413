#include "stats/direction_test.h"

#include <algorithm>
#include <cmath>

namespace wp {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Matplotlib's inferno colour map as the degree-6 polynomial fit darts uses
// (Matt Zucker's public-domain fit of the matplotlib table). Not clamped: the
// values past the 99.95th percentile go past 1, and the writer clamps.
glm::dvec3 inferno(double t) {
  static const glm::dvec3 c[7] = {{0.0002189403691192265, 0.001651004631001012, -0.01948089843709184},
                                  {0.1065134194856116, 0.5639564367884091, 3.932712388889277},
                                  {11.60249308247187, -3.972853965665698, -15.9423941062914},
                                  {-41.70399613139459, 17.43639888205313, 44.35414519872813},
                                  {77.162935699427, -33.40235894210092, -81.80730925738993},
                                  {-71.31942824499214, 32.62606426397723, 73.20951985803202},
                                  {25.13112622477341, -12.24266895238567, -23.07032500287172}};
  glm::dvec3 v = c[6];
  for (int i = 5; i >= 0; --i) v = c[i] + t * v;
  return v;
}

RgbImage upsampled(const std::vector<double>& values, glm::ivec2 size, uint32_t up, const std::function<glm::dvec3(double)>& colour) {
  RgbImage image;
  image.width = size.x * int(up);
  image.height = size.y * int(up);
  image.rgb.resize(size_t(image.width) * size_t(image.height) * 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      glm::dvec3 c = colour(values[size_t(y / int(up)) * size_t(size.x) + size_t(x / int(up))]);
      float* out = &image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3];
      out[0] = float(c.x);
      out[1] = float(c.y);
      out[2] = float(c.z);
    }
  return image;
}

}  // namespace

glm::dvec2 direction_to_cell(glm::dvec3 d, glm::ivec2 size) {
  double phi = std::atan2(-d.y, -d.x) + kPi;
  double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
  return glm::dvec2(phi * size.x / (2.0 * kPi), theta * size.y / kPi);
}

glm::dvec3 cell_to_direction(glm::dvec2 cell, glm::ivec2 size) {
  double phi = cell.x * 2.0 * kPi / size.x, theta = cell.y * kPi / size.y;
  return glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

DirectionHistogram::DirectionHistogram(glm::ivec2 size, uint64_t totalSamples)
    : size_(size), total_(totalSamples), density_(size_t(size.x) * size_t(size.y), 0.0), counts_(density_.size(), 0.0) {}

void DirectionHistogram::keep_counts_after(uint64_t samples) {
  keepAfter_ = std::max(samples, seen_);  // samples already added stay counted
  if (seen_ == keepAfter_) kept_ = counts_;
}

void DirectionHistogram::count_sample() {
  if (++seen_ == keepAfter_) kept_ = counts_;
}

void DirectionHistogram::add(glm::vec3 dir) {
  add_valid(dir);
  count_sample();
}

void DirectionHistogram::add_invalid() {
  count_sample();
}

void DirectionHistogram::add_valid(glm::vec3 dir) {
  if (!std::isfinite(dir.x) || !std::isfinite(dir.y) || !std::isfinite(dir.z) || !(glm::length(dir) > 0.0f)) {
    nonFinite_ = true;
    return;
  }
  glm::dvec3 d = glm::normalize(glm::dvec3(dir));
  glm::dvec2 cell = direction_to_cell(d, size_);
  const int x = int(cell.x), y = int(cell.y);
  if (x < 0 || y < 0 || x >= size_.x || y >= size_.y) return;
  // The sample's weight: cells over the sphere's (phi, theta) area 2 pi^2,
  // per sample, over the Jacobian sin theta of the mapping, which darts
  // computes in floats from the normalised float direction, at least 1e-8
  // (darts-2022 src/tests/test.cpp:119, 134-135). Near the poles 1 - z^2
  // cancels: a direction within 2.4e-4 rad of one has z = 1 exactly and
  // weighs 1e8 / (2 pi^2 N) cells; the course's quad-sampled-ref.exr owes 94 %
  // of its sum to such samples in its first row. The histogram image is what
  // darts writes; the chi-square reads the counts, not these weights.
  const glm::vec3 df = glm::normalize(dir);
  const double sinTheta = std::max(1e-8f, std::sqrt(std::max(1.0f - df.z * df.z, 0.0f)));
  size_t i = size_t(y) * size_t(size_.x) + size_t(x);
  density_[i] += double(density_.size()) / (2.0 * kPi * kPi * double(total_) * sinTheta);
  counts_[i] += 1.0;
  ++valid_;
}

namespace {

// What res x res midpoints of a cell say of the pdf there.
struct CellPoints {
  double sum = 0.0;       // of the values
  double integral = 0.0;  // midpoint rule over the cell's solid angle
  double low = INFINITY, high = 0.0;
};

// The pdf at res x res midpoints of each listed cell, a million points to a
// call of `evaluate`.
std::vector<CellPoints> integrate_cells(glm::ivec2 size, uint32_t res, const std::vector<size_t>& cells,
                                        const std::function<std::vector<float>(const std::vector<glm::vec3>&)>& evaluate) {
  const double pointArea = (kPi / res) * (2.0 * kPi / res) / (double(size.x) * double(size.y));  // times sin theta
  const size_t perCell = size_t(res) * res;
  const size_t cellsPerBatch = std::max<size_t>(1, (size_t(1) << 20) / perCell);
  std::vector<CellPoints> out(cells.size());
  std::vector<glm::vec3> dirs;
  std::vector<double> sinThetas;
  for (size_t c0 = 0; c0 < cells.size(); c0 += cellsPerBatch) {
    const size_t c1 = std::min(cells.size(), c0 + cellsPerBatch);
    dirs.clear();
    sinThetas.clear();
    for (size_t k = c0; k < c1; ++k) {
      const int x = int(cells[k] % size_t(size.x)), y = int(cells[k] / size_t(size.x));
      for (uint32_t sx = 0; sx < res; ++sx)
        for (uint32_t sy = 0; sy < res; ++sy) {
          glm::dvec3 d = cell_to_direction(glm::dvec2(x + (sx + 0.5) / res, y + (sy + 0.5) / res), size);
          dirs.push_back(glm::vec3(d));
          sinThetas.push_back(std::sqrt(std::max(1.0 - d.z * d.z, 0.0)));
        }
    }
    std::vector<float> pdf = evaluate(dirs);
    size_t i = 0;
    for (size_t k = c0; k < c1; ++k) {
      CellPoints& c = out[k];
      for (size_t s = 0; s < perCell; ++s, ++i) {
        double value = pdf[i];
        c.sum += value;
        c.integral += pointArea * sinThetas[i] * value;
        c.low = std::min(c.low, value);
        c.high = std::max(c.high, value);
      }
    }
  }
  return out;
}

}  // namespace

PdfGrid integrate_pdf(glm::ivec2 size, uint32_t super, const std::function<std::vector<float>(const std::vector<glm::vec3>&)>& evaluate,
                      uint32_t refine) {
  const size_t cells = size_t(size.x) * size_t(size.y);
  std::vector<size_t> all(cells);
  for (size_t i = 0; i < cells; ++i) all[i] = i;
  const std::vector<CellPoints> points = integrate_cells(size, super, all, evaluate);
  PdfGrid grid;
  grid.mean.resize(cells);
  grid.cellIntegral.resize(cells);
  grid.cellError.assign(cells, 0.0);
  for (size_t i = 0; i < cells; ++i) {
    grid.mean[i] = points[i].sum / (double(super) * super);
    grid.cellIntegral[i] = points[i].integral;
    grid.integral += points[i].integral;
  }
  // Where the pdf varies across a cell (an edge, a peak), or a cell where it
  // vanishes touches one where it does not (a sliver of support), the
  // midpoint rule may err by more than a chi-square of millions of samples
  // forgives: integrate those cells again, refine times finer in each
  // direction, and keep the change as the estimate's error.
  auto nonzero_near = [&](size_t i) {
    const int x = int(i % size_t(size.x)), y = int(i / size_t(size.x));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = (x + dx + size.x) % size.x, ny = y + dy;  // phi wraps around
        if (ny >= 0 && ny < size.y && points[size_t(ny) * size_t(size.x) + size_t(nx)].high > 0.0) return true;
      }
    return false;
  };
  std::vector<size_t> rough;
  for (size_t i = 0; i < cells; ++i)
    if (points[i].high > 1.05 * points[i].low || (points[i].high == 0.0 && nonzero_near(i))) rough.push_back(i);
  if (refine > 1 && !rough.empty()) {
    const std::vector<CellPoints> finer = integrate_cells(size, super * refine, rough, evaluate);
    for (size_t k = 0; k < rough.size(); ++k) {
      grid.cellError[rough[k]] = std::fabs(finer[k].integral - grid.cellIntegral[rough[k]]);
      grid.cellIntegral[rough[k]] = finer[k].integral;
    }
  }
  return grid;
}

uint64_t chi2_sample_budget(const PdfGrid& pdf) {
  // A cell's expected count N p carries the error N e of its integral, which
  // adds about N e^2 / p to the statistic. Keep the sum under a quarter of
  // the statistic's standard deviation, sqrt(2 dof).
  double sensitivity = 0.0;
  size_t cells = 0;
  for (size_t i = 0; i < pdf.cellIntegral.size(); ++i) {
    if (pdf.cellIntegral[i] <= 0.0) continue;
    ++cells;
    sensitivity += pdf.cellError[i] * pdf.cellError[i] / pdf.cellIntegral[i];
  }
  const double allowed = 0.25 * std::sqrt(2.0 * double(std::max<size_t>(cells, 1)));
  return sensitivity > 0.0 ? uint64_t(std::min(allowed / sensitivity, 1e18)) : UINT64_MAX;
}

Chi2Result direction_chi2(const std::vector<double>& counts, const PdfGrid& pdf, uint64_t samples) {
  std::vector<double> expected(pdf.cellIntegral.size());
  for (size_t i = 0; i < expected.size(); ++i) expected[i] = pdf.cellIntegral[i] * double(samples);
  return chi2_test(counts, expected, double(samples));
}

double heatmap_exposure(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  std::vector<double> v = values;
  auto at = v.begin() + ptrdiff_t(double(v.size() - 1) * 0.9995);
  std::nth_element(v.begin(), at, v.end());
  return *at > 0.0 ? 1.0 / *at : 0.0;
}

RgbImage heatmap_image(const std::vector<double>& values, glm::ivec2 size, uint32_t up, double exposure) {
  return upsampled(values, size, up, [&](double v) { return inferno(v * exposure); });
}

RgbImage graymap_image(const std::vector<double>& values, glm::ivec2 size, uint32_t up) {
  return upsampled(values, size, up, [](double v) { return glm::dvec3(v); });
}

}  // namespace wp
