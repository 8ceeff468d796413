// view_camera.h — the camera of `wavepath view`, moved as the CS184
// pathtracer's window moves it (orbit about a target, pan, zoom; the course's
// camera.cpp and application.cpp, cited in docs/viewer.md) and flown with
// pbrt-v4's keys. No window here: the controller is plain arithmetic,
// unit-tested without a display (tests/test_view.cpp).
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace wp {

class ViewCamera {
 public:
  // The scene's camera as the window starts: its view unchanged until the
  // user moves it. `bounds` (the scene's) scale pan, zoom and flight as the
  // course scales them, by its canonical view distance: 1.5 times half the
  // bounds' diagonal.
  ViewCamera(const Camera& sceneCamera, std::pair<glm::vec3, glm::vec3> bounds);

  // Left-drag by (dx, dy) pixels, y down, in a window `height` pixels high
  // and `width` wide: the course's rotate_by(-dy * pi / H, -dx * pi / W),
  // the polar angle about the scene's up axis kept in [0, pi].
  void orbit(double dx, double dy, int width, int height);
  // Right-drag: the course's move_by(-dx, dy, canonical distance), which
  // moves the camera and its target so a point at that distance follows the
  // cursor.
  void pan(double dx, double dy, int height);
  // Mouse wheel: the course's move_forward(-offset * canonical / 10), the
  // distance to the target clamped to [canonical / 10, canonical * 20]
  // (wheel up moves away, as in the course).
  void zoom(double wheelOffset);
  // Flight (pbrt-v4's W/A/S/D/Q/E): `move` in the camera's own axes (x
  // right, y up, z back), in canonical distances.
  void fly(glm::dvec3 move);
  // Space: back to the scene's camera.
  void reset();
  // A new image size (the window resized): the vertical field stays, the
  // horizontal one follows the window's shape (square pixels).
  void set_resolution(int width, int height);

  // The lens, as the course's K/L and ;/' keys change it (never below 0).
  void change_aperture(double delta);
  void change_focus(double delta);
  void set_focus(double distance);

  // The scene's camera seen through this view: the course's camera settings
  // file (D) written with full precision and read back as `render -c` reads
  // it, so the window and `render -c` render the same rays.
  Camera camera() const;
  // That file's 30 numbers (hFov vFov ar nClip fClip / pos target / phi
  // theta r minR maxR / c2w row by row / screenW screenH screenDist /
  // focalDistance lensRadius), and the file's text.
  std::vector<double> settings() const;
  std::string settings_text() const;

  glm::dvec3 position() const { return position_; }
  glm::dvec3 target() const { return target_; }
  double distance() const { return glm::length(position_ - target_); }
  double canonical_distance() const { return canonical_; }
  glm::dvec3 up_axis() const { return up_; }
  // Columns: right, up, back (the camera looks down -back).
  const glm::dmat3& orientation() const { return orientation_; }

 private:
  void look_at_target();

  Camera scene_;
  glm::dvec3 up_{0, 1, 0};  // the world's up: the scene camera's nearest axis
  double canonical_ = 1.0;
  glm::dvec3 position_, target_;
  glm::dmat3 orientation_{1.0};
  double aperture_ = 0.0, focus_ = 1.0;
  struct Home {
    glm::dvec3 position, target;
    glm::dmat3 orientation;
    double aperture, focus;
  } home_;  // the scene's camera, for reset
};

}  // namespace wp
