// exr.h — OpenEXR files through the OpenEXR library (Debian's
// libopenexr-dev): scanline images of named float and 32-bit unsigned
// channels with string attributes, read and written a block of rows at a
// time, so that merging renders larger than memory holds needs no image
// whole (docs/partial-renders.md). Every EXR wavepath reads or writes goes
// through here: renders and partial renders (image.cpp), plain RGB images
// (image_file.cpp) and EXR textures (texture_image.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace wp {

enum class ExrType { Float, Uint };

struct ExrChannel {
  std::string name;
  ExrType type = ExrType::Float;
};

// Where a block of rows of one channel goes, or comes from: width x rows
// values of the channel's type, row after row.
struct ExrPlane {
  std::string channel;
  void* data = nullptr;
};

class ExrReader {
 public:
  // The file at `path`, or an image in memory named `name` in messages.
  // Throws InputError, naming it, where it is not an EXR wavepath can read:
  // damaged, tiled or deep, or larger than MAX_IMAGE_SIZE a side.
  explicit ExrReader(const std::string& path);
  ExrReader(const std::vector<unsigned char>& bytes, const std::string& name);
  ~ExrReader();
  ExrReader(const ExrReader&) = delete;
  ExrReader& operator=(const ExrReader&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<ExrChannel>& channels() const { return channels_; }
  // The channel's type, or nullptr where the file has no such channel.
  const ExrType* type_of(const std::string& channel) const;
  // A string attribute of the header, or "" where there is none.
  std::string attribute(const std::string& name) const;
  // Rows [y0, y1) (0 the top row) of the named channels, each converted to
  // the type its plane asks for (`types[i]` for planes[i]). Throws
  // InputError where the file's data is damaged.
  void read(int y0, int y1, const std::vector<ExrPlane>& planes, const std::vector<ExrType>& types);

 private:
  void describe();  // the size and channels, from the header
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string name_;
  int width_ = 0, height_ = 0, minX_ = 0, minY_ = 0;
  std::vector<ExrChannel> channels_;
};

class ExrWriter {
 public:
  // Starts `path` (the caller's temporary file: write_atomically names it)
  // with these channels and string attributes; ZIP-compressed or not.
  ExrWriter(const std::string& path, int width, int height, const std::vector<ExrChannel>& channels,
            const std::vector<std::pair<std::string, std::string>>& attributes, bool compress);
  ~ExrWriter();
  ExrWriter(const ExrWriter&) = delete;
  ExrWriter& operator=(const ExrWriter&) = delete;
  // The next `rows` rows of the channels: one plane per channel, by name.
  void write(int rows, const std::vector<ExrPlane>& planes);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_ = 0, next_ = 0;
  std::vector<ExrChannel> channels_;
};

}  // namespace wp
