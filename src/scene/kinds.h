// kinds.h — the kind tables of shaders/shared/kinds.glsl (materials,
// textures, lights, other features) as C++ data: names for the loaders'
// messages and for `wavepath info`, and kind masks by name.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "../../shaders/shared/kinds.glsl"

namespace wp {

struct KindInfo {
  uint32_t id;        // MAT_*, TEX_*, LIGHT_* or FEATURE_*: its bit in a mask is 1 << id
  const char* name;   // as scene files and messages spell it
  uint32_t lobes;     // materials: LOBE_* flags; 0 otherwise
};

// Each table's rows in id order (ids are 0, 1, 2, ...; tested).
const std::vector<KindInfo>& material_kinds();
const std::vector<KindInfo>& texture_kinds();
const std::vector<KindInfo>& light_kinds();
const std::vector<KindInfo>& feature_kinds();
const std::vector<KindInfo>& medium_kinds();

// Whether material kind `kind` is a layer over a base material (LOBE_LAYER:
// clearcoat, sheen).
bool is_layer(uint32_t kind);

// The kind of a table named `name`, if any.
std::optional<uint32_t> kind_named(const std::vector<KindInfo>& table, const std::string& name);

// The names of a table's rows whose bit is in `mask`, as "a, b or c" (for
// "expected ..." in messages) or "a, b, c" (lists).
std::string kind_list(const std::vector<KindInfo>& table, uint32_t mask = ALL_KINDS, const char* lastSeparator = " or ");

// What a kind mask (SceneParams.kinds: materials, textures, lights,
// features) holds, for `wavepath info`: "materials lambertian, metal;
// textures constant; lights area lights; features none".
std::string kinds_description(glm::uvec4 kinds);

}  // namespace wp
