// Struct layouts: the offsets glslang assigned to every member of every shared
// struct in a buffer block (read from the compiled SPIR-V's Offset and
// ArrayStride decorations) must equal the C++ offsets, so host and kernels
// read the same bytes. The records read as texels must decode, through the
// kernels' own load functions, to what the host wrote.
#include "test_support.h"

#include <cstddef>
#include <fstream>
#include <cstring>
#include <map>

namespace wp::test {
namespace {

using namespace shader;

struct SpirvLayouts {
  std::map<uint32_t, std::string> names;                          // id -> OpName
  std::map<uint32_t, std::map<uint32_t, std::string>> memberNames;  // struct id -> member -> name
  std::map<uint32_t, std::map<uint32_t, uint32_t>> offsets;       // struct id -> member -> offset
  std::map<uint32_t, uint32_t> arrayStrides;                      // array type id -> stride
  std::map<uint32_t, uint32_t> runtimeArrayElement;               // array type id -> element type id

  explicit SpirvLayouts(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<uint32_t> w(bytes.size() / 4);
    std::memcpy(w.data(), bytes.data(), w.size() * 4);
    if (w.size() < 5 || w[0] != 0x07230203u) throw std::runtime_error(path + " is not SPIR-V");
    for (size_t i = 5; i < w.size();) {
      uint32_t count = w[i] >> 16, op = w[i] & 0xffffu;
      if (count == 0) break;
      auto str = [&](size_t at) { return std::string(reinterpret_cast<const char*>(&w[at])); };
      if (op == 5) names[w[i + 1]] = str(i + 2);                                       // OpName
      if (op == 6) memberNames[w[i + 1]][w[i + 2]] = str(i + 3);                       // OpMemberName
      if (op == 72 && w[i + 3] == 35) offsets[w[i + 1]][w[i + 2]] = w[i + 4];          // OpMemberDecorate Offset
      if (op == 71 && w[i + 2] == 6) arrayStrides[w[i + 1]] = w[i + 3];                // OpDecorate ArrayStride
      if (op == 29) runtimeArrayElement[w[i + 1]] = w[i + 2];                          // OpTypeRuntimeArray
      i += count;
    }
  }
};

struct Field {
  const char* name;
  size_t offset;
};
#define FIELD(T, m) Field{#m, offsetof(T, m)}

struct Expected {
  const char* type;
  size_t size;
  std::vector<Field> fields;
};

std::vector<Expected> expected_layouts() {
  return {
      {"Sphere", sizeof(Sphere),
       {FIELD(Sphere, toWorld0), FIELD(Sphere, toWorld1), FIELD(Sphere, toWorld2), FIELD(Sphere, toObject0),
        FIELD(Sphere, toObject1), FIELD(Sphere, toObject2), FIELD(Sphere, material), FIELD(Sphere, emitter),
        FIELD(Sphere, area), FIELD(Sphere, pad)}},
      {"Material", sizeof(Material), {FIELD(Material, info), FIELD(Material, children), FIELD(Material, params)}},
      {"Texture", sizeof(Texture),
       {FIELD(Texture, info), FIELD(Texture, color0), FIELD(Texture, color1), FIELD(Texture, map0), FIELD(Texture, map1),
        FIELD(Texture, map2)}},
      {"PointLight", sizeof(PointLight), {FIELD(PointLight, position), FIELD(PointLight, intensity)}},
      {"Emitter", sizeof(Emitter), {FIELD(Emitter, prim), FIELD(Emitter, alias), FIELD(Emitter, threshold), FIELD(Emitter, pmf)}},
      {"SceneParams", sizeof(SceneParams),
       {FIELD(SceneParams, camToWorld0), FIELD(SceneParams, camToWorld1), FIELD(SceneParams, camToWorld2),
        FIELD(SceneParams, camLens), FIELD(SceneParams, background), FIELD(SceneParams, image), FIELD(SceneParams, counts),
        FIELD(SceneParams, debug), FIELD(SceneParams, debugRegion), FIELD(SceneParams, mode), FIELD(SceneParams, environment),
        FIELD(SceneParams, accel)}},
      {"PathState", sizeof(PathState),
       {FIELD(PathState, origin), FIELD(PathState, pixel), FIELD(PathState, dir), FIELD(PathState, rng),
        FIELD(PathState, throughput), FIELD(PathState, flags), FIELD(PathState, radiance), FIELD(PathState, bsdfPdf)}},
      {"Hit", sizeof(Hit), {FIELD(Hit, t), FIELD(Hit, prim), FIELD(Hit, u), FIELD(Hit, v)}},
      {"ShadowRay", sizeof(ShadowRay),
       {FIELD(ShadowRay, origin), FIELD(ShadowRay, tmax), FIELD(ShadowRay, dir), FIELD(ShadowRay, path),
        FIELD(ShadowRay, contribution), FIELD(ShadowRay, pad)}},
      {"PixelAccum", sizeof(PixelAccum), {FIELD(PixelAccum, sum), FIELD(PixelAccum, sumSq)}},
      {"KernelPush", sizeof(KernelPush),
       {FIELD(KernelPush, waveStart), FIELD(KernelPush, pathCount), FIELD(KernelPush, sampleIndex), FIELD(KernelPush, queueIn),
        FIELD(KernelPush, capacity), FIELD(KernelPush, phase), FIELD(KernelPush, pad0), FIELD(KernelPush, pad1)}},
  };
}

TEST(Layout, EveryKernelAgreesWithTheHostOnEveryStruct) {
  std::map<std::string, int> checked;
  for (const char* kernel : {"generate", "prepare", "extend", "shade", "connect", "connect_multi", "accumulate", "raycast", "texprobe"}) {
    SpirvLayouts spv(std::string(WAVEPATH_SPV_DIR) + "/" + kernel + ".spv");
    for (const Expected& e : expected_layouts()) {
      for (const auto& [id, name] : spv.names) {
        if (name != e.type || !spv.offsets.count(id)) continue;  // only types used in a buffer carry offsets
        const auto& offs = spv.offsets.at(id);
        ASSERT_EQ(offs.size(), e.fields.size()) << kernel << ": " << e.type << " member count";
        for (uint32_t m = 0; m < e.fields.size(); ++m) {
          EXPECT_EQ(spv.memberNames[id][m], e.fields[m].name) << kernel << ": " << e.type;
          EXPECT_EQ(offs.at(m), e.fields[m].offset) << kernel << ": " << e.type << "." << e.fields[m].name;
        }
        checked[e.type]++;
      }
      // Arrays of the struct in storage buffers step by sizeof on the host.
      for (const auto& [arr, elem] : spv.runtimeArrayElement) {
        if (spv.names[elem] == e.type) {
          EXPECT_EQ(spv.arrayStrides.at(arr), e.size) << kernel << ": stride of " << e.type << "[]";
        }
      }
    }
  }
  for (const Expected& e : expected_layouts()) EXPECT_GT(checked[e.type], 0) << e.type << " never checked";
}

// Every field a distinct value, so a field read from the wrong texel shows.
template <typename T>
T numbered() {
  static_assert(sizeof(T) % 4 == 0);
  T t;
  uint32_t words[sizeof(T) / 4];
  for (uint32_t i = 0; i < sizeof(T) / 4; ++i) words[i] = 0x3f800000u + i * 0x10001u;  // finite floats
  std::memcpy(&t, words, sizeof(T));
  return t;
}

template <typename T>
void expect_same_bytes(const T& a, const T& b, const char* what) {
  EXPECT_EQ(std::memcmp(&a, &b, sizeof(T)), 0) << what << " does not decode to what the host wrote";
}

TEST(Layout, TexelRecordsDecodeToTheHostStructs) {
  BvhNode node[2] = {numbered<BvhNode>(), numbered<BvhNode>()};
  WideNode wide[2] = {numbered<WideNode>(), numbered<WideNode>()};
  Triangle tri[2] = {numbered<Triangle>(), numbered<Triangle>()};
  TriangleShading shading[2] = {numbered<TriangleShading>(), numbered<TriangleShading>()};
  node[1].leftFirst = 77;
  wide[1].primBase = 77;
  tri[1].shading = 77;
  shading[1].hasNormals = 77;
  SceneView view;
  view.nodeTexels = reinterpret_cast<const glm::uvec4*>(node);
  view.wideNodeTexels = reinterpret_cast<const glm::uvec4*>(wide);
  view.triangleTexels = reinterpret_cast<const glm::uvec4*>(tri);
  view.shadingTexels = reinterpret_cast<const glm::uvec4*>(shading);
  expect_same_bytes(view.load_node(1), node[1], "BvhNode");
  expect_same_bytes(view.load_wide_node(1), wide[1], "WideNode");
  expect_same_bytes(view.load_triangle(1), tri[1], "Triangle");
  expect_same_bytes(view.load_shading(1), shading[1], "TriangleShading");
}

}  // namespace
}  // namespace wp::test
