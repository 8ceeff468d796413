#include "image/image.h"

#include <stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <unistd.h>

#include "util/error.h"

namespace wp {

glm::dvec3 ImageStats::mean(size_t p) const {
  double n = count[p];
  if (n <= 0.0) return glm::dvec3(0.0);
  return glm::dvec3(sum[3 * p], sum[3 * p + 1], sum[3 * p + 2]) / n;
}

glm::dvec3 ImageStats::variance(size_t p) const {
  double n = count[p];
  if (n < 2.0) return glm::dvec3(0.0);
  glm::dvec3 m = mean(p);
  glm::dvec3 s2(sumSq[3 * p], sumSq[3 * p + 1], sumSq[3 * p + 2]);
  return glm::max((s2 - n * m * m) / (n - 1.0), glm::dvec3(0.0));
}

double ImageStats::mean_luminance() const {
  double total = 0.0;
  for (size_t p = 0; p < pixels(); ++p) {
    glm::dvec3 m = mean(p);
    total += 0.2126 * m.x + 0.7152 * m.y + 0.0722 * m.z;
  }
  return pixels() ? total / double(pixels()) : 0.0;
}

// Writes encoded PNG bytes atomically (see write_png).
static void write_png_bytes(const std::string& path, const std::vector<uint8_t>& png);

double ImageStats::illuminance_sum(size_t pixel) const {
  return 0.2126 * sum[3 * pixel] + 0.7152 * sum[3 * pixel + 1] + 0.0722 * sum[3 * pixel + 2];
}

namespace {

uint8_t to_srgb8(double linear) {
  double c = std::clamp(linear, 0.0, 1.0);
  double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return uint8_t(std::lround(s * 255.0));
}

// Writes through `write(tmpPath)` then renames over `path`.
template <typename F>
void write_atomically(const std::string& path, const char* what, F write) {
  std::string tmp = path + ".tmp" + std::to_string(::getpid());
  std::string error;
  if (!write(tmp, error)) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write " + what + (error.empty() ? "" : ": " + error));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write " + what + ": " + ec.message());
  }
}

}  // namespace

std::vector<uint8_t> to_srgb8(const ImageStats& image) {
  std::vector<uint8_t> rgb(image.pixels() * 3);
  for (size_t p = 0; p < image.pixels(); ++p) {
    glm::dvec3 m = image.mean(p);
    rgb[3 * p] = to_srgb8(m.x);
    rgb[3 * p + 1] = to_srgb8(m.y);
    rgb[3 * p + 2] = to_srgb8(m.z);
  }
  return rgb;
}

std::vector<uint8_t> encode_png(int width, int height, const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> out;
  auto append = [](void* ctx, void* data, int size) {
    auto* v = static_cast<std::vector<uint8_t>*>(ctx);
    v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &out, width, height, 3, rgb.data(), width * 3)) out.clear();
  return out;
}

void write_png(const std::string& path, const ImageStats& image) {
  write_png_bytes(path, encode_png(image.width, image.height, to_srgb8(image)));
}

void write_sample_rate_png(const std::string& path, const ImageStats& image, int maxSamples) {
  std::vector<uint8_t> rgb(image.pixels() * 3);
  for (size_t p = 0; p < image.pixels(); ++p) {
    double t = std::clamp(image.count[p] / double(std::max(maxSamples, 1)), 0.0, 1.0);
    // Blue at 0, green at 1/2, red at 1.
    double r = std::clamp(2.0 * t - 1.0, 0.0, 1.0), g = 1.0 - std::fabs(2.0 * t - 1.0), b = std::clamp(1.0 - 2.0 * t, 0.0, 1.0);
    rgb[3 * p] = uint8_t(std::lround(255.0 * r));
    rgb[3 * p + 1] = uint8_t(std::lround(255.0 * g));
    rgb[3 * p + 2] = uint8_t(std::lround(255.0 * b));
  }
  write_png_bytes(path, encode_png(image.width, image.height, rgb));
}

static void write_png_bytes(const std::string& path, const std::vector<uint8_t>& png) {
  write_atomically(path, "PNG", [&](const std::string& tmp, std::string& error) {
    if (png.empty()) {
      error = "PNG encoding failed";
      return false;
    }
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return false;
    bool ok = std::fwrite(png.data(), 1, png.size(), f) == png.size();
    return std::fclose(f) == 0 && ok;
  });
}

void write_exr(const std::string& path, const ImageStats& image) {
  // EXR wants channels sorted by name.
  const char* names[] = {"B", "G", "R", "n", "var.B", "var.G", "var.R"};
  const int kChannels = 7;
  std::vector<std::vector<float>> planes(kChannels, std::vector<float>(image.pixels()));
  for (size_t p = 0; p < image.pixels(); ++p) {
    glm::dvec3 m = image.mean(p);
    glm::dvec3 v = image.variance(p);
    planes[0][p] = float(m.z);
    planes[1][p] = float(m.y);
    planes[2][p] = float(m.x);
    planes[3][p] = float(image.count[p]);
    planes[4][p] = float(v.z);
    planes[5][p] = float(v.y);
    planes[6][p] = float(v.x);
  }
  EXRHeader header;
  InitEXRHeader(&header);
  EXRImage exr;
  InitEXRImage(&exr);
  std::vector<unsigned char*> ptrs(kChannels);
  for (int c = 0; c < kChannels; ++c) ptrs[size_t(c)] = reinterpret_cast<unsigned char*>(planes[size_t(c)].data());
  exr.images = ptrs.data();
  exr.num_channels = kChannels;
  exr.width = image.width;
  exr.height = image.height;
  std::vector<EXRChannelInfo> channels(kChannels);
  std::vector<int> types(kChannels, TINYEXR_PIXELTYPE_FLOAT);
  for (int c = 0; c < kChannels; ++c) {
    std::snprintf(channels[size_t(c)].name, sizeof(channels[size_t(c)].name), "%s", names[c]);
  }
  header.num_channels = kChannels;
  header.channels = channels.data();
  header.pixel_types = types.data();
  header.requested_pixel_types = types.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  write_atomically(path, "EXR", [&](const std::string& tmp, std::string& error) {
    const char* err = nullptr;
    int rc = SaveEXRImageToFile(&exr, &header, tmp.c_str(), &err);
    if (err) {
      error = err;
      FreeEXRErrorMessage(err);
    }
    return rc == TINYEXR_SUCCESS;
  });
}

ImageStats read_exr(const std::string& path) {
  EXRVersion version;
  if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS)
    throw InputError(path + ": not an OpenEXR file (or cannot be read)");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  auto fail = [&](const std::string& what) {
    std::string msg = path + ": " + what + (err ? std::string(": ") + err : "");
    if (err) FreeEXRErrorMessage(err);
    throw InputError(msg);
  };
  if (ParseEXRHeaderFromFile(&header, &version, path.c_str(), &err) != TINYEXR_SUCCESS) fail("bad EXR header");
  for (int c = 0; c < header.num_channels; ++c) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  EXRImage exr;
  InitEXRImage(&exr);
  if (LoadEXRImageFromFile(&exr, &header, path.c_str(), &err) != TINYEXR_SUCCESS) {
    FreeEXRHeader(&header);
    fail("cannot decode EXR");
  }
  std::map<std::string, const float*> planes;
  for (int c = 0; c < header.num_channels; ++c)
    planes[header.channels[c].name] = reinterpret_cast<const float*>(exr.images ? exr.images[c] : nullptr);
  ImageStats out(exr.width, exr.height);
  std::string missing;
  for (const char* n : {"R", "G", "B", "n", "var.R", "var.G", "var.B"})
    if (!planes.count(n) || !planes[n]) missing += std::string(missing.empty() ? "" : ", ") + n;
  if (missing.empty()) {
    const char* rgb[3] = {"R", "G", "B"};
    const char* var[3] = {"var.R", "var.G", "var.B"};
    for (size_t p = 0; p < out.pixels(); ++p) {
      double n = planes["n"][p];
      out.count[p] = n;
      for (int c = 0; c < 3; ++c) {
        double m = planes[rgb[c]][p];
        double v = planes[var[c]][p];
        out.sum[3 * p + size_t(c)] = m * n;
        out.sumSq[3 * p + size_t(c)] = v * std::max(n - 1.0, 0.0) + n * m * m;
      }
    }
  }
  FreeEXRImage(&exr);
  FreeEXRHeader(&header);
  if (!missing.empty()) throw InputError(path + ": EXR lacks the channels wavepath writes (" + missing + "): not a wavepath render");
  return out;
}

}  // namespace wp
