// viewer_input.cpp — what `wavepath view` reads from its window (mouse,
// keys, resizes) and what it changes: the view, the render's settings, the
// cell rendered (viewer_impl.h).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/compiled_scene.h"
#include "scene/load_scene.h"
#include "util/error.h"
#include "view/viewer_impl.h"

namespace wp {

namespace {

constexpr double kFlyStep = 0.05;  // canonical view distances per key press or repeat
// A window resize is applied once it has settled: each size needs new kernels.
constexpr auto kResizeSettles = std::chrono::milliseconds(300);

}  // namespace

void Viewer::install_callbacks() {
  glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action != GLFW_RELEASE) static_cast<WindowInput*>(glfwGetWindowUserPointer(w))->keys.push_back({key, mods, action == GLFW_REPEAT});
  });
  glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
    WindowInput& in = *static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    const bool down = action == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
      in.left = down;
      (down ? in.leftPressed : in.leftReleased) = true;
    }
    if (button == GLFW_MOUSE_BUTTON_RIGHT) {
      if (!down && in.right && in.rightTravel < 3.0) {
        in.focusClick = true;
        in.focusX = in.x;
        in.focusY = in.y;
      }
      in.right = down;
      in.rightTravel = 0;
    }
  });
  glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
    WindowInput& in = *static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    const double dx = x - in.x, dy = y - in.y;
    if (in.left && !in.right) in.orbit.emplace_back(dx, dy);
    if (in.right && !in.left) {
      in.pan.emplace_back(dx, dy);
      in.rightTravel += std::abs(dx) + std::abs(dy);
    }
    in.x = x;
    in.y = y;
  });
  glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) { static_cast<WindowInput*>(glfwGetWindowUserPointer(w))->wheel += dy; });
  glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) {
    WindowInput& in = *static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    in.resized = true;
    in.resizedAt = std::chrono::steady_clock::now();
  });
}

// Reads the input gathered since the last look. Returns false to stop the
// render where it is (the view or the render changed, or quit).
bool Viewer::handle_input() {
  glfwPollEvents();
  WindowInput& in = input_;
  int fbW = 0, fbH = 0, winW = 1, winH = 1;
  glfwGetFramebufferSize(window_, &fbW, &fbH);
  glfwGetWindowSize(window_, &winW, &winH);
  const double toPixels = winW > 0 ? double(fbW) / winW : 1.0;
  bool moved = false, rebuildNeeded = false, restartNeeded = false;
  if (cellMode_) {
    const std::vector<int> before = cell_;
    in.orbit.clear();
    drag_cell(in, toPixels);
    rebuildNeeded = cell_ != before;
    if (dragging_) shown_ = false;
  }
  in.leftPressed = in.leftReleased = false;
  for (auto [dx, dy] : in.orbit) view_->orbit(dx * toPixels, dy * toPixels, fbW, fbH);
  for (auto [dx, dy] : in.pan) view_->pan(dx * toPixels, dy * toPixels, fbH);
  moved = !in.orbit.empty() || !in.pan.empty() || in.wheel != 0.0;
  if (in.wheel != 0.0) view_->zoom(in.wheel);
  in.orbit.clear();
  in.pan.clear();
  in.wheel = 0;
  if (in.focusClick) {
    in.focusClick = false;
    autofocus(in.focusX * toPixels, in.focusY * toPixels);
    moved = true;
  }
  std::vector<WindowInput::Key> keys;
  keys.swap(in.keys);
  for (const auto [key, mods, repeat] : keys) {
    const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
    glm::dvec3 flight(0.0);
    switch (key) {
      case GLFW_KEY_W: flight.z = -1; break;
      case GLFW_KEY_UP: flight.z = -1; break;
      case GLFW_KEY_DOWN: flight.z = 1; break;
      case GLFW_KEY_A: flight.x = -1; break;
      case GLFW_KEY_LEFT: flight.x = -1; break;
      case GLFW_KEY_RIGHT: flight.x = 1; break;
      case GLFW_KEY_Q: flight.y = -1; break;
      case GLFW_KEY_E: flight.y = 1; break;
      case GLFW_KEY_S: if (shift) flight.z = 1; break;
      case GLFW_KEY_D: if (shift) flight.x = 1; break;
      default: break;
    }
    if (flight != glm::dvec3(0.0)) {
      view_->fly(flight * kFlyStep);
      moved = true;
      continue;
    }
    if (repeat) continue;  // the course acts on presses only
    switch (key) {
      case GLFW_KEY_ESCAPE: quit_ = true; break;
      case GLFW_KEY_R: restartNeeded = true; break;
      case GLFW_KEY_SPACE: view_->reset(); moved = true; break;
      case GLFW_KEY_S: save(); break;
      case GLFW_KEY_D: write_camera(scene_stem(r_.scene) + "_cam_settings.txt"); break;
      case GLFW_KEY_H:
        hemisphere_ = !hemisphere_;
        std::printf("view: %s\n", hemisphere_ ? "uniform hemisphere sampling" : "light sampling");
        rebuildNeeded = true;
        break;
      case GLFW_KEY_RIGHT_BRACKET:
      case GLFW_KEY_LEFT_BRACKET:
        // More samples continue the image; fewer than it holds start it
        // again, as does any change under correlated multi-jittered
        // sampling, whose strata depend on the count.
        if (acc_.set_target(key == GLFW_KEY_RIGHT_BRACKET ? std::min(acc_.target() * 2, uint32_t(MAX_SAMPLES_PER_PIXEL))
                                                          : acc_.target() / 2))
          restartNeeded = true;
        std::printf("view: %u samples per pixel\n", acc_.target());
        compiled_->spp = int(acc_.target());
        compiled_->params.mode.z = acc_.target();
        if (!restartNeeded) renderer_->update_params();
        break;
      case GLFW_KEY_EQUAL:
      case GLFW_KEY_MINUS: {
        int& l = lightSamples_;
        if (l <= 0) l = r_.lightSamples;
        const int before = l;
        l = key == GLFW_KEY_EQUAL ? std::min(l * 2, int(MAX_LIGHT_SAMPLES)) : std::max(l / 2, 1);
        std::printf("view: %d light samples per vertex\n", l);
        rebuildNeeded = rebuildNeeded || l != before;
        break;
      }
      case GLFW_KEY_PERIOD: ++bounces_; restartNeeded = true; std::printf("view: at most %d bounces\n", bounces_); break;
      case GLFW_KEY_COMMA:
        if (bounces_ > 0) --bounces_;
        restartNeeded = true;
        std::printf("view: at most %d bounces\n", bounces_);
        break;
      case GLFW_KEY_K: view_->change_aperture(-0.05); moved = true; break;
      case GLFW_KEY_L: view_->change_aperture(0.05); moved = true; break;
      case GLFW_KEY_SEMICOLON: view_->change_focus(-0.1); moved = true; break;
      case GLFW_KEY_APOSTROPHE: view_->change_focus(0.1); moved = true; break;
      case GLFW_KEY_TAB:
        layer_ = (layer_ + 1) % kShownLayerCount;
        if (is_aov(layer_) && compiled_->aovs.empty()) {
          r_.aovs = all_aov_names();  // the first hits' layers, from now on
          rebuildNeeded = true;
        }
        encode();
        shown_ = false;
        break;
      case GLFW_KEY_X: exposure_ += 1.0; encode(); shown_ = false; break;
      case GLFW_KEY_Z: exposure_ -= 1.0; encode(); shown_ = false; break;
      case GLFW_KEY_F: reload_ = true; break;
      case GLFW_KEY_C:
        cellMode_ = !cellMode_;
        std::printf("view: %s\n", cellMode_ ? "cell mode: drag a rectangle to render it alone" : "the whole frame");
        if (!cellMode_ && !cell_.empty()) {
          cell_.clear();
          rebuildNeeded = true;
        }
        shown_ = false;
        break;
      case GLFW_KEY_SLASH:
        if (shift) std::fputs(viewer_keys(), stdout);
        break;
      default: break;
    }
  }
  if (glfwWindowShouldClose(window_)) quit_ = true;
  // The render's size follows the window's, once the resize has settled.
  if (in.resized && std::chrono::steady_clock::now() - in.resizedAt > kResizeSettles) {
    in.resized = false;
    const Camera frame = view_->camera();
    if (fbW > 0 && fbH > 0 && (fbW != frame.width || fbH != frame.height)) {
      cell_.clear();  // as the course's window drops its cell on a resize
      cellMode_ = false;
      r_.resolution = {fbW, fbH};
      view_->set_resolution(fbW, fbH);
      std::printf("view: %dx%d\n", fbW, fbH);
      rebuildNeeded = true;
    }
  }
  if (!reload_ && std::chrono::steady_clock::now() - lastCheck_ > std::chrono::milliseconds(500)) {
    lastCheck_ = std::chrono::steady_clock::now();
    if (modified() != lastWrite_) reload_ = true;
  }
  if (reload_) {
    reload_ = false;
    lastWrite_ = modified();
    try {
      Scene fresh = load_scene_with_overrides(r_);
      previousScene_ = std::make_unique<Scene>(std::move(scene_));
      scene_ = std::move(fresh);
      std::printf("view: reloaded %s\n", r_.scene.c_str());
      rebuildNeeded = true;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "wavepath view: %s (the scene as it was stays)\n", e.what());
    }
  }
  pendingRebuild_ = pendingRebuild_ || rebuildNeeded;
  pendingRestart_ = pendingRestart_ || moved || restartNeeded;
  return !quit_ && !pendingRebuild_ && !pendingRestart_;
}

// The lens focused at the depth under the window pixel (x, y): the
// distance along the view axis to what the ray through it meets first.
void Viewer::autofocus(double x, double y) {
  const Camera c = view_->camera();
  const int w = c.width, h = c.height;
  const glm::dvec2 at = frame_at(x, y);
  const double px = at.x, py = at.y;
  if (px < 0 || py < 0 || px >= w || py >= h || c.orthoHalfHeight > 0) return;
  const double tanHalf = std::tan(glm::radians(double(c.vfovDegrees)) / 2);
  const double aspect = c.aspect > 0 ? c.aspect : double(w) / h;
  const glm::dvec3 local((2 * px / w - 1) * tanHalf * aspect, (1 - 2 * py / h) * tanHalf, -1.0);
  const glm::dmat3 frame = view_->orientation();
  const glm::dvec3 dir = glm::normalize(frame * local);
  shader::ShadowRay ray{};
  ray.origin = glm::vec3(view_->position());
  ray.dir = glm::vec3(dir);
  ray.tmax = 1e30f;
  const std::vector<shader::Hit> hits = renderer_->cast_rays({ray});
  if (hits.empty() || hits[0].prim == WP_INVALID) return;
  const double depth = hits[0].t * glm::dot(dir, -glm::normalize(frame[2]));
  view_->set_focus(depth);
  std::printf("view: focus distance %.4g\n", depth);
}

// The frame's pixel (full frame, rows from the top) under window
// framebuffer position (x, y).
glm::dvec2 Viewer::frame_at(double x, double y) const {
  const Camera c = view_->camera();
  const vk::Extent2D e = presenter_->extent();
  return Letterbox(int(e.width), int(e.height), c.width, c.height).image_at(x, y);
}

// The camera rendered: the view's, through the cell where one is chosen.
Camera Viewer::viewed() const {
  Camera c = view_->camera();
  if (!cell_.empty()) set_cell(c, cell_[0], cell_[1], cell_[2], cell_[3]);
  return c;
}

// The course's cell mode (C): a left-drag chooses a rectangle of the frame,
// rendered alone as -p renders it, over the frame as it was.
void Viewer::drag_cell(WindowInput& in, double toPixels) {
  const Camera frame = view_->camera();
  const glm::dvec2 at = glm::clamp(frame_at(in.x * toPixels, in.y * toPixels), glm::dvec2(0.0), glm::dvec2(frame.width, frame.height));
  if (in.leftPressed) cellFrom_ = cellTo_ = at;
  if (in.left || in.leftReleased) cellTo_ = at;
  dragging_ = in.left;
  in.leftPressed = false;
  if (!in.leftReleased) return;
  in.leftReleased = false;
  const glm::ivec2 lo(glm::floor(glm::min(cellFrom_, cellTo_))), hi(glm::ceil(glm::max(cellFrom_, cellTo_)));
  if (hi.x - lo.x < 2 || hi.y - lo.y < 2) return;
  dragging_ = false;
  compose();  // the frame as it is, without the rectangle
  backdrop_ = displayBytes_;
  cell_ = {lo.x, frame.height - hi.y, hi.x - lo.x, hi.y - lo.y};
  std::printf("view: cell %dx%d at %d %d (rows from the bottom, as -p counts them)\n", cell_[2], cell_[3], cell_[0], cell_[1]);
}

}  // namespace wp
