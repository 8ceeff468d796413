#include "scene/texture_image.h"

#include <stb_image.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "util/error.h"

namespace wp {

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

namespace {

// Images larger than this are refused before decoding: a texture this size
// would not fit the GPU's per-binding limit anyway.
constexpr long long kMaxPixels = 1LL << 25;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// stb_image picks its decoder by the file's content, whatever its name, and
// Debian 12's copy has open CVEs (2023-45661 to 45667), several of them in the
// GIF decoder. Only the formats wavepath documents reach it: PNG, JPEG, BMP
// and Radiance HDR by their signatures (HDR's as stbi_is_hdr tests it), and
// TGA, which has none, by its extension when the content carries no other
// decoder's signature.
enum class StbFormat { None, Ldr, Hdr };

StbFormat stb_format(const std::string& path, const std::string& ext) {
  unsigned char head[11] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head), sizeof(head));
  const size_t n = size_t(in.gcount());
  auto starts = [&](const char* sig, size_t len) { return n >= len && std::memcmp(head, sig, len) == 0; };
  if (starts("#?RADIANCE\n", 11) || starts("#?RGBE\n", 7)) return StbFormat::Hdr;
  if (starts("\x89PNG\r\n\x1a\n", 8) || starts("\xff\xd8\xff", 3) || starts("BM", 2)) return StbFormat::Ldr;
  const bool otherDecoder = starts("GIF8", 4) || starts("8BPS", 4) || starts("\x53\x80\xf6\x34", 4) ||
                            (n >= 2 && head[0] == 'P' && head[1] >= '1' && head[1] <= '7');
  return ext == ".tga" && !otherDecoder ? StbFormat::Ldr : StbFormat::None;
}

// The size an OpenEXR file's header declares, read before LoadEXR, which
// allocates whatever the header asks for.
void check_exr_size(const std::string& path) {
  EXRVersion version;
  if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS) throw InputError(path + ": not an OpenEXR image");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  if (ParseEXRHeaderFromFile(&header, &version, path.c_str(), &err) != TINYEXR_SUCCESS) {
    std::string reason = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    FreeEXRHeader(&header);
    throw InputError(path + ": cannot read EXR image: " + reason);
  }
  const long long w = (long long)header.data_window.max_x - header.data_window.min_x + 1;
  const long long h = (long long)header.data_window.max_y - header.data_window.min_y + 1;
  FreeEXRHeader(&header);
  if (w <= 0 || h <= 0 || w * h > kMaxPixels)
    throw InputError(path + ": image is " + std::to_string(w) + "x" + std::to_string(h) + ", larger than wavepath accepts");
}

LinearImage load_exr(const std::string& path) {
  check_exr_size(path);
  float* rgba = nullptr;
  int w = 0;
  int h = 0;
  const char* err = nullptr;
  if (LoadEXR(&rgba, &w, &h, path.c_str(), &err) != TINYEXR_SUCCESS) {
    std::string reason = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    throw InputError(path + ": cannot read EXR image: " + reason);
  }
  LinearImage img;
  img.width = w;
  img.height = h;
  img.pixels.resize(size_t(w) * size_t(h));
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
  free(rgba);
  return img;
}

}  // namespace

LinearImage load_linear_image(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": cannot open image (no such file)");
  std::string ext = lower_extension(path);
  LinearImage img;
  if (ext == ".exr") {
    img = load_exr(path);
  } else {
    int w = 0;
    int h = 0;
    int channels = 0;
    const StbFormat format = stb_format(path, ext);
    if (format == StbFormat::None) throw InputError(path + ": not a PNG, JPEG, BMP, TGA, Radiance HDR or OpenEXR image");
    if (!stbi_info(path.c_str(), &w, &h, &channels)) {
      throw InputError(path + ": cannot read image: " + std::string(stbi_failure_reason()));
    }
    if (w <= 0 || h <= 0 || (long long)w * h > kMaxPixels) {
      throw InputError(path + ": image is " + std::to_string(w) + "x" + std::to_string(h) + ", larger than wavepath accepts");
    }
    const bool hdr = format == StbFormat::Hdr;
    img.width = w;
    img.height = h;
    img.pixels.resize(size_t(w) * size_t(h));
    // The decoder's size must be the one stbi_info read, which sized the pixels.
    auto check_size = [&](void* data) {
      if (!data) throw InputError(path + ": cannot decode image: " + std::string(stbi_failure_reason()));
      if (w != img.width || h != img.height) {
        stbi_image_free(data);
        throw InputError(path + ": the image's header and its data disagree on its size");
      }
    };
    if (hdr) {
      float* data = stbi_loadf(path.c_str(), &w, &h, &channels, 3);
      check_size(data);
      for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
      stbi_image_free(data);
    } else {
      unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
      check_size(data);
      float lut[256];
      for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(float(i) / 255.0f);
      for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(lut[data[3 * i]], lut[data[3 * i + 1]], lut[data[3 * i + 2]]);
      stbi_image_free(data);
    }
  }
  if (img.width <= 0 || img.height <= 0 || (long long)img.width * img.height > kMaxPixels) {
    throw InputError(path + ": image size " + std::to_string(img.width) + "x" + std::to_string(img.height) + " is not supported");
  }
  for (const glm::vec3& p : img.pixels) {
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) || p.x < 0.0f || p.y < 0.0f || p.z < 0.0f) {
      throw InputError(path + ": image has negative or non-finite pixels");
    }
  }
  return img;
}

}  // namespace wp
