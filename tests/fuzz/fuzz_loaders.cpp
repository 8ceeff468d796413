#include "fuzz/fuzz_loaders.h"

#include <stb_image_write.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "render/compiled_scene.h"
#include "render/partial.h"
#include "render/shader_cpp.h"
#include "scene/darts_tests.h"
#include "scene/importers.h"
#include "scene/load_scene.h"
#include "scene/obj_mesh.h"
#include "scene/texture_image.h"
#include "util/error.h"

namespace wp {

namespace {

// The private folder, made once per process with the files a scene may name.
const std::filesystem::path& fuzz_folder() {
  static const std::filesystem::path folder = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "wavepath-fuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a temporary folder for fuzzed inputs");
    std::filesystem::path f(pattern);
    std::ofstream(f / "mesh.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n";
    // A scene whose camera sits in the medium of input.nvdb.
    std::ofstream(f / "grid.json") << R"({ "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] },
      "resolution": [2, 2], "medium": "m" }, "media": [ { "type": "nanovdb", "name": "m", "filename": "input.nvdb" } ],
      "surfaces": [ { "type": "sphere", "radius": 1, "material": { "type": "lambertian" } } ] })";
    const unsigned char texels[2 * 2 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    if (!stbi_write_png((f / "tex.png").c_str(), 2, 2, 3, texels, 2 * 3)) throw std::runtime_error("cannot write tex.png");
    return f;
  }();
  return folder;
}

std::string write_input(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = (fuzz_folder() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  if (!out) throw std::runtime_error("cannot write " + path);
  return path;
}

}  // namespace

FuzzedInput fuzzed_input_named(const std::string& name) {
  if (name == "scene") return FuzzedInput::Scene;
  if (name == "obj") return FuzzedInput::Obj;
  if (name == "image") return FuzzedInput::Image;
  if (name == "partial") return FuzzedInput::Partial;
  if (name == "gltf") return FuzzedInput::Gltf;
  if (name == "collada") return FuzzedInput::Collada;
  if (name == "nvdb") return FuzzedInput::Nvdb;
  throw std::invalid_argument("no fuzzed input kind named \"" + name + "\"");
}

bool load_fuzzed(FuzzedInput kind, const uint8_t* data, size_t size) {
  std::string path;
  try {
    switch (kind) {
      case FuzzedInput::Scene: {
        path = write_input("scene.json", data, size);
        RenderOptions options;
        options.spp = 1;
        if (is_darts_test_file(path)) {  // darts' test files: each test's scene, as wavepath test builds it
          for (const DartsTest& t : import_darts_tests(path))
            if (t.loadError.empty()) compile_scene(t.scene, options);
        } else {
          compile_scene(load_scene(path), options);
        }
        break;
      }
      case FuzzedInput::Obj:
        path = write_input("input.obj", data, size);
        load_obj(path);
        break;
      case FuzzedInput::Image: {
        // The name's extension matters: .exr goes to OpenEXR, .tga lets stb_image try TGA.
        const char* names[3] = {"input.png", "input.exr", "input.tga"};
        path = write_input(names[size > 0 ? data[0] % 3 : 0], size > 0 ? data + 1 : data, size > 0 ? size - 1 : 0);
        load_linear_image(path);
        break;
      }
      case FuzzedInput::Partial:
        path = write_input("part.exr", data, size);
        read_partial(path);
        break;
      case FuzzedInput::Gltf: {
        // Beside it, tex.png and mesh.obj: a fuzzed model may name them as URIs.
        const char* names[2] = {"input.gltf", "input.glb"};
        path = write_input(names[size > 0 ? data[0] % 2 : 0], size > 0 ? data + 1 : data, size > 0 ? size - 1 : 0);
        RenderOptions options;
        options.spp = 1;
        const CompiledScene cs = compile_scene(load_scene(path), options);
        // Rays through whatever the node tree built (instances' walks and
        // surfaces included), from inside and outside the scene's box.
        shader::SceneView view = cs.view();
        for (int i = 0; i < 16; ++i) {
          const glm::vec3 o = i < 8 ? glm::vec3(0.0f) : glm::vec3(float(i % 3) - 1.0f, float(i % 5) * 0.5f, 10.0f);
          const glm::vec3 d = glm::normalize(glm::vec3(float(i % 4) - 1.5f, float(i / 4) - 1.7f, i < 8 ? 1.0f : -1.0f));
          shader::Hit h;
          if (view.trace_ray(o, d, WP_INF, false, h) == TRACE_OK && h.prim != WP_INVALID) view.surface_at(o, d, h);
        }
        break;
      }
      case FuzzedInput::Collada: {
        path = write_input("input.dae", data, size);
        RenderOptions options;
        options.spp = 1;
        Scene scene = load_scene(path);
        compile_scene(scene, options);
        use_consistent_lights(scene);
        compile_scene(scene, options);
        break;
      }
      case FuzzedInput::Nvdb: {
        path = write_input("input.nvdb", data, size);
        RenderOptions options;
        options.spp = 1;
        CompiledScene cs = compile_scene(load_scene((fuzz_folder() / "grid.json").string()), options);
        // Lookups and majorant walks through whatever the grid holds: the
        // kernels' code reads it with PNanoVDB through bounded reads.
        shader::SceneView view = cs.view();
        shader::SceneView::MediumCoefficients c;
        const shader::Medium m = view.load_medium_at(1, glm::vec4(0.0f), c);
        uint32_t rng = 1;
        for (int i = 0; i < 16; ++i) {
          const glm::vec3 o(float(i % 4) - 1.5f, float(i / 4) - 1.5f, 3.0f);
          shader::Spectrum throughput(1.0f);
          float t;
          view.medium_free_flight(m, c, o, glm::normalize(glm::vec3(0.1f, 0.2f, -1.0f)), 6.0f, rng, throughput, t);
          view.medium_transmittance(m, c, o, glm::vec3(-0.2f, 0.1f, -1.0f), 6.0f, rng);
        }
        break;
      }
    }
  } catch (const InputError& e) {
    // The one line a user sees must say which file is wrong.
    if (std::string(e.what()).find(path) == std::string::npos)
      throw std::logic_error(std::string("an input error that does not name the file: ") + e.what());
    return false;
  }
  return true;
}

}  // namespace wp
