// image_file.h — a colour image (linear RGB floats) written in any format
// darts can save, picked by the file's extension: PNG, JPEG, BMP, TGA (8-bit
// sRGB, clamped), Radiance HDR, PFM and OpenEXR (32-bit float, linear).
// Every file is written to a temporary name and renamed, so a failed or
// interrupted write never leaves a complete-looking image.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace wp {

enum class ImageFormat { Png, Jpeg, Bmp, Tga, Hdr, Pfm, Exr };

// The format a file name's extension asks for (case-insensitive), if any.
std::optional<ImageFormat> image_format_of(const std::string& path);
// The format a name such as "png" or "jpg" (darts' --format) names, if any.
std::optional<ImageFormat> image_format_named(const std::string& name);
// "png, jpg, jpeg, bmp, tga, hdr, pfm, exr", for messages.
const char* image_format_names();

// How the 8-bit formats encode radiance, as each scene format's own
// renderer writes them: the sRGB curve rounded (wavepath's own, glTF);
// the sRGB curve truncated, as darts' Image3f::save does (darts-2022
// src/image.cpp:250); CS184's (sqrt(2) L)^(1/2.2), truncated (its
// util/image.h, toColor). Clamped to [0, 1] first.
enum class EightBitCurve { Srgb, DartsSrgb, Cs184 };
uint8_t encode_8bit_value(double linear, EightBitCurve curve = EightBitCurve::Srgb);
// Its name in a partial render's record ("srgb", "darts", "cs184") and back.
const char* eight_bit_curve_name(EightBitCurve curve);
EightBitCurve eight_bit_curve_named(const std::string& name);

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // 3 floats a pixel, rows top to bottom
};

// An image's pixels as 8-bit RGB in `curve`, non-finite ones magenta.
std::vector<uint8_t> encode_8bit_pixels(const RgbImage& image, EightBitCurve curve);

// Writes `image` in the format of `path`'s extension, 8-bit formats through
// `curve`; an InputError names the file where the extension is not a format,
// a RenderError where the write fails.
void write_image(const std::string& path, const RgbImage& image, EightBitCurve curve = EightBitCurve::Srgb);

// The file contents of 8-bit RGB pixels (three bytes a pixel, rows top to
// bottom) in PNG, JPEG, BMP or TGA; empty where encoding fails.
std::vector<uint8_t> encode_8bit(ImageFormat format, int width, int height, const std::vector<uint8_t>& rgb);

// Writes encoded file contents as write_atomically does; empty contents
// (a failed encoding) are an error.
void write_bytes_atomically(const std::string& path, const char* what, const std::vector<uint8_t>& bytes);

// Throws InputError naming `path` where its folder does not exist or cannot
// be written to: checked before work whose output would be lost.
void require_output_directory(const std::string& path);


// Writes through write(temporaryPath, error), then renames over `path`;
// throws RenderError("PATH: cannot write WHAT: error") where either fails
// (the folder was checked up front, so this is the disk's doing: full,
// failing). A file at `path` before is then left as it was.
void write_atomically(const std::string& path, const char* what, const std::function<bool(const std::string&, std::string&)>& write);

}  // namespace wp
