// presenter.cpp — the window's swapchain (presenter.h).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "view/presenter.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "util/error.h"

namespace wp {

Presenter::Presenter(const VulkanContext& ctx, GLFWwindow* window) : ctx_(ctx), window_(window) {
  acquired_ = vk::raii::Semaphore(ctx.device(), vk::SemaphoreCreateInfo());
  fence_ = vk::raii::Fence(ctx.device(), vk::FenceCreateInfo());
  pool_ = vk::raii::CommandPool(ctx.device(), vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer, ctx.queue_family()));
  commands_ = std::move(vk::raii::CommandBuffers(ctx.device(), vk::CommandBufferAllocateInfo(*pool_, vk::CommandBufferLevel::ePrimary, 1))[0]);
  create();
}

void Presenter::present(const std::vector<uint8_t>& rgb8, int width, int height) {
  if (stale_) create();
  if (extent_.width == 0 || extent_.height == 0) return;  // minimised
  uint32_t index = 0;
  try {
    auto [result, i] = chain_.acquireNextImage(UINT64_MAX, *acquired_, nullptr);
    index = i;
    if (result == vk::Result::eSuboptimalKHR) stale_ = true;
  } catch (const vk::OutOfDateKHRError&) {
    stale_ = true;
    return;
  }
  fill(rgb8, width, height);
  vk::CommandBuffer cb = *commands_;
  cb.reset();
  cb.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  vk::ImageSubresourceRange all(vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1);
  vk::ImageMemoryBarrier toCopy({}, vk::AccessFlagBits::eTransferWrite, vk::ImageLayout::eUndefined, vk::ImageLayout::eTransferDstOptimal,
                                VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED, images_[index], all);
  cb.pipelineBarrier(vk::PipelineStageFlagBits::eTopOfPipe, vk::PipelineStageFlagBits::eTransfer, {}, {}, {}, toCopy);
  cb.copyBufferToImage(staging_->handle(), images_[index], vk::ImageLayout::eTransferDstOptimal,
                       vk::BufferImageCopy(0, 0, 0, vk::ImageSubresourceLayers(vk::ImageAspectFlagBits::eColor, 0, 0, 1), {0, 0, 0},
                                           vk::Extent3D(extent_, 1)));
  vk::ImageMemoryBarrier toPresent(vk::AccessFlagBits::eTransferWrite, {}, vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::ePresentSrcKHR,
                                   VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED, images_[index], all);
  cb.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eBottomOfPipe, {}, {}, {}, toPresent);
  cb.end();
  vk::PipelineStageFlags wait = vk::PipelineStageFlagBits::eTransfer;
  ctx_.device().resetFences(*fence_);
  ctx_.queue().submit(vk::SubmitInfo(*acquired_, wait, cb, *drawn_[index]), *fence_);
  while (ctx_.device().waitForFences(*fence_, VK_TRUE, 1000000000ull) == vk::Result::eTimeout) {
  }
  try {
    vk::Result r = ctx_.queue().presentKHR(vk::PresentInfoKHR(*drawn_[index], *chain_, index));
    if (r == vk::Result::eSuboptimalKHR) stale_ = true;
  } catch (const vk::OutOfDateKHRError&) {
    stale_ = true;
  }
}

Presenter::~Presenter() { ctx_.device().waitIdle(); }

void Presenter::create() {
  ctx_.device().waitIdle();
  const vk::raii::PhysicalDevice& pd = ctx_.physical();
  vk::SurfaceKHR surface = **ctx_.surface();
  vk::SurfaceCapabilitiesKHR caps = pd.getSurfaceCapabilitiesKHR(surface);
  int fbW = 0, fbH = 0;
  glfwGetFramebufferSize(window_, &fbW, &fbH);
  extent_ = caps.currentExtent.width != UINT32_MAX
                ? caps.currentExtent
                : vk::Extent2D(std::clamp(uint32_t(fbW), caps.minImageExtent.width, caps.maxImageExtent.width),
                               std::clamp(uint32_t(fbH), caps.minImageExtent.height, caps.maxImageExtent.height));
  stale_ = false;
  if (extent_.width == 0 || extent_.height == 0) return;
  if (!(caps.supportedUsageFlags & vk::ImageUsageFlagBits::eTransferDst))
    throw RenderError(ctx_.info().name + " cannot copy into the window's images (no transfer-destination swapchain usage)");
  // Any 8-bit BGRA or RGBA format: the bytes copied are already encoded
  // (as the PNG's are), and a copy converts nothing.
  std::vector<vk::SurfaceFormatKHR> formats = pd.getSurfaceFormatsKHR(surface);
  auto chosen = std::find_if(formats.begin(), formats.end(), [](const vk::SurfaceFormatKHR& f) {
    return f.format == vk::Format::eB8G8R8A8Unorm || f.format == vk::Format::eB8G8R8A8Srgb || f.format == vk::Format::eR8G8B8A8Unorm ||
           f.format == vk::Format::eR8G8B8A8Srgb;
  });
  if (chosen == formats.end()) throw RenderError(ctx_.info().name + " offers the window no 8-bit RGBA or BGRA format");
  bgra_ = chosen->format == vk::Format::eB8G8R8A8Unorm || chosen->format == vk::Format::eB8G8R8A8Srgb;
  uint32_t count = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);
  vk::SwapchainCreateInfoKHR ci({}, surface, count, chosen->format, chosen->colorSpace, extent_, 1, vk::ImageUsageFlagBits::eTransferDst,
                                vk::SharingMode::eExclusive, {}, caps.currentTransform, vk::CompositeAlphaFlagBitsKHR::eOpaque,
                                vk::PresentModeKHR::eFifo, VK_TRUE, *chain_);
  chain_ = vk::raii::SwapchainKHR(ctx_.device(), ci);
  images_ = chain_.getImages();
  drawn_.clear();
  for (size_t i = 0; i < images_.size(); ++i) drawn_.emplace_back(ctx_.device(), vk::SemaphoreCreateInfo());
  staging_ = std::make_unique<Buffer>(ctx_, vk::DeviceSize(extent_.width) * extent_.height * 4, vk::BufferUsageFlagBits::eTransferSrc, true);
}

void Presenter::fill(const std::vector<uint8_t>& rgb8, int width, int height) {
  const int W = int(extent_.width), H = int(extent_.height);
  const Letterbox box(W, H, width, height);
  auto* out = static_cast<uint8_t*>(staging_->mapped());
  const int r = bgra_ ? 2 : 0, b = bgra_ ? 0 : 2;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      uint8_t* o = out + (size_t(y) * W + x) * 4;
      const glm::dvec2 at = box.image_at(x, y);
      const int ix = int(std::floor(at.x)), iy = int(std::floor(at.y));
      if (x < box.x0 || y < box.y0 || ix < 0 || iy < 0 || ix >= width || iy >= height) {
        o[0] = o[1] = o[2] = 0;
      } else {
        const uint8_t* p = &rgb8[(size_t(iy) * width + ix) * 3];
        o[r] = p[0];
        o[1] = p[1];
        o[b] = p[2];
      }
      o[3] = 255;
    }
  }
}

}  // namespace wp
