// render(), read() and Render: a render as `wavepath render` runs it
// (plan_render, run_render_job), its images as NumPy arrays, and save() in
// the command line's formats.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "image/image_file.h"
#include "job/render_job.h"
#include "python/bindings.h"
#include "render/partial.h"

namespace wp::python {

namespace {

// Makes a NumPy array read-only: the arrays show what a render holds.
py::array read_only(py::array a) {
  a.attr("flags").attr("writeable") = false;
  return a;
}

// Row-major strides of `shape` in elements of `size` bytes.
std::vector<py::ssize_t> strides_of(const std::vector<py::ssize_t>& shape, size_t size) {
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t s = py::ssize_t(size);
  for (size_t i = shape.size(); i-- > 0;) {
    strides[i] = s;
    s *= shape[i];
  }
  return strides;
}

// An array owning `values` (moved, not copied): the capsule frees them with it.
py::array owning(std::vector<float>&& values, const std::vector<py::ssize_t>& shape) {
  auto* owned = new std::vector<float>(std::move(values));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return read_only(py::array(py::dtype::of<float>(), shape, strides_of(shape, sizeof(float)), owned->data(), free));
}

// An array viewing `values`, which `data` holds: the capsule keeps the
// render's data alive as long as the array (zero copies).
py::array viewing(const std::shared_ptr<const RenderData>& data, const std::vector<double>& values, const std::vector<py::ssize_t>& shape) {
  auto* keep = new std::shared_ptr<const RenderData>(data);
  py::capsule release(keep, [](void* p) { delete static_cast<std::shared_ptr<const RenderData>*>(p); });
  return read_only(py::array(py::dtype::of<double>(), shape, strides_of(shape, sizeof(double)), values.data(), release));
}

std::vector<py::ssize_t> image_shape(const ImageStats& image, size_t channels) {
  std::vector<py::ssize_t> shape{py::ssize_t(image.height), py::ssize_t(image.width)};
  if (channels > 0) shape.push_back(py::ssize_t(channels));
  return shape;
}

uint32_t render_spp(const RenderData& d) { return d.record.settings.empty() ? 0u : samples_of_settings(d.record.settings); }

// What the stop reason says of a KeyboardInterrupt, in the file's header.
constexpr const char* kInterrupted = "interrupted by KeyboardInterrupt";

// The Python side of a render's pass hooks: the progress callback and
// Ctrl-C (PyErr_CheckSignals), with the GIL taken for each.
struct PassState {
  py::object progress;
  SampleRange range;
  // What stopped the render: a KeyboardInterrupt (the samples done are
  // returned), or another exception of the callback or a signal handler
  // (raised once the render has stopped).
  std::optional<py::error_already_set> interrupt, error;

  void stop_for(py::error_already_set&& e) {
    if (e.matches(PyExc_KeyboardInterrupt)) interrupt = std::move(e);
    else error = std::move(e);
  }
  bool stopped() const { return interrupt || error; }
};

std::string stop_reason(PassState& st) {
  py::gil_scoped_acquire gil;
  if (!st.stopped() && PyErr_CheckSignals() != 0) st.stop_for(py::error_already_set());
  return st.interrupt ? kInterrupted : st.error ? "stopped by an exception" : "";
}

void report_progress(PassState& st, const std::vector<SampleRange>& sofar) {
  if (st.progress.is_none() || st.stopped()) return;
  uint64_t held = 0;
  for (SampleRange r : sofar) held += std::min(r.end, st.range.end) - std::min(std::max(r.begin, st.range.begin), std::min(r.end, st.range.end));
  py::gil_scoped_acquire gil;
  try {
    st.progress(st.range.size() ? double(held) / double(st.range.size()) : 1.0);
  } catch (py::error_already_set& e) {
    st.stop_for(std::move(e));
  }
}

// wavepath.DeviceLost, a RuntimeError (bind_render makes it).
PyObject* g_deviceLost = nullptr;

// Raises DeviceLost(message) with its `render` the samples kept (or None).
[[noreturn]] void raise_device_lost(const std::string& message, const py::object& kept) {
  py::object e = py::reinterpret_borrow<py::object>(g_deviceLost)(message);
  e.attr("render") = kept;
  PyErr_SetObject(g_deviceLost, e.ptr());
  throw py::error_already_set();
}

// What DeviceLost says: the device, what was kept, and how to finish.
std::string device_lost_message(const RenderOutcome& run, const RenderJob& job) {
  const std::string lost = "device lost: " + run.lostNames;
  if (run.imageBroken) return lost + ", part-way through a batch of adaptive samples, which no image records: no samples kept; render again";
  if (job.done.empty()) return lost + ", before a single pass was done: no samples kept; render again";
  std::vector<SampleRange> missing;
  for (SampleRange r : missing_ranges(job.done, job.range.end))
    if (r.end > job.range.begin) missing.push_back({std::max(r.begin, job.range.begin), r.end});
  std::string rest;
  for (SampleRange r : missing) rest += (rest.empty() ? "" : ", ") + std::string("samples=(") + std::to_string(r.begin) + ", " + std::to_string(r.end) + ")";
  return lost + ": kept samples " + format_sample_ranges(job.done) + " (of " + format_sample_ranges({job.range}) +
         ") in this exception's render; finish with a render of " + rest + ", as this one otherwise, and merge() the two";
}

PyRender render(const std::shared_ptr<PyScene>& scene, const py::object& device, const py::object& variant, const py::object& seed,
                const py::object& samples, const py::object& aov, const py::object& time, const py::object& progress,
                const py::object& threads) {
  RenderArgs a;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(scene->mutex);
    a = scene->args;
  }
  a.quiet = true;  // progress goes to the callback
  if (!device.is_none()) {
    const std::string d = py::str(device);
    a.cpu = d == "cpu";
    a.device = a.cpu ? "" : d;
  }
  if (!variant.is_none()) a.variant = py::str(variant);
  if (a.cpu && !a.variant.empty()) throw InputError("variant " + a.variant + ": a kernel variant, and the device is the CPU reference");
  if (!seed.is_none()) a.seed = seed.cast<uint32_t>();
  if (!threads.is_none()) a.threads = threads.cast<int>();
  if (py::isinstance<py::str>(aov)) {  // "albedo,depth", as --aov takes them
    std::stringstream names(aov.cast<std::string>());
    a.aovs.clear();
    for (std::string n; std::getline(names, n, ',');) a.aovs.push_back(n);
  } else if (!aov.is_none()) {
    a.aovs = aov.cast<std::vector<std::string>>();
  }
  if (py::isinstance<py::tuple>(samples) || py::isinstance<py::list>(samples)) {
    const std::vector<long long> r = samples.cast<std::vector<long long>>();
    if (r.size() != 2) throw InputError("samples: a range (A, B) of two numbers");
    a.samples = std::to_string(r[0]) + ":" + std::to_string(r[1]);
  } else if (!samples.is_none()) {
    a.samples = py::str(samples);
  }
  RenderControl control;
  if (py::isinstance<py::str>(time)) {
    a.time = py::str(time);
    control.budgetSeconds = parse_duration(a.time, "time");
  } else if (!time.is_none()) {
    control.budgetSeconds = time.cast<double>();
    if (!(control.budgetSeconds > 0.0) || !std::isfinite(control.budgetSeconds)) throw InputError("time: the budget must be a positive number of seconds");
    char text[32];
    std::snprintf(text, sizeof text, "%gs", control.budgetSeconds);
    a.time = text;
  }
  control.budgetText = a.time;
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) throw py::type_error("progress: a callable taking the fraction done");

  PassState st;
  st.progress = progress;
  control.stopReason = [&st] { return stop_reason(st); };
  control.afterPass = [&st](const ImageStats&, const std::vector<SampleRange>& sofar) { report_progress(st, sofar); };
  auto data = std::make_shared<RenderData>();
  bool stoppedEmpty = false;
  std::string deviceLost;  // DeviceLost's message, where the device was lost
  bool lostAll = false;    // and nothing was kept
  {
    py::gil_scoped_release release;
    RenderJob job;
    {
      std::lock_guard<std::mutex> lock(scene->mutex);
      check_image_fits_host(scene->scene.camera.width, scene->scene.camera.height, a.aovs);
      control.start = std::chrono::steady_clock::now();
      job = plan_render(scene->scene, a);
    }
    st.range = job.range;
    try {
      const RenderOutcome run = run_render_job(job, a, control);
      if (run.deviceLost) {
        deviceLost = device_lost_message(run, job);
        lostAll = run.imageBroken || job.done.empty();
      }
      data->image = std::move(job.image);
      data->record = job.record;
      data->ranges = job.done;
      data->saveExactSums = keeps_exact_sums(a, run.complete);
      data->where = run.where;
      data->seconds = run.seconds;
      data->times = run.times;
    } catch (const RenderError&) {
      // Stopped before a single pass: the KeyboardInterrupt or the
      // callback's exception is raised instead, as no samples are left to return.
      if (!st.stopped()) throw;
      stoppedEmpty = true;
    }
  }
  if (st.error) throw std::move(*st.error);
  // A lost device is an error, as the command line's exit status says,
  // which carries the samples done (a KeyboardInterrupt returns them).
  if (!deviceLost.empty()) raise_device_lost(deviceLost, lostAll ? py::none() : py::cast(make_render(data)));
  if (stoppedEmpty) throw std::move(*st.interrupt);
  if (!progress.is_none() && data->record.status == "complete") progress(1.0);
  return make_render(data);
}

std::shared_ptr<const RenderData> read(const py::object& path) {
  const std::string p = path_of(path);
  auto data = std::make_shared<RenderData>();
  reading_files({p}, [&] {
    data->image = read_exr(p, &data->record);
    data->sumsExact = data->saveExactSums = data->record.exactSums;
    if (!data->record.samples.empty()) data->ranges = parse_sample_ranges(data->record.samples, p + ": wavepath:samples");
  });
  return data;
}

void save(const PyRender& r, const py::object& path, const py::object& exactSums) {
  const std::string p = path_of(path);
  const RenderData& d = *r.data;
  const bool sums = exactSums.is_none() ? d.saveExactSums : exactSums.cast<bool>();
  std::string failed;
  {
    py::gil_scoped_release release;
    std::optional<ImageFormat> format = image_format_of(p);
    if (!format) throw InputError(p + ": the output image's extension must name one of " + image_format_names());
    require_output_directory(p);
    try {
      if (*format == ImageFormat::Exr) {
        write_exr(p, d.image, d.record, sums);
      } else {
        write_image(p, mean_rgb(d.image), eight_bit_curve_named(render_setting(d.record.settings, "png")));
      }
    } catch (const RenderError& e) {  // the write failed (a full disk): the file before, if any, is as it was
      failed = e.what();
    }
  }
  if (!failed.empty()) {
    PyErr_SetString(PyExc_OSError, failed.c_str());
    throw py::error_already_set();
  }
}

}  // namespace

PyRender make_render(std::shared_ptr<const RenderData> data) {
  PyRender r;
  r.data = std::move(data);
  return r;
}

void bind_render(py::module_& m) {
  py::class_<PyRender> cls(m, "Render", R"(A render: the image as per-pixel statistics, and what it is.

mean, variance (H, W, 3 float32, linear), count (H, W float64), aov[name] and
the exact sums (sum, sum_sq: H, W, channels float64) are read-only NumPy
arrays that outlive the Render. See docs/python.md for which are views.)");

  g_deviceLost = py::module_::import("builtins")
                     .attr("type")("DeviceLost", py::make_tuple(py::handle(PyExc_RuntimeError)),
                                   py::dict(py::arg("__module__") = "wavepath",
                                            py::arg("__doc__") = "The render's Vulkan device was lost (VK_ERROR_DEVICE_LOST): a RuntimeError "
                                                                 "whose render attribute holds the samples of the passes that ended, marked "
                                                                 "partial (None where none did).",
                                            py::arg("render") = py::none()))
                     .release()
                     .ptr();
  m.attr("DeviceLost") = py::handle(g_deviceLost);

  m.def("render", &render, py::arg("scene"), py::arg("device") = py::none(), py::arg("variant") = py::none(), py::arg("seed") = py::none(),
        py::arg("samples") = py::none(), py::arg("aov") = py::tuple(), py::arg("time") = py::none(),
        py::arg("progress") = py::none(), py::arg("threads") = py::none(),
        R"(render(scene, device=None, variant=None, seed=None, samples=None, aov=(), time=None, progress=None, threads=None) -> Render

Renders as `wavepath render` does, with the GIL released. device: a Vulkan
device's index or part of its name, or "cpu" for the CPU reference (default:
the scene's, else the first suitable device); variant: a kernel variant
(default: the device's); seed (default: the scene's, 0); samples: (A, B) or
"A:B", samples A to B-1 of every pixel of the render of scene.spp samples;
aov: layers among "albedo", "normal", "depth"; time: a budget in seconds (or
"90s", "5m"), whole passes until it is spent; progress: called with the
fraction done between passes; threads: the CPU reference's.

Ctrl-C (KeyboardInterrupt) stops the render at the end of its pass and
returns the samples done, marked partial. Bad input raises ValueError, a
device failure RuntimeError; a lost device raises DeviceLost (a
RuntimeError) whose render holds the samples done, marked partial.)");

  m.def("read", [](const py::object& path) { return make_render(read(path)); }, py::arg("path"),
        "read(path) -> Render: an EXR that `wavepath render` or save() wrote, with the record in its header (a partial render's exact sums)");

  cls.def(
      "save", &save, py::arg("path"), py::arg("exact_sums") = py::none(),
      R"(save(path, exact_sums=None): writes the image in the format of the path's extension, as the command line's -o does
(PNG, JPEG, BMP, TGA: 8-bit in the scene format's curve; HDR, PFM: linear; EXR: the render's EXR with its record).
An EXR keeps the exact sums a merge or resume needs where the command line's would (a part, a budgeted or
stopped render; any merge or file read with them) unless exact_sums says otherwise.
A write that fails (a full disk) raises OSError naming the file and the error; a file there before is left as it was.)");
  cls.def_property_readonly("mean", [](PyRender& r) {
    if (!r.mean) r.mean = owning(std::move(mean_rgb(r.data->image).rgb), image_shape(r.data->image, 3));
    return r.mean;
  }, "(H, W, 3) float32: the mean colour, linear (the EXR's R, G, B); one copy, made once");
  cls.def_property_readonly("variance", [](PyRender& r) {
    if (!r.variance) {
      const ImageStats& im = r.data->image;
      std::vector<float> v(im.pixels() * 3);
      for (size_t p = 0; p < im.pixels(); ++p) {
        const glm::dvec3 s = im.variance(p);
        for (int c = 0; c < 3; ++c) v[3 * p + size_t(c)] = float(s[c]);
      }
      r.variance = owning(std::move(v), image_shape(im, 3));
    }
    return r.variance;
  }, "(H, W, 3) float32: the per-pixel sample variance of one sample (the EXR's var.R, ...); that of the mean is it over count");
  cls.def_property_readonly("count", [](PyRender& r) { return viewing(r.data, r.data->image.count, image_shape(r.data->image, 0)); },
                               "(H, W) float64: the samples of each pixel (a view of the render's buffer)");
  cls.def_property_readonly("sum", [](PyRender& r) { return viewing(r.data, r.data->image.sum, image_shape(r.data->image, r.data->image.stride)); },
                               "(H, W, C) float64: each channel's sum over the samples (a view; channels names them)");
  cls.def_property_readonly("sum_sq", [](PyRender& r) {
    return viewing(r.data, r.data->image.sumSq, image_shape(r.data->image, r.data->image.stride));
  }, "(H, W, C) float64: each channel's sum of squares (a view)");
  cls.def_property_readonly("channels", [](PyRender& r) {
    std::vector<std::string> names;
    for (const ImageLayer& l : r.data->image.layers)
      for (const std::string& c : l.channels) names.push_back(l.name == "color" ? c : l.name + "." + c);
    return names;
  }, "the names of sum's and sum_sq's channels: R, G, B, Y (illuminance), then LAYER.CHANNEL of each AOV");
  cls.def_property_readonly("aov", [](PyRender& r) {
    if (!r.aov) {
      py::dict layers;
      const ImageStats& im = r.data->image;
      for (size_t li = 1; li < im.layers.size(); ++li) {
        const ImageLayer& l = im.layers[li];
        std::vector<float> v(im.pixels() * l.channels.size());
        for (size_t p = 0; p < im.pixels(); ++p)
          for (size_t c = 0; c < l.channels.size(); ++c) v[p * l.channels.size() + c] = float(im.layer_mean(p, l, c));
        layers[py::str(l.name)] = owning(std::move(v), image_shape(im, l.channels.size()));
      }
      r.aov = py::module_::import("types").attr("MappingProxyType")(layers);
    }
    return r.aov;
  }, "the AOV layers rendered, name to (H, W, C) float32 mean as the EXR stores it: albedo (R, G, B), normal (X, Y, Z), depth (Z over the samples that hit, inf where none; A their fraction)");
  cls.def_property_readonly("width", [](PyRender& r) { return r.data->image.width; });
  cls.def_property_readonly("height", [](PyRender& r) { return r.data->image.height; });
  cls.def_property_readonly("spp", [](PyRender& r) { return render_spp(*r.data); }, "samples per pixel of the whole render");
  cls.def_property_readonly("samples", [](PyRender& r) {
    std::vector<std::pair<uint32_t, uint32_t>> out;
    for (SampleRange s : r.data->ranges) out.push_back({s.begin, s.end});
    return out;
  }, "the ranges (A, B) of samples every pixel holds");
  cls.def_property_readonly("partial", [](PyRender& r) {
    const std::vector<SampleRange>& h = r.data->ranges;
    return !(h.size() == 1 && h[0].begin == 0 && h[0].end == render_spp(*r.data));
  }, "True unless it holds every sample of the render (0 to spp): a range of them, or a render stopped early (Ctrl-C, a time budget)");
  cls.def_property_readonly("status", [](PyRender& r) { return r.data->record.status; },
                               "complete, or why it stopped early (the EXR's wavepath:status)");
  cls.def_property_readonly("renderer", [](PyRender& r) { return r.data->record.renderer; }, "what rendered it");
  cls.def_property_readonly("settings", [](PyRender& r) { return r.data->record.settings; },
                               "the settings that change the image, key=value; ... (the EXR's wavepath:settings)");
  cls.def_property_readonly("scene_hash", [](PyRender& r) { return r.data->record.sceneHash; });
  cls.def_property_readonly("seconds", [](PyRender& r) { return r.data->seconds; }, "wall time of the rendering (0 for a merge or a file)");
  cls.def_property_readonly("non_finite", [](PyRender& r) { return r.data->image.nonFinite; }, "NaN or infinite samples dropped");
  cls.def_property_readonly("stage_times", [](PyRender& r) {
    py::dict d;
    const StageTimes& t = r.data->times;
    for (int s = 0; s < StageTimes::kStages; ++s)
      if (t.dispatches[s] > 0) d[StageTimes::kNames[s]] = t.seconds[s];
    return d;
  }, "GPU seconds per kernel stage (a GPU render; empty otherwise)");
  cls.def("__repr__", [](PyRender& r) {
    const RenderData& d = *r.data;
    std::ostringstream s;
    s << "<wavepath.Render " << d.image.width << "x" << d.image.height << ", samples " << d.record.samples << " of " << render_spp(d) << ", "
      << d.record.status << (d.record.renderer.empty() ? "" : ", " + d.record.renderer) << ">";
    return s.str();
  });
}

}  // namespace wp::python
