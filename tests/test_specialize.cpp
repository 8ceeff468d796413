// The kernels' SPIR-V specialized on the host (gpu/specialize.h): what the
// optimizer hands the driver must be valid SPIR-V for every kernel under
// every kind of scene, and must hold less code where a scene uses less.
// That the images stay the same is Gpu.SpecializingTheSpirvLeavesTheImageUnchanged.
#include "test_support.h"

#include <spirv-tools/libspirv.hpp>

#include <cstring>

#include "gpu/specialize.h"

namespace wp::test {
namespace {

using namespace shader;

std::vector<uint32_t> read_spirv(const std::string& kernel) {
  std::ifstream in(std::string(WAVEPATH_SPV_DIR) + "/" + kernel + ".spv", std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<uint32_t> words(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), words.size() * 4);
  return words;
}

// The constants of a scene: `kinds` (materials, textures, lights, features)
// and the integrator; the rest as the renderer sets them on a CPU device.
std::vector<uint32_t> constants(glm::uvec4 kinds, uint32_t integrator, uint32_t bvhLayout) {
  std::vector<uint32_t> v(SPEC_COUNT, 0u);
  v[SPEC_WORKGROUP_SIZE] = WORKGROUP_SIZE;
  v[SPEC_INTEGRATOR] = integrator;
  v[SPEC_LIGHT_SAMPLES] = 1;
  v[SPEC_BVH_LAYOUT] = bvhLayout;
  v[SPEC_MATERIAL_KINDS] = kinds.x;
  v[SPEC_TEXTURE_KINDS] = kinds.y;
  v[SPEC_LIGHT_KINDS] = kinds.z;
  v[SPEC_FEATURES] = kinds.w;
  v[SPEC_STACK_SIZE] = 24;
  v[SPEC_COMPACTION] = 1;
  v[SPEC_RAYS_PER_INVOCATION] = bvhLayout == BVH_LAYOUT_WIDE ? 16 : 1;
  v[SPEC_WORKGROUP_INTERLEAVE] = 1;
  v[SPEC_SHADE_KEY] = SORT_KEYS;
  return v;
}

const char* const kKernels[] = {"generate", "prepare", "extend", "sort", "shade", "connect", "connect_multi",
                                "accumulate", "megakernel", "raycast", "probe"};

TEST(KernelSpecialization, EveryKernelStaysValidSpirvForEveryKindOfScene) {
  const glm::uvec4 everything(~0u), lambertianOnly(KIND_BIT(MAT_LAMBERTIAN), KIND_BIT(TEX_CONSTANT), KIND_BIT(LIGHT_AREA), 0u);
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_1);
  std::string messages;
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t& at, const char* m) {
    messages += "word " + std::to_string(at.index) + ": " + m + "\n";
  });
  for (const char* kernel : kKernels) {
    std::vector<uint32_t> code = read_spirv(kernel);
    ASSERT_GT(code.size(), 5u) << kernel;
    // Each integrator and BVH layout once, with every kind and with the fewest.
    const struct { glm::uvec4 kinds; uint32_t integrator, layout; } scenes[] = {
        {everything, INTEGRATOR_PATH, BVH_LAYOUT_WIDE},
        {lambertianOnly, INTEGRATOR_AO, BVH_LAYOUT_BINARY},
        {everything, INTEGRATOR_MIXTURE, BVH_LAYOUT_BINARY}};
    for (const auto& scene : scenes) {
      // The walks' kernels are folded to their branches only (pipelines.cpp).
      const std::string name = kernel;
      const bool walks = name == "extend" || name == "connect" || name == "connect_multi" || name == "raycast";
      for (Folding folding : {Folding::Branches, Folding::ThroughLocals}) {
        if (folding == Folding::Branches && !walks) continue;
        std::string error;
        std::vector<uint32_t> out =
            specialize_kernel(code.data(), code.size(), constants(scene.kinds, scene.integrator, scene.layout), error, folding);
        ASSERT_FALSE(out.empty()) << kernel << ": " << error;
        messages.clear();
        EXPECT_TRUE(tools.Validate(out)) << kernel << ", kinds " << scene.kinds.x << " " << scene.kinds.w << ", integrator "
                                         << scene.integrator << ", layout " << scene.layout << ", folding "
                                         << (folding == Folding::Branches ? "branches" : "through locals") << ":\n" << messages;
      }
    }
  }
}

// Without this the driver would be handed every scene's code again: shade for
// a Lambertian-only scene must lose most of what shade for every kind holds.
TEST(KernelSpecialization, KindsASceneLacksLeaveTheKernel) {
  std::vector<uint32_t> shade = read_spirv("shade");
  std::string error;
  const glm::uvec4 lambertianOnly(KIND_BIT(MAT_LAMBERTIAN), KIND_BIT(TEX_CONSTANT), KIND_BIT(LIGHT_AREA), 0u);
  size_t all = specialize_kernel(shade.data(), shade.size(), constants(glm::uvec4(~0u), INTEGRATOR_PATH, BVH_LAYOUT_WIDE), error).size();
  size_t few = specialize_kernel(shade.data(), shade.size(), constants(lambertianOnly, INTEGRATOR_PATH, BVH_LAYOUT_WIDE), error).size();
  EXPECT_LT(few * 2, all) << error;
  EXPECT_LT(all, shade.size() + shade.size() / 10) << "specializing should never grow the kernel much";
}

}  // namespace
}  // namespace wp::test
