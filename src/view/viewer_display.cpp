// viewer_display.cpp — the frame `wavepath view` shows: the layer chosen,
// encoded as `render` writes its PNG, the cell over the frame it was chosen
// on, and the window's title (viewer_impl.h).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/image_file.h"
#include "render/partial.h"
#include "view/viewer_impl.h"

namespace wp {

// The image shown, as 8-bit RGB: the layer chosen, through the scene's
// 8-bit curve, as `render` writes its PNG (at exposure 0).
void Viewer::encode() {
  const size_t n = image_.pixels();
  shownBytes_.resize(n * 3);
  const double gain = std::exp2(exposure_);
  const EightBitCurve curve = compiled_->eightBitCurve;
  auto put = [&](size_t p, glm::dvec3 v) {
    for (int c = 0; c < 3; ++c) shownBytes_[p * 3 + c] = encode_8bit_value(v[c] * gain, curve);
  };
  const std::string name = kShownLayers[layer_];
  if (layer_ == 0) {
    for (size_t p = 0; p < n; ++p) put(p, image_.mean(p));
  } else if (name == "variance") {
    for (size_t p = 0; p < n; ++p) put(p, image_.count[p] > 0 ? image_.variance(p) / image_.count[p] : glm::dvec3(0.0));
  } else if (name == "samples") {
    shownBytes_ = sample_rate_rgb8(image_, int(acc_.target()));  // the course's rate image
  } else if (image_.layer(name)) {
    // First hits, as the normals integrator shows them: albedo as it is,
    // normals mapped from [-1, 1], depth over the deepest hit.
    const ImageStats layer = layer_as_color(image_, name);
    double deepest = 0.0;
    for (size_t p = 0; p < n && name == "depth"; ++p) deepest = std::max(deepest, layer.mean(p).x);
    for (size_t p = 0; p < n; ++p) {
      const glm::dvec3 m = layer.mean(p);
      put(p, name == "normal" ? (m + 1.0) * 0.5 : name == "depth" ? glm::dvec3(deepest > 0 ? m.x / deepest : 0.0) : m);
    }
  }
}

// The frame shown: the image, or the cell's image over the frame as it
// was, and the rectangle being dragged in red.
void Viewer::compose() {
  const Camera frame = view_->camera();
  const int W = frame.width, H = frame.height;
  if (cell_.empty()) {
    displayBytes_ = shownBytes_;
  } else {
    if (backdrop_.size() != size_t(W) * H * 3) backdrop_.assign(size_t(W) * H * 3, 0);
    displayBytes_ = backdrop_;
    const int x0 = cell_[0], y0 = H - cell_[1] - cell_[3];
    for (int y = 0; y < cell_[3]; ++y)
      std::copy_n(&shownBytes_[size_t(y) * cell_[2] * 3], size_t(cell_[2]) * 3, &displayBytes_[(size_t(y0 + y) * W + x0) * 3]);
  }
  if (!cellMode_ || !dragging_ || displayBytes_.size() != size_t(W) * H * 3) return;
  const glm::ivec2 lo(glm::min(cellFrom_, cellTo_)), hi(glm::min(glm::max(cellFrom_, cellTo_), glm::dvec2(W - 1, H - 1)));
  auto red = [&](int x, int y) {
    uint8_t* p = &displayBytes_[(size_t(y) * W + x) * 3];
    p[0] = 255, p[1] = 0, p[2] = 0;
  };
  for (int x = lo.x; x <= hi.x; ++x) red(x, lo.y), red(x, hi.y);
  for (int y = lo.y; y <= hi.y; ++y) red(lo.x, y), red(hi.x, y);
}

void Viewer::show() {
  compose();
  const Camera frame = view_->camera();
  presenter_->present(displayBytes_, frame.width, frame.height);
  ++frames_;
  shown_ = true;
  const std::string layer = kShownLayers[layer_];
  const double elapsed = std::chrono::duration<double>((acc_.done() ? finished_ : std::chrono::steady_clock::now()) - started_).count();
  char title[512];
  std::snprintf(title, sizeof title, "wavepath: %s | %dx%d | %u/%u spp | %.2f Msamples/s | %.1f s | %s%s | %s%s", scene_stem(r_.scene).c_str(),
                compiled_->width, compiled_->height, acc_.reached(), acc_.target(), elapsed > 0 ? double(image_.pixels()) * acc_.reached() / elapsed * 1e-6 : 0.0, elapsed,
                integrator_name(compiled_->params).c_str(), hemisphere_ ? " (hemisphere)" : "", layer.c_str(),
                (std::string(cellMode_ ? " | cell mode" : "") + (exposure_ != 0 ? " | exposure " + std::to_string(int(exposure_)) : "")).c_str());
  glfwSetWindowTitle(window_, title);
}

}  // namespace wp
