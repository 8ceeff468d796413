#include "scene/kinds.h"

namespace wp {

#define WP_MATERIAL_ROW(id, name, prefix, lobes) KindInfo{id, name, lobes},
#define WP_KIND_ROW(id, name) KindInfo{id, name, 0u},

const std::vector<KindInfo>& material_kinds() {
  static const std::vector<KindInfo> kRows{WP_MATERIAL_KINDS(WP_MATERIAL_ROW)};
  return kRows;
}

const std::vector<KindInfo>& texture_kinds() {
  static const std::vector<KindInfo> kRows{WP_TEXTURE_KINDS(WP_KIND_ROW)};
  return kRows;
}

const std::vector<KindInfo>& light_kinds() {
  static const std::vector<KindInfo> kRows{WP_LIGHT_KINDS(WP_KIND_ROW)};
  return kRows;
}

const std::vector<KindInfo>& feature_kinds() {
  static const std::vector<KindInfo> kRows{WP_FEATURES(WP_KIND_ROW)};
  return kRows;
}

std::optional<uint32_t> kind_named(const std::vector<KindInfo>& table, const std::string& name) {
  for (const KindInfo& k : table)
    if (name == k.name) return k.id;
  return std::nullopt;
}

std::string kind_list(const std::vector<KindInfo>& table, uint32_t mask, const char* lastSeparator) {
  std::vector<const char*> names;
  for (const KindInfo& k : table)
    if (mask & KIND_BIT(k.id)) names.push_back(k.name);
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? lastSeparator : ", ";
    out += names[i];
  }
  return out.empty() ? "none" : out;
}

std::string kinds_description(glm::uvec4 kinds) {
  return "materials " + kind_list(material_kinds(), kinds.x, ", ") + "; textures " + kind_list(texture_kinds(), kinds.y, ", ") +
         "; lights " + kind_list(light_kinds(), kinds.z, ", ") + "; features " + kind_list(feature_kinds(), kinds.w, ", ");
}

}  // namespace wp
