#include "image/image_file.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "image/exr.h"

#include "util/error.h"
#include "util/fault.h"

namespace wp {

namespace {

struct FormatName {
  const char* name;
  ImageFormat format;
};

const FormatName kFormats[] = {{"png", ImageFormat::Png}, {"jpg", ImageFormat::Jpeg}, {"jpeg", ImageFormat::Jpeg},
                               {"bmp", ImageFormat::Bmp}, {"tga", ImageFormat::Tga},  {"hdr", ImageFormat::Hdr},
                               {"pfm", ImageFormat::Pfm}, {"exr", ImageFormat::Exr}};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// Whether a format holds linear floating-point values (HDR, PFM, EXR).
bool is_float_format(ImageFormat f) {
  return f == ImageFormat::Hdr || f == ImageFormat::Pfm || f == ImageFormat::Exr;
}

// stb_image_write's callback: appends to the std::vector<uint8_t> ctx.
void append_bytes(void* ctx, void* data, int size) {
  auto* v = static_cast<std::vector<uint8_t>*>(ctx);
  v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}

// Sets `error` to the system's reason where the file cannot be written.
bool write_file(const std::string& path, const std::vector<uint8_t>& bytes, std::string& error) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    error = std::strerror(errno);
    return false;
  }
  bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (!ok) error = std::strerror(errno);
  if (std::fclose(f) != 0 && ok) {  // buffered bytes the disk had no room for
    error = std::strerror(errno);
    ok = false;
  }
  return ok;
}

// PFM (Portable Float Map): "PF", width and height, and a scale whose sign
// gives the byte order (negative: little-endian), then float RGB rows from the
// bottom up.
std::vector<uint8_t> encode_pfm(const RgbImage& image) {
  const std::string header = "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
  const size_t rowBytes = size_t(image.width) * 3 * sizeof(float);
  std::vector<uint8_t> bytes(header.begin(), header.end());
  bytes.resize(header.size() + rowBytes * size_t(image.height));
  for (int y = 0; y < image.height; ++y)
    std::memcpy(bytes.data() + header.size() + size_t(y) * rowBytes, image.rgb.data() + size_t(image.height - 1 - y) * size_t(image.width) * 3,
                rowBytes);
  return bytes;
}

bool write_exr_rgb(const std::string& path, const RgbImage& image, std::string& error) {
  const size_t n = size_t(image.width) * size_t(image.height);
  std::vector<float> planes[3];
  for (int c = 0; c < 3; ++c) {
    planes[c].resize(n);
    for (size_t p = 0; p < n; ++p) planes[c][p] = image.rgb[3 * p + size_t(c)];
  }
  try {
    ExrWriter w(path, image.width, image.height, {{"R", ExrType::Float}, {"G", ExrType::Float}, {"B", ExrType::Float}}, {}, true);
    w.write(image.height, {{"R", planes[0].data()}, {"G", planes[1].data()}, {"B", planes[2].data()}});
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  return true;
}

}  // namespace

std::optional<ImageFormat> image_format_named(const std::string& name) {
  const std::string n = lower(name);
  for (const FormatName& f : kFormats)
    if (n == f.name) return f.format;
  return std::nullopt;
}

std::optional<ImageFormat> image_format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (ext.empty()) return std::nullopt;
  return image_format_named(ext.substr(1));
}

const char* image_format_names() {
  return "png, jpg, jpeg, bmp, tga, hdr, pfm, exr";
}

uint8_t encode_8bit_value(double linear, EightBitCurve curve) {
  if (curve == EightBitCurve::Cs184) {
    // The course's constants are floats: exposure sqrt(2^1), 1 / gamma.
    const float exposure = float(std::sqrt(std::pow(2.0, 1.0))), oneOverGamma = 1.0f / 2.2f;
    const double v = std::max(0.0, std::min(std::pow(linear * exposure, double(oneOverGamma)), 1.0));
    return uint8_t(uint32_t(float(v) * 255));
  }
  if (curve == EightBitCurve::DartsSrgb) {
    // darts' to_sRGB in floats (include/darts/math.h:254-257), clamped, times
    // 255, truncated: 1.0 comes out as 254, as in its references.
    const float c = float(linear);
    const float s = c <= 0.0031308f ? c * 12.92f : (1.0f + 0.055f) * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return uint8_t(std::clamp(s, 0.0f, 1.0f) * 255.0f);
  }
  const double c = std::clamp(linear, 0.0, 1.0);
  const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return uint8_t(std::lround(s * 255.0));
}

const char* eight_bit_curve_name(EightBitCurve curve) {
  return curve == EightBitCurve::Cs184 ? "cs184" : curve == EightBitCurve::DartsSrgb ? "darts" : "srgb";
}

EightBitCurve eight_bit_curve_named(const std::string& name) {
  return name == "cs184" ? EightBitCurve::Cs184 : name == "darts" ? EightBitCurve::DartsSrgb : EightBitCurve::Srgb;
}

std::vector<uint8_t> encode_8bit(ImageFormat format, int width, int height, const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> out;
  int ok = 0;
  switch (format) {
    case ImageFormat::Png: ok = stbi_write_png_to_func(append_bytes, &out, width, height, 3, rgb.data(), width * 3); break;
    case ImageFormat::Jpeg: ok = stbi_write_jpg_to_func(append_bytes, &out, width, height, 3, rgb.data(), 95); break;
    case ImageFormat::Bmp: ok = stbi_write_bmp_to_func(append_bytes, &out, width, height, 3, rgb.data()); break;
    case ImageFormat::Tga: ok = stbi_write_tga_to_func(append_bytes, &out, width, height, 3, rgb.data()); break;
    default: break;  // not an 8-bit format
  }
  if (!ok) out.clear();
  return out;
}

void write_bytes_atomically(const std::string& path, const char* what, const std::vector<uint8_t>& bytes) {
  write_atomically(path, what, [&](const std::string& tmp, std::string& error) {
    if (bytes.empty()) {
      error = "encoding failed";
      return false;
    }
    return write_file(tmp, bytes, error);
  });
}

void require_output_directory(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) throw InputError(path + ": the output directory does not exist");
  if (::access(dir.empty() ? "." : dir.c_str(), W_OK) != 0) throw InputError(path + ": the output directory is not writable");
}

void write_atomically(const std::string& path, const char* what, const std::function<bool(const std::string&, std::string&)>& write) {
  std::string tmp = path + ".tmp" + std::to_string(::getpid());
  std::string error;
  bool ok = write(tmp, error);
  if (ok && fault::disk_full_at_write()) {  // as if the disk filled before the file's end (util/fault.h)
    error = std::strerror(ENOSPC);
    ok = false;
  }
  if (!ok) {
    std::remove(tmp.c_str());
    throw RenderError(path + ": cannot write " + what + (error.empty() ? "" : ": " + error));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw RenderError(path + ": cannot write " + what + ": " + ec.message());
  }
}

std::vector<uint8_t> encode_8bit_pixels(const RgbImage& image, EightBitCurve curve) {
  // Non-finite values show as magenta, as darts shows them.
  std::vector<uint8_t> bytes(image.rgb.size());
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    bool finite = std::isfinite(image.rgb[i]) && std::isfinite(image.rgb[i + 1]) && std::isfinite(image.rgb[i + 2]);
    for (size_t c = 0; c < 3; ++c) bytes[i + c] = finite ? encode_8bit_value(image.rgb[i + c], curve) : (c == 1 ? 0 : 255);
  }
  return bytes;
}

void write_image(const std::string& path, const RgbImage& image, EightBitCurve curve) {
  std::optional<ImageFormat> format = image_format_of(path);
  if (!format) throw InputError(path + ": unknown image format (expected the extension of one of " + image_format_names() + ")");
  if (image.rgb.size() != size_t(image.width) * size_t(image.height) * 3 || image.width <= 0 || image.height <= 0)
    throw InputError(path + ": internal error: the image's size does not match its pixels");
  const std::vector<uint8_t> bytes = is_float_format(*format) ? std::vector<uint8_t>() : encode_8bit_pixels(image, curve);
  if (*format == ImageFormat::Exr) {
    write_atomically(path, "image", [&](const std::string& tmp, std::string& error) { return write_exr_rgb(tmp, image, error); });
    return;
  }
  std::vector<uint8_t> encoded;
  if (*format == ImageFormat::Pfm) {
    encoded = encode_pfm(image);
  } else if (*format == ImageFormat::Hdr) {
    if (!stbi_write_hdr_to_func(append_bytes, &encoded, image.width, image.height, 3, image.rgb.data())) encoded.clear();
  } else {
    encoded = encode_8bit(*format, image.width, image.height, bytes);
  }
  write_bytes_atomically(path, "image", encoded);
}

}  // namespace wp
