#include "image/exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/openexr.h>

#include <Iex.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "../../shaders/shared/limits.glsl"
#include "util/error.h"

namespace wp {

namespace {

// OpenEXR sizes its buffers by what a header declares: no render or texture
// wavepath reads is larger than this a side.
void limit_image_size() {
  static std::once_flag once;
  std::call_once(once, [] { Imf::Header::setMaxImageSize(MAX_IMAGE_SIZE, MAX_IMAGE_SIZE); });
}

// An EXR in memory (an image embedded in a glTF or read whole).
class MemoryStream : public Imf::IStream {
 public:
  MemoryStream(const std::vector<unsigned char>& bytes, const std::string& name) : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || uint64_t(n) > bytes_.size() - at_) throw Iex::InputExc("unexpected end of file");
    std::memcpy(c, bytes_.data() + at_, size_t(n));
    at_ += uint64_t(n);
    return at_ < bytes_.size();
  }
  uint64_t tellg() override { return at_; }
  void seekg(uint64_t pos) override { at_ = std::min<uint64_t>(pos, bytes_.size()); }

 private:
  const std::vector<unsigned char>& bytes_;
  uint64_t at_ = 0;
};

// OpenEXR's C++ reader allocates an attribute's value by the size its
// header declares, and line buffers by the data window, the channels and
// the rows a compressed block holds. So the header is read first by
// OpenEXR's core library (OpenEXRCore), which checks every size against
// the file, and refused where it is damaged, deep or multi-part, or
// declares pixel data far beyond what the file can hold (deflate's best is
// about 1032:1).
struct MemorySource {
  const unsigned char* data;
  uint64_t size;
};

int64_t read_memory(exr_const_context_t, void* user, void* buffer, uint64_t sz, uint64_t offset, exr_stream_error_func_ptr_t) {
  const auto* m = static_cast<const MemorySource*>(user);
  if (offset >= m->size) return 0;
  const uint64_t n = std::min(sz, m->size - offset);
  std::memcpy(buffer, m->data + offset, n);
  return int64_t(n);
}

int64_t size_of_memory(exr_const_context_t, void* user) {
  return int64_t(static_cast<const MemorySource*>(user)->size);
}

void quiet_errors(exr_const_context_t, exr_result_t, const char*) {}

// OpenEXR's C++ reader reads an attribute of a known type by its type, not
// by the size its header gives (a channel list up to its empty name, a
// box as 16 bytes), and reads on from where it stopped; OpenEXRCore skips
// by the size. Where the two disagree the C++ reader reads garbage as the
// next attribute: the sizes of those types must be what their values take.
bool attribute_sizes_agree(const unsigned char* data, uint64_t n) {
  static const std::pair<const char*, uint32_t> kFixed[] = {
      {"box2i", 16}, {"box2f", 16}, {"compression", 1}, {"lineOrder", 1}, {"envmap", 1}, {"deepImageState", 1},
      {"float", 4},  {"int", 4},    {"double", 8},      {"v2i", 8},       {"v2f", 8},    {"v2d", 16},
      {"v3i", 12},   {"v3f", 12},   {"v3d", 24},        {"m33f", 36},     {"m33d", 72},  {"m44f", 64},
      {"m44d", 128}, {"rational", 8}, {"timecode", 8},  {"keycode", 28},  {"chromaticities", 32}, {"tiledesc", 9}};
  uint64_t at = 8;
  auto cstring = [&](std::string& out) {
    const uint64_t start = at;
    while (at < n && data[at] != 0) ++at;
    if (at >= n) return false;
    out.assign(reinterpret_cast<const char*>(data + start), at - start);
    ++at;
    return true;
  };
  for (;;) {
    std::string attribute, type;
    if (!cstring(attribute)) return false;
    if (attribute.empty()) return true;
    if (!cstring(type) || at + 4 > n) return false;
    uint32_t size;
    std::memcpy(&size, data + at, 4);
    at += 4;
    if (size > n - at) return false;
    for (const auto& [t, bytes] : kFixed)
      if (type == t && size != bytes) return false;
    if (type == "chlist") {
      uint64_t c = at;
      while (c < at + size && data[c] != 0) {
        while (c < at + size && data[c] != 0) ++c;
        c += 17;
      }
      if (c + 1 != at + size) return false;
    }
    if (type == "preview") {
      if (size < 8) return false;
      uint32_t wh[2];
      std::memcpy(wh, data + at, 8);
      if (uint64_t(wh[0]) * wh[1] * 4 + 8 != size) return false;
    }
    at += size;
  }
}

void check_header(const std::string& path, const std::vector<unsigned char>* bytes, uint64_t fileBytes, const std::string& name) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet_errors;
  init.max_image_width = MAX_IMAGE_SIZE;
  init.max_image_height = MAX_IMAGE_SIZE;
  MemorySource source{bytes ? bytes->data() : nullptr, bytes ? bytes->size() : 0};
  if (bytes) {
    init.user_data = &source;
    init.read_fn = read_memory;
    init.size_fn = size_of_memory;
  }
  exr_context_t ctx = nullptr;
  std::string problem;
  int parts = 0;
  exr_storage_t storage = EXR_STORAGE_SCANLINE;
  exr_attr_box2i_t window{};
  const exr_attr_chlist_t* channels = nullptr;
  int32_t rows = 1;
  // The header's first bytes (no real header is larger) for the C++ reader's walk.
  std::vector<unsigned char> head;
  if (bytes) {
    head.assign(bytes->begin(), bytes->begin() + ptrdiff_t(std::min<size_t>(bytes->size(), 1 << 20)));
  } else if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    head.resize(1 << 20);
    head.resize(std::fread(head.data(), 1, head.size(), f));
    std::fclose(f);
  }
  if (exr_start_read(&ctx, bytes ? name.c_str() : path.c_str(), &init) != EXR_ERR_SUCCESS) {
    problem = "a damaged or unreadable header";
  } else if (!attribute_sizes_agree(head.data(), head.size())) {
    problem = "an attribute whose size is not what its value takes";
  } else if (exr_get_count(ctx, &parts) != EXR_ERR_SUCCESS || parts != 1 || exr_get_storage(ctx, 0, &storage) != EXR_ERR_SUCCESS ||
             (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)) {
    problem = "deep or multi-part images are not read";
  } else if (exr_get_data_window(ctx, 0, &window) != EXR_ERR_SUCCESS || exr_get_channels(ctx, 0, &channels) != EXR_ERR_SUCCESS) {
    problem = "no data window or channels";
  } else {
    if (storage == EXR_STORAGE_SCANLINE && exr_get_scanlines_per_chunk(ctx, 0, &rows) != EXR_ERR_SUCCESS) rows = 256;
    const int64_t width = int64_t(window.max.x) - window.min.x + 1, height = int64_t(window.max.y) - window.min.y + 1;
    const int64_t count = channels ? channels->num_channels : 0;
    const int64_t declared = width * std::max<int64_t>(height, rows) * std::max<int64_t>(count, 1) * 4;
    if (width <= 0 || height <= 0 || count > 256 || uint64_t(declared) > 1100 * fileBytes + (1 << 20))
      problem = std::to_string(width) + "x" + std::to_string(height) + " pixels of " + std::to_string(count) + " channels, more than the file holds";
  }
  if (ctx) exr_finish(&ctx);
  if (!problem.empty()) throw InputError(name + ": not an OpenEXR " + (bytes ? "image" : "file") + " wavepath reads (" + problem + ")");
}

Imf::PixelType pixel_type(ExrType t) {
  return t == ExrType::Uint ? Imf::UINT : Imf::FLOAT;
}

}  // namespace

struct ExrReader::Impl {
  std::unique_ptr<MemoryStream> stream;
  std::unique_ptr<Imf::InputFile> file;
};

ExrReader::ExrReader(const std::string& path) : impl_(std::make_unique<Impl>()), name_(path) {
  limit_image_size();
  std::error_code ec;
  const uint64_t fileBytes = uint64_t(std::filesystem::file_size(path, ec));
  if (ec) throw InputError(path + ": cannot read (" + ec.message() + ")");
  check_header(path, nullptr, fileBytes, path);
  try {
    impl_->file = std::make_unique<Imf::InputFile>(path.c_str(), 0);
  } catch (const std::exception& e) {
    throw InputError(path + ": not an OpenEXR file wavepath reads (" + e.what() + ")");
  }
  describe();
}

ExrReader::ExrReader(const std::vector<unsigned char>& bytes, const std::string& name)
    : impl_(std::make_unique<Impl>()), name_(name) {
  limit_image_size();
  check_header("", &bytes, bytes.size(), name);
  try {
    impl_->stream = std::make_unique<MemoryStream>(bytes, name);
    impl_->file = std::make_unique<Imf::InputFile>(*impl_->stream, 0);
  } catch (const std::exception& e) {
    throw InputError(name + ": not an OpenEXR image wavepath reads (" + e.what() + ")");
  }
  describe();
}

ExrReader::~ExrReader() = default;

void ExrReader::describe() {
  const Imath::Box2i w = impl_->file->header().dataWindow();
  minX_ = w.min.x;
  minY_ = w.min.y;
  width_ = w.max.x - w.min.x + 1;
  height_ = w.max.y - w.min.y + 1;
  for (auto it = impl_->file->header().channels().begin(); it != impl_->file->header().channels().end(); ++it)
    channels_.push_back({it.name(), it.channel().type == Imf::UINT ? ExrType::Uint : ExrType::Float});
}

const ExrType* ExrReader::type_of(const std::string& channel) const {
  for (const ExrChannel& c : channels_)
    if (c.name == channel) return &c.type;
  return nullptr;
}

std::string ExrReader::attribute(const std::string& name) const {
  const auto* a = impl_->file->header().findTypedAttribute<Imf::StringAttribute>(name);
  return a ? a->value() : std::string();
}

void ExrReader::read(int y0, int y1, const std::vector<ExrPlane>& planes, const std::vector<ExrType>& types) {
  if (y0 < 0 || y1 > height_ || y0 >= y1) return;
  Imf::FrameBuffer fb;
  for (size_t i = 0; i < planes.size(); ++i) {
    const size_t x = 4;  // float and uint alike
    const size_t row = x * size_t(width_);
    // The slice's origin is pixel (0, 0) of the data window's coordinates.
    char* base = static_cast<char*>(planes[i].data) - ptrdiff_t(minX_) * ptrdiff_t(x) - ptrdiff_t(minY_ + y0) * ptrdiff_t(row);
    fb.insert(planes[i].channel, Imf::Slice(pixel_type(types[i]), base, x, row));
  }
  try {
    impl_->file->setFrameBuffer(fb);
    impl_->file->readPixels(minY_ + y0, minY_ + y1 - 1);
  } catch (const std::exception& e) {
    throw InputError(name_ + ": cannot read EXR pixels (" + e.what() + ")");
  }
}

struct ExrWriter::Impl {
  std::unique_ptr<Imf::OutputFile> file;
};

ExrWriter::ExrWriter(const std::string& path, int width, int height, const std::vector<ExrChannel>& channels,
                     const std::vector<std::pair<std::string, std::string>>& attributes, bool compress)
    : impl_(std::make_unique<Impl>()), width_(width), channels_(channels) {
  Imf::Header header(width, height);
  header.compression() = compress ? Imf::ZIP_COMPRESSION : Imf::NO_COMPRESSION;
  for (const ExrChannel& c : channels) header.channels().insert(c.name, Imf::Channel(pixel_type(c.type)));
  for (const auto& [name, value] : attributes) header.insert(name, Imf::StringAttribute(value));
  try {
    impl_->file = std::make_unique<Imf::OutputFile>(path.c_str(), header, 0);
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot write EXR (" + e.what() + ")");
  }
}

ExrWriter::~ExrWriter() = default;

void ExrWriter::write(int rows, const std::vector<ExrPlane>& planes) {
  Imf::FrameBuffer fb;
  for (const ExrPlane& p : planes) {
    const ExrChannel* c = nullptr;
    for (const ExrChannel& ch : channels_)
      if (ch.name == p.channel) c = &ch;
    if (!c) continue;
    const size_t row = 4 * size_t(width_);
    char* base = static_cast<char*>(p.data) - ptrdiff_t(next_) * ptrdiff_t(row);
    fb.insert(p.channel, Imf::Slice(pixel_type(c->type), base, 4, row));
  }
  try {
    impl_->file->setFrameBuffer(fb);
    impl_->file->writePixels(rows);
  } catch (const std::exception& e) {
    throw InputError(std::string("cannot write EXR rows (") + e.what() + ")");
  }
  next_ += rows;
}

}  // namespace wp
