#include "scene/load_scene.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "scene/importers.h"
#include "util/error.h"
#include "util/files.h"

namespace wp {

namespace fs = std::filesystem;

SceneFormat scene_format(const std::string& path, const std::string& head) {
  const std::string ext = lower_extension(path);
  // Content first: binary glTF by its magic; a JSON object is a darts scene
  // whatever its name says, unless the name says glTF (which is JSON too).
  if (head.compare(0, 4, "glTF") == 0) return SceneFormat::Gltf;
  if (ext == ".gltf" || ext == ".glb") return SceneFormat::Gltf;  // its importer reports what is wrong with it
  if (ext == ".dae" || head.find("<COLLADA") != std::string::npos) return SceneFormat::Collada;
  auto first = std::find_if(head.begin(), head.end(), [](unsigned char c) { return !std::isspace(c); });
  if (first != head.end() && *first == '{') return SceneFormat::Darts;
  if (ext == ".json") return SceneFormat::Darts;
  return SceneFormat::Unknown;
}

Scene load_scene(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open scene file (" + (fs::exists(path) ? "permission denied" : "no such file") + ")");
  std::string head(256, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  Scene scene;
  switch (scene_format(path, head)) {
    case SceneFormat::Darts: scene = import_darts(path); break;
    case SceneFormat::Gltf: scene = import_gltf(path); break;
    case SceneFormat::Collada: scene = import_collada(path); break;
    case SceneFormat::Unknown:
      throw InputError(path + ": not a scene file wavepath reads (expected a darts JSON scene, .json; glTF 2.0, .gltf or .glb; or CS184 COLLADA, .dae)");
  }
  scene.inputFiles.insert(scene.inputFiles.begin(), path);
  return scene;
}

void apply_environment(Scene& scene, const std::string& env) {
  if (env == "none") {
    scene.environment = WP_INVALID;
    scene.background = glm::vec3(0.0f);
  } else if (env == "sky") {
    scene.environment = WP_INVALID;
    scene.background = glm::vec3(1.0f);
  } else if (!env.empty()) {
    scene.environment = add_image_texture(scene, env, "given by --env");
  }
  if (scene.defaultSky && env.empty())
    std::fprintf(stderr, "wavepath: %s: no light of its own worth the name, so it is lit by a uniform white sky of radiance 1 (--env none removes it)\n",
                 scene.sourcePath.c_str());
}

}  // namespace wp
