// image.h — a rendered image as statistics: per pixel and channel the sum and
// sum of squares of the samples, and per pixel the sample count, in double
// precision. The PNG shows the mean; the EXR keeps mean, variance and count so
// that `wavepath compare` and the tests can judge images later.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "image/exr.h"
#include "image/image_file.h"

namespace wp {

// One output layer: its name and its channels' names. Layer 0 of every
// image is the colour: R, G, B and the illuminance Y (whose sums of squares
// adaptive sampling needs). AOV layers follow, as layers.glsl lists them.
struct ImageLayer {
  std::string name;
  std::vector<std::string> channels;
  size_t first = 0;  // index of its first channel among the image's channels
};

// The layers an image holds: the colour, then `aovs` (names from
// layers.glsl's table, in any order; stored in the table's order). Throws
// InputError naming the known layers for an unknown name.
std::vector<ImageLayer> image_layers(const std::vector<std::string>& aovs = {});
// The AOV layer names known, "albedo, normal, depth".
std::string aov_layer_names();
// Every AOV layer's name, in the table's order.
std::vector<std::string> all_aov_names();
// Where an AOV layer's channels start in a sample's AovSample record.
size_t aov_sample_channel(const std::string& layer);

struct ImageStats {
  int width = 0;
  int height = 0;
  std::vector<ImageLayer> layers;  // layers[0] is the colour
  size_t stride = 0;               // channels per pixel, over all layers
  std::vector<double> sum;    // stride per pixel
  std::vector<double> sumSq;  // stride per pixel
  std::vector<double> count;  // 1 per pixel
  uint64_t nonFinite = 0;     // samples dropped because they were NaN or infinite

  static constexpr size_t kY = 3;  // the colour's illuminance channel

  ImageStats() = default;
  ImageStats(int w, int h, std::vector<ImageLayer> layerList = image_layers());
  size_t pixels() const { return size_t(width) * size_t(height); }
  // The layer named `name`, or nullptr.
  const ImageLayer* layer(const std::string& name) const;
  std::vector<std::string> aov_names() const;
  glm::dvec3 mean(size_t pixel) const;
  // The mean of channel `c` of AOV layer `l` (one of `layers`) at a pixel,
  // as the EXR stores it: over the pixel's samples, but the depth's Z over
  // those that hit (its A, the coverage, is their fraction), infinite where
  // none did; 0 without samples.
  double layer_mean(size_t pixel, const ImageLayer& l, size_t c) const;
  // Unbiased sample variance of one sample (not of the mean); 0 below 2 samples.
  glm::dvec3 variance(size_t pixel) const;
  double mean_luminance() const;
  // Sum of the illuminance (luminance) of the samples of a pixel, and of its squares.
  double illuminance_sum(size_t pixel) const { return sum[pixel * stride + kY]; }
  double illuminance_sum_sq(size_t pixel) const { return sumSq[pixel * stride + kY]; }
  // Adds another image's sums and counts (same size and layers) to this one:
  // the exact merge of two disjoint sample ranges, in double precision.
  void add(const ImageStats& other);
  // Rows [y0, y1) as an image of their own, and such rows put back from row y0.
  ImageStats rows(int y0, int y1) const;
  void set_rows(int y0, const ImageStats& rows);
};

// A layer of `image` seen as a colour image (its first three channels as
// R, G, B, missing ones zero), with the same counts, so that
// compare_images and the PNG writer work on any layer.
ImageStats layer_as_color(const ImageStats& image, const std::string& layer);

// The mean colour, as floats (image_file.h writes it in any format).
RgbImage mean_rgb(const ImageStats& image);

// The mean in 8-bit sRGB, clamped: three bytes per pixel, row by row.
std::vector<uint8_t> to_srgb8(const ImageStats& image);
// PNG file contents for 8-bit RGB pixels.
std::vector<uint8_t> encode_png(int width, int height, const std::vector<uint8_t>& rgb);

// Samples per pixel as colour, CS184's sample-rate image: blue (few) through
// green to red (maxSamples).
// CS184's sample-rate image in 8-bit RGB: each pixel's samples over
// maxSamples, blue at 0, green at half, red at all.
std::vector<uint8_t> sample_rate_rgb8(const ImageStats& image, int maxSamples);
void write_sample_rate_png(const std::string& path, const ImageStats& image, int maxSamples);

// What an EXR's header says of the render it holds (a partial file: see
// docs/partial-renders.md): the scene's content hash, the settings that change the
// image, the sample ranges it accumulates, whether it stopped early, and the
// wavepath version that wrote it. Empty where a file was not written by a
// render (write_exr leaves such attributes out).
struct RenderRecord {
  std::string sceneHash;
  std::string settings;  // "key=value; ..." in a fixed order
  std::string samples;   // ranges "A:B" or "A:B,C:D" (sample_ranges.h)
  std::string status;    // "complete", or why the render stopped early
  std::string renderer;  // what rendered it (a device and variant, the CPU reference, several)
  std::string version;
  bool exactSums = false;  // read_exr: the file held the exact sums (a merge needs them)
};

// OpenEXR: 32-bit float channels R, G, B (mean), var.R, var.G, var.B (sample
// variance) and n (sample count); each AOV layer's means (LAYER.CHANNEL; the
// depth's Z over the samples that hit, its A their fraction); and, with
// `exactSums` (a partial render, for merging and resuming), every channel's
// sum and sum of squares as doubles, each split into two 32-bit unsigned
// channels (sum.CHANNEL.hi / .lo and sumsq...); an image with AOV layers
// always has them (the layers' variances are in no other channel). The record goes into the
// header as wavepath:* string attributes. ZIP-compressed, except with exact
// sums: their low-order bits do not compress (ZIP saved 9 % of a partial
// file and took six times as long to write; docs/benchmarks.md). Written
// atomically like the PNG.
void write_exr(const std::string& path, const ImageStats& image, const RenderRecord& record = {}, bool exactSums = false);
// Reads what write_exr wrote: the exact sums where the file has them, else
// sums rebuilt from the float mean, variance and count (to float precision).
ImageStats read_exr(const std::string& path, RenderRecord* record = nullptr);

// Rows of a width-pixel image with `layers` to read or write an EXR by: about
// 16 MiB of sums.
int exr_block_rows(int width, const std::vector<ImageLayer>& layers);

// write_exr's file a block of rows at a time (wavepath merge): the layers
// and the record up front, then the rows top to bottom, `height` in all.
// Into `path` as it is: the caller writes a temporary file (write_atomically).
class RenderExrWriter {
 public:
  RenderExrWriter(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers, const RenderRecord& record,
                  bool exactSums);
  ~RenderExrWriter();
  void write(const ImageStats& rows);  // the next rows.height rows

 private:
  std::vector<ImageLayer> layers_;
  bool sums_;
  std::unique_ptr<class ExrWriter> writer_;
};

// read_exr a block of rows at a time: the header (size, layers, record)
// when opened, rows on demand. Throws InputError naming the file where it
// is not a wavepath render, or where its data is damaged.
class RenderExrReader {
 public:
  explicit RenderExrReader(const std::string& path);
  int width() const { return file_.width(); }
  int height() const { return file_.height(); }
  const std::vector<ImageLayer>& layers() const { return layers_; }
  const RenderRecord& record() const { return record_; }
  // Rows [y0, y1) as an image of width x (y1 - y0); all of them, read a block at a time.
  ImageStats rows(int y0, int y1);
  ImageStats all();

 private:
  ExrReader file_;
  std::vector<ImageLayer> layers_;
  RenderRecord record_;
};


}  // namespace wp
