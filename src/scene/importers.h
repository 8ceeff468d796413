// importers.h — one function per scene format, each producing the
// format-neutral Scene (scene.h). load_scene (load_scene.h) picks one by the
// file's extension and content. Every importer reports a problem as an
// InputError naming the file, the place (line:column or a JSON path) and the
// problem.
#pragma once

#include <string>

#include "scene/scene.h"

namespace wp {

// Dartmouth CS 87 "darts" JSON scenes, with OBJ meshes (docs/scene-format.md).
Scene import_darts(const std::string& path);

// glTF 2.0, .gltf or .glb (docs/scene-format.md, "glTF 2.0").
Scene import_gltf(const std::string& path);

}  // namespace wp
