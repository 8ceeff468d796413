#include "view/view_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scene/importers.h"

namespace wp {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kPolarMargin = 1e-5;  // the course's EPS_F keeps sin(phi) off 0

// An orthonormal frame about the up axis: theta is measured from `b`
// towards `a`, as the course measures it from +Z towards +X about +Y.
struct OrbitFrame {
  glm::dvec3 a, u, b;
};

OrbitFrame orbit_frame(glm::dvec3 up) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(up[i]) > std::abs(up[k])) k = i;
  glm::dvec3 b(0.0);
  b[(k + 1) % 3] = 1.0;
  return {glm::cross(up, b), up, b};
}

}  // namespace

ViewCamera::ViewCamera(const Camera& sceneCamera, std::pair<glm::vec3, glm::vec3> bounds) : scene_(sceneCamera) {
  const glm::dvec3 lo(bounds.first), hi(bounds.second);
  const bool empty = !(lo.x <= hi.x);
  canonical_ = empty ? 1.0 : std::max(1.5 * 0.5 * glm::length(hi - lo), 1e-6);
  // The world's up: the axis nearest the scene camera's own up (darts scenes
  // may stand on Z, glTF and CS184 on Y).
  const glm::dvec3 cameraUp(sceneCamera.toWorld[1]);
  int k = 1;
  for (int i = 0; i < 3; ++i)
    if (std::abs(cameraUp[i]) > std::abs(cameraUp[k]) + 1e-9) k = i;
  up_ = glm::dvec3(0.0);
  up_[k] = cameraUp[k] < 0.0 ? -1.0 : 1.0;
  position_ = glm::dvec3(sceneCamera.toWorld[3]);
  orientation_ = glm::dmat3(glm::dvec3(sceneCamera.toWorld[0]), glm::dvec3(sceneCamera.toWorld[1]), glm::dvec3(sceneCamera.toWorld[2]));
  // The target: the bounds' centre, at its depth in front of the camera.
  const glm::dvec3 forward = -glm::normalize(orientation_[2]);
  double depth = empty ? canonical_ : glm::dot(0.5 * (lo + hi) - position_, forward);
  if (!(depth > canonical_ / 10.0)) depth = canonical_;
  target_ = position_ + forward * depth;
  aperture_ = sceneCamera.apertureRadius;
  focus_ = sceneCamera.focusDistance;
  home_ = {position_, target_, orientation_, aperture_, focus_};
}

void ViewCamera::reset() {
  position_ = home_.position;
  target_ = home_.target;
  orientation_ = home_.orientation;
  aperture_ = home_.aperture;
  focus_ = home_.focus;
}

void ViewCamera::set_resolution(int width, int height) {
  wp::set_resolution(scene_, width, height);
  scene_.aspect = 0.0f;
}

void ViewCamera::look_at_target() {
  const glm::dvec3 back = glm::normalize(position_ - target_);
  const glm::dvec3 right = glm::normalize(glm::cross(up_, back));
  orientation_ = glm::dmat3(right, glm::cross(back, right), back);
}

void ViewCamera::orbit(double dx, double dy, int width, int height) {
  const OrbitFrame f = orbit_frame(up_);
  const glm::dvec3 d = position_ - target_;
  const double r = glm::length(d);
  if (!(r > 0.0) || width <= 0 || height <= 0) return;
  double phi = std::acos(std::clamp(glm::dot(d, f.u) / r, -1.0, 1.0));
  double theta = std::atan2(glm::dot(d, f.a), glm::dot(d, f.b));
  phi = std::clamp(phi - dy * kPi / height, kPolarMargin, kPi - kPolarMargin);
  theta -= dx * kPi / width;
  position_ = target_ + r * (std::sin(phi) * std::sin(theta) * f.a + std::cos(phi) * f.u + std::sin(phi) * std::cos(theta) * f.b);
  look_at_target();
}

void ViewCamera::pan(double dx, double dy, int height) {
  if (height <= 0) return;
  const double screenDistance = height / (2.0 * std::tan(glm::radians(double(scene_.vfovDegrees)) / 2.0));
  const double s = canonical_ / screenDistance;
  const glm::dvec3 move = glm::normalize(orientation_[0]) * (-dx * s) + glm::normalize(orientation_[1]) * (dy * s);
  position_ += move;
  target_ += move;
}

void ViewCamera::zoom(double wheelOffset) {
  const double r = distance();
  if (!(r > 0.0)) return;
  const double nearest = std::min(canonical_ / 10.0, r), farthest = std::max(canonical_ * 20.0, r);
  const double newR = std::clamp(r + wheelOffset * canonical_ / 10.0, nearest, farthest);
  position_ = target_ + (position_ - target_) * (newR / r);
}

void ViewCamera::fly(glm::dvec3 move) {
  const glm::dvec3 world = (glm::normalize(orientation_[0]) * move.x + glm::normalize(orientation_[1]) * move.y +
                            glm::normalize(orientation_[2]) * move.z) * canonical_;
  position_ += world;
  target_ += world;
}

void ViewCamera::change_aperture(double delta) { aperture_ = std::max(aperture_ + delta, 0.0); }
void ViewCamera::change_focus(double delta) { focus_ = std::max(focus_ + delta, 0.0); }
void ViewCamera::set_focus(double distance) {
  if (distance > 0.0 && std::isfinite(distance)) focus_ = distance;
}

std::vector<double> ViewCamera::settings() const {
  const double vFov = scene_.vfovDegrees;
  const double aspect = scene_.aspect > 0.0f ? double(scene_.aspect) : double(scene_.width) / double(scene_.height);
  const double hFov = glm::degrees(2.0 * std::atan(aspect * std::tan(glm::radians(vFov) / 2.0)));
  const OrbitFrame f = orbit_frame(up_);
  const glm::dvec3 d = position_ - target_;
  const double r = glm::length(d);
  const double phi = r > 0.0 ? std::acos(std::clamp(glm::dot(d, f.u) / r, -1.0, 1.0)) : 0.0;
  const double theta = std::atan2(glm::dot(d, f.a), glm::dot(d, f.b));
  std::vector<double> v = {hFov, vFov, aspect, 0.01, 100.0, position_.x, position_.y, position_.z, target_.x, target_.y, target_.z,
                           phi, theta, r, std::min(canonical_ / 10.0, r), std::max(canonical_ * 20.0, r)};
  for (int i = 0; i < 9; ++i) v.push_back(orientation_[i % 3][i / 3]);  // row i / 3, column i % 3
  const double screenDistance = scene_.height / (2.0 * std::tan(glm::radians(vFov) / 2.0));
  for (double x : {double(scene_.width), double(scene_.height), screenDistance, focus_, aperture_}) v.push_back(x);
  return v;
}

std::string ViewCamera::settings_text() const {
  const std::vector<double> v = settings();
  // The course's six lines; every number with the digits that read it back exactly.
  static const size_t lineEnds[] = {5, 11, 16, 25, 28, 30};
  std::string text;
  size_t i = 0;
  for (size_t end : lineEnds) {
    for (; i < end; ++i) {
      char number[32];
      std::snprintf(number, sizeof number, "%.17g", v[i]);
      text += number;
      text += i + 1 < end ? " " : "\n";
    }
  }
  return text;
}

Camera ViewCamera::camera() const {
  Camera c = scene_;
  const float aspect = c.aspect;
  apply_cs184_camera_settings(settings(), c, "the window's view");
  // The aspect comes back through both fields' tangents; where that is the
  // scene's own to rounding, the scene's value stays, so an unmoved window
  // renders the scene's camera exactly.
  const float sceneAspect = aspect > 0.0f ? aspect : float(c.width) / float(c.height);
  if (std::abs(c.aspect - sceneAspect) <= 1e-6f * sceneAspect) c.aspect = aspect;
  c.apertureRadius = float(aperture_);
  c.focusDistance = float(focus_);
  return c;
}

}  // namespace wp
