// load_scene.h — darts JSON scenes (Dartmouth CS 87/287 schema, see
// docs/scene-format.md). Every problem is an InputError naming the file and
// the JSON path (or line and column for syntax errors).
#pragma once

#include <string>

#include "scene/scene.h"

namespace wp {

Scene load_scene(const std::string& path);

}  // namespace wp
