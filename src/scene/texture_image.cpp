#include "scene/texture_image.h"

#include <stb_image.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "util/error.h"
#include "util/files.h"

namespace wp {

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

namespace {

// Images larger than this are refused before decoding: a texture this size
// would not fit the GPU's per-binding limit anyway.
constexpr long long kMaxPixels = 1LL << 25;

// stb_image picks its decoder by the file's content, whatever its name, and
// Debian 12's copy has open CVEs (2023-45661 to 45667), several of them in the
// GIF decoder. Only the formats wavepath documents reach it: PNG, JPEG, BMP
// and Radiance HDR by their signatures (HDR's as stbi_is_hdr tests it), and
// TGA, which has none, by its extension when the content carries no other
// decoder's signature.
enum class StbFormat { None, Ldr, Hdr };

StbFormat stb_format(const std::vector<unsigned char>& bytes, const std::string& ext) {
  auto starts = [&](const char* sig, size_t len) { return bytes.size() >= len && std::memcmp(bytes.data(), sig, len) == 0; };
  if (starts("#?RADIANCE\n", 11) || starts("#?RGBE\n", 7)) return StbFormat::Hdr;
  if (starts("\x89PNG\r\n\x1a\n", 8) || starts("\xff\xd8\xff", 3) || starts("BM", 2)) return StbFormat::Ldr;
  const bool otherDecoder = starts("GIF8", 4) || starts("8BPS", 4) || starts("\x53\x80\xf6\x34", 4) ||
                            (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '7');
  return ext == ".tga" && !otherDecoder ? StbFormat::Ldr : StbFormat::None;
}

bool is_exr(const std::vector<unsigned char>& bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "\x76\x2f\x31\x01", 4) == 0;
}

void check_size(const std::string& name, long long w, long long h) {
  if (w <= 0 || h <= 0 || w * h > kMaxPixels)
    throw InputError(name + ": image is " + std::to_string(w) + "x" + std::to_string(h) + ", larger than wavepath accepts");
}

// The size an OpenEXR image's header declares, read before LoadEXR, which
// allocates whatever the header asks for.
void check_exr_size(const std::vector<unsigned char>& bytes, const std::string& name) {
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS) throw InputError(name + ": not an OpenEXR image");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  if (ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS) {
    std::string reason = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    FreeEXRHeader(&header);
    throw InputError(name + ": cannot read EXR image: " + reason);
  }
  const long long w = (long long)header.data_window.max_x - header.data_window.min_x + 1;
  const long long h = (long long)header.data_window.max_y - header.data_window.min_y + 1;
  FreeEXRHeader(&header);
  check_size(name, w, h);
}

LinearImage decode_exr(const std::vector<unsigned char>& bytes, const std::string& name) {
  check_exr_size(bytes, name);
  float* rgba = nullptr;
  int w = 0;
  int h = 0;
  const char* err = nullptr;
  if (LoadEXRFromMemory(&rgba, &w, &h, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS) {
    std::string reason = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    throw InputError(name + ": cannot read EXR image: " + reason);
  }
  LinearImage img;
  img.width = w;
  img.height = h;
  img.pixels.resize(size_t(w) * size_t(h));
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
  free(rgba);
  return img;
}

LinearImage decode_stb(const std::vector<unsigned char>& bytes, const std::string& name, StbFormat format, ColorEncoding encoding) {
  const stbi_uc* data8 = bytes.data();
  const int size = int(std::min<size_t>(bytes.size(), size_t(INT32_MAX)));
  int w = 0;
  int h = 0;
  int channels = 0;
  if (!stbi_info_from_memory(data8, size, &w, &h, &channels)) {
    throw InputError(name + ": cannot read image: " + std::string(stbi_failure_reason()));
  }
  check_size(name, w, h);
  LinearImage img;
  img.width = w;
  img.height = h;
  img.pixels.resize(size_t(w) * size_t(h));
  // The decoder's size must be the one stbi_info read, which sized the pixels.
  auto check_decoded = [&](void* data) {
    if (!data) throw InputError(name + ": cannot decode image: " + std::string(stbi_failure_reason()));
    if (w != img.width || h != img.height) {
      stbi_image_free(data);
      throw InputError(name + ": the image's header and its data disagree on its size");
    }
  };
  if (format == StbFormat::Hdr) {
    float* data = stbi_loadf_from_memory(data8, size, &w, &h, &channels, 3);
    check_decoded(data);
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
    stbi_image_free(data);
  } else {
    // Grey + alpha and RGBA files keep their alpha (linear whatever the colours' encoding).
    const bool hasAlpha = channels == 2 || channels == 4;
    const int n = hasAlpha ? 4 : 3;
    unsigned char* data = stbi_load_from_memory(data8, size, &w, &h, &channels, n);
    check_decoded(data);
    float lut[256];
    for (int i = 0; i < 256; ++i) lut[i] = encoding == ColorEncoding::Srgb ? srgb_to_linear(float(i) / 255.0f) : float(i) / 255.0f;
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(lut[data[n * i]], lut[data[n * i + 1]], lut[data[n * i + 2]]);
    if (hasAlpha) {
      img.alpha.resize(img.pixels.size());
      for (size_t i = 0; i < img.pixels.size(); ++i) img.alpha[i] = float(data[4 * i + 3]) / 255.0f;
    }
    stbi_image_free(data);
  }
  return img;
}

}  // namespace

LinearImage decode_linear_image(const std::vector<unsigned char>& bytes, const std::string& name, const std::string& extension,
                                ColorEncoding encoding) {
  LinearImage img;
  if (is_exr(bytes)) {
    img = decode_exr(bytes, name);
  } else {
    const StbFormat format = stb_format(bytes, extension);
    if (format == StbFormat::None) throw InputError(name + ": not a PNG, JPEG, BMP, TGA, Radiance HDR or OpenEXR image");
    img = decode_stb(bytes, name, format, encoding);
  }
  if (encoding == ColorEncoding::AlphaAsGrey) {
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = glm::vec3(img.alpha.empty() ? 1.0f : img.alpha[i]);
    img.alpha.clear();
  }
  for (const glm::vec3& p : img.pixels) {
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) || p.x < 0.0f || p.y < 0.0f || p.z < 0.0f) {
      throw InputError(name + ": image has negative or non-finite pixels");
    }
  }
  return img;
}

LinearImage load_linear_image(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": cannot open image (no such file)");
  const std::optional<std::vector<unsigned char>> bytes = read_file_bytes(path);
  if (!bytes) throw InputError(path + ": cannot read image");
  const std::string ext = lower_extension(path);
  if (ext == ".exr" && !is_exr(*bytes)) throw InputError(path + ": not an OpenEXR image");
  return decode_linear_image(*bytes, path, ext, ColorEncoding::Srgb);
}

}  // namespace wp
