// transform.h — darts transforms: one object, or an array applied in order
// (each later one multiplies from the left).
#pragma once

#include <glm/glm.hpp>

#include "scene/json_cursor.h"

namespace wp {

glm::mat4 parse_transform(const JsonCursor& j);

// darts look-at: the result maps camera space (looking down -Z) to the world.
glm::mat4 look_at(glm::vec3 from, glm::vec3 at, glm::vec3 up);

}  // namespace wp
