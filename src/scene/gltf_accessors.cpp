#include "scene/gltf_accessors.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>

#include "util/error.h"

namespace wp {

namespace {

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    default: return 0;  // matrices: no attribute wavepath reads is one
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    default: return "a matrix";
  }
}

size_t component_size(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

// One component as a float, normalized to [0, 1] or [-1, 1] if asked.
float component(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(float(v) / 127.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? float(*p) / 255.0f : float(*p);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? float(v) / 65535.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return float(v);
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

uint32_t unsigned_index(const unsigned char* p, int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

bool is_index_type(int componentType) {
  return componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

}  // namespace

void AccessorReader::fail(const std::string& where, const std::string& what) const {
  throw InputError(file_ + ": " + where + ": " + what);
}

const unsigned char* AccessorReader::view_data(int view, const std::string& where) const {
  if (view < 0 || view >= int(model_.bufferViews.size())) fail(where, "names buffer view " + std::to_string(view) + ", which does not exist");
  const tinygltf::BufferView& v = model_.bufferViews[size_t(view)];
  const std::string vat = "/bufferViews/" + std::to_string(view);
  if (v.buffer < 0 || v.buffer >= int(model_.buffers.size())) fail(vat + "/buffer", "names buffer " + std::to_string(v.buffer) + ", which does not exist");
  const std::vector<unsigned char>& data = model_.buffers[size_t(v.buffer)].data;
  if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
    fail(vat, "reaches past the end of buffer " + std::to_string(v.buffer) + " (" + std::to_string(data.size()) + " bytes)");
  return data.data() + v.byteOffset;
}

const unsigned char* AccessorReader::elements(int view, size_t offset, size_t count, size_t elementSize, size_t* stride,
                                              const std::string& where) const {
  const unsigned char* data = view_data(view, where);
  const tinygltf::BufferView& v = model_.bufferViews[size_t(view)];
  *stride = v.byteStride != 0 ? v.byteStride : elementSize;
  if (*stride < elementSize || *stride > 252)
    fail("/bufferViews/" + std::to_string(view) + "/byteStride", "a stride of " + std::to_string(*stride) + " bytes cannot hold its elements");
  if (count == 0) return data;
  // The last element ends at offset + stride * (count - 1) + elementSize.
  if (offset > v.byteLength || (count - 1) > (v.byteLength - offset) / *stride ||
      elementSize > v.byteLength - offset - (count - 1) * *stride)
    fail(where, "its " + std::to_string(count) + " elements reach past the end of buffer view " + std::to_string(view));
  return data + offset;
}

const tinygltf::Accessor& AccessorReader::accessor(int index, const std::string& where) const {
  if (index < 0 || index >= int(model_.accessors.size())) fail(where, "names accessor " + std::to_string(index) + ", which does not exist");
  const tinygltf::Accessor& a = model_.accessors[size_t(index)];
  if (a.count > kMaxAccessorCount) fail("/accessors/" + std::to_string(index) + "/count", "more than " + std::to_string(kMaxAccessorCount) + " elements");
  // Without a buffer view an accessor is zeros (but for its sparse values),
  // and its count alone would size what is read: it gets no more elements
  // than a mesh could use.
  if (a.bufferView < 0 && a.count > kMaxAccessorCountWithoutView)
    fail("/accessors/" + std::to_string(index) + "/count", "more than " + std::to_string(kMaxAccessorCountWithoutView) +
                                                               " elements without a buffer view");
  if (component_size(a.componentType) == 0)
    fail("/accessors/" + std::to_string(index) + "/componentType", "unknown component type " + std::to_string(a.componentType));
  return a;
}

void AccessorReader::for_each_element(int index, size_t elementSize, const std::function<void(size_t, const unsigned char*)>& use) const {
  const tinygltf::Accessor& a = model_.accessors[size_t(index)];
  const std::string at = "/accessors/" + std::to_string(index);
  if (a.bufferView >= 0) {  // without one, every element is zero until the sparse values replace some
    size_t stride;
    const unsigned char* p = elements(a.bufferView, a.byteOffset, a.count, elementSize, &stride, at);
    for (size_t i = 0; i < a.count; ++i) use(i, p + i * stride);
  }
  if (!a.sparse.isSparse) return;
  const std::string sat = at + "/sparse";
  if (a.sparse.count <= 0 || size_t(a.sparse.count) > a.count)
    fail(sat + "/count", "must lie from 1 to the accessor's count, " + std::to_string(a.count));
  const size_t k = size_t(a.sparse.count);
  if (!is_index_type(a.sparse.indices.componentType)) fail(sat + "/indices/componentType", "must be an unsigned byte, short or int");
  const size_t isize = component_size(a.sparse.indices.componentType);
  size_t ignored;  // sparse arrays are tightly packed, whatever their views' strides
  const unsigned char* ip = elements(a.sparse.indices.bufferView, size_t(std::max(a.sparse.indices.byteOffset, 0)), k, isize, &ignored, sat + "/indices");
  const unsigned char* vp = elements(a.sparse.values.bufferView, size_t(std::max(a.sparse.values.byteOffset, 0)), k, elementSize, &ignored, sat + "/values");
  for (size_t i = 0; i < k; ++i) {
    const uint32_t target = unsigned_index(ip + i * isize, a.sparse.indices.componentType);
    if (target >= a.count) fail(sat + "/indices", "index " + std::to_string(target) + " lies past the accessor's " + std::to_string(a.count) + " elements");
    use(target, vp + i * elementSize);
  }
}

std::vector<unsigned char> AccessorReader::view_bytes(int view, const std::string& where) const {
  const unsigned char* p = view_data(view, where);
  return std::vector<unsigned char>(p, p + model_.bufferViews[size_t(view)].byteLength);
}

std::vector<glm::vec4> AccessorReader::read(int index, std::initializer_list<int> types, const std::string& where, size_t count) const {
  const tinygltf::Accessor& a = accessor(index, where);
  const std::string at = "/accessors/" + std::to_string(index);
  if (std::find(types.begin(), types.end(), a.type) == types.end()) {
    std::string expected;
    for (int t : types) expected += (expected.empty() ? "" : " or ") + std::string(type_name(t));
    fail(at + "/type", std::string("is ") + type_name(a.type) + ", but " + where + " needs " + expected);
  }
  if (count != std::numeric_limits<size_t>::max() && a.count != count)
    fail(at + "/count", "has " + std::to_string(a.count) + " elements where " + where + " needs " + std::to_string(count));
  const size_t csize = component_size(a.componentType);
  const int n = component_count(a.type);
  std::vector<glm::vec4> out(a.count, glm::vec4(0.0f));
  for_each_element(index, csize * size_t(n), [&](size_t i, const unsigned char* p) {
    for (int c = 0; c < n; ++c) out[i][c] = component(p + size_t(c) * csize, a.componentType, a.normalized);
  });
  return out;
}

std::vector<uint32_t> AccessorReader::indices(int index, const std::string& where, size_t vertices) const {
  const tinygltf::Accessor& a = accessor(index, where);
  const std::string at = "/accessors/" + std::to_string(index);
  if (a.type != TINYGLTF_TYPE_SCALAR) fail(at + "/type", "indices must be SCALAR");
  if (!is_index_type(a.componentType)) fail(at + "/componentType", "indices must be unsigned bytes, shorts or ints");
  if (a.normalized) fail(at + "/normalized", "indices cannot be normalized");
  std::vector<uint32_t> out(a.count, 0u);
  for_each_element(index, component_size(a.componentType), [&](size_t i, const unsigned char* p) {
    const uint32_t v = unsigned_index(p, a.componentType);
    if (v >= vertices) fail(at, "index " + std::to_string(v) + " names no vertex (the primitive has " + std::to_string(vertices) + ")");
    out[i] = v;
  });
  if (a.count > 0 && vertices == 0) fail(at, "indexes a primitive without vertices");
  return out;
}

}  // namespace wp
