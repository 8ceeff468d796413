#include "image/image.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "../../shaders/shared/layers.glsl"
#include "../../shaders/shared/limits.glsl"
#include "image/exr.h"
#include "image/image_file.h"
#include "util/error.h"

namespace wp {

namespace {

// The AOV layers of layers.glsl's table: name, first channel in AovSample, channels.
struct AovRow {
  const char* name;
  size_t first;
  std::vector<std::string> channels;
};

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  for (size_t i = 0; i <= s.size(); ++i) {
    if (i == s.size() || s[i] == ',') {
      out.push_back(s.substr(start, i - start));
      start = i + 1;
    }
  }
  return out;
}

const std::vector<AovRow>& aov_rows() {
  static const std::vector<AovRow> rows = {
#define WP_AOV_ROW(id, name, first, channels) {name, first, split_commas(channels)},
      WP_AOV_LAYERS(WP_AOV_ROW)
#undef WP_AOV_ROW
  };
  return rows;
}

}  // namespace

std::vector<std::string> all_aov_names() {
  std::vector<std::string> names;
  for (const AovRow& r : aov_rows()) names.push_back(r.name);
  return names;
}

std::string aov_layer_names() {
  std::string names;
  for (const AovRow& r : aov_rows()) names += (names.empty() ? "" : ", ") + std::string(r.name);
  return names;
}

std::vector<ImageLayer> image_layers(const std::vector<std::string>& aovs) {
  for (const std::string& a : aovs) {
    bool known = false;
    for (const AovRow& r : aov_rows()) known = known || a == r.name;
    if (!known) throw InputError("unknown output layer \"" + a + "\" (expected " + aov_layer_names() + ")");
  }
  std::vector<ImageLayer> layers = {{"color", {"R", "G", "B", "Y"}, 0}};
  size_t next = 4;
  for (const AovRow& r : aov_rows()) {
    if (std::find(aovs.begin(), aovs.end(), r.name) == aovs.end()) continue;
    layers.push_back({r.name, r.channels, next});
    next += r.channels.size();
  }
  return layers;
}

size_t aov_sample_channel(const std::string& layer) {
  for (const AovRow& r : aov_rows())
    if (layer == r.name) return r.first;
  throw InputError("unknown output layer \"" + layer + "\"");
}

ImageStats::ImageStats(int w, int h, std::vector<ImageLayer> layerList) : width(w), height(h), layers(std::move(layerList)) {
  for (const ImageLayer& l : layers) stride = std::max(stride, l.first + l.channels.size());
  sum.assign(pixels() * stride, 0.0);
  sumSq.assign(pixels() * stride, 0.0);
  count.assign(pixels(), 0.0);
}

const ImageLayer* ImageStats::layer(const std::string& name) const {
  for (const ImageLayer& l : layers)
    if (l.name == name) return &l;
  return nullptr;
}

std::vector<std::string> ImageStats::aov_names() const {
  std::vector<std::string> names;
  for (size_t i = 1; i < layers.size(); ++i) names.push_back(layers[i].name);
  return names;
}

glm::dvec3 ImageStats::mean(size_t p) const {
  double n = count[p];
  if (n <= 0.0) return glm::dvec3(0.0);
  const double* s = &sum[p * stride];
  return glm::dvec3(s[0], s[1], s[2]) / n;
}

double ImageStats::layer_mean(size_t p, const ImageLayer& l, size_t c) const {
  const bool depthZ = l.name == "depth" && c == 0;
  const double over = depthZ ? sum[p * stride + l.first + 1] : count[p];
  return over > 0.0 ? sum[p * stride + l.first + c] / over : depthZ ? INFINITY : 0.0;
}

glm::dvec3 ImageStats::variance(size_t p) const {
  double n = count[p];
  if (n < 2.0) return glm::dvec3(0.0);
  glm::dvec3 m = mean(p);
  const double* s = &sumSq[p * stride];
  glm::dvec3 s2(s[0], s[1], s[2]);
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

void ImageStats::add(const ImageStats& o) {
  for (size_t i = 0; i < sum.size(); ++i) {
    sum[i] += o.sum[i];
    sumSq[i] += o.sumSq[i];
  }
  for (size_t p = 0; p < pixels(); ++p) count[p] += o.count[p];
  nonFinite += o.nonFinite;
}

ImageStats layer_as_color(const ImageStats& image, const std::string& name) {
  const ImageLayer* l = image.layer(name);
  if (!l) throw InputError("the image has no \"" + name + "\" layer");
  ImageStats out(image.width, image.height);
  out.count = image.count;
  for (size_t p = 0; p < image.pixels(); ++p) {
    for (size_t c = 0; c < std::min<size_t>(3, l->channels.size()); ++c) {
      out.sum[p * out.stride + c] = image.sum[p * image.stride + l->first + c];
      out.sumSq[p * out.stride + c] = image.sumSq[p * image.stride + l->first + c];
    }
  }
  return out;
}



RgbImage mean_rgb(const ImageStats& image) {
  RgbImage out;
  out.width = image.width;
  out.height = image.height;
  out.rgb.resize(image.pixels() * 3);
  for (size_t p = 0; p < image.pixels(); ++p) {
    glm::dvec3 m = image.mean(p);
    for (int c = 0; c < 3; ++c) out.rgb[3 * p + size_t(c)] = float(m[c]);
  }
  return out;
}

std::vector<uint8_t> to_srgb8(const ImageStats& image) {
  std::vector<uint8_t> rgb(image.pixels() * 3);
  for (size_t p = 0; p < image.pixels(); ++p) {
    glm::dvec3 m = image.mean(p);
    for (int c = 0; c < 3; ++c) rgb[3 * p + size_t(c)] = encode_8bit_value(m[c]);
  }
  return rgb;
}

std::vector<uint8_t> encode_png(int width, int height, const std::vector<uint8_t>& rgb) {
  return encode_8bit(ImageFormat::Png, width, height, rgb);
}

std::vector<uint8_t> sample_rate_rgb8(const ImageStats& image, int maxSamples) {
  std::vector<uint8_t> rgb(image.pixels() * 3);
  for (size_t p = 0; p < image.pixels(); ++p) {
    double t = std::clamp(image.count[p] / double(std::max(maxSamples, 1)), 0.0, 1.0);
    // Blue at 0, green at 1/2, red at 1.
    double r = std::clamp(2.0 * t - 1.0, 0.0, 1.0), g = 1.0 - std::fabs(2.0 * t - 1.0), b = std::clamp(1.0 - 2.0 * t, 0.0, 1.0);
    rgb[3 * p] = uint8_t(std::lround(255.0 * r));
    rgb[3 * p + 1] = uint8_t(std::lround(255.0 * g));
    rgb[3 * p + 2] = uint8_t(std::lround(255.0 * b));
  }
  return rgb;
}

void write_sample_rate_png(const std::string& path, const ImageStats& image, int maxSamples) {
  write_bytes_atomically(path, "PNG", encode_png(image.width, image.height, sample_rate_rgb8(image, maxSamples)));
}

namespace {

// The EXR names of an image's channels: the colour's as they are (R, G, B, Y),
// an AOV layer's as LAYER.CHANNEL.
std::string channel_name(const ImageLayer& l, size_t c) {
  return l.name == "color" ? l.channels[c] : l.name + "." + l.channels[c];
}

const char* const kRecordKeys[] = {"wavepath:scene", "wavepath:settings", "wavepath:samples",
                                   "wavepath:status", "wavepath:renderer", "wavepath:version"};

std::string* record_field(RenderRecord& r, int i) {
  std::string* fields[] = {&r.sceneHash, &r.settings, &r.samples, &r.status, &r.renderer, &r.version};
  return fields[i];
}

// One channel of a render's EXR and where its values come from.
struct RenderChannel {
  enum Kind { Mean, Variance, Count, AovMean, SumHi, SumLo } kind;
  size_t layer = 0, channel = 0;  // of the image's layers
  int moment = 0;                 // SumHi / SumLo: 0 the sum, 1 the sum of squares
  std::string name;
};

std::vector<RenderChannel> render_channels(const std::vector<ImageLayer>& layers, bool sums) {
  std::vector<RenderChannel> out;
  const char* rgb[3] = {"R", "G", "B"};
  for (size_t c = 0; c < 3; ++c) {
    out.push_back({RenderChannel::Mean, 0, c, 0, rgb[c]});
    out.push_back({RenderChannel::Variance, 0, c, 0, std::string("var.") + rgb[c]});
  }
  out.push_back({RenderChannel::Count, 0, 0, 0, "n"});
  for (size_t li = 1; li < layers.size(); ++li)
    for (size_t c = 0; c < layers[li].channels.size(); ++c) out.push_back({RenderChannel::AovMean, li, c, 0, channel_name(layers[li], c)});
  for (size_t li = 0; sums && li < layers.size(); ++li) {
    for (size_t c = 0; c < layers[li].channels.size(); ++c) {
      for (int moment = 0; moment < 2; ++moment) {
        const std::string base = std::string(moment == 0 ? "sum." : "sumsq.") + channel_name(layers[li], c);
        out.push_back({RenderChannel::SumHi, li, c, moment, base + ".hi"});
        out.push_back({RenderChannel::SumLo, li, c, moment, base + ".lo"});
      }
    }
  }
  return out;
}

bool is_word(const RenderChannel& c) {
  return c.kind == RenderChannel::SumHi || c.kind == RenderChannel::SumLo;
}

}  // namespace

RenderExrWriter::RenderExrWriter(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
                                 const RenderRecord& record, bool exactSums)
    : layers_(layers), sums_(exactSums || layers.size() > 1) {  // AOV layers' variances are in their sums alone
  std::vector<ExrChannel> channels;
  for (const RenderChannel& c : render_channels(layers_, sums_)) channels.push_back({c.name, is_word(c) ? ExrType::Uint : ExrType::Float});
  std::vector<std::pair<std::string, std::string>> attributes;
  RenderRecord r = record;
  for (int i = 0; i < 6; ++i)
    if (!record_field(r, i)->empty()) attributes.emplace_back(kRecordKeys[i], *record_field(r, i));
  writer_ = std::make_unique<ExrWriter>(path, width, height, channels, attributes, !sums_);
}

RenderExrWriter::~RenderExrWriter() = default;

void RenderExrWriter::write(const ImageStats& rows) {
  const size_t n = rows.pixels();
  const std::vector<RenderChannel> channels = render_channels(layers_, sums_);
  std::vector<std::vector<uint32_t>> values(channels.size(), std::vector<uint32_t>(n));
  std::vector<ExrPlane> planes;
  for (size_t k = 0; k < channels.size(); ++k) {
    const RenderChannel& ch = channels[k];
    const ImageLayer& l = rows.layers[ch.layer];
    uint32_t* out = values[k].data();
    auto put = [&](size_t p, float v) { std::memcpy(&out[p], &v, sizeof v); };
    for (size_t p = 0; p < n; ++p) {
      switch (ch.kind) {
        case RenderChannel::Mean: put(p, float(rows.mean(p)[int(ch.channel)])); break;
        case RenderChannel::Variance: put(p, float(rows.variance(p)[int(ch.channel)])); break;
        case RenderChannel::Count: put(p, float(rows.count[p])); break;
        case RenderChannel::AovMean: put(p, float(rows.layer_mean(p, l, ch.channel))); break;
        case RenderChannel::SumHi:
        case RenderChannel::SumLo: {
          const std::vector<double>& src = ch.moment == 0 ? rows.sum : rows.sumSq;
          uint64_t bits;
          std::memcpy(&bits, &src[p * rows.stride + l.first + ch.channel], sizeof bits);
          out[p] = ch.kind == RenderChannel::SumHi ? uint32_t(bits >> 32) : uint32_t(bits);
          break;
        }
      }
    }
    planes.push_back({ch.name, out});
  }
  writer_->write(rows.height, planes);
}

int exr_block_rows(int width, const std::vector<ImageLayer>& layers) {
  const size_t rowBytes = size_t(std::max(width, 1)) * (2 * ImageStats(1, 1, layers).stride + 1) * sizeof(double);
  return int(std::max<size_t>(1, (size_t(16) << 20) / rowBytes));
}

ImageStats ImageStats::rows(int y0, int y1) const {
  ImageStats out(width, y1 - y0, layers);
  const size_t first = size_t(y0) * size_t(width), n = out.pixels();
  std::copy(sum.begin() + ptrdiff_t(first * stride), sum.begin() + ptrdiff_t((first + n) * stride), out.sum.begin());
  std::copy(sumSq.begin() + ptrdiff_t(first * stride), sumSq.begin() + ptrdiff_t((first + n) * stride), out.sumSq.begin());
  std::copy(count.begin() + ptrdiff_t(first), count.begin() + ptrdiff_t(first + n), out.count.begin());
  return out;
}

void ImageStats::set_rows(int y0, const ImageStats& r) {
  const size_t first = size_t(y0) * size_t(width);
  std::copy(r.sum.begin(), r.sum.end(), sum.begin() + ptrdiff_t(first * stride));
  std::copy(r.sumSq.begin(), r.sumSq.end(), sumSq.begin() + ptrdiff_t(first * stride));
  std::copy(r.count.begin(), r.count.end(), count.begin() + ptrdiff_t(first));
}

void write_exr(const std::string& path, const ImageStats& image, const RenderRecord& record, bool exactSums) {
  write_atomically(path, "EXR", [&](const std::string& tmp, std::string& error) {
    try {
      RenderExrWriter w(tmp, image.width, image.height, image.layers, record, exactSums);
      // A block of rows at a time: the file's channels of a whole 8K image
      // would take 3 GB more.
      const int blockRows = exr_block_rows(image.width, image.layers);
      for (int y0 = 0; y0 < image.height; y0 += blockRows) w.write(image.rows(y0, std::min(image.height, y0 + blockRows)));
      return true;
    } catch (const std::exception& e) {
      error = e.what();
      return false;
    }
  });
}

RenderExrReader::RenderExrReader(const std::string& path) : file_(path) {
  std::string missing;
  for (const char* n : {"R", "G", "B", "n", "var.R", "var.G", "var.B"})
    if (!file_.type_of(n)) missing += std::string(missing.empty() ? "" : ", ") + n;
  if (!missing.empty()) throw InputError(path + ": EXR lacks the channels wavepath writes (" + missing + "): not a wavepath render");
  for (int i = 0; i < 6; ++i) *record_field(record_, i) = file_.attribute(kRecordKeys[i]);
  // The AOV layers the file holds sums of (their means alone carry no
  // variance: a file with AOVs always has the sums).
  std::vector<std::string> aovs;
  for (const ImageLayer& l : image_layers(all_aov_names()))
    if (l.name != "color" && file_.type_of("sum." + channel_name(l, 0) + ".hi")) aovs.push_back(l.name);
  layers_ = image_layers(aovs);
  // Exact sums where every channel has both words of both moments.
  bool exact = true;
  for (const RenderChannel& c : render_channels(layers_, true))
    if (is_word(c)) exact = exact && file_.type_of(c.name);
  record_.exactSums = exact;
}

ImageStats RenderExrReader::rows(int y0, int y1) {
  ImageStats out(width(), y1 - y0, layers_);
  const size_t n = out.pixels();
  const std::vector<RenderChannel> channels = render_channels(layers_, record_.exactSums);
  std::vector<std::vector<uint32_t>> values(channels.size(), std::vector<uint32_t>(n));
  std::vector<ExrPlane> planes;
  std::vector<ExrType> types;
  for (size_t k = 0; k < channels.size(); ++k) {
    // The AOVs' means are in their sums; so are the colour's, where the file has them.
    const bool inSums = channels[k].kind == RenderChannel::AovMean ||
                        (record_.exactSums && (channels[k].kind == RenderChannel::Mean || channels[k].kind == RenderChannel::Variance));
    if (inSums) continue;
    planes.push_back({channels[k].name, values[k].data()});
    types.push_back(is_word(channels[k]) ? ExrType::Uint : ExrType::Float);
  }
  file_.read(y0, y1, planes, types);
  auto f = [&](size_t k, size_t p) {
    float v;
    std::memcpy(&v, &values[k][p], sizeof v);
    return double(v);
  };
  for (size_t k = 0; k < channels.size(); ++k) {
    const RenderChannel& ch = channels[k];
    if (ch.kind == RenderChannel::Count)
      for (size_t p = 0; p < n; ++p) out.count[p] = f(k, p);
    if (ch.kind != RenderChannel::SumHi) continue;
    // Its .lo is the next channel.
    std::vector<double>& dst = ch.moment == 0 ? out.sum : out.sumSq;
    const size_t at = out.layers[ch.layer].first + ch.channel;
    for (size_t p = 0; p < n; ++p) {
      const uint64_t bits = uint64_t(values[k][p]) << 32 | values[k + 1][p];
      std::memcpy(&dst[p * out.stride + at], &bits, sizeof bits);
    }
  }
  if (!record_.exactSums) {
    // A file without them (written by an older wavepath or another
    // program): the colour's sums from mean, variance and count, to float
    // precision; no illuminance squares, no AOVs. Channels 0-5 are R,
    // var.R, G, var.G, B, var.B (render_channels).
    for (size_t p = 0; p < n; ++p) {
      const double count = out.count[p];
      for (size_t c = 0; c < 3; ++c) {
        const double m = f(2 * c, p), v = f(2 * c + 1, p);
        out.sum[p * out.stride + c] = m * count;
        out.sumSq[p * out.stride + c] = v * std::max(count - 1.0, 0.0) + count * m * m;
      }
      out.sum[p * out.stride + ImageStats::kY] =
          0.2126 * out.sum[p * out.stride] + 0.7152 * out.sum[p * out.stride + 1] + 0.0722 * out.sum[p * out.stride + 2];
    }
  }
  return out;
}

ImageStats RenderExrReader::all() {
  ImageStats out(width(), height(), layers_);
  const int blockRows = exr_block_rows(width(), layers_);
  for (int y0 = 0; y0 < height(); y0 += blockRows) out.set_rows(y0, rows(y0, std::min(height(), y0 + blockRows)));
  return out;
}

ImageStats read_exr(const std::string& path, RenderRecord* record) {
  RenderExrReader r(path);
  if (record) *record = r.record();
  return r.all();
}

}  // namespace wp
