// transform.h — darts transforms: one object, or an array applied in order
// (each later one multiplies from the left).
#pragma once

#include <glm/glm.hpp>

#include "scene/json_cursor.h"

namespace wp {

glm::mat4 parse_transform(const JsonCursor& j);

// darts look-at: the result maps camera space (looking down -Z) to the world.
glm::mat4 look_at(glm::vec3 from, glm::vec3 at, glm::vec3 up);

// The top three rows of an affine transform, as the kernels store them (3x4).
void rows_3x4(const glm::mat4& m, glm::vec4& r0, glm::vec4& r1, glm::vec4& r2);

// The matrix that carries normals through `m` (inverse transpose of its linear part).
glm::mat3 normal_matrix(const glm::mat4& m);

}  // namespace wp
