// load_scene.h — a scene file of any format wavepath reads, as a Scene.
#pragma once

#include <string>

#include "scene/scene.h"

namespace wp {

// The formats load_scene tells apart.
enum class SceneFormat { Darts, Gltf, Collada, Unknown };

// The format of a file with this name whose first bytes are `head`: by
// content where it is telling (a JSON object), else by extension.
SceneFormat scene_format(const std::string& path, const std::string& head);

// Loads `path` with the importer of its format (importers.h). Throws
// InputError naming the file and the problem; an unreadable or unknown file
// too.
Scene load_scene(const std::string& path);

// What the command line's --env asks of `scene`'s surroundings: "" leaves
// the scene's own, "none" a black background, "sky" the uniform white sky
// of radiance 1, anything else an equirectangular image file. Where the
// scene renders under the default sky its importer added for want of a
// light (Scene::defaultSky), one line on stderr says so.
void apply_environment(Scene& scene, const std::string& env);

}  // namespace wp
