// bindings.h — the Python module `wavepath` (docs/python.md): what its
// files share. The module calls the command line's own functions
// (src/job/, src/cli/render_args.cpp, the merge, comparison and benchmark
// code); nothing here renders, merges or compares by itself.
//
//   module.cpp  the module: errors as Python exceptions, the functions' registration
//   scene.cpp   load() and Scene: a scene file with the command line's overrides
//   render.cpp  render(), read() and Render: images as NumPy arrays, save()
//   tools.cpp   merge(), compare(), devices(), variants(), bench()
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gpu/wavefront.h"
#include "image/image.h"
#include "job/render_args.h"
#include "render/render_control.h"
#include "scene/scene.h"
#include "util/error.h"

namespace wp::python {

namespace py = pybind11;

// A scene file loaded with the command line's overrides. `scene` holds the
// file with the overrides of its content (lights, instances, environment)
// and of its camera; `fileCamera` is its camera before the camera's
// overrides, which Scene.set applies again to it, without loading the file.
struct PyScene {
  RenderArgs args;
  Scene scene;
  Camera fileCamera;
  double loadSeconds = 0.0;
  std::mutex mutex;  // guards the above between threads; taken without the GIL
};

// A render's image and what it is: a render's, a merge's, or a file's.
// Never changed once made, so NumPy arrays may view its buffers from any
// thread for as long as they live (each holds a reference).
struct RenderData {
  ImageStats image;
  RenderRecord record;               // identity, samples held, status, renderer
  std::vector<SampleRange> ranges;   // the samples of every pixel it holds, joined
  bool sumsExact = true;             // the sums are exact (a file's may be rebuilt from its floats): merge() takes it
  bool saveExactSums = true;         // save() writes the EXR's exact sums (a partial file)
  std::string where;                 // what rendered it ("" for a merge or a file)
  double seconds = 0.0;              // rendering (0 for a merge or a file)
  StageTimes times;                  // per stage, for a GPU render
};

// The Python Render: its data and the arrays made from it once asked for.
struct PyRender {
  std::shared_ptr<const RenderData> data;
  py::object mean, variance, aov;
};

// The render options of the command line (add_scene_options) that `kwargs`
// names, Python style (spp=4, resolution=(64, 64), max_bounces=8,
// integrator="path tracer nee", hemisphere=True), parsed by the command
// line's own parser into a copy of `base`. Throws TypeError for a name that
// is no option, InputError (ValueError) with the parser's message for a bad value.
RenderArgs parse_overrides(const RenderArgs& base, const py::kwargs& kwargs, const char* function);

// Runs `f` without the GIL. An InputError about a file of `paths` that does
// not exist becomes FileNotFoundError, carrying the command line's message.
template <class F>
auto reading_files(const std::vector<std::string>& paths, F&& f) -> decltype(f());
[[noreturn]] void raise_file_not_found(const std::string& path, const std::string& message);
bool is_missing(const std::string& path);

// A file-system path given as str or os.PathLike, as a string.
std::string path_of(const py::handle& path);

PyRender make_render(std::shared_ptr<const RenderData> data);

void bind_scene(py::module_& m);
void bind_render(py::module_& m);
void bind_tools(py::module_& m);

template <class F>
auto reading_files(const std::vector<std::string>& paths, F&& f) -> decltype(f()) {
  std::string missing, message;
  try {
    py::gil_scoped_release release;
    return f();
  } catch (const InputError& e) {
    for (const std::string& p : paths)
      if (missing.empty() && is_missing(p)) missing = p;
    if (missing.empty()) throw;
    message = e.what();
  }
  raise_file_not_found(missing, message);
}

}  // namespace wp::python
