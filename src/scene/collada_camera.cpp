// collada_camera.cpp — the COLLADA reader's camera, placed by the course's
// rule (collada_reader.h), and CS184's camera settings files (importers.h).
#include <algorithm>
#include <cmath>

#include "scene/collada_reader.h"
#include "scene/importers.h"

namespace wp {

namespace collada_import {

// ---- the camera -------------------------------------------------------------

// The course's camera: xfov and yfov (50 and 35 where absent; yfov from
// the aspect ratio when only that is given), fitted to 800x600 by widening
// the narrower field (camera.cpp, configure); then an orbit camera placed by
// application.cpp: looking at the centre of the objects' bounding box from
// 1.5 times its diagonal, along the direction the camera node's transform
// gives the point (0, 0, -1) (translation included), up +Y.
void ColladaReader::place_camera(pugi::xml_node camera, const glm::dmat4& toWorld, const Bounds& bounds) {
  double hFov = 50.0, vFov = 35.0;
  glm::dvec3 dir(0.0, 0.0, 1.0);
  if (camera) {
    pugi::xml_node optics = required(camera, "optics");
    pugi::xml_node common = required(optics, "technique_common");
    pugi::xml_node persp = common.child("perspective");
    if (!persp) {
      if (pugi::xml_node ortho = common.child("orthographic")) unsupported(ortho);
      fail(common, "the camera has no <perspective>");
    }
    pugi::xml_node xfov = persp.child("xfov"), yfov = persp.child("yfov");
    if (xfov) hFov = number(xfov, "<xfov>");
    if (yfov) vFov = number(yfov, "<yfov>");
    if (!yfov) {
      pugi::xml_node aspect = persp.child("aspect_ratio");
      if (!aspect) fail(persp, "<perspective> has neither <yfov> nor <aspect_ratio>");
      const double ar = number(aspect, "<aspect_ratio>");
      if (!(ar > 0.0)) fail(aspect, "the aspect ratio must be positive");
      vFov = 2.0 * glm::degrees(std::atan(std::tan(glm::radians(0.5 * hFov)) / ar));
    }
    if (!(hFov > 0.0 && hFov < 180.0 && vFov > 0.0 && vFov < 180.0)) fail(persp, "fields of view must lie between 0 and 180 degrees");
    dir = glm::dvec3(toWorld * glm::dvec4(0, 0, -1, 1));
    if (!(glm::length(dir) > 0.0)) fail(camera, "the camera node's transform takes (0, 0, -1) to the origin: no direction");
    dir = glm::normalize(dir);
  }
  const int w = 800, h = 600;
  const double ar1 = std::tan(glm::radians(hFov) / 2) / std::tan(glm::radians(vFov) / 2), ar = double(w) / h;
  if (ar1 > ar) vFov = 2.0 * glm::degrees(std::atan(std::tan(glm::radians(hFov) / 2) / ar));
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.vfovDegrees = float(vFov);
  cam.resizeKeepsFocalLength = true;
  if (!bounds.empty()) {
    const glm::dvec3 target = 0.5 * (bounds.lo + bounds.hi);
    const double r = 1.5 * glm::length(bounds.hi - bounds.lo);
    double phi = std::acos(std::clamp(dir.y, -1.0, 1.0));
    const double theta = std::atan2(dir.x, dir.z);
    if (std::sin(phi) == 0.0) phi += 1e-5;  // EPS_F, as camera.cpp nudges the poles
    const glm::dvec3 toCamera(r * std::sin(phi) * std::sin(theta), r * std::cos(phi), r * std::sin(phi) * std::cos(theta));
    const glm::dvec3 up(0.0, std::sin(phi) > 0.0 ? 1.0 : -1.0, 0.0);
    const glm::dvec3 x = glm::normalize(glm::cross(up, toCamera));
    const glm::dvec3 y = glm::normalize(glm::cross(toCamera, x));
    cam.toWorld = glm::mat4(glm::dmat4(glm::dvec4(x, 0), glm::dvec4(y, 0), glm::dvec4(glm::normalize(toCamera), 0),
                                       glm::dvec4(target + toCamera, 1)));
  }
  scene_.camera = cam;
}

}  // namespace collada_import

// ---- CS184 camera settings files ---------------------------------------------

using collada_import::read_numbers;

std::vector<double> read_cs184_camera_settings(const std::string& path) {
  auto bytes = read_file_bytes(path);
  if (!bytes) throw InputError(path + ": cannot read the camera settings file");
  std::vector<double> v;
  const char* s = reinterpret_cast<const char*>(bytes->data());
  const std::string problem = read_numbers(s, s + bytes->size(), 30, v);
  if (!problem.empty()) throw InputError(path + ": " + problem + " (a CS184 camera settings file holds 30)");
  if (v.size() != 30) throw InputError(path + ": " + std::to_string(v.size()) + " numbers, where a CS184 camera settings file holds 30");
  return v;
}

void apply_cs184_camera_settings(const std::vector<double>& v, Camera& camera, const std::string& where) {
  // hFov vFov ar nClip fClip / pos target / phi theta r minR maxR / c2w (9,
  // row by row) / screenW screenH screenDist / focalDistance lensRadius.
  const double hFov = v[0], vFov = v[1];
  if (!(hFov > 0.0 && hFov < 180.0 && vFov > 0.0 && vFov < 180.0))
    throw InputError(where + ": the fields of view (" + std::to_string(hFov) + ", " + std::to_string(vFov) + ") must lie between 0 and 180 degrees");
  glm::dmat3 c2w;
  for (int i = 0; i < 9; ++i) c2w[i % 3][i / 3] = v[size_t(16 + i)];  // row i / 3, column i % 3
  if (std::abs(glm::determinant(c2w)) < 1e-6) throw InputError(where + ": the camera's orientation matrix is singular");
  camera.toWorld = glm::mat4(glm::dmat4(glm::dvec4(c2w[0], 0), glm::dvec4(c2w[1], 0), glm::dvec4(c2w[2], 0), glm::dvec4(v[5], v[6], v[7], 1)));
  camera.vfovDegrees = float(vFov);
  camera.aspect = float(std::tan(glm::radians(hFov) / 2) / std::tan(glm::radians(vFov) / 2));
}

void apply_cs184_camera_settings(const std::string& path, Camera& camera) {
  apply_cs184_camera_settings(read_cs184_camera_settings(path), camera, path);
}

}  // namespace wp
