// reference_diff.h — how far an image is from a reference image that carries
// no variance: a course's *-ref.png or *-ref.exr, or a peer renderer's
// output. Statistics cannot decide this (the reference's own noise and its
// 8-bit rounding are unknown), so it measures and a tolerance decides: the
// ratio of the image's mean to the reference's per channel, the relative
// error of the whole mean, and the relative error of the means of 16x16
// blocks (their median and 95th percentile, over blocks brighter than 2 %
// of the brightest, where the reference's noise does not dominate).
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <string>

#include "image/image_file.h"
#include "scene/texture_image.h"

namespace wp {

struct ReferenceDiffSettings {
  int excludeTop = 0, excludeBottom = 0;  // rows left out (darts' histograms weigh their pole rows by rounding)
  glm::ivec4 mask{0};                     // pixels [x0, x1) x [y0, y1) left out (a watermark); empty by default
  int block = 16;
  // Pixels where either image reaches this in a channel are left out, and
  // so are their blocks: an 8-bit image clips there and says nothing more.
  float clipped = INFINITY;
};

struct ReferenceDiff {
  glm::dvec3 ratio{1.0};         // per channel: mean of the image over mean of the reference (1 where both are 0)
  double meanError = 0.0;        // |sum of the image / sum of the reference - 1| over every compared value
  double blockMedian = 0.0;      // relative error of block means: median
  double blockP95 = 0.0;         // and 95th percentile
  size_t blocks = 0;             // blocks compared
  int block = 16;                // their side, in pixels
  std::string summary() const;
};

// Throws InputError if the images differ in size.
ReferenceDiff diff_against_reference(const LinearImage& image, const LinearImage& reference, const ReferenceDiffSettings& settings = {});

// The radiance an 8-bit image clips at, read back through its curve.
float clip_radiance(EightBitCurve curve);

// An image to compare, as radiance: OpenEXR and Radiance HDR as they are;
// 8-bit images through the inverse of the curve that wrote them (sRGB,
// rounded or truncated alike; CS184's curve read at the middle of each
// truncated step). Throws InputError naming the file.
LinearImage load_image_as_radiance(const std::string& path, EightBitCurve curve);

}  // namespace wp
