// gltf_accessors.h — reading glTF accessors with every bound checked: the
// accessor, its buffer view and buffer exist, every element it addresses
// (with the view's stride) lies inside them, sparse substitutions index
// within the accessor, and indices name existing vertices. Integer
// components are normalized where the accessor says so. A problem is an
// InputError naming the file and the JSON path of what is wrong.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
struct Accessor;
}

namespace wp {

// The most elements wavepath reads from one accessor.
inline constexpr size_t kMaxAccessorCount = size_t(1) << 28;
inline constexpr size_t kMaxAccessorCountWithoutView = size_t(1) << 20;

class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, const std::string& file) : model_(model), file_(file) {}

  // Accessor `index` as up to four floats per element (the rest zero), of
  // one of `types` (TINYGLTF_TYPE_*); `where` is the JSON path that names
  // it. `count`, unless SIZE_MAX, is the element count it must have (a
  // vertex attribute's: the POSITION count).
  std::vector<glm::vec4> read(int index, std::initializer_list<int> types, const std::string& where,
                              size_t count = std::numeric_limits<size_t>::max()) const;

  // Accessor `index` as vertex indices (unsigned byte, short or int
  // scalars), each below `vertices`.
  std::vector<uint32_t> indices(int index, const std::string& where, size_t vertices) const;

  // The bytes of buffer view `view` (an image's), checked against its buffer.
  std::vector<unsigned char> view_bytes(int view, const std::string& where) const;

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const;
  // Accessor `index`, its count and component type checked.
  const tinygltf::Accessor& accessor(int index, const std::string& where) const;
  // Calls use(i, bytes) for each element i of the accessor's buffer view,
  // then for each sparse substitution (which may repeat an i).
  void for_each_element(int index, size_t elementSize, const std::function<void(size_t, const unsigned char*)>& use) const;
  // The first byte of buffer view `view`, checked to lie with all its bytes inside its buffer.
  const unsigned char* view_data(int view, const std::string& where) const;
  // The bytes of `count` elements of `elementSize` bytes from buffer view
  // `view` at `offset`, `stride` apart (0: packed), checked against the view
  // and its buffer; returns the first element's address.
  const unsigned char* elements(int view, size_t offset, size_t count, size_t elementSize, size_t* stride, const std::string& where) const;

  const tinygltf::Model& model_;
  std::string file_;
};

}  // namespace wp
