// vulkan_context.h — the Vulkan instance, the chosen device and its compute
// queue, owned through Vulkan-Hpp's RAII wrappers. With validation on, every
// message of the Khronos validation layer is printed and counted, and the
// program fails if any was reported.
#pragma once

#include <vulkan/vulkan_raii.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "util/error.h"

namespace wp {

// The device was lost (VK_ERROR_DEVICE_LOST: a driver reset, an Xid error, a
// hung kernel killed by a watchdog): nothing more runs on it. A renderer
// that was rendering says what its image holds (WavefrontRenderer::render).
class DeviceLost : public RenderError {
 public:
  explicit DeviceLost(const std::string& device)
      : RenderError("the device " + device + " was lost (VK_ERROR_DEVICE_LOST)"), device(device) {}
  std::string device;
  // The sample every pixel of the image being rendered holds, and whether it
  // holds just those: false where samples past it were already added (an
  // adaptive batch part done), so that the image must not be written.
  uint32_t reached = 0;
  bool intact = false;
};

// A device memory allocation failed (VK_ERROR_OUT_OF_DEVICE_MEMORY).
class DeviceOutOfMemory : public RenderError {
 public:
  DeviceOutOfMemory(const std::string& device, uint64_t bytes)
      : RenderError("out of device memory on " + device + " allocating " + std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"),
        bytes(bytes) {}
  uint64_t bytes;
};

struct GpuDeviceInfo {
  uint32_t index = 0;
  std::string name;
  std::string type;  // discrete, integrated, virtual, cpu, other
  std::string driver;
  std::string apiVersion;
  uint64_t maxStorageBufferRange = 0;
  uint64_t maxTexelBufferElements = 0;
  uint32_t maxComputeWorkGroupCount = 0;
  uint32_t maxComputeWorkGroupInvocations = 0;
  uint32_t subgroupSize = 0;
  uint64_t deviceLocalMemory = 0;
  bool suitable = false;  // Vulkan 1.1 with a compute queue and subgroup ballots in compute shaders
  bool floatAtomicAdd = false;  // set for the chosen device: VK_EXT_shader_atomic_float enabled
  bool pipelineStatistics = false;  // set for the chosen device: VK_KHR_pipeline_executable_properties enabled
  bool presents = false;  // with a window: its compute queue presents to the window's surface (VK_KHR_swapchain)
  // The driver's own traversal (VK_KHR_ray_query with VK_KHR_acceleration_structure): the anchor
  // that wavepath's traversal is measured against where a device has it.
  bool rayQuery = false;
};

// What a window asks of the context (`wavepath view`): the instance
// extensions its surface needs, and the surface, made once the instance
// exists. The device is then one whose compute queue presents to it.
struct Presentation {
  std::vector<std::string> instanceExtensions;
  std::function<VkSurfaceKHR(VkInstance)> makeSurface;
};

class Buffer {
 public:
  // Throws DeviceOutOfMemory where the device has no room for it.
  Buffer(const class VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage, bool hostVisible);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  vk::Buffer handle() const { return *buffer_; }
  vk::DeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // null unless host visible

 private:
  vk::DeviceSize size_;
  vk::raii::DeviceMemory memory_;  // declared first: destroyed after the buffer bound to it
  vk::raii::Buffer buffer_;
  void* mapped_ = nullptr;
  uint64_t held_ = 0;  // bytes of device memory counted by util/fault.h
};

class VulkanContext {
 public:
  // selector: "" picks the best device (discrete > integrated > virtual > cpu);
  // otherwise an index from list_devices() or part of a device name.
  VulkanContext(const std::string& selector, bool validation, const Presentation* presentation = nullptr);
  ~VulkanContext();

  static std::vector<GpuDeviceInfo> list_devices(bool validation);
  // The device a context made with `selector` would open (without a window),
  // described without opening it: what a scene's compilation may depend on.
  static GpuDeviceInfo selected_device(const std::string& selector);
  static bool validation_requested_by_environment();  // WAVEPATH_VALIDATION=1

  const GpuDeviceInfo& info() const { return info_; }
  const vk::raii::Device& device() const { return *device_; }
  const vk::raii::PhysicalDevice& physical() const { return *physical_; }
  const vk::raii::SurfaceKHR* surface() const { return surface_.get(); }  // null without a window
  vk::Queue queue() const { return queue_; }
  uint32_t queue_family() const { return queueFamily_; }
  uint64_t validation_messages() const { return validationMessages_->load(); }

  // Copies host data into a device buffer: directly when it is mapped (as all
  // of lavapipe's memory is), else with upload_staged.
  void upload(const Buffer& dst, const void* data, size_t bytes) const;
  // Copies host data into a device buffer through a staging buffer of at
  // most `chunkBytes`, one chunk at a time, so that a large scene never needs
  // a second, staged copy of a whole array (10M triangles: 458 MiB).
  static constexpr size_t kUploadChunkBytes = size_t(64) << 20;
  void upload_staged(const Buffer& dst, const void* data, size_t bytes, size_t chunkBytes = kUploadChunkBytes) const;
  // Records into a one-shot command buffer, submits and waits.
  void run_now(const std::function<void(vk::CommandBuffer)>& record) const;
  // Submits `cb` and waits for `fence` (reset first). Every submission of
  // a render goes through here: where the device is lost it throws
  // DeviceLost, and so does every later call. `samples`: the submission
  // renders samples, which WAVEPATH_FAULT's device-lost@submit counts
  // (util/fault.h; uploads, which only some devices submit, do not).
  void submit_and_wait(vk::CommandBuffer cb, const vk::raii::Fence& fence, bool samples = false) const;
  bool lost() const { return lost_; }
  uint32_t memory_type(uint32_t typeBits, vk::MemoryPropertyFlags want) const;

 private:
  std::unique_ptr<vk::raii::Context> context_;
  std::unique_ptr<vk::raii::Instance> instance_;
  std::unique_ptr<vk::raii::DebugUtilsMessengerEXT> messenger_;
  std::unique_ptr<vk::raii::SurfaceKHR> surface_;
  std::unique_ptr<vk::raii::PhysicalDevice> physical_;
  std::unique_ptr<vk::raii::Device> device_;
  std::unique_ptr<vk::raii::CommandPool> pool_;
  vk::Queue queue_;
  uint32_t queueFamily_ = 0;
  GpuDeviceInfo info_;
  mutable bool lost_ = false;
  std::shared_ptr<std::atomic<uint64_t>> validationMessages_ = std::make_shared<std::atomic<uint64_t>>(0);
};

}  // namespace wp
