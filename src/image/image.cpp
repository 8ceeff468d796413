#include "image/image.h"

#include <stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../../shaders/shared/layers.glsl"
#include "../../shaders/shared/limits.glsl"
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

// One EXR channel to write: its name, pixel type and values.
struct ExrPlane {
  std::string name;
  int type = TINYEXR_PIXELTYPE_FLOAT;
  std::vector<float> f;
  std::vector<uint32_t> u;
};

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

}  // namespace

void write_exr(const std::string& path, const ImageStats& image, const RenderRecord& recordIn, bool exactSums) {
  const size_t n = image.pixels();
  const bool sums = exactSums || image.layers.size() > 1;  // AOV layers' variances are in their sums alone
  std::deque<ExrPlane> planes;  // a deque: the references plane() returns stay valid as it grows
  auto plane = [&](const std::string& name, int type) -> ExrPlane& {
    planes.push_back({name, type, {}, {}});
    if (type == TINYEXR_PIXELTYPE_FLOAT) planes.back().f.resize(n);
    else planes.back().u.resize(n);
    return planes.back();
  };
  // What a viewer shows: the colour's mean, variance and count.
  const char* rgb[3] = {"R", "G", "B"};
  ExrPlane* mean[3];
  ExrPlane* var[3];
  for (int c = 0; c < 3; ++c) {
    mean[c] = &plane(rgb[c], TINYEXR_PIXELTYPE_FLOAT);
    var[c] = &plane(std::string("var.") + rgb[c], TINYEXR_PIXELTYPE_FLOAT);
  }
  for (size_t p = 0; p < n; ++p) {
    const glm::dvec3 m = image.mean(p), v = image.variance(p);
    for (int c = 0; c < 3; ++c) {
      mean[c]->f[p] = float(m[c]);
      var[c]->f[p] = float(v[c]);
    }
  }
  ExrPlane& count = plane("n", TINYEXR_PIXELTYPE_FLOAT);
  for (size_t p = 0; p < n; ++p) count.f[p] = float(image.count[p]);
  // The AOV layers' means; depth over the samples that hit (A, the
  // coverage, is its last channel), infinite where none did.
  for (size_t li = 1; li < image.layers.size(); ++li) {
    const ImageLayer& l = image.layers[li];
    bool depth = l.name == "depth";
    for (size_t c = 0; c < l.channels.size(); ++c) {
      ExrPlane& m = plane(channel_name(l, c), TINYEXR_PIXELTYPE_FLOAT);
      for (size_t p = 0; p < n; ++p) {
        double s = image.sum[p * image.stride + l.first + c];
        double over = depth && c == 0 ? image.sum[p * image.stride + l.first + 1] : image.count[p];
        m.f[p] = over > 0.0 ? float(s / over) : (depth && c == 0 ? INFINITY : 0.0f);
      }
    }
  }
  // The exact sums, for merging: each double as its high and low 32 bits.
  for (const ImageLayer& l : sums ? image.layers : std::vector<ImageLayer>{}) {
    for (size_t c = 0; c < l.channels.size(); ++c) {
      for (int moment = 0; moment < 2; ++moment) {
        const std::vector<double>& src = moment == 0 ? image.sum : image.sumSq;
        std::string base = std::string(moment == 0 ? "sum." : "sumsq.") + channel_name(l, c);
        ExrPlane& hi = plane(base + ".hi", TINYEXR_PIXELTYPE_UINT);
        ExrPlane& lo = plane(base + ".lo", TINYEXR_PIXELTYPE_UINT);
        for (size_t p = 0; p < n; ++p) {
          uint64_t bits;
          std::memcpy(&bits, &src[p * image.stride + l.first + c], sizeof bits);
          hi.u[p] = uint32_t(bits >> 32);
          lo.u[p] = uint32_t(bits);
        }
      }
    }
  }
  // EXR wants channels sorted by name.
  std::sort(planes.begin(), planes.end(), [](const ExrPlane& a, const ExrPlane& b) { return a.name < b.name; });

  RenderRecord record = recordIn;
  std::vector<EXRAttribute> attributes;
  for (int i = 0; i < 6; ++i) {
    const std::string& value = *record_field(record, i);
    if (value.empty()) continue;
    EXRAttribute a{};
    std::snprintf(a.name, sizeof a.name, "%s", kRecordKeys[i]);
    std::snprintf(a.type, sizeof a.type, "string");
    a.value = reinterpret_cast<unsigned char*>(const_cast<char*>(value.data()));
    a.size = int(value.size());
    attributes.push_back(a);
  }

  EXRHeader header;
  InitEXRHeader(&header);
  EXRImage exr;
  InitEXRImage(&exr);
  const int kChannels = int(planes.size());
  std::vector<unsigned char*> ptrs(planes.size());
  std::vector<EXRChannelInfo> channels(planes.size());
  std::vector<int> types(planes.size());
  for (size_t c = 0; c < planes.size(); ++c) {
    ptrs[c] = planes[c].type == TINYEXR_PIXELTYPE_FLOAT ? reinterpret_cast<unsigned char*>(planes[c].f.data())
                                                        : reinterpret_cast<unsigned char*>(planes[c].u.data());
    std::snprintf(channels[c].name, sizeof(channels[c].name), "%s", planes[c].name.c_str());
    types[c] = planes[c].type;
  }
  exr.images = ptrs.data();
  exr.num_channels = kChannels;
  exr.width = image.width;
  exr.height = image.height;
  header.num_channels = kChannels;
  header.channels = channels.data();
  header.pixel_types = types.data();
  header.requested_pixel_types = types.data();
  header.compression_type = sums ? TINYEXR_COMPRESSIONTYPE_NONE : TINYEXR_COMPRESSIONTYPE_ZIP;
  header.num_custom_attributes = int(attributes.size());
  header.custom_attributes = attributes.empty() ? nullptr : attributes.data();
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

namespace {

// A file mapped read-only: tinyexr's *FromFile functions read a whole file
// into a buffer of their own first, a third of a merge's memory at 4096x4096.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path) {
    int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return;
    struct stat st {};
    if (::fstat(fd, &st) == 0 && st.st_size > 0) {
      void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (p != MAP_FAILED) {
        data_ = static_cast<const unsigned char*>(p);
        size_ = size_t(st.st_size);
      }
    }
    ::close(fd);
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<unsigned char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  const unsigned char* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  const unsigned char* data_ = nullptr;
  size_t size_ = 0;
};

}  // namespace

ImageStats read_exr(const std::string& path, RenderRecord* recordOut) {
  MappedFile file(path);
  EXRVersion version;
  if (!file.data() || ParseEXRVersionFromMemory(&version, file.data(), file.size()) != TINYEXR_SUCCESS)
    throw InputError(path + ": not an OpenEXR file (or cannot be read)");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  auto fail = [&](const std::string& what) {
    std::string msg = path + ": " + what + (err ? std::string(": ") + err : "");
    if (err) FreeEXRErrorMessage(err);
    throw InputError(msg);
  };
  if (ParseEXRHeaderFromMemory(&header, &version, file.data(), file.size(), &err) != TINYEXR_SUCCESS) fail("bad EXR header");
  // tinyexr allocates whatever the header declares before decoding: refuse
  // sizes no render has, and more pixel data than deflate (at most about
  // 1032:1) can have packed into the file.
  {
    const long long w = (long long)header.data_window.max_x - header.data_window.min_x + 1;
    const long long h = (long long)header.data_window.max_y - header.data_window.min_y + 1;
    const long long channels = header.num_channels;
    const bool renderSized = w > 0 && h > 0 && w <= MAX_IMAGE_SIZE && h <= MAX_IMAGE_SIZE && channels <= 256;
    if (!renderSized || w * h * channels * 4 > 1100LL * (long long)file.size()) {
      FreeEXRHeader(&header);
      throw InputError(path + ": EXR declares " + std::to_string(w) + "x" + std::to_string(h) + " pixels of " +
                       std::to_string(channels) + " channels, more than a wavepath render or the file holds");
    }
  }
  // Floats as floats, the exact sums' words as they are.
  for (int c = 0; c < header.num_channels; ++c)
    header.requested_pixel_types[c] = header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT ? TINYEXR_PIXELTYPE_UINT : TINYEXR_PIXELTYPE_FLOAT;
  RenderRecord record;
  for (int a = 0; a < header.num_custom_attributes; ++a) {
    const EXRAttribute& attr = header.custom_attributes[a];
    for (int i = 0; i < 6; ++i) {
      if (std::strcmp(attr.name, kRecordKeys[i]) == 0 && std::strcmp(attr.type, "string") == 0 && attr.size >= 0)
        record_field(record, i)->assign(reinterpret_cast<const char*>(attr.value), size_t(attr.size));
    }
  }
  EXRImage exr;
  InitEXRImage(&exr);
  if (LoadEXRImageFromMemory(&exr, &header, file.data(), file.size(), &err) != TINYEXR_SUCCESS) {
    FreeEXRHeader(&header);
    fail("cannot decode EXR");
  }
  // Channels by name: float planes and the words of the exact sums.
  std::map<std::string, const float*> floats;
  std::map<std::string, const uint32_t*> words;
  for (int c = 0; c < header.num_channels; ++c) {
    const unsigned char* data = exr.images ? exr.images[c] : nullptr;
    if (!data) continue;
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT) words[header.channels[c].name] = reinterpret_cast<const uint32_t*>(data);
    else floats[header.channels[c].name] = reinterpret_cast<const float*>(data);
  }
  std::string problem;
  std::string missing;
  for (const char* n : {"R", "G", "B", "n", "var.R", "var.G", "var.B"})
    if (!floats.count(n)) missing += std::string(missing.empty() ? "" : ", ") + n;
  // The AOV layers the file holds sums of (their means alone carry no
  // variance: a file with AOVs always has the sums).
  std::vector<std::string> aovs;
  for (const ImageLayer& l : image_layers(all_aov_names()))
    if (l.name != "color" && words.count("sum." + channel_name(l, 0) + ".hi")) aovs.push_back(l.name);
  ImageStats out;
  if (missing.empty()) {
    out = ImageStats(exr.width, exr.height, image_layers(aovs));
    const float* countPlane = floats["n"];
    for (size_t p = 0; p < out.pixels(); ++p) out.count[p] = countPlane[p];
    // Exact sums where every channel has both words of both moments.
    bool exact = true;
    for (const ImageLayer& l : out.layers)
      for (size_t c = 0; c < l.channels.size(); ++c)
        for (const char* m : {"sum.", "sumsq."})
          exact = exact && words.count(m + channel_name(l, c) + ".hi") && words.count(m + channel_name(l, c) + ".lo");
    record.exactSums = exact;
    if (exact) {
      for (const ImageLayer& l : out.layers) {
        for (size_t c = 0; c < l.channels.size(); ++c) {
          for (int moment = 0; moment < 2; ++moment) {
            std::string base = std::string(moment == 0 ? "sum." : "sumsq.") + channel_name(l, c);
            const uint32_t* hi = words[base + ".hi"];
            const uint32_t* lo = words[base + ".lo"];
            std::vector<double>& dst = moment == 0 ? out.sum : out.sumSq;
            for (size_t p = 0; p < out.pixels(); ++p) {
              uint64_t bits = uint64_t(hi[p]) << 32 | lo[p];
              std::memcpy(&dst[p * out.stride + l.first + c], &bits, sizeof bits);
            }
          }
        }
      }
    } else {
      // A file without them (written by an older wavepath or another
      // program): the colour's sums from mean, variance and count, to float
      // precision; no illuminance squares, no AOVs.
      const char* rgb[3] = {"R", "G", "B"};
      for (size_t p = 0; p < out.pixels(); ++p) {
        double n = out.count[p];
        for (int c = 0; c < 3; ++c) {
          double m = floats[rgb[c]][p];
          double v = floats[std::string("var.") + rgb[c]][p];
          out.sum[p * out.stride + size_t(c)] = m * n;
          out.sumSq[p * out.stride + size_t(c)] = v * std::max(n - 1.0, 0.0) + n * m * m;
        }
        out.sum[p * out.stride + ImageStats::kY] = 0.2126 * out.sum[p * out.stride] + 0.7152 * out.sum[p * out.stride + 1] +
                                                   0.0722 * out.sum[p * out.stride + 2];
      }
    }
  }
  FreeEXRImage(&exr);
  FreeEXRHeader(&header);
  if (!missing.empty()) throw InputError(path + ": EXR lacks the channels wavepath writes (" + missing + "): not a wavepath render");
  if (recordOut) *recordOut = record;
  return out;
}

}  // namespace wp
