// render_args.h — what everything that renders as `wavepath render` does
// shares (the commands render, compare, convergence and view, and the
// Python module): a render's scene and options as the command line names
// them, the overrides those options make to a scene, and rendering on the
// CPU reference or a kernel variant, on one device or several.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gpu/wavefront.h"
#include "image/image.h"
#include "render/compiled_scene.h"
#include "scene/scene.h"

namespace wp {

struct RenderArgs {
  std::string scene;
  std::string output;
  std::string format;  // darts' -f FORMAT: the default output name's extension
  std::string exr;
  int spp = -1;
  int maxBounces = -1;
  uint32_t seed = 0;
  std::string device;
  bool cpu = false;
  int threads = 0;
  bool quiet = false;
  bool validation = false;
  std::vector<int> resolution;
  bool stageTimes = false;
  std::string variant;  // empty: the device's default (default_variant)
  std::string photonPass = "auto";  // who traces a GPU renderer's photon map: auto, kernels or host (PhotonPass)
  uint32_t tilePixels = 0;          // a GPU renderer's tiles: at most this many pixels (0: as the device allows)
  std::string integrator;  // darts integrator name, overriding the scene's
  std::string sampler;     // independent or cmj
  float aperture = -1.0f;  // lens radius, overriding the scene's (CS184 -b)
  float focusDistance = -1.0f;  // (CS184 -d)
  std::string environment;      // environment map replacing the background (CS184 -e)
  std::string camera;           // a glTF camera by name or index (default: the first)
  bool flattenInstances = false;  // place every instance's triangles in world space (no two-level BVH)
  std::string cameraSettings;   // a CS184 camera settings file (CS184 -c)
  std::vector<int> cell;        // X Y DX DY: render one cell of the frame, Y from the bottom (CS184 -p)
  bool consistentLights = false;  // CS184 scenes read physically (use_consistent_lights)
  std::string cs184Skeleton;      // CS184 scenes: "3-1" (default) or "3-2" (use_cs184_3_2_skeleton)
  std::vector<double> adaptive;  // batch, tolerance (CS184 -a)
  int lightSamples = 1;          // NEE samples per vertex (CS184 -l)
  std::vector<std::string> aovs;  // AOV layers (layers.glsl names)
  bool spectral = false;  // render spectrally, whatever the scene says (--spectral)
  bool rgb = false;       // render in RGB, whatever the scene says (--rgb)
  // Partial renders (render.cpp): a sample range "A:B", a time budget, a
  // checkpoint file and how often to write it, a partial file to resume.
  std::string samples;
  std::string time;
  std::string checkpoint;
  std::string checkpointEvery = "60s";
  std::string resume;
  // Several renderers in one process (render --devices): Vulkan device
  // indices or names (each running `variant`) and "cpu" for the reference.
  std::vector<std::string> devices;
};

// The render options the arguments ask for, with `seed`. Throws InputError
// for an unknown integrator or sampler or a bad adaptive setting.
RenderOptions options_from(const RenderArgs& a, uint32_t seed);

// The scene file with the arguments' overrides (resolution, lens, environment).
Scene load_scene_with_overrides(const RenderArgs& a);
// Its three parts, in its order: the scene file with the overrides of what
// it holds (its lights read physically or as CS184's 3-2 skeleton does,
// instances flattened); the overrides of its camera (which one, the
// resolution, a CS184 settings file, a cell, the lens) applied to
// scene.camera, the file's camera (the Python module's Scene applies them
// again to that camera when they change, without loading the file again);
// then the environment, apply_environment(scene, a.environment)
// (scene/load_scene.h), whose note on a default sky follows any error of
// the camera's.
Scene load_scene_content(const RenderArgs& a);
void apply_camera_overrides(Scene& scene, const RenderArgs& a);

// "90s", "1.5m", "2h", "45" (seconds) as seconds; throws InputError naming `option`.
double parse_duration(const std::string& text, const std::string& option);

// Throws InputError where a width x height render with `aovs` would need
// more memory than the host has: the image's double-precision sums, and
// the files written from them. (A device's own limits only tile it.)
void check_image_fits_host(int width, int height, const std::vector<std::string>& aovs);

// A GPU renderer's settings: the variant's, with the arguments' photon pass and tiles.
WavefrontSettings renderer_settings(const KernelVariant& variant, const RenderArgs& a);

// Renders with `renderer`: "cpu" (the reference) or a kernel variant ("gpu",
// "gpu-mega", ...) on the chosen Vulkan device. Sets *where to a description
// of what rendered it, and *times (if given) to the GPU's per-stage times.
ImageStats render_on(const std::string& renderer, const CompiledScene& compiled, const RenderArgs& a, std::string* where,
                     StageTimes* times = nullptr);
// The same for samples `range`, added to `image` (which may hold earlier
// samples), with `afterPass` called between passes; returns the sample
// reached (render_control.h).
uint32_t render_on(const std::string& renderer, const CompiledScene& compiled, const RenderArgs& a, ImageStats& image,
                   SampleRange range, const PassHook& afterPass, std::string* where, StageTimes* times = nullptr);

// One renderer of a render on several: the CPU reference or a kernel
// variant on a Vulkan device, with the scene compiled for it.
struct RenderDevice {
  std::string renderer;  // "cpu" or a kernel variant
  std::string device;    // Vulkan device selector ("" for the CPU)
  const CompiledScene* scene = nullptr;
};

// Called when a renderer of render_on_devices has added a chunk's sums to
// the image (under the lock that guards it): the image and the ranges done.
using ChunkHook = std::function<void(const ImageStats& image, const std::vector<SampleRange>& done)>;

// Renders the sample ranges `todo` on every device at once: chunks of
// samples, each renderer's first its own, the others dealt to whichever
// renderer is free, each chunk rendered into an
// image of its own and its sums added to `image` when it ends. `shouldStop`
// (checked between passes) ends every renderer at its pass's end; a chunk
// stopped part-way adds the samples it took. A device lost (DeviceLost)
// adds the samples of its chunk up to its last pass, and the others render
// the rest of its chunk and the chunks left; *lostDevices gets a line on
// each (its name, its chunk, what it kept). Returns the ranges done (with
// what `image` held before: `done`), joined where adjacent (gaps remain
// where every device was lost); *where names the renderers.
std::vector<SampleRange> render_on_devices(const std::vector<RenderDevice>& devices, const RenderArgs& a, ImageStats& image,
                                           std::vector<SampleRange> done, const std::vector<SampleRange>& todo,
                                           const std::function<bool()>& shouldStop, const ChunkHook& afterChunk,
                                           std::string* where, std::vector<std::string>* lostDevices);

// `ranges` sorted and joined where adjacent.
std::vector<SampleRange> join_ranges(std::vector<SampleRange> ranges);

}  // namespace wp
