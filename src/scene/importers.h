// importers.h — one function per scene format, each producing the
// format-neutral Scene (scene.h). load_scene (load_scene.h) picks one by the
// file's extension and content. Every importer reports a problem as an
// InputError naming the file, the place (line:column or a JSON path) and the
// problem.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace wp {

// Dartmouth CS 87 "darts" JSON scenes, with OBJ meshes (docs/scene-format.md).
Scene import_darts(const std::string& path);

// glTF 2.0, .gltf or .glb (docs/scene-format.md, "glTF 2.0").
Scene import_gltf(const std::string& path);

// Berkeley CS184's COLLADA scenes, .dae, with the course's conventions
// (docs/scene-format.md, "CS184").
Scene import_collada(const std::string& path);

// Points `camera` as a CS184 camera settings file says (the file the
// course's viewer writes with D, camera.cpp's dump_settings): position,
// orientation and both fields of view. The lens stays as it is, as the
// course's renderer sets it from the command line.
void apply_cs184_camera_settings(const std::string& path, Camera& camera);
// The 30 numbers of a CS184 camera settings file, in the file's order.
std::vector<double> read_cs184_camera_settings(const std::string& path);
// The same from those numbers (`where` names them in errors): what `render
// -c` makes of a file, so a view written as one renders the same.
void apply_cs184_camera_settings(const std::vector<double>& values, Camera& camera, const std::string& where);

// CS184 scenes read physically (render --consistent-lights): area lights
// become one-sided emissive quads that rays meet, emissive surfaces light
// the scene, and the estimator is wavepath's own (docs/scene-format.md).
void use_consistent_lights(Scene& scene);

// CS184 scenes as the 3-2 skeleton builds them (render --cs184 3-2), the
// course's renderer students of project 3-2 compare against: emissive meshes
// emit nothing, and every area light is also a one-sided quad that rays
// meet, emitting its radiance over its area times the cosine and absorbing
// what reaches it (docs/scene-format.md cites the skeleton's lines).
void use_cs184_3_2_skeleton(Scene& scene);

}  // namespace wp
