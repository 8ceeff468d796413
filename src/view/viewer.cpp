// The window of `wavepath view`: GLFW for the window and input, a Vulkan
// swapchain on the renderer's own device and queue for presenting. The image
// shown is the render's: passes of the same kernels accumulate into the same
// ImageStats `render` writes, and each refresh copies its 8-bit encoding into
// the swapchain image (no second renderer, no raster preview).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "view/viewer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>

#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render/compiled_scene.h"
#include "render/partial.h"
#include "scene/load_scene.h"
#include "util/error.h"
#include "util/progress.h"
#include "view/accumulation.h"
#include "view/presenter.h"
#include "view/view_camera.h"

namespace wp {

const char* viewer_keys() {
  return "mouse   left-drag orbits about the target, right-drag pans, the wheel zooms (wheel up: away)\n"
         "        right-click (no drag) focuses the lens at the depth under the cursor\n"
         "W A Q E  fly forward, left, down, up (with Shift: W A S D Q E; the arrow keys: forward, back, left, right)\n"
         "Space   back to the scene's camera\n"
         "R       render again from sample 0\n"
         "C       cell mode: a left-drag chooses a rectangle, rendered alone as -p renders it (C again: the whole frame)\n"
         "S       save the image: PNG, the EXR `render` writes (resumable) and the camera file\n"
         "D       write the camera settings file (SCENE_cam_settings.txt) that `render -c` reads\n"
         "H       uniform hemisphere sampling on/off (instead of light sampling)\n"
         "] [     twice, half the samples per pixel\n"
         "= -     twice, half the light samples per vertex\n"
         ". ,     one more, one fewer bounce\n"
         "L K     lens radius +0.05, -0.05\n"
         "' ;     focus distance +0.1, -0.1\n"
         "Tab     next layer: colour, albedo, normal, depth (first hits; asking for one renders them from then on),\n"
         "        per-pixel variance of the mean, samples per pixel (the course's rate image: blue none, green half, red all)\n"
         "X Z     exposure +1, -1 stop (the display only; the files are written as `render` writes them)\n"
         "F       reload the scene from disk (it also reloads when its file changes), keeping the view\n"
         "?       this list\n"
         "Esc     save (as S) and quit; closing the window does the same\n";
}

namespace {

constexpr double kFlyStep = 0.05;  // canonical view distances per key press or repeat
// What Tab shows, in turn; the AOVs by their layer names (layers.glsl).
const char* const kShownLayers[] = {"colour", "albedo", "normal", "depth", "variance", "samples"};
constexpr size_t kShownLayerCount = sizeof(kShownLayers) / sizeof(kShownLayers[0]);
bool is_aov(size_t layer) { return layer >= 1 && layer <= 3; }
// A window resize is applied once it has settled: each size needs new kernels.
constexpr auto kResizeSettles = std::chrono::milliseconds(300);

struct Input {
  double x = 0, y = 0;            // cursor, window coordinates
  bool left = false, right = false;
  double rightTravel = 0;          // cursor travel since the right button went down
  struct Key {
    int key, mods;
    bool repeat;  // held down: the flight keys act on repeats, the rest only on presses
  };
  std::vector<Key> keys;  // since the last look
  std::vector<std::pair<double, double>> orbit, pan;
  double wheel = 0;
  bool focusClick = false;
  double focusX = 0, focusY = 0;
  bool resized = false;
  std::chrono::steady_clock::time_point resizedAt;
  bool leftPressed = false, leftReleased = false;  // since the last look
};

std::string scene_stem(const std::string& path) {
  // The course names its files after the scene: the text after the last '/'
  // up to its first ".dae" (main.cpp); wavepath after any extension.
  std::string name = std::filesystem::path(path).filename().string();
  size_t dae = name.find(".dae");
  return dae != std::string::npos ? name.substr(0, dae) : std::filesystem::path(path).stem().string();
}

class Viewer {
 public:
  explicit Viewer(const ViewerArgs& a) : args_(a), r_(a.render) {}

  int run() {
    if (!glfwInit()) {
      const char* why = nullptr;
      glfwGetError(&why);
      std::fprintf(stderr, "wavepath view: no display to open a window on (%s); `wavepath render` renders without one\n",
                   why ? why : "GLFW could not start");
      return 2;
    }
    struct Terminate {
      ~Terminate() { glfwTerminate(); }
    } terminate;
    if (!glfwVulkanSupported()) {
      std::fprintf(stderr, "wavepath view: the Vulkan loader offers no surface for a window here; `wavepath render` renders without one\n");
      return 2;
    }
    scene_ = load_scene_with_overrides(r_);
    view_ = std::make_unique<ViewCamera>(scene_.camera, scene_bounds(scene_));
    acc_ = ViewAccumulation(uint32_t(r_.spp > 0 ? r_.spp : scene_.samplesPerPixel), scene_.sampler == SamplerKind::Cmj);
    bounces_ = r_.maxBounces;
    lastWrite_ = modified();

    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(scene_.camera.width, scene_.camera.height, ("wavepath: " + scene_stem(r_.scene)).c_str(), nullptr, nullptr);
    if (!window_) {
      std::fprintf(stderr, "wavepath view: the display refused a %dx%d window\n", scene_.camera.width, scene_.camera.height);
      return 2;
    }
    glfwSetWindowUserPointer(window_, &input_);
    install_callbacks();
    Presentation presentation;
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    for (uint32_t i = 0; i < n; ++i) presentation.instanceExtensions.emplace_back(names[i]);
    presentation.makeSurface = [this](VkInstance instance) {
      VkSurfaceKHR surface = VK_NULL_HANDLE;
      if (glfwCreateWindowSurface(instance, window_, nullptr, &surface) != VK_SUCCESS)
        throw RenderError("cannot make a Vulkan surface for the window");
      return surface;
    };
    try {
      ctx_ = std::make_unique<VulkanContext>(r_.device, r_.validation || VulkanContext::validation_requested_by_environment(), &presentation);
      presenter_ = std::make_unique<Presenter>(*ctx_, window_);
      variant_ = r_.variant.empty() ? default_variant(ctx_->info()).name : r_.variant;
    } catch (const RenderError& e) {
      std::fprintf(stderr, "wavepath view: %s; `wavepath render` renders without a window\n", e.what());
      return 2;
    }
    rebuild();
    const int status = loop();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - opened_).count();
    if (!r_.quiet)
      std::printf("view: %llu frames in %.2f s (%.1f per second), %.3f Msamples/s while rendering\n", (unsigned long long)frames_, seconds,
                  frames_ / seconds, renderSeconds_ > 0 ? double(samplesRendered_) / renderSeconds_ * 1e-6 : 0.0);
    presenter_.reset();
    renderer_.reset();
    if (ctx_->validation_messages() > 0) {
      std::fprintf(stderr, "wavepath view: %llu Vulkan validation messages\n", (unsigned long long)ctx_->validation_messages());
      return 3;
    }
    return status;
  }

 private:
  void install_callbacks() {
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
      if (action != GLFW_RELEASE) static_cast<Input*>(glfwGetWindowUserPointer(w))->keys.push_back({key, mods, action == GLFW_REPEAT});
    });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
      Input& in = *static_cast<Input*>(glfwGetWindowUserPointer(w));
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
      Input& in = *static_cast<Input*>(glfwGetWindowUserPointer(w));
      const double dx = x - in.x, dy = y - in.y;
      if (in.left && !in.right) in.orbit.emplace_back(dx, dy);
      if (in.right && !in.left) {
        in.pan.emplace_back(dx, dy);
        in.rightTravel += std::abs(dx) + std::abs(dy);
      }
      in.x = x;
      in.y = y;
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) { static_cast<Input*>(glfwGetWindowUserPointer(w))->wheel += dy; });
    glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) {
      Input& in = *static_cast<Input*>(glfwGetWindowUserPointer(w));
      in.resized = true;
      in.resizedAt = std::chrono::steady_clock::now();
    });
  }

  RenderOptions options() const {
    RenderArgs a = r_;
    a.spp = int(acc_.target());
    a.maxBounces = bounces_;
    a.integrator = hemisphere_ ? "path tracer hemisphere" : r_.integrator;
    a.lightSamples = lightSamples_ > 0 ? lightSamples_ : r_.lightSamples;
    return variant_options(options_from(a, a.seed), variant_);  // the variant's BVH layout
  }

  // A new renderer: the scene compiled again (kinds, integrator or light
  // samples changed, or the file was reloaded).
  void rebuild() {
    scene_.camera = viewed();
    renderer_.reset();
    compiled_ = std::make_unique<CompiledScene>(compile_scene(scene_, options()));
    if (bounces_ < 0) bounces_ = int(compiled_->params.image.z);
    acc_.set_stratified(compiled_->params.mode.y == SAMPLER_CMJ);
    WavefrontSettings settings = renderer_settings(kernel_variant(variant_), r_);
    settings.targetSubmitSeconds = 1.0 / 15.0;  // a refresh after each submission
    renderer_ = std::make_unique<WavefrontRenderer>(*ctx_, *compiled_, settings);
    restart();
  }

  // From sample 0 with the view and bounces as they are now.
  void restart() {
    scene_.camera = viewed();
    set_camera_params(scene_.camera, compiled_->params);
    compiled_->params.image.z = uint32_t(bounces_);
    compiled_->spp = int(acc_.target());
    compiled_->params.mode.z = acc_.target();
    renderer_->update_params();
    image_ = ImageStats(compiled_->width, compiled_->height, image_layers(compiled_->aovs));
    acc_.restart();
    started_ = std::chrono::steady_clock::now();
    encode();
  }

  // Reads the input gathered since the last look. Returns false to stop the
  // render where it is (the view or the render changed, or quit).
  bool handle_input() {
    glfwPollEvents();
    Input& in = input_;
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
    std::vector<Input::Key> keys;
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

  // What the input asked for, once the renderer is between renders.
  void apply_pending() {
    try {
      if (pendingRebuild_) rebuild();
      else if (pendingRestart_) restart();
    } catch (const InputError& e) {
      // A reloaded file that loads but does not compile (too many emitters
      // for the mixture, say): the scene as it was stays.
      if (!previousScene_) throw;
      std::fprintf(stderr, "wavepath view: %s (the scene as it was stays)\n", e.what());
      scene_ = std::move(*previousScene_);
      previousScene_.reset();
      rebuild();
    }
    previousScene_.reset();
    pendingRebuild_ = pendingRestart_ = false;
  }

  // The lens focused at the depth under the window pixel (x, y): the
  // distance along the view axis to what the ray through it meets first.
  void autofocus(double x, double y) {
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
  glm::dvec2 frame_at(double x, double y) const {
    const Camera c = view_->camera();
    const vk::Extent2D e = presenter_->extent();
    return Letterbox(int(e.width), int(e.height), c.width, c.height).image_at(x, y);
  }

  // The camera rendered: the view's, through the cell where one is chosen.
  Camera viewed() const {
    Camera c = view_->camera();
    if (!cell_.empty()) set_cell(c, cell_[0], cell_[1], cell_[2], cell_[3]);
    return c;
  }

  // The course's cell mode (C): a left-drag chooses a rectangle of the frame,
  // rendered alone as -p renders it, over the frame as it was.
  void drag_cell(Input& in, double toPixels) {
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

  // The image shown, as 8-bit RGB: the layer chosen, through the scene's
  // 8-bit curve, as `render` writes its PNG (at exposure 0).
  void encode() {
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
  void compose() {
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

  void show() {
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

  int loop() {
    opened_ = std::chrono::steady_clock::now();
    Progress quiet("", 0, false);
    while (!quit_) {
      if (!acc_.done()) {
        const auto t0 = std::chrono::steady_clock::now();
        const uint32_t from = acc_.reached();
        PassHook afterPass = [&](const ImageStats&, uint32_t sample) {
          acc_.reach(sample);
          encode();
          show();
          return handle_input();
        };
        const uint32_t sample = renderer_->render(image_, acc_.todo(), quiet, afterPass);
        renderSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        samplesRendered_ += uint64_t(image_.pixels()) * (sample - from);
        acc_.reach(sample);
        if (pendingRebuild_ || pendingRestart_) {
          apply_pending();
          continue;
        }
        if (acc_.done()) finished_ = std::chrono::steady_clock::now();
        encode();
        show();
        if (acc_.done() && args_.exitWhenDone) {
          save();
          return 0;
        }
        handle_input();
        apply_pending();
      } else {
        if (!shown_) show();
        glfwWaitEventsTimeout(0.25);
        handle_input();
        apply_pending();
      }
    }
    save();
    return 0;
  }

  std::filesystem::file_time_type modified() const {
    std::error_code ec;
    return std::filesystem::last_write_time(r_.scene, ec);
  }

  void write_camera(const std::string& path) {
    write_bytes_atomically(path, "camera settings", [&] {
      const std::string text = view_->settings_text();
      return std::vector<uint8_t>(text.begin(), text.end());
    }());
    std::printf("view: wrote the camera to %s (render it with -c %s)\n", path.c_str(), path.c_str());
  }

  // S, Esc and closing the window: the image shown (its colour) as `render`
  // writes it (PNG and the EXR with the render's identity, resumable with
  // `render --resume`), and the camera file that reproduces the view.
  void save() {
    if (acc_.reached() == 0) {
      std::printf("view: no samples yet, nothing saved\n");
      return;
    }
    std::string png = r_.output;
    if (png.empty()) {
      std::time_t now = std::time(nullptr);
      std::tm t = *std::localtime(&now);
      char name[64];
      std::snprintf(name, sizeof name, "_screenshot_%d-%d_%d-%d-%d.png", t.tm_mon + 1, t.tm_mday, t.tm_hour, t.tm_min, t.tm_sec);
      png = scene_stem(r_.scene) + name;
    }
    const std::filesystem::path base = std::filesystem::path(png).replace_extension("");
    const std::string exr = base.string() + ".exr", camera = base.string() + "_cam_settings.txt";
    RenderRecord record;
    record.sceneHash = scene_content_hash(scene_);
    record.settings = render_settings(*compiled_);
    record.version = wavepath_version();
    record.renderer = variant_ + " in the window";
    record.samples = format_sample_ranges({{0, acc_.reached()}});
    const bool complete = acc_.done();
    record.status = complete ? "complete" : "stopped in the window";
    write_exr(exr, image_, record, !complete);
    write_image(png, mean_rgb(image_), compiled_->eightBitCurve);
    write_camera(camera);
    if (compiled_->adaptive.enabled()) write_sample_rate_png(base.string() + "_rate.png", image_, int(acc_.target()));
    // The command line that renders this view, as the window renders it.
    RenderArgs again = r_;
    again.output.clear();
    again.cameraSettings = camera;
    again.spp = int(acc_.target());
    again.maxBounces = bounces_;
    again.integrator = hemisphere_ ? "path tracer hemisphere" : r_.integrator;
    if (lightSamples_ > 0) again.lightSamples = lightSamples_;
    again.cell = cell_;
    again.aperture = scene_.camera.apertureRadius;
    again.focusDistance = scene_.camera.focusDistance;
    if (!complete) again.resume = exr;
    std::printf("view: wrote %s and %s (%u of %u samples per pixel)\n", png.c_str(), exr.c_str(), acc_.reached(), acc_.target());
    std::printf("view: %s with: %s\n", complete ? "render it again" : "finish it", cli::render_command_line(again).c_str());
  }

  ViewerArgs args_;
  RenderArgs r_;
  Scene scene_;
  std::unique_ptr<Scene> previousScene_;  // the scene before a reload, until the reload compiles
  std::unique_ptr<ViewCamera> view_;
  std::unique_ptr<VulkanContext> ctx_;
  std::string variant_;  // --variant, or the window's device's default
  std::unique_ptr<Presenter> presenter_;
  std::unique_ptr<CompiledScene> compiled_;
  std::unique_ptr<WavefrontRenderer> renderer_;
  ImageStats image_;
  std::vector<uint8_t> shownBytes_;    // the image rendered, 8-bit
  std::vector<uint8_t> displayBytes_;  // the frame shown (compose)
  std::vector<uint8_t> backdrop_;      // the frame under the cell
  bool cellMode_ = false, dragging_ = false;
  std::vector<int> cell_;  // X Y DX DY of the cell rendered, rows from the bottom (-p's); empty: the whole frame
  glm::dvec2 cellFrom_{0.0}, cellTo_{0.0};
  GLFWwindow* window_ = nullptr;
  Input input_;
  ViewAccumulation acc_{1, false};
  int bounces_ = -1, lightSamples_ = 0;
  bool hemisphere_ = false, quit_ = false, reload_ = false, shown_ = false;
  bool pendingRebuild_ = false, pendingRestart_ = false;
  size_t layer_ = 0;
  double exposure_ = 0.0;
  std::chrono::steady_clock::time_point opened_, started_, finished_, lastCheck_;
  std::filesystem::file_time_type lastWrite_;
  uint64_t frames_ = 0, samplesRendered_ = 0;
  double renderSeconds_ = 0.0;
};

}  // namespace

int run_viewer(const ViewerArgs& args) { return Viewer(args).run(); }

}  // namespace wp
