// merge(), compare(), devices(), variants() and bench(): the command line's
// commands of those names, on Renders as well as files.
#include "bench/bench.h"
#include "gpu/vulkan_context.h"
#include "python/bindings.h"
#include "render/partial.h"
#include "report/html_report.h"
#include "stats/compare.h"

namespace wp::python {

namespace {

// A Render's or an EXR file's image for compare(): the Render's own (held,
// not copied) or the file's, and how the report names it.
struct Operand {
  std::shared_ptr<const RenderData> render;
  ImageStats read;
  std::string label;
  const ImageStats& image() const { return render ? render->image : read; }
};

Operand operand(const py::handle& x, const char* name) {
  Operand o;
  if (py::isinstance<PyRender>(x)) {
    o.render = x.cast<const PyRender&>().data;
    o.label = std::string(name) + ": " + (o.render->record.renderer.empty() ? "render" : o.render->record.renderer) + ", samples " +
              o.render->record.samples;
    return o;
  }
  const std::string path = path_of(x);
  o.read = reading_files({path}, [&] { return read_exr(path); });
  o.label = path;
  return o;
}

std::shared_ptr<const RenderData> merge(const py::iterable& renders, bool allowGaps) {
  // In memory, the parts' headers and images at once; `wavepath merge`
  // reads files a block of rows at a time, adding the same sums in the same order.
  std::vector<py::object> items;
  for (py::handle r : renders) items.push_back(py::reinterpret_borrow<py::object>(r));
  std::vector<std::shared_ptr<const RenderData>> inMemory(items.size());
  std::vector<std::string> paths(items.size());
  for (size_t i = 0; i < items.size(); ++i) {
    if (py::isinstance<PyRender>(items[i])) inMemory[i] = items[i].cast<const PyRender&>().data;
    else paths[i] = path_of(items[i]);
  }
  auto out = std::make_shared<RenderData>();
  reading_files(paths, [&] {
    PartialMerger merger;
    for (size_t i = 0; i < items.size(); ++i) {
      if (!inMemory[i]) {
        merger.add(read_partial(paths[i]));
        continue;
      }
      const RenderData& d = *inMemory[i];
      PartialFile part;
      part.path = "renders[" + std::to_string(i) + "]";
      if (d.record.sceneHash.empty() || d.record.settings.empty() || d.ranges.empty())
        throw InputError(part.path + ": not a partial render (it lacks wavepath's render record)");
      if (!d.sumsExact)
        throw InputError(part.path + ": not a partial render (read from a file without the exact sums a merge adds up)");
      part.image = d.image;
      part.width = d.image.width;
      part.height = d.image.height;
      part.aovs = d.image.aov_names();
      part.record = d.record;
      part.ranges = d.ranges;
      merger.add(std::move(part));
    }
    PartialFile merged = merger.finish(allowGaps);
    out->image = std::move(merged.image);
    out->record = merged.record;
    out->ranges = merged.ranges;
    out->saveExactSums = true;  // as `wavepath merge` writes its combined partial
  });
  return out;
}

CompareResult compare(const py::object& a, const py::object& b, double alpha, const py::object& report, const std::string& layer) {
  if (!(alpha >= 1e-12 && alpha <= 0.5)) throw InputError("alpha: the significance level must lie in [1e-12, 0.5]");
  Operand A = operand(a, "A"), B = operand(b, "B");
  const std::string dir = report.is_none() ? "" : path_of(report);
  py::gil_scoped_release release;
  CompareSettings settings;
  settings.alpha = alpha;
  auto run = [&](const ImageStats& x, const ImageStats& y) {
    CompareResult r = compare_images(x, y, settings);
    if (!dir.empty()) write_html_report(dir, x, y, r, ReportLabels{A.label + " vs " + B.label, A.label, B.label});
    return r;
  };
  if (layer == "color") return run(A.image(), B.image());
  return run(layer_as_color(A.image(), layer), layer_as_color(B.image(), layer));
}

py::list bench(const py::object& scenes, const py::object& variants, int spp, int repeats, const py::object& resolution, int checkSpp,
               const py::object& device, const std::string& mode) {
  BenchOptions o;
  if (scenes.is_none()) {
    o.scenes.push_back("scenes/cornell-box.json");
  } else if (py::isinstance<py::str>(scenes) || py::hasattr(scenes, "__fspath__")) {
    o.scenes.push_back(path_of(scenes));
  } else {
    for (py::handle s : scenes) o.scenes.push_back(path_of(s));
  }
  if (mode != "render" && mode != "raycast" && mode != "build" && mode != "simt")
    throw InputError("bench: mode is render, raycast, build or simt, not " + mode);
  if (variants.is_none() && mode == "simt") {
    o.variants = simt_variants();
  } else if (variants.is_none()) {
    for (const KernelVariant& v : kernel_variants()) o.variants.push_back(v.name);
  } else if (py::isinstance<py::str>(variants)) {
    o.variants.push_back(variants.cast<std::string>());
  } else {
    o.variants = variants.cast<std::vector<std::string>>();
  }
  if (spp < 1 || repeats < 1 || checkSpp < 1) throw InputError("bench: spp, repeats and check_spp must be at least 1");
  o.spp = spp;
  o.repeats = repeats;
  o.checkSpp = checkSpp;
  if (!resolution.is_none()) {
    o.resolution = resolution.cast<std::vector<int>>();
    if (o.resolution.size() != 2 || o.resolution[0] < 1 || o.resolution[1] < 1 || o.resolution[0] > MAX_IMAGE_SIZE || o.resolution[1] > MAX_IMAGE_SIZE)
      throw InputError("bench: resolution is (W, H), each 1 to " + std::to_string(MAX_IMAGE_SIZE));
  }
  if (!device.is_none()) o.device = py::str(device);
  o.raycast = mode == "raycast";
  o.build = mode == "build";
  o.simt = mode == "simt";
  std::string json;
  o.results = &json;
  reading_files(o.scenes, [&] {
    if (o.build) run_build_bench(o);
    else if (o.simt) run_simt_bench(o);
    else if (o.raycast) run_raycast_bench(o);
    else run_bench(o);
  });
  // The rows of the table the command prints, from the JSON document its
  // --out writes: one per scene and variant (raycast: and ray set; build: per scene).
  const py::object doc = py::module_::import("json").attr("loads")(json);
  py::list rows;
  if (o.build || o.simt) {  // simt: one per scene, ray set, variant and warp width, each naming its GPU model
    for (py::handle r : doc[o.build ? "build" : "simt"]) rows.append(r);
    return rows;
  }
  const py::object deviceName = doc["device"]["name"];
  if (o.raycast) {
    for (py::handle r : doc["raycast"]) {
      r["device"] = deviceName;
      rows.append(r);
    }
    return rows;
  }
  for (py::handle s : doc["scenes"]) {
    for (py::handle v : s["variants"]) {
      py::dict row;
      row["device"] = deviceName;
      for (auto item : s.cast<py::dict>())
        if (py::str(item.first).cast<std::string>() != "variants") row[item.first] = item.second;
      for (auto item : v.cast<py::dict>()) row[item.first] = item.second;
      rows.append(row);
    }
  }
  return rows;
}

}  // namespace

void bind_tools(py::module_& m) {
  m.def("merge", [](const py::iterable& renders, bool allowGaps) { return make_render(merge(renders, allowGaps)); }, py::arg("renders"),
        py::arg("allow_gaps") = false,
        R"(merge(renders, allow_gaps=False) -> Render

Adds partial renders (Renders of sample ranges of one render, or the partial
EXR files of them) up into the render of all their samples, exactly, as
`wavepath merge` does: refusing parts of other renders, overlapping parts,
and missing samples unless allow_gaps.)");

  py::class_<TileResult>(m, "Tile", "a tile of the comparison's tile test")
      .def_property_readonly("bounds", [](const TileResult& t) { return std::make_tuple(t.x0, t.y0, t.x1, t.y1); }, "(x0, y0, x1, y1), exclusive ends")
      .def_readonly("z", &TileResult::z)
      .def_readonly("p", &TileResult::p)
      .def_readonly("relative_bias", &TileResult::relativeBias)
      .def_readonly("failed", &TileResult::failed)
      .def("__repr__", [](const TileResult& t) {
        return "<wavepath.Tile (" + std::to_string(t.x0) + ", " + std::to_string(t.y0) + ")-(" + std::to_string(t.x1) + ", " +
               std::to_string(t.y1) + ") z " + std::to_string(t.z) + (t.failed ? " failed>" : ">");
      });
  py::class_<CompareResult>(m, "Comparison", "the verdict of compare() and the figures of its three tests (docs/comparison.md)")
      .def_property_readonly("passed", &CompareResult::passed, "the images estimate the same image: all three tests pass")
      .def("__bool__", &CompareResult::passed)
      .def_property_readonly("summary", &CompareResult::summary, "the line `wavepath compare` prints")
      .def("__str__", &CompareResult::summary)
      .def("__repr__", [](const CompareResult& r) { return "<wavepath.Comparison " + r.summary() + ">"; })
      .def_readonly("pixel_channels", &CompareResult::pixelChannels)
      .def_readonly("failing_pixel_channels", &CompareResult::failingPixelChannels)
      .def_readonly("pixel_pass_fraction", &CompareResult::pixelPassFraction)
      .def_readonly("pixel_test_passed", &CompareResult::pixelTestPassed)
      .def_readonly("mean_a", &CompareResult::meanA)
      .def_readonly("mean_b", &CompareResult::meanB)
      .def_readonly("mean_z", &CompareResult::meanZ)
      .def_readonly("mean_p", &CompareResult::meanP)
      .def_readonly("mean_test_passed", &CompareResult::meanTestPassed)
      .def_readonly("relative_bias", &CompareResult::relativeBias, "mean of A over mean of B, less 1")
      .def_readonly("relative_bias_ci95", &CompareResult::relativeBiasCi95, "the half-width of its 95 % interval")
      .def_readonly("tiles", &CompareResult::tiles)
      .def_readonly("failing_tiles", &CompareResult::failingTiles)
      .def_readonly("tile_test_passed", &CompareResult::tileTestPassed)
      .def("worst_tiles", &CompareResult::worst_tiles, py::arg("count") = 5)
      .def_property_readonly("z_map", [](const CompareResult& r) {
        // The last tile ends at the image's last row and column.
        const size_t width = r.tiles.empty() ? 0 : size_t(r.tiles.back().x1), height = r.tiles.empty() ? 0 : size_t(r.tiles.back().y1);
        py::array_t<float> z({height, width});
        if (width * height == r.zMap.size()) std::copy(r.zMap.begin(), r.zMap.end(), z.mutable_data());
        return z;
      }, "(H, W) float32: per pixel, the z of the channel with the largest |z| (a copy)");

  m.def("compare", &compare, py::arg("a"), py::arg("b"), py::arg("alpha") = 0.01, py::arg("report") = py::none(), py::arg("layer") = "color",
        R"(compare(a, b, alpha=0.01, report=None, layer="color") -> Comparison

Do two renders estimate the same image? a and b are Renders or EXR paths;
the tests are `wavepath compare`'s (per-pixel Welch, whole-image mean,
per-tile means; alpha each test's family-wise level). report: a directory
to write the HTML report to. layer: an AOV layer to compare instead.)");

  m.def(
      "devices",
      [] {
        std::vector<GpuDeviceInfo> list;
        {
          py::gil_scoped_release release;
          list = VulkanContext::list_devices(false);
        }
        py::list out;
        for (const GpuDeviceInfo& d : list) {
          py::dict row;
          row["index"] = d.index;
          row["name"] = d.name;
          row["type"] = d.type;
          row["driver"] = d.driver;
          row["vulkan"] = d.apiVersion;
          row["suitable"] = d.suitable;
          row["default_variant"] = default_variant(d).name;
          row["max_storage_buffer_bytes"] = d.maxStorageBufferRange;
          row["max_texel_buffer_elements"] = d.maxTexelBufferElements;
          row["subgroup_size"] = d.subgroupSize;
          row["device_local_bytes"] = d.deviceLocalMemory;
          row["ray_query"] = d.rayQuery;
          out.append(row);
        }
        return out;
      },
      "devices() -> list of dict: the Vulkan devices `wavepath devices` lists, each with its default kernel variant (empty without a Vulkan driver)");
  m.def(
      "variants",
      [] {
        py::dict out;
        for (const KernelVariant& v : kernel_variants()) out[py::str(v.name)] = v.description;
        return out;
      },
      "variants() -> dict: the kernel variants, name to description");
  m.def("bench", &bench, py::arg("scenes") = py::none(), py::arg("variants") = py::none(), py::arg("spp") = 4, py::arg("repeats") = 3,
        py::arg("resolution") = py::none(), py::arg("check_spp") = 64, py::arg("device") = py::none(), py::arg("mode") = "render",
        R"(bench(scenes=None, variants=None, spp=4, repeats=3, resolution=None, check_spp=64, device=None, mode="render") -> list of dict

Runs `wavepath bench` (mode "raycast": --raycast, "build": --build, "simt":
--simt, the SIMT model at its defaults) and returns the rows of its table, as
its --out JSON holds them: one per scene and variant (and ray set; simt: and
warp width), a variant that disagreed with the CPU reference with
check_passed False and no times. Defaults as the command's: the Cornell box,
every variant (simt: those whose walks differ). It also prints the table to
the process's stdout.)");
}

}  // namespace wp::python
