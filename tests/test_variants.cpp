// The default kernel variant of each class of device (variants.cpp's table).
#include <gtest/gtest.h>

#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"

namespace wp {
namespace {

GpuDeviceInfo device(const std::string& type, const std::string& driver) {
  GpuDeviceInfo d;
  d.type = type;
  d.driver = driver;
  return d;
}

TEST(DefaultVariant, LavapipeKeepsTheWavefrontKernels) {
  EXPECT_EQ(default_variant(device("cpu", "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)")).name, "gpu");
}

TEST(DefaultVariant, NvidiaGpusTakeTheMegakernelOverTheBinaryTree) {
  const KernelVariant& v = default_variant(device("discrete", "NVIDIA 580.159.04"));
  EXPECT_EQ(v.name, "gpu-mega-bvh2");
  EXPECT_TRUE(v.settings.megakernel);
  EXPECT_EQ(v.bvhLayout, BvhLayout::Binary);
}

TEST(DefaultVariant, AnUnmeasuredDeviceKeepsTheWavefrontKernels) {
  EXPECT_EQ(default_variant(device("discrete", "AMD open-source driver 2023.Q4.2")).name, "gpu");
  EXPECT_EQ(default_variant(device("integrated", "Intel open-source Mesa driver")).name, "gpu");
}

}  // namespace
}  // namespace wp
