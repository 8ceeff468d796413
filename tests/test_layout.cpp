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
      {"SceneParams", sizeof(SceneParams),
       {FIELD(SceneParams, camToWorld0), FIELD(SceneParams, camToWorld1), FIELD(SceneParams, camToWorld2),
        FIELD(SceneParams, camLens), FIELD(SceneParams, background), FIELD(SceneParams, image), FIELD(SceneParams, counts),
        FIELD(SceneParams, mode), FIELD(SceneParams, environment),
        FIELD(SceneParams, accel), FIELD(SceneParams, kinds), FIELD(SceneParams, mis), FIELD(SceneParams, camWindow),
        FIELD(SceneParams, media), FIELD(SceneParams, photons)}},
      // Hit, ShadowRay and PathState are no buffer members: the kernels
      // store them as whole uvec4 texels (write_hit, write_shadow_ray,
      // write_path in kernel.glsl; connect_multi adds to a path's radiance
      // as floats) and read them through texel views, field by field, in a
      // layout the spectral kernels extend; the ray-casting and
      // texture-probe tests of test_gpu.cpp write shadow rays on the host and
      // read hits back field by field.
      {"PixelAccum", sizeof(PixelAccum), {FIELD(PixelAccum, sum), FIELD(PixelAccum, sumSq)}},
      {"AovSample", sizeof(AovSample), {FIELD(AovSample, a), FIELD(AovSample, b)}},
      {"AovAccum", sizeof(AovAccum),
       {FIELD(AovAccum, sumA), FIELD(AovAccum, sumB), FIELD(AovAccum, sumSqA), FIELD(AovAccum, sumSqB)}},
      {"KernelPush", sizeof(KernelPush),
       {FIELD(KernelPush, waveStart), FIELD(KernelPush, pathCount), FIELD(KernelPush, sampleIndex), FIELD(KernelPush, queueIn),
        FIELD(KernelPush, capacity), FIELD(KernelPush, phase), FIELD(KernelPush, photonSeed), FIELD(KernelPush, accumBase),
        FIELD(KernelPush, waveSpan), FIELD(KernelPush, pad0), FIELD(KernelPush, pad1), FIELD(KernelPush, pad2)}},
  };
}

TEST(Layout, EveryKernelAgreesWithTheHostOnEveryStruct) {
  std::map<std::string, int> checked;
  for (const std::string mode : {"", "_spectral"})
  for (const char* kernel : {"generate", "prepare", "extend", "sort", "shade", "connect", "connect_multi", "accumulate", "megakernel", "raycast", "probe"}) {
    SpirvLayouts spv(std::string(WAVEPATH_SPV_DIR) + "/" + kernel + mode + ".spv");
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

// Record 1 of an array of two numbered records, the second one changed so
// that reading record 0 instead would show.
template <typename T>
struct TwoRecords {
  T r[2] = {numbered<T>(), numbered<T>()};
  TwoRecords() {
    uint32_t first;
    std::memcpy(&first, &r[1], 4);
    first ^= 0x77u;
    std::memcpy(&r[1], &first, 4);
  }
  const glm::uvec4* texels() const { return reinterpret_cast<const glm::uvec4*>(r); }
};

TEST(Layout, TexelRecordsDecodeToTheHostStructs) {
  TwoRecords<BvhNode> node;
  TwoRecords<WideNode> wide;
  TwoRecords<Triangle> tri;
  TwoRecords<TriangleShading> shading;
  TwoRecords<TriangleVertexData> vertexData;
  TwoRecords<Sphere> sphere;
  TwoRecords<Material> material;
  TwoRecords<Texture> texture;
  TwoRecords<PointLight> light;
  TwoRecords<Emitter> emitter;
  TwoRecords<Medium> medium;
  TwoRecords<Photon> photon;
  SceneView view;
  view.nodeTexels = node.texels();
  view.wideNodeTexels = wide.texels();
  view.triangleTexels = tri.texels();
  view.shadingTexels = shading.texels();
  view.vertexDataTexels = vertexData.texels();
  view.sphereTexels = sphere.texels();
  view.materialTexels = material.texels();
  view.textureTexels = texture.texels();
  view.pointLightTexels = light.texels();
  view.emitterTexels = emitter.texels();
  view.mediumTexels = medium.texels();
  view.photonTexels = photon.texels();
  expect_same_bytes(view.load_node(1), node.r[1], "BvhNode");
  expect_same_bytes(view.load_wide_node(1), wide.r[1], "WideNode");
  expect_same_bytes(view.load_triangle(1), tri.r[1], "Triangle");
  expect_same_bytes(view.load_shading(1), shading.r[1], "TriangleShading");
  expect_same_bytes(view.load_vertex_data(1), vertexData.r[1], "TriangleVertexData");
  expect_same_bytes(view.load_sphere(1), sphere.r[1], "Sphere");
  expect_same_bytes(view.load_material(1), material.r[1], "Material");
  expect_same_bytes(view.load_texture(1), texture.r[1], "Texture");
  expect_same_bytes(view.load_point_light(1), light.r[1], "PointLight");
  expect_same_bytes(view.load_emitter(1), emitter.r[1], "Emitter");
  expect_same_bytes(view.load_medium(1), medium.r[1], "Medium");
  expect_same_bytes(view.load_photon(1), photon.r[1], "Photon");
}

}  // namespace
}  // namespace wp::test
