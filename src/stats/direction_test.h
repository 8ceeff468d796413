// direction_test.h — darts' check of a direction sampler (darts-2022
// src/tests/test.cpp), and a chi-square test on top: sampled directions are
// binned in a latitude-longitude grid (x: phi = atan2(-y, -x) + pi over
// [0, 2 pi), y: theta = acos z over [0, pi]), each weighted by the cell's
// solid angle so that the histogram estimates the density per steradian; the
// pdf is averaged over super x super points of each cell, and integrated over
// the sphere. The chi-square compares each cell's count with the pdf's
// integral over the cell, times the samples.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "image/image_file.h"
#include "stats/chi2.h"

namespace wp {

// darts' Spherical::direction_to_spherical_coordinates scaled to cells, and back.
glm::dvec2 direction_to_cell(glm::dvec3 dir, glm::ivec2 size);
glm::dvec3 cell_to_direction(glm::dvec2 cell, glm::ivec2 size);

class DirectionHistogram {
 public:
  DirectionHistogram(glm::ivec2 size, uint64_t totalSamples);
  // One sample, as darts counts it: non-finite directions are flagged and
  // dropped, the rest normalised and binned. Samples that produced no
  // direction are added as invalid. Samples are numbered in the order added.
  void add(glm::vec3 dir);
  void add_invalid();
  // Keep the cell counts as they stand after the first `samples` samples
  // (call before adding them), for a chi-square that may not take them all.
  void keep_counts_after(uint64_t samples);
  // Those counts (all counts, where fewer samples were added).
  const std::vector<double>& kept_counts() const { return seen_ > keepAfter_ ? kept_ : counts_; }
  uint64_t kept_samples() const { return std::min(seen_, keepAfter_); }
  // darts' histogram: per cell, the samples' weights cells / (2 pi^2 N sin theta).
  const std::vector<double>& density() const { return density_; }
  const std::vector<double>& counts() const { return counts_; }
  uint64_t valid() const { return valid_; }
  bool non_finite() const { return nonFinite_; }
  glm::ivec2 size() const { return size_; }

 private:
  glm::ivec2 size_;
  uint64_t total_;
  std::vector<double> density_, counts_;
  uint64_t valid_ = 0;
  bool nonFinite_ = false;
  uint64_t seen_ = 0;
  uint64_t keepAfter_ = UINT64_MAX;
  std::vector<double> kept_;

  void add_valid(glm::vec3 dir);
  void count_sample();
};

// The pdf over the grid: per cell the mean of super x super evaluations
// (darts' pdf image), and its integral over the sphere from the same points
// (darts' "Integral of PDF"); and for the chi-square, the integral over each
// cell, where the pdf varies across the cell from refine x finer points.
struct PdfGrid {
  std::vector<double> mean;
  std::vector<double> cellIntegral;
  std::vector<double> cellError;  // how much refining changed a cell's integral
  double integral = 0.0;
};

// evaluate(dirs) returns the pdf at each direction; it is called with about
// a million points at a time, so that a GPU evaluates many at once.
PdfGrid integrate_pdf(glm::ivec2 size, uint32_t super, const std::function<std::vector<float>(const std::vector<glm::vec3>&)>& evaluate,
                      uint32_t refine = 4);

// How many samples a chi-square against `pdf` may take before the error of
// its cell integrals, rather than the sampler, would decide the verdict: all
// of them for smooth densities; fewer where the density has sharp edges or
// grows without bound (darts' rough metal has such a rim).
uint64_t chi2_sample_budget(const PdfGrid& pdf);

// Chi-square of cell counts of `samples` samples against the pdf grid's cell integrals.
Chi2Result direction_chi2(const std::vector<double>& counts, const PdfGrid& pdf, uint64_t samples);

// darts' two images of a density over the grid, up x up pixels a cell: the
// heat map (matplotlib's inferno of value times an exposure) and the grey
// map (the values themselves). The exposure darts picks is one over the
// 99.95th percentile of the values (more robust than their maximum).
double heatmap_exposure(const std::vector<double>& values);
RgbImage heatmap_image(const std::vector<double>& values, glm::ivec2 size, uint32_t up, double exposure);
RgbImage graymap_image(const std::vector<double>& values, glm::ivec2 size, uint32_t up);

}  // namespace wp
