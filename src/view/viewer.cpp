// The window of `wavepath view`: GLFW for the window and input, a Vulkan
// swapchain on the renderer's own device and queue for presenting. The image
// shown is the render's: passes of the same kernels accumulate into the same
// ImageStats `render` writes, and each refresh copies its 8-bit encoding into
// the swapchain image (no second renderer, no raster preview). This file:
// the window's life, the render loop and saving; viewer_impl.h names the rest.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "view/viewer.h"

#include <algorithm>
#include <chrono>
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
#include "view/viewer_impl.h"

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

std::string scene_stem(const std::string& path) {
  // The course names its files after the scene: the text after the last '/'
  // up to its first ".dae" (main.cpp); wavepath after any extension.
  std::string name = std::filesystem::path(path).filename().string();
  size_t dae = name.find(".dae");
  return dae != std::string::npos ? name.substr(0, dae) : std::filesystem::path(path).stem().string();
}

int Viewer::run() {
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

RenderOptions Viewer::options() const {
  RenderArgs a = r_;
  a.spp = int(acc_.target());
  a.maxBounces = bounces_;
  a.integrator = hemisphere_ ? "path tracer hemisphere" : r_.integrator;
  a.lightSamples = lightSamples_ > 0 ? lightSamples_ : r_.lightSamples;
  return variant_options(options_from(a, a.seed), variant_);  // the variant's BVH layout
}

// A new renderer: the scene compiled again (kinds, integrator or light
// samples changed, or the file was reloaded).
void Viewer::rebuild() {
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
void Viewer::restart() {
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

// What the input asked for, once the renderer is between renders.
void Viewer::apply_pending() {
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

int Viewer::loop() {
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

std::filesystem::file_time_type Viewer::modified() const {
  std::error_code ec;
  return std::filesystem::last_write_time(r_.scene, ec);
}

void Viewer::write_camera(const std::string& path) {
  write_bytes_atomically(path, "camera settings", [&] {
    const std::string text = view_->settings_text();
    return std::vector<uint8_t>(text.begin(), text.end());
  }());
  std::printf("view: wrote the camera to %s (render it with -c %s)\n", path.c_str(), path.c_str());
}

// S, Esc and closing the window: the image shown (its colour) as `render`
// writes it (PNG and the EXR with the render's identity, resumable with
// `render --resume`), and the camera file that reproduces the view.
void Viewer::save() {
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

int run_viewer(const ViewerArgs& args) { return Viewer(args).run(); }

}  // namespace wp
