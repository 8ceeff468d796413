#include "scene/texture_image.h"

#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "image/exr.h"
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
  if (w <= 0 || h <= 0) throw InputError(name + ": the image's header gives it a size of " + std::to_string(w) + "x" + std::to_string(h));
  if (w * h > kMaxPixels) {
    throw InputError(name + ": the image is too large: " + std::to_string(w) + "x" + std::to_string(h) + " pixels, more than the " +
                     std::to_string(kMaxPixels) + " (8192x4096) wavepath accepts");
  }
}

// A PNG's size from its header (IHDR, which the format puts first), read
// before stb_image's: stb_image refuses a PNG of more than 2^30 bytes of
// pixels while reading its header, and then reports every other decoder's
// refusal instead ("unknown image type").
void check_png_size(const std::vector<unsigned char>& bytes, const std::string& name) {
  if (bytes.size() < 24 || std::memcmp(bytes.data() + 12, "IHDR", 4) != 0) return;  // stb_image says what is wrong
  auto be32 = [&](size_t at) { return (long long)bytes[at] << 24 | bytes[at + 1] << 16 | bytes[at + 2] << 8 | bytes[at + 3]; };
  check_size(name, be32(16), be32(20));
}

// An OpenEXR image's colour: R, G and B; a luminance image's Y (or its one
// channel) in all three.
LinearImage decode_exr(const std::vector<unsigned char>& bytes, const std::string& name) {
  ExrReader exr(bytes, name);
  check_size(name, exr.width(), exr.height());
  const size_t n = size_t(exr.width()) * size_t(exr.height());
  std::vector<std::string> names = {"R", "G", "B"};
  if (!exr.type_of("R") && !exr.type_of("G") && !exr.type_of("B")) {
    const std::string grey = exr.type_of("Y") ? "Y" : exr.channels().size() == 1 ? exr.channels()[0].name : "R";
    names = {grey, grey, grey};
  }
  std::vector<float> planes[3];
  std::vector<ExrPlane> wanted;
  for (int c = 0; c < 3; ++c) {
    planes[c].assign(n, 0.0f);
    if (c == 0 || names[c] != names[0]) wanted.push_back({names[c], planes[c].data()});
  }
  exr.read(0, exr.height(), wanted, std::vector<ExrType>(wanted.size(), ExrType::Float));
  if (names[1] == names[0]) planes[1] = planes[2] = planes[0];
  LinearImage img;
  img.width = exr.width();
  img.height = exr.height();
  img.pixels.resize(n);
  for (size_t i = 0; i < n; ++i) img.pixels[i] = glm::vec3(planes[0][i], planes[1][i], planes[2][i]);
  return img;
}

LinearImage decode_stb(const std::vector<unsigned char>& bytes, const std::string& name, StbFormat format, ColorEncoding encoding) {
  const stbi_uc* data8 = bytes.data();
  const int size = int(std::min<size_t>(bytes.size(), size_t(INT32_MAX)));
  int w = 0;
  int h = 0;
  int channels = 0;
  check_png_size(bytes, name);
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
