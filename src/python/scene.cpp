// load() and Scene: a scene file read once, with the command line's
// overrides, whose camera and render settings change between renders.
#include <chrono>
#include <sstream>

#include "cli/render_args.h"
#include "job/scene_info.h"
#include "python/bindings.h"
#include "render/compiled_scene.h"
#include "scene/load_scene.h"
#include "scene/transform.h"

namespace wp::python {

namespace {

// The option a keyword names: resolution -> --resolution, max_bounces -> --max-bounces.
std::string option_name(const std::string& keyword) {
  std::string name = "--" + keyword;
  for (char& c : name)
    if (c == '_') c = '-';
  return name;
}

// The overrides' names, for the TypeError of a name that is none.
std::string override_names(CLI::App& app) {
  std::string names;
  for (const CLI::Option* o : app.get_options()) {
    if (o->get_lnames().empty()) continue;
    std::string n = o->get_lnames()[0];
    for (char& c : n)
      if (c == '-') c = '_';
    names += (names.empty() ? "" : ", ") + n;
  }
  return names;
}

// The overrides that change what the file holds, which a new value loads again.
bool same_content(const RenderArgs& a, const RenderArgs& b) {
  return a.consistentLights == b.consistentLights && a.cs184Skeleton == b.cs184Skeleton &&
         a.flattenInstances == b.flattenInstances && a.environment == b.environment;
}

// The file `env` names, if it names one ("none" and "sky" do not).
std::string environment_file(const RenderArgs& a) { return a.environment == "none" || a.environment == "sky" ? "" : a.environment; }

std::shared_ptr<PyScene> load(const py::object& path, const py::kwargs& overrides) {
  auto s = std::make_shared<PyScene>();
  s->args.scene = path_of(path);
  s->args = parse_overrides(s->args, overrides, "load");
  const RenderArgs& a = s->args;
  reading_files({a.scene, environment_file(a), a.cameraSettings}, [&] {
    if (a.resolution.size() == 2) check_image_fits_host(a.resolution[0], a.resolution[1], a.aovs);
    const auto t0 = std::chrono::steady_clock::now();
    s->scene = load_scene_content(a);
    s->fileCamera = s->scene.camera;
    apply_camera_overrides(s->scene, a);
    apply_environment(s->scene, a.environment);
    s->loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  });
  return s;
}

// Applies `overrides` to the scene: its camera and settings as they are, a
// new environment or lights' reading by loading the file again. On an
// error the scene stays as it was.
void set(PyScene& s, const py::kwargs& overrides) {
  RenderArgs now;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(s.mutex);
    now = s.args;
  }
  const RenderArgs next = parse_overrides(now, overrides, "Scene.set");
  reading_files({environment_file(next), next.cameraSettings}, [&] {
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!same_content(s.args, next)) {
      Scene fresh = load_scene_content(next);
      const Camera fileCamera = fresh.camera;
      apply_camera_overrides(fresh, next);
      apply_environment(fresh, next.environment);
      s.scene = std::move(fresh);
      s.fileCamera = fileCamera;
    } else {
      const Camera was = s.scene.camera;
      s.scene.camera = s.fileCamera;
      try {
        apply_camera_overrides(s.scene, next);
      } catch (...) {
        s.scene.camera = was;
        throw;
      }
    }
    s.args = next;
  });
}

// One override through set(), for the properties' setters.
void set_one(PyScene& s, const char* name, const py::object& value) {
  py::kwargs k;
  k[name] = value;
  set(s, k);
}

template <class T>
T locked(PyScene& s, const std::function<T(const PyScene&)>& f) {
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(s.mutex);
  return f(s);
}

}  // namespace

RenderArgs parse_overrides(const RenderArgs& base, const py::kwargs& kwargs, const char* function) {
  RenderArgs args = base;
  bool hemisphere = false;
  CLI::App app{"wavepath"};
  app.set_help_flag();
  cli::add_scene_options(app, args, hemisphere);
  std::vector<std::string> argv;
  for (auto item : kwargs) {
    const std::string key = py::str(item.first);
    const py::handle value = item.second;
    const std::string name = option_name(key);
    if (!app.get_option_no_throw(name))
      throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" + key + "' (the overrides are the command line's: " +
                           override_names(app) + ")");
    if (value.is_none()) continue;
    if (py::isinstance<py::bool_>(value)) {
      if (value.cast<bool>()) argv.push_back(name);
      continue;
    }
    argv.push_back(name);
    if (py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) {
      for (const py::handle v : value) argv.push_back(py::str(v));
    } else if (py::hasattr(value, "__fspath__")) {
      argv.push_back(path_of(value));
    } else {
      argv.push_back(py::str(value));
    }
  }
  std::reverse(argv.begin(), argv.end());  // CLI11 takes them last first
  app.parse(argv);
  cli::apply_hemisphere_flag(args, hemisphere);
  options_from(args, args.seed);  // an unknown integrator or sampler, a bad adaptive setting: refused now, as the command line refuses them
  return args;
}

void bind_scene(py::module_& m) {
  py::class_<PyScene, std::shared_ptr<PyScene>> scene(m, "Scene", R"(A scene file loaded once, with the command line's overrides.

Its camera, resolution, samples per pixel, integrator and the other render
options change between renders without loading the file again: set(...)
takes the overrides load() takes, and the properties below set one each.)");
  m.def("load", &load, py::arg("path"),
        R"(load(path, **overrides) -> Scene

Reads a scene in any format the command line reads (darts JSON with OBJ
meshes, glTF 2.0 .gltf/.glb, CS184 COLLADA .dae). The overrides are the
command line's render options, named as in Python: resolution=(W, H),
spp=N, max_bounces=N, integrator="path tracer nee", sampler="cmj",
aperture=R, focus_distance=D, light_samples=N, env="sky.hdr" or "none",
camera=NAME_OR_INDEX, camera_settings=FILE, cs184="3-2",
consistent_lights=True, hemisphere=True, adaptive=(BATCH, TOLERANCE),
flatten_instances=True, seed=N, device=..., variant=...

Raises FileNotFoundError for a missing file, ValueError with the command
line's message for bad input (the file, the line:column or JSON path, the
problem), TypeError for an unknown override.)");

  scene.def("set", &set, R"(set(**overrides)

Changes the overrides load() took (the same names). The camera's and the
render's take effect at once; env, consistent_lights, cs184 and
flatten_instances load the file again.)");
  scene.def(
      "look_at",
      [](PyScene& s, std::vector<float> origin, std::vector<float> target, std::vector<float> up, py::object fov) {
        if (origin.size() != 3 || target.size() != 3 || up.size() != 3) throw InputError("look_at: origin, target and up are 3 numbers each");
        const float vfov = fov.is_none() ? -1.0f : fov.cast<float>();
        if (!fov.is_none() && !(vfov > 0.0f && vfov < 180.0f)) throw InputError("look_at: fov is the vertical field in degrees, between 0 and 180");
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(s.mutex);
        // The pose replaces the file's camera; a named camera is no longer chosen.
        RenderArgs next = s.args;
        next.camera.clear();
        Camera c = s.fileCamera;
        c.toWorld = look_at(glm::vec3(origin[0], origin[1], origin[2]), glm::vec3(target[0], target[1], target[2]), glm::vec3(up[0], up[1], up[2]));
        if (vfov > 0.0f) c.vfovDegrees = vfov;
        Camera was = s.scene.camera;
        s.scene.camera = c;
        try {
          apply_camera_overrides(s.scene, next);
        } catch (...) {
          s.scene.camera = was;
          throw;
        }
        s.fileCamera = c;
        s.args = next;
      },
      py::arg("origin"), py::arg("target"), py::arg("up") = std::vector<float>{0.0f, 1.0f, 0.0f}, py::arg("fov") = py::none(),
      "look_at(origin, target, up=(0, 1, 0), fov=None): the camera at `origin` looking at `target` (darts' look-at), fov the vertical field in degrees");
  scene.def(
      "info",
      [](PyScene& s, const std::string& variant) {
        return locked<std::string>(s, [&](const PyScene& p) {
          const RenderOptions options = info_options(options_from(p.args, p.args.seed), variant);
          return scene_info(p.args.scene, p.scene, compile_scene(p.scene, options), p.loadSeconds);
        });
      },
      py::arg("variant") = "gpu",
      "info(variant='gpu') -> str: what `wavepath info` prints of the scene with its overrides (the BVH of `variant`, or 'cpu')");

  scene.def_property_readonly("path", [](PyScene& s) { return locked<std::string>(s, [](const PyScene& p) { return p.args.scene; }); });
  scene.def_property(
      "resolution",
      [](PyScene& s) {
        return locked<std::pair<int, int>>(s, [](const PyScene& p) { return std::make_pair(p.scene.camera.width, p.scene.camera.height); });
      },
      [](PyScene& s, const py::object& v) { set_one(s, "resolution", v); }, "(width, height) of the image");
  scene.def_property(
      "spp", [](PyScene& s) { return locked<int>(s, [](const PyScene& p) { return p.args.spp > 0 ? p.args.spp : p.scene.samplesPerPixel; }); },
      [](PyScene& s, const py::object& v) { set_one(s, "spp", v); }, "samples per pixel (the scene's sampler's unless set)");
  scene.def_property(
      "max_bounces",
      [](PyScene& s) {
        return locked<int>(s, [](const PyScene& p) { return p.args.maxBounces >= 0 ? p.args.maxBounces : p.scene.integrator.maxBounces; });
      },
      [](PyScene& s, const py::object& v) { set_one(s, "max_bounces", v); }, "maximum scattering events per path");
  scene.def_property(
      "integrator",
      [](PyScene& s) {
        return locked<std::string>(
            s, [](const PyScene& p) { return p.args.integrator.empty() ? integrator_kind_name(p.scene.integrator.kind) : p.args.integrator; });
      },
      [](PyScene& s, const py::object& v) { set_one(s, "integrator", v); }, "the integrator's darts name");
  scene.def_property(
      "sampler",
      [](PyScene& s) {
        return locked<std::string>(s, [](const PyScene& p) {
          return !p.args.sampler.empty() ? p.args.sampler : p.scene.sampler == SamplerKind::Cmj ? "cmj" : "independent";
        });
      },
      [](PyScene& s, const py::object& v) { set_one(s, "sampler", v); }, "independent or cmj");
  scene.def_property(
      "light_samples", [](PyScene& s) { return locked<int>(s, [](const PyScene& p) { return p.args.lightSamples; }); },
      [](PyScene& s, const py::object& v) { set_one(s, "light_samples", v); }, "next-event estimation samples per path vertex");
  scene.def_property(
      "aperture", [](PyScene& s) { return locked<float>(s, [](const PyScene& p) { return p.scene.camera.apertureRadius; }); },
      [](PyScene& s, const py::object& v) { set_one(s, "aperture", v); }, "the thin lens's radius");
  scene.def_property(
      "focus_distance", [](PyScene& s) { return locked<float>(s, [](const PyScene& p) { return p.scene.camera.focusDistance; }); },
      [](PyScene& s, const py::object& v) { set_one(s, "focus_distance", v); }, "the thin lens's focus distance");
  scene.def_property(
      "fov", [](PyScene& s) { return locked<float>(s, [](const PyScene& p) { return p.scene.camera.vfovDegrees; }); },
      [](PyScene& s, float fov) {
        if (!(fov > 0.0f && fov < 180.0f)) throw InputError("fov is the vertical field in degrees, between 0 and 180");
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(s.mutex);
        s.fileCamera.vfovDegrees = fov;
        s.scene.camera.vfovDegrees = fov;
      },
      "the camera's vertical field of view, in degrees");
  scene.def_property(
      "camera", [](PyScene& s) { return locked<std::string>(s, [](const PyScene& p) { return p.scene.camera.name; }); },
      [](PyScene& s, const py::object& v) { set_one(s, "camera", v); },
      "the name of the file's camera rendered through (a glTF file's, chosen by name or index)");
  scene.def_property_readonly("cameras", [](PyScene& s) {
    return locked<std::vector<std::string>>(s, [](const PyScene& p) {
      std::vector<std::string> names;
      for (const NamedCamera& c : p.scene.cameras) names.push_back(c.name.empty() ? std::to_string(c.index) : c.name);
      return names;
    });
  }, "the file's cameras (a glTF file's), which camera= chooses");
  scene.def("__repr__", [](PyScene& s) {
    return locked<std::string>(s, [](const PyScene& p) {
      std::ostringstream r;
      r << "<wavepath.Scene '" << p.args.scene << "' " << p.scene.camera.width << "x" << p.scene.camera.height << ", "
        << (p.args.spp > 0 ? p.args.spp : p.scene.samplesPerPixel) << " spp, " << p.scene.triangles.size() << " triangles, "
        << p.scene.spheres.size() << " spheres>";
      return r.str();
    });
  });
}

}  // namespace wp::python
