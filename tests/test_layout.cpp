// Struct layouts: the offsets glslang assigned to every member of every shared
// struct (read from the compiled SPIR-V's Offset and ArrayStride decorations)
// must equal the C++ offsets, so host and kernels read the same bytes.
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
      {"BvhNode", sizeof(BvhNode), {FIELD(BvhNode, bmin), FIELD(BvhNode, leftFirst), FIELD(BvhNode, bmax), FIELD(BvhNode, count)}},
      {"Triangle", sizeof(Triangle),
       {FIELD(Triangle, v0), FIELD(Triangle, material), FIELD(Triangle, v1), FIELD(Triangle, emitter), FIELD(Triangle, v2),
        FIELD(Triangle, shading)}},
      {"TriangleShading", sizeof(TriangleShading),
       {FIELD(TriangleShading, n0), FIELD(TriangleShading, u0), FIELD(TriangleShading, n1), FIELD(TriangleShading, v0),
        FIELD(TriangleShading, n2), FIELD(TriangleShading, hasNormals), FIELD(TriangleShading, uv12)}},
      {"Sphere", sizeof(Sphere),
       {FIELD(Sphere, toWorld0), FIELD(Sphere, toWorld1), FIELD(Sphere, toWorld2), FIELD(Sphere, toObject0),
        FIELD(Sphere, toObject1), FIELD(Sphere, toObject2), FIELD(Sphere, material), FIELD(Sphere, emitter),
        FIELD(Sphere, area), FIELD(Sphere, sourceIndex)}},
      {"Material", sizeof(Material), {FIELD(Material, info), FIELD(Material, children), FIELD(Material, params)}},
      {"Texture", sizeof(Texture),
       {FIELD(Texture, info), FIELD(Texture, color0), FIELD(Texture, color1), FIELD(Texture, map0), FIELD(Texture, map1),
        FIELD(Texture, map2)}},
      {"PointLight", sizeof(PointLight), {FIELD(PointLight, position), FIELD(PointLight, intensity)}},
      {"Emitter", sizeof(Emitter), {FIELD(Emitter, prim), FIELD(Emitter, alias), FIELD(Emitter, threshold), FIELD(Emitter, pmf)}},
      {"SceneParams", sizeof(SceneParams),
       {FIELD(SceneParams, camToWorld0), FIELD(SceneParams, camToWorld1), FIELD(SceneParams, camToWorld2),
        FIELD(SceneParams, camLens), FIELD(SceneParams, background), FIELD(SceneParams, image), FIELD(SceneParams, counts),
        FIELD(SceneParams, debug), FIELD(SceneParams, debugRegion), FIELD(SceneParams, mode), FIELD(SceneParams, environment)}},
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

}  // namespace
}  // namespace wp::test
