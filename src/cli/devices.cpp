// `wavepath devices`: the kernel variants and the Vulkan devices with the
// limits that matter to wavepath.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "util/error.h"

namespace wp::cli {

namespace {

int run_devices(bool validation) {
  std::printf("kernel variants:");
  for (const KernelVariant& v : kernel_variants()) std::printf(" %s", v.name.c_str());
  std::printf("\n");
  auto devices = VulkanContext::list_devices(validation);
  if (devices.empty()) throw RenderError("no Vulkan device found; install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers");
  for (const GpuDeviceInfo& d : devices) {
    std::printf("%u: %s\n   type %s, driver %s, Vulkan %s%s\n", d.index, d.name.c_str(), d.type.c_str(), d.driver.c_str(),
                d.apiVersion.c_str(), d.suitable ? "" : " (unsuitable: needs Vulkan 1.1, a compute queue and subgroup ballots in compute shaders)");
    std::printf("   max texel buffer %llu M texels (scene data), max storage buffer %llu MiB (work buffers), max workgroups %u,\n"
                "   max invocations %u, subgroup %u, device-local memory %llu MiB, driver ray queries %s\n",
                (unsigned long long)(d.maxTexelBufferElements >> 20), (unsigned long long)(d.maxStorageBufferRange >> 20),
                d.maxComputeWorkGroupCount, d.maxComputeWorkGroupInvocations, d.subgroupSize,
                (unsigned long long)(d.deviceLocalMemory >> 20), d.rayQuery ? "offered" : "not offered");
    std::printf("   default variant %s\n", default_variant(d).name.c_str());
  }
  return 0;
}

}  // namespace

Command add_devices(CLI::App& app) {
  auto validation = std::make_shared<bool>(false);
  CLI::App* devices = app.add_subcommand("devices", "list Vulkan devices and the limits that matter to wavepath");
  devices->add_flag("--validation", *validation, "enable Vulkan validation");

  return {devices, [validation] { return run_devices(*validation); }};
}

}  // namespace wp::cli
