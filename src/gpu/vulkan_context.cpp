#include "gpu/vulkan_context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <type_traits>

#include "util/error.h"
#include "util/fault.h"
#include "util/huge_pages.h"

namespace wp {

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
  static_cast<std::atomic<uint64_t>*>(user)->fetch_add(1);
  std::fprintf(stderr, "wavepath: validation: %s\n", data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

std::string type_name(vk::PhysicalDeviceType t) {
  switch (t) {
    case vk::PhysicalDeviceType::eDiscreteGpu: return "discrete";
    case vk::PhysicalDeviceType::eIntegratedGpu: return "integrated";
    case vk::PhysicalDeviceType::eVirtualGpu: return "virtual";
    case vk::PhysicalDeviceType::eCpu: return "cpu";
    default: return "other";
  }
}

int type_rank(const std::string& type) {
  const char* order[] = {"discrete", "integrated", "virtual", "cpu"};
  for (int i = 0; i < 4; ++i)
    if (type == order[i]) return i;
  return 4;
}

// The device `selector` names among `infos`: "" the best suitable one
// (discrete > integrated > virtual > cpu), else an index or part of a name.
// `window`: the devices were checked for presenting to a window's surface.
size_t choose_device(const std::vector<GpuDeviceInfo>& infos, const std::string& selector, bool window) {
  int chosen = -1;
  if (selector.empty()) {
    for (uint32_t i = 0; i < infos.size(); ++i) {
      if (!infos[i].suitable) continue;
      if (chosen < 0 || type_rank(infos[i].type) < type_rank(infos[size_t(chosen)].type)) chosen = int(i);
    }
    if (chosen < 0 && window) throw RenderError("no Vulkan device can present to the window from a compute queue");
    if (chosen < 0) throw RenderError("no suitable Vulkan device (Vulkan 1.1 with a compute queue and subgroup ballots in compute shaders) found");
    return size_t(chosen);
  }
  char* end = nullptr;
  long idx = std::strtol(selector.c_str(), &end, 10);
  if (end != selector.c_str() && *end == '\0') {
    if (idx < 0 || size_t(idx) >= infos.size())
      throw InputError("--device " + selector + ": no such device index (wavepath devices lists " + std::to_string(infos.size()) + ")");
    chosen = int(idx);
  } else {
    std::string want = selector;
    std::transform(want.begin(), want.end(), want.begin(), ::tolower);
    for (uint32_t i = 0; i < infos.size() && chosen < 0; ++i) {
      std::string name = infos[i].name;
      std::transform(name.begin(), name.end(), name.begin(), ::tolower);
      if (name.find(want) != std::string::npos) chosen = int(i);
    }
    if (chosen < 0) throw InputError("--device " + selector + ": no device name contains that text (see wavepath devices)");
  }
  const GpuDeviceInfo& info = infos[size_t(chosen)];
  if (window && !info.presents) throw RenderError("device " + info.name + " cannot present to the window");
  if (!info.suitable) throw RenderError("device " + info.name + " lacks Vulkan 1.1, a compute queue or subgroup ballots in compute shaders");
  return size_t(chosen);
}

std::optional<uint32_t> compute_queue_family(const vk::raii::PhysicalDevice& pd) {
  auto families = pd.getQueueFamilyProperties();
  for (uint32_t i = 0; i < families.size(); ++i)
    if (families[i].queueFlags & vk::QueueFlagBits::eCompute) return i;
  return std::nullopt;
}

GpuDeviceInfo describe(const vk::raii::PhysicalDevice& pd, uint32_t index) {
  GpuDeviceInfo info;
  info.index = index;
  auto chain = pd.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties,
                                 vk::PhysicalDeviceSubgroupProperties>();
  const auto& p = chain.get<vk::PhysicalDeviceProperties2>().properties;
  const auto& d = chain.get<vk::PhysicalDeviceDriverProperties>();
  info.name = p.deviceName.data();
  info.type = type_name(p.deviceType);
  info.driver = std::string(d.driverName.data()) + " " + d.driverInfo.data();
  info.apiVersion = std::to_string(VK_API_VERSION_MAJOR(p.apiVersion)) + "." + std::to_string(VK_API_VERSION_MINOR(p.apiVersion)) +
                    "." + std::to_string(VK_API_VERSION_PATCH(p.apiVersion));
  info.maxStorageBufferRange = p.limits.maxStorageBufferRange;
  info.maxTexelBufferElements = p.limits.maxTexelBufferElements;
  info.maxComputeWorkGroupCount = p.limits.maxComputeWorkGroupCount[0];
  info.maxComputeWorkGroupInvocations = p.limits.maxComputeWorkGroupInvocations;
  info.subgroupSize = chain.get<vk::PhysicalDeviceSubgroupProperties>().subgroupSize;
  auto mem = pd.getMemoryProperties();
  for (uint32_t h = 0; h < mem.memoryHeapCount; ++h)
    if (mem.memoryHeaps[h].flags & vk::MemoryHeapFlagBits::eDeviceLocal) info.deviceLocalMemory += mem.memoryHeaps[h].size;
  // shade.comp reserves its output slots with one atomic per subgroup (ballot).
  const auto& sg = chain.get<vk::PhysicalDeviceSubgroupProperties>();
  bool ballot = (sg.supportedStages & vk::ShaderStageFlagBits::eCompute) &&
                (sg.supportedOperations & vk::SubgroupFeatureFlagBits::eBasic) &&
                (sg.supportedOperations & vk::SubgroupFeatureFlagBits::eBallot);
  info.suitable = p.apiVersion >= VK_API_VERSION_1_1 && compute_queue_family(pd).has_value() && ballot;
  bool query = false, structures = false;
  for (const vk::ExtensionProperties& x : pd.enumerateDeviceExtensionProperties()) {
    query = query || std::strcmp(x.extensionName, VK_KHR_RAY_QUERY_EXTENSION_NAME) == 0;
    structures = structures || std::strcmp(x.extensionName, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) == 0;
  }
  info.rayQuery = query && structures;
  return info;
}

std::unique_ptr<vk::raii::Instance> make_instance(const vk::raii::Context& ctx, bool validation,
                                                  const std::vector<std::string>& windowExtensions = {}) {
  vk::ApplicationInfo app("wavepath", 1, "wavepath", 1, VK_API_VERSION_1_1);
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  for (const std::string& e : windowExtensions) extensions.push_back(e.c_str());
  if (validation) {
    bool found = false;
    for (const auto& l : ctx.enumerateInstanceLayerProperties()) found = found || std::strcmp(l.layerName, kValidationLayer) == 0;
    if (!found) throw RenderError("validation was requested but VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  vk::InstanceCreateInfo ci({}, &app, layers, extensions);
  try {
    return std::make_unique<vk::raii::Instance>(ctx, ci);
  } catch (const vk::SystemError& e) {
    throw RenderError(std::string("no Vulkan device: cannot create a Vulkan instance (") + e.what() +
                      "); install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers for lavapipe");
  }
}

std::unique_ptr<vk::raii::Context> make_context() {
  try {
    return std::make_unique<vk::raii::Context>();
  } catch (const std::exception& e) {
    throw RenderError(std::string("no Vulkan device: the Vulkan loader is missing (") + e.what() + "); install libvulkan1");
  }
}

}  // namespace

bool VulkanContext::validation_requested_by_environment() {
  const char* v = std::getenv("WAVEPATH_VALIDATION");
  return v && std::strcmp(v, "0") != 0 && *v != '\0';
}

std::vector<GpuDeviceInfo> VulkanContext::list_devices(bool validation) {
  auto ctx = make_context();
  auto instance = make_instance(*ctx, validation);
  std::vector<GpuDeviceInfo> out;
  vk::raii::PhysicalDevices devices(*instance);
  for (uint32_t i = 0; i < devices.size(); ++i) out.push_back(describe(devices[i], i));
  return out;
}

GpuDeviceInfo VulkanContext::selected_device(const std::string& selector) {
  std::vector<GpuDeviceInfo> infos = list_devices(false);
  if (infos.empty()) throw RenderError("no Vulkan device found; install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers for lavapipe");
  return infos[choose_device(infos, selector, false)];
}

VulkanContext::VulkanContext(const std::string& selector, bool validation, const Presentation* presentation) {
  context_ = make_context();
  instance_ = make_instance(*context_, validation, presentation ? presentation->instanceExtensions : std::vector<std::string>{});
  if (validation) {
    using S = vk::DebugUtilsMessageSeverityFlagBitsEXT;
    using T = vk::DebugUtilsMessageTypeFlagBitsEXT;
    vk::DebugUtilsMessengerCreateInfoEXT ci({}, S::eWarning | S::eError, T::eGeneral | T::eValidation | T::ePerformance,
                                            &on_validation_message, validationMessages_.get());
    messenger_ = std::make_unique<vk::raii::DebugUtilsMessengerEXT>(*instance_, ci);
  }
  if (presentation) surface_ = std::make_unique<vk::raii::SurfaceKHR>(*instance_, presentation->makeSurface(**instance_));
  vk::raii::PhysicalDevices devices(*instance_);
  if (devices.empty()) throw RenderError("no Vulkan device found; install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers for lavapipe");
  std::vector<GpuDeviceInfo> infos;
  for (uint32_t i = 0; i < devices.size(); ++i) {
    infos.push_back(describe(devices[i], i));
    // A window's device presents from the queue it computes on.
    if (surface_ && infos.back().suitable) {
      std::optional<uint32_t> family = compute_queue_family(devices[i]);
      bool swapchain = false;
      for (const vk::ExtensionProperties& x : devices[i].enumerateDeviceExtensionProperties())
        swapchain = swapchain || std::strcmp(x.extensionName.data(), VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0;
      infos.back().presents = swapchain && family && devices[i].getSurfaceSupportKHR(*family, **surface_);
      if (!infos.back().presents) infos.back().suitable = false;
    }
  }

  const size_t chosen = choose_device(infos, selector, surface_ != nullptr);
  physical_ = std::make_unique<vk::raii::PhysicalDevice>(std::move(devices[chosen]));
  info_ = infos[chosen];
  queueFamily_ = *compute_queue_family(*physical_);
  float priority = 1.0f;
  vk::DeviceQueueCreateInfo qci({}, queueFamily_, 1, &priority);
  vk::DeviceCreateInfo dci({}, qci);
  // Float atomic adds on storage buffers, where the device has them: several
  // light samples per vertex add to one path's radiance (connect_multi.comp).
  // Pipeline statistics (registers, spills, instruction counts: whatever the
  // driver reports), where offered: `wavepath info --kernels` shows them.
  std::vector<const char*> extensions;
  if (surface_) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat;
  vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR executableProperties;
  // The device's support for a feature struct's features, and enabling one.
  auto offered = [&](const auto& features) {
    using Features = std::decay_t<decltype(features)>;
    return physical_->getFeatures2<vk::PhysicalDeviceFeatures2, Features>().template get<Features>();
  };
  auto enable = [&](auto& features, const char* extension) {
    features.pNext = const_cast<void*>(dci.pNext);
    dci.pNext = &features;
    extensions.push_back(extension);
  };
  for (const vk::ExtensionProperties& e : physical_->enumerateDeviceExtensionProperties()) {
    std::string name = e.extensionName.data();
    if (name == VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME && offered(atomicFloat).shaderBufferFloat32AtomicAdd) {
      atomicFloat.shaderBufferFloat32AtomicAdd = VK_TRUE;
      enable(atomicFloat, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
      info_.floatAtomicAdd = true;
    } else if (name == VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME && offered(executableProperties).pipelineExecutableInfo) {
      executableProperties.pipelineExecutableInfo = VK_TRUE;
      enable(executableProperties, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
      info_.pipelineStatistics = true;
    }
  }
  dci.setPEnabledExtensionNames(extensions);
  device_ = std::make_unique<vk::raii::Device>(*physical_, dci);
  queue_ = *device_->getQueue(queueFamily_, 0);
  pool_ = std::make_unique<vk::raii::CommandPool>(
      *device_, vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer, queueFamily_));
}

VulkanContext::~VulkanContext() {
  // A lost device has nothing left to wait for (and waiting would throw).
  if (!device_ || lost_) return;
  try {
    device_->waitIdle();
  } catch (const vk::SystemError&) {
  }
}

uint32_t VulkanContext::memory_type(uint32_t typeBits, vk::MemoryPropertyFlags want) const {
  auto props = physical_->getMemoryProperties();
  for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (props.memoryTypes[i].propertyFlags & want) == want) return i;
  return UINT32_MAX;
}

void VulkanContext::run_now(const std::function<void(vk::CommandBuffer)>& record) const {
  vk::raii::CommandBuffers cbs(*device_, vk::CommandBufferAllocateInfo(**pool_, vk::CommandBufferLevel::ePrimary, 1));
  vk::CommandBuffer cb = *cbs[0];
  cb.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  record(cb);
  cb.end();
  vk::raii::Fence fence(*device_, vk::FenceCreateInfo());
  submit_and_wait(cb, fence);
}

void VulkanContext::submit_and_wait(vk::CommandBuffer cb, const vk::raii::Fence& fence, bool samples) const {
  if (lost_ || (samples && fault::device_lost_at_submit())) {
    lost_ = true;
    throw DeviceLost(info_.name);
  }
  try {
    device_->resetFences(*fence);
    queue_.submit(vk::SubmitInfo({}, {}, cb), *fence);
    while (device_->waitForFences(*fence, VK_TRUE, 1000000000ull) == vk::Result::eTimeout) {
    }
  } catch (const vk::DeviceLostError&) {
    lost_ = true;
    throw DeviceLost(info_.name);
  }
}

void VulkanContext::upload(const Buffer& dst, const void* data, size_t bytes) const {
  if (bytes == 0) return;
  if (dst.mapped()) {
    std::memcpy(dst.mapped(), data, bytes);
    return;
  }
  upload_staged(dst, data, bytes);
}

void VulkanContext::upload_staged(const Buffer& dst, const void* data, size_t bytes, size_t chunkBytes) const {
  if (bytes == 0) return;
  const size_t stagingBytes = std::min(bytes, std::max<size_t>(chunkBytes, 1));
  Buffer staging(*this, stagingBytes, vk::BufferUsageFlagBits::eTransferSrc, true);
  for (size_t at = 0; at < bytes; at += stagingBytes) {
    const size_t n = std::min(stagingBytes, bytes - at);
    std::memcpy(staging.mapped(), static_cast<const char*>(data) + at, n);
    run_now([&](vk::CommandBuffer cb) { cb.copyBuffer(staging.handle(), dst.handle(), vk::BufferCopy(0, at, n)); });
  }
}

Buffer::Buffer(const VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage, bool hostVisible)
    : size_(size),
      memory_(nullptr),
      buffer_(ctx.device(), vk::BufferCreateInfo({}, std::max<vk::DeviceSize>(size, 16), usage)) {
  auto req = buffer_.getMemoryRequirements();
  using M = vk::MemoryPropertyFlagBits;
  uint32_t type = hostVisible ? ctx.memory_type(req.memoryTypeBits, M::eHostVisible | M::eHostCoherent)
                              : ctx.memory_type(req.memoryTypeBits, M::eDeviceLocal);
  if (type == UINT32_MAX) type = ctx.memory_type(req.memoryTypeBits, {});
  if (type == UINT32_MAX) throw RenderError("no Vulkan memory type fits a buffer");
  if (fault::device_memory_exhausted(req.size)) throw DeviceOutOfMemory(ctx.info().name, req.size);
  try {
    memory_ = vk::raii::DeviceMemory(ctx.device(), vk::MemoryAllocateInfo(req.size, type));
  } catch (const vk::SystemError& e) {
    fault::device_memory_freed(req.size);
    if (e.code() == vk::Result::eErrorOutOfDeviceMemory || e.code() == vk::Result::eErrorOutOfHostMemory)
      throw DeviceOutOfMemory(ctx.info().name, req.size);
    throw RenderError("cannot allocate " + std::to_string(req.size >> 20) + " MiB of memory on " + ctx.info().name + " (" + e.what() + ")");
  }
  held_ = req.size;
  buffer_.bindMemory(*memory_, 0);
  auto flags = ctx.physical().getMemoryProperties().memoryTypes[type].propertyFlags;
  if ((flags & M::eHostVisible) && (flags & M::eHostCoherent)) mapped_ = memory_.mapMemory(0, VK_WHOLE_SIZE);
  // On a CPU device (lavapipe) the buffer is ordinary process memory, fresh
  // from the allocator and not yet touched: on huge pages its first writes
  // (the upload, or the kernels) fault once per 2 MiB instead of once per
  // 4 KiB. A 10M-triangle scene's process took 1.1-4.3 s less on the
  // benchmark VM (docs/benchmarks.md, "Fresh memory").
  if (mapped_ && ctx.info().type == "cpu") advise_huge_pages(mapped_, req.size);
}

Buffer::~Buffer() {
  fault::device_memory_freed(held_);
}

}  // namespace wp
