#include "stats/reference_diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "util/error.h"
#include "util/files.h"

namespace wp {

ReferenceDiff diff_against_reference(const LinearImage& image, const LinearImage& reference, const ReferenceDiffSettings& s) {
  if (image.width != reference.width || image.height != reference.height) {
    throw InputError("images differ in size: " + std::to_string(image.width) + "x" + std::to_string(image.height) + " vs " +
                     std::to_string(reference.width) + "x" + std::to_string(reference.height) + " (the reference)");
  }
  const int w = image.width, h = image.height, b = std::max(1, s.block);
  auto compared = [&](int x, int y) {
    if (y < s.excludeTop || y >= h - s.excludeBottom) return false;
    if (x >= s.mask.x && x < s.mask.z && y >= s.mask.y && y < s.mask.w) return false;
    const size_t p = size_t(y) * size_t(w) + size_t(x);
    const glm::vec3 top = glm::max(image.pixels[p], reference.pixels[p]);
    return std::max(top.x, std::max(top.y, top.z)) < s.clipped;
  };
  glm::dvec3 sumImage(0.0), sumReference(0.0);
  const int blocksX = w / b, blocksY = h / b;
  std::vector<double> blockImage(size_t(blocksX) * size_t(blocksY), 0.0), blockReference(blockImage.size(), 0.0);
  std::vector<int> blockPixels(blockImage.size(), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!compared(x, y)) continue;
      const size_t p = size_t(y) * size_t(w) + size_t(x);
      const glm::dvec3 a(image.pixels[p]), r(reference.pixels[p]);
      sumImage += a;
      sumReference += r;
      if (x / b < blocksX && y / b < blocksY) {
        const size_t k = size_t(y / b) * size_t(blocksX) + size_t(x / b);
        blockImage[k] += a.x + a.y + a.z;
        blockReference[k] += r.x + r.y + r.z;
        ++blockPixels[k];
      }
    }
  }
  ReferenceDiff d;
  d.block = b;
  for (int c = 0; c < 3; ++c) d.ratio[c] = sumReference[c] > 0.0 ? sumImage[c] / sumReference[c] : (sumImage[c] > 0.0 ? INFINITY : 1.0);
  const double totalReference = sumReference.x + sumReference.y + sumReference.z;
  const double totalImage = sumImage.x + sumImage.y + sumImage.z;
  d.meanError = totalReference > 0.0 ? std::fabs(totalImage / totalReference - 1.0) : (totalImage > 0.0 ? INFINITY : 0.0);
  // Whole blocks only, brighter than 2 % of the brightest.
  double brightest = 0.0;
  for (size_t k = 0; k < blockReference.size(); ++k)
    if (blockPixels[k] == b * b) brightest = std::max(brightest, blockReference[k]);
  std::vector<double> errors;
  for (size_t k = 0; k < blockReference.size(); ++k)
    if (blockPixels[k] == b * b && blockReference[k] > 0.02 * brightest && blockReference[k] > 0.0)
      errors.push_back(std::fabs(blockImage[k] - blockReference[k]) / blockReference[k]);
  d.blocks = errors.size();
  if (!errors.empty()) {
    std::sort(errors.begin(), errors.end());
    d.blockMedian = errors[errors.size() / 2];
    d.blockP95 = errors[std::min(errors.size() - 1, size_t(0.95 * double(errors.size())))];
  }
  return d;
}

std::string ReferenceDiff::summary() const {
  char line[320];
  std::snprintf(line, sizeof line,
                "mean / reference R %.4f G %.4f B %.4f; mean error %.2f%%; %zu blocks of %dx%d: median error %.2f%%, 95th percentile %.2f%%",
                ratio.x, ratio.y, ratio.z, 100.0 * meanError, blocks, block, block, 100.0 * blockMedian, 100.0 * blockP95);
  return line;
}

float clip_radiance(EightBitCurve curve) {
  // Byte 255, read back as load_image_as_radiance reads it.
  return curve == EightBitCurve::Cs184 ? float(std::pow(std::min(255.0 + 0.5, 255.0) / 255.0, 2.2) / std::sqrt(2.0)) : 1.0f;
}

LinearImage load_image_as_radiance(const std::string& path, EightBitCurve curve) {
  if (curve != EightBitCurve::Cs184) return load_linear_image(path);
  const std::optional<std::vector<unsigned char>> bytes = read_file_bytes(path);
  if (!bytes) throw InputError(path + ": cannot open image");
  const std::string ext = lower_extension(path);
  LinearImage image = decode_linear_image(*bytes, path, ext, ColorEncoding::Linear);  // 8 bits as v / 255
  if (ext == ".exr" || ext == ".hdr") return image;
  const double exposure = std::sqrt(2.0);
  for (glm::vec3& p : image.pixels)
    for (int c = 0; c < 3; ++c) {
      const double step = std::round(double(p[c]) * 255.0);
      p[c] = step <= 0.0 ? 0.0f : float(std::pow(std::min(step + 0.5, 255.0) / 255.0, 2.2) / exposure);
    }
  return image;
}

}  // namespace wp
