// viewer_impl.h — the window of `wavepath view` (viewer.h), shared by the
// files that implement it (src/view/): its life and render loop, saving
// (viewer.cpp), the input it reads and acts on (viewer_input.cpp), and the
// frame it shows (viewer_display.cpp; presenter.h puts it in the window).
// Not part of the viewer's interface.
#pragma once

#include <glm/glm.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "image/image.h"
#include "render/compiled_scene.h"
#include "scene/scene.h"
#include "view/accumulation.h"
#include "view/presenter.h"
#include "view/view_camera.h"
#include "view/viewer.h"

struct GLFWwindow;

namespace wp {

// What Tab shows, in turn; the AOVs by their layer names (layers.glsl).
const char* const kShownLayers[] = {"colour", "albedo", "normal", "depth", "variance", "samples"};
constexpr size_t kShownLayerCount = sizeof(kShownLayers) / sizeof(kShownLayers[0]);
inline bool is_aov(size_t layer) { return layer >= 1 && layer <= 3; }

// What the window's callbacks gathered since the viewer last looked
// (Viewer::handle_input).
struct WindowInput {
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

// The name the course gives files of this scene.
std::string scene_stem(const std::string& path);

class Viewer {
 public:
  explicit Viewer(const ViewerArgs& a) : args_(a), r_(a.render) {}

  int run();

 private:
  // viewer.cpp: the renderer's life, the render loop, saving.
  RenderOptions options() const;
  void rebuild();
  void restart();
  void apply_pending();
  int loop();
  std::filesystem::file_time_type modified() const;
  void write_camera(const std::string& path);
  void save();

  // viewer_input.cpp: the window's input, and the view and render it changes.
  void install_callbacks();
  bool handle_input();
  void autofocus(double x, double y);
  glm::dvec2 frame_at(double x, double y) const;
  Camera viewed() const;
  void drag_cell(WindowInput& in, double toPixels);

  // viewer_display.cpp: the frame shown.
  void encode();
  void compose();
  void show();

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
  WindowInput input_;
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

}  // namespace wp
