#include "image/exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <Iex.h>

#include <cstring>
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
  try {
    impl_->file = std::make_unique<Imf::InputFile>(path.c_str(), 0);
  } catch (const std::exception& e) {
    throw InputError(path + ": not an OpenEXR file wavepath reads (" + e.what() + ")");
  }
  describe();
}

ExrReader::ExrReader(const std::vector<unsigned char>& bytes, const std::string& name) : impl_(std::make_unique<Impl>()), name_(name) {
  limit_image_size();
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
