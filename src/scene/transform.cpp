#include "scene/transform.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace wp {

glm::mat4 look_at(glm::vec3 from, glm::vec3 at, glm::vec3 up) {
  glm::vec3 dir = glm::normalize(from - at);  // camera +Z points back, away from `at`
  glm::vec3 left = glm::normalize(glm::cross(up, dir));
  glm::vec3 newUp = glm::cross(dir, left);
  glm::mat4 m(1.0f);
  m[0] = glm::vec4(left, 0.0f);
  m[1] = glm::vec4(newUp, 0.0f);
  m[2] = glm::vec4(dir, 0.0f);
  m[3] = glm::vec4(from, 1.0f);
  return m;
}

static bool finite_matrix(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

static glm::mat4 parse_one(const JsonCursor& j) {
  j.expect_object();
  bool lookAt = j.has("from") || j.has("at") || j.has("to") || j.has("up");
  bool frame = j.has("o") || j.has("x") || j.has("y") || j.has("z");
  int forms = int(lookAt) + int(frame) + int(j.has("translate")) + int(j.has("scale")) + int(j.has("rotate")) +
              int(j.has("matrix"));
  if (forms != 1) {
    if (forms == 0 && j.json().empty()) return glm::mat4(1.0f);
    if (forms == 0) j.allow_only({"from", "at", "to", "up", "o", "x", "y", "z", "translate", "scale", "rotate", "matrix"});
    j.fail("a transform object holds exactly one of look-at {from, at, up}, frame {o, x, y, z}, translate, scale, "
           "rotate or matrix; combine several with an array");
  }
  if (lookAt) {
    j.allow_only({"from", "at", "to", "up"});
    if (j.has("at") && j.has("to")) j.fail("give \"at\" or \"to\", not both");
    glm::vec3 from = j.vec3_or("from", glm::vec3(0, 0, 1));
    glm::vec3 at = j.has("to") ? j["to"].vec3() : j.vec3_or("at", glm::vec3(0.0f));
    glm::vec3 up = j.vec3_or("up", glm::vec3(0, 1, 0));
    if (glm::length(from - at) == 0.0f) j.fail("look-at \"from\" and \"at\" are the same point");
    if (glm::length(glm::cross(up, from - at)) == 0.0f) j.fail("look-at \"up\" is parallel to the viewing direction");
    return look_at(from, at, up);
  }
  if (frame) {
    j.allow_only({"o", "x", "y", "z"});
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(j.vec3_or("x", glm::vec3(1, 0, 0)), 0.0f);
    m[1] = glm::vec4(j.vec3_or("y", glm::vec3(0, 1, 0)), 0.0f);
    m[2] = glm::vec4(j.vec3_or("z", glm::vec3(0, 0, 1)), 0.0f);
    m[3] = glm::vec4(j.vec3_or("o", glm::vec3(0)), 1.0f);
    return m;
  }
  if (j.has("translate")) {
    j.allow_only({"translate"});
    return glm::translate(glm::mat4(1.0f), j["translate"].vec3());
  }
  if (j.has("scale")) {
    j.allow_only({"scale"});
    glm::vec3 s = j["scale"].vec3();
    if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f) j["scale"].fail("scale factors must be non-zero");
    return glm::scale(glm::mat4(1.0f), s);
  }
  if (j.has("rotate")) {
    j.allow_only({"rotate"});
    JsonCursor r = j["rotate"].expect_array();
    if (r.size() != 4) r.fail("expected [degrees, axis x, axis y, axis z]");
    glm::vec3 axis(r[1].number(), r[2].number(), r[3].number());
    if (glm::length(axis) == 0.0f) r.fail("rotation axis is zero");
    return glm::rotate(glm::mat4(1.0f), glm::radians(r[size_t(0)].number()), glm::normalize(axis));
  }
  j.allow_only({"matrix"});
  // darts takes one number s as diag(s, s, s, s), with a warning: it scales
  // directions, not points. Say what to write instead.
  if (j["matrix"].is_number()) j["matrix"].fail("one number is not a matrix: give 16 numbers (row-major), or {\"scale\": s}");
  JsonCursor m = j["matrix"].expect_array();
  if (m.size() != 16) m.fail("expected 16 numbers (a row-major 4x4 matrix), got " + std::to_string(m.size()));
  glm::mat4 out;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) out[col][row] = m[size_t(row * 4 + col)].number();
  if (out[0][3] != 0.0f || out[1][3] != 0.0f || out[2][3] != 0.0f || out[3][3] != 1.0f)
    m.fail("the last row must be [0, 0, 0, 1] (projective matrices are not transforms of surfaces)");
  return out;
}

glm::mat4 parse_transform(const JsonCursor& j) {
  glm::mat4 m(1.0f);
  if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) m = parse_one(j[i]) * m;
  } else {
    m = parse_one(j);
  }
  if (!finite_matrix(m)) j.fail("transform is not finite");
  if (glm::determinant(glm::mat3(m)) == 0.0f) j.fail("transform is singular (it flattens space)");
  return m;
}

void rows_3x4(const glm::mat4& m, glm::vec4& r0, glm::vec4& r1, glm::vec4& r2) {
  glm::mat4 t = glm::transpose(m);
  r0 = t[0];
  r1 = t[1];
  r2 = t[2];
}

glm::mat3 normal_matrix(const glm::mat4& m) {
  return glm::transpose(glm::inverse(glm::mat3(m)));
}

}  // namespace wp
