// gltf_cameras_lights.cpp — the glTF importer's cameras and
// KHR_lights_punctual lights, placed by their nodes, and the camera the
// render uses (gltf_importer.h).
#include <algorithm>
#include <cmath>

#include "scene/gltf_importer.h"

namespace wp::gltf_import {

namespace {

// Default image width; the height follows the camera's aspect ratio.
constexpr int kDefaultWidth = 800;

}  // namespace

// ---- cameras and lights --------------------------------------------------

void GltfImporter::add_camera(int index, const glm::mat4& toWorld, const std::string& where) {
  if (index >= int(model_.cameras.size())) fail(where, "names camera " + std::to_string(index) + ", which does not exist");
  const tinygltf::Camera& c = model_.cameras[size_t(index)];
  const std::string at = "/cameras/" + std::to_string(index);
  NamedCamera nc;
  nc.name = c.name.empty() ? std::to_string(index) : c.name;
  nc.index = index;
  if (c.type != "perspective" && c.type != "orthographic") {
    nc.problem = at + "/type: wavepath renders perspective and orthographic cameras, not \"" + c.type + "\"";
  } else {
    double aspect = 4.0 / 3.0;
    if (c.type == "perspective") {
      const double yfov = c.perspective.yfov;
      if (!(yfov > 0.0 && yfov < M_PI)) fail(at + "/perspective/yfov", "must lie between 0 and pi radians");
      if (c.perspective.aspectRatio > 0.0) aspect = c.perspective.aspectRatio;
      nc.camera.vfovDegrees = float(glm::degrees(yfov));
    } else {
      // xmag and ymag: half the width and height it sees (the image's
      // aspect follows them).
      const double xmag = c.orthographic.xmag, ymag = c.orthographic.ymag;
      if (!(xmag > 0.0 && xmag < 1e9)) fail(at + "/orthographic/xmag", "must be a positive number");
      if (!(ymag > 0.0 && ymag < 1e9)) fail(at + "/orthographic/ymag", "must be a positive number");
      nc.camera.orthoHalfHeight = float(ymag);
      aspect = xmag / ymag;
    }
    if (!(aspect > 1e-3 && aspect < 1e3)) fail(at + "/" + c.type + (c.type == "perspective" ? "/aspectRatio" : "/xmag"), "gives an aspect ratio outside 0.001 to 1000");
    nc.camera.width = kDefaultWidth;
    nc.camera.height = std::max(1, int(std::lround(kDefaultWidth / aspect)));
    // The node's rotation and translation; a camera ignores scale.
    glm::vec3 x = glm::normalize(glm::vec3(toWorld[0])), y = glm::vec3(toWorld[1]);
    glm::vec3 z = glm::normalize(glm::cross(x, y));
    y = glm::cross(z, x);
    if (!is_finite(x) || !is_finite(z) || !is_finite(glm::vec3(toWorld[3])))
      fail(where, "the node's transform does not place the camera (it is singular or not finite)");
    nc.camera.toWorld = glm::mat4(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(z, 0.0f), toWorld[3]);
    nc.camera.focusDistance = 1.0f;
  }
  nc.camera.name = nc.name;
  scene_.cameras.push_back(nc);
}

void GltfImporter::add_light(const tinygltf::Value& ext, const glm::mat4& toWorld, const std::string& where) {
  if (!ext.Has("light") || !ext.Get("light").IsInt()) fail(where, "names no light");
  const int index = ext.Get("light").GetNumberAsInt();
  if (index < 0 || index >= int(model_.lights.size())) fail(where + "/light", "names light " + std::to_string(index) + ", which does not exist");
  const tinygltf::Light& l = model_.lights[size_t(index)];
  const std::string at = "/extensions/KHR_lights_punctual/lights/" + std::to_string(index);
  ScenePointLight p;
  if (l.type == "spot") p.kind = ScenePointLight::Kind::Spot;
  else if (l.type == "directional") p.kind = ScenePointLight::Kind::Directional;
  else if (l.type != "point") fail(at + "/type", "unknown light type \"" + l.type + "\" (expected point, spot or directional)");
  const glm::vec3 color = factor3(l.color, glm::vec3(1.0f), at + "/color");
  if (!(l.intensity >= 0.0 && l.intensity < 1e9)) fail(at + "/intensity", "must be a number from 0 to 1e9");
  // Candela (lm/sr) to W/sr, lux (lm/m^2) to W/m^2, at the luminous
  // efficacy of 555 nm light.
  p.intensity = color * float(l.intensity / kLumensPerWatt);
  p.position = glm::vec3(toWorld[3]);
  // Spot and directional lights shine down their node's -Z axis.
  p.direction = glm::normalize(glm::vec3(toWorld * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
  if (!is_finite(p.position) || !is_finite(p.direction)) fail(where, "the node's transform does not place the light (it is singular or not finite)");
  if (p.kind == ScenePointLight::Kind::Spot) {
    const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner < outer && outer <= M_PI / 2))
      fail(at + "/spot", "needs 0 <= innerConeAngle < outerConeAngle <= pi / 2 (it has " + std::to_string(inner) + " and " +
                             std::to_string(outer) + ")");
    p.cosInner = float(std::cos(inner));
    p.cosOuter = float(std::cos(outer));
  }
  scene_.pointLights.push_back(p);
}

// The camera the render uses: the first camera of the tree,
// or one framing the scene's bounds (the command line may pick another).
void GltfImporter::default_camera() {
  for (const NamedCamera& c : scene_.cameras)
    if (c.problem.empty()) {
      scene_.camera = c.camera;
      return;
    }
  scene_.camera = framing_camera(scene_);
}

}  // namespace wp::gltf_import
