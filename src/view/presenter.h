// presenter.h — how `wavepath view` puts a frame in its window: a Vulkan
// swapchain on the renderer's own device and queue, each frame's 8-bit
// bytes copied into its image (no raster pipeline), letterboxed.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "gpu/vulkan_context.h"

struct GLFWwindow;

namespace wp {

// Where an image of w x h pixels lies in a window of W x H: magnified by
// whole pixels where the window is larger, shrunk where it is smaller,
// centred on black.
struct Letterbox {
  double scale;
  int x0, y0;
  Letterbox(int W, int H, int w, int h) {
    scale = std::min(double(W) / w, double(H) / h);
    if (scale >= 1.0) scale = std::floor(scale);
    x0 = (W - int(w * scale)) / 2;
    y0 = (H - int(h * scale)) / 2;
  }
  // The image pixel at window position (x, y), which may lie outside it.
  glm::dvec2 image_at(double x, double y) const { return {(x - x0) / scale, (y - y0) / scale}; }
};

// One image per swapchain image; the renderer's queue presents.
class Presenter {
 public:
  Presenter(const VulkanContext& ctx, GLFWwindow* window);
  ~Presenter();

  vk::Extent2D extent() const { return extent_; }

  // Shows `rgb8` (width x height, 3 bytes a pixel), scaled to fit the window
  // by whole pixels where it is larger, centred on black.
  void present(const std::vector<uint8_t>& rgb8, int width, int height);

 private:
  void create();
  void fill(const std::vector<uint8_t>& rgb8, int width, int height);

  const VulkanContext& ctx_;
  GLFWwindow* window_;
  vk::raii::CommandPool pool_{nullptr};
  vk::raii::SwapchainKHR chain_{nullptr};
  std::vector<vk::Image> images_;
  std::vector<vk::raii::Semaphore> drawn_;
  vk::raii::Semaphore acquired_{nullptr};
  vk::raii::Fence fence_{nullptr};
  vk::raii::CommandBuffer commands_{nullptr};
  std::unique_ptr<Buffer> staging_;
  vk::Extent2D extent_;
  bool bgra_ = true;
  bool stale_ = false;
};

}  // namespace wp
