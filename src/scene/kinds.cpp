#include "scene/kinds.h"

namespace wp {

namespace {

#define WP_MATERIAL_ROW(id, name, prefix, lobes) KindInfo{id, name, lobes},
#define WP_KIND_ROW(id, name) KindInfo{id, name, 0u},
#define WP_FEATURE_ROW(id, name, material, lobe) KindInfo{id, name, 0u},

struct Tables {
  std::vector<KindInfo> materials{WP_MATERIAL_KINDS(WP_MATERIAL_ROW)};
  std::vector<KindInfo> textures{WP_TEXTURE_KINDS(WP_KIND_ROW)};
  std::vector<KindInfo> lights{WP_LIGHT_KINDS(WP_KIND_ROW)};
  std::vector<KindInfo> features{WP_FEATURES(WP_FEATURE_ROW)};
  std::vector<KindInfo> media{WP_MEDIUM_KINDS(WP_KIND_ROW)};
};

const Tables& tables() {
  static const Tables kTables;
  return kTables;
}

}  // namespace

const std::vector<KindInfo>& material_kinds() { return tables().materials; }
const std::vector<KindInfo>& texture_kinds() { return tables().textures; }
const std::vector<KindInfo>& light_kinds() { return tables().lights; }
const std::vector<KindInfo>& feature_kinds() { return tables().features; }
const std::vector<KindInfo>& medium_kinds() { return tables().media; }

bool is_layer(uint32_t kind) {
  for (const KindInfo& k : material_kinds())
    if (k.id == kind) return (k.lobes & LOBE_LAYER) != 0u;
  return false;
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
