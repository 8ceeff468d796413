// darts_materials.cpp — the darts importer's textures (colour parameters,
// procedural and image textures, their mappings), its background and its
// materials (darts_importer.h).
#include <cmath>
#include <map>
#include <optional>

#include "scene/darts_importer.h"

namespace wp::darts_import {

// ---- textures ------------------------------------------------------------

uint32_t DartsImporter::add_texture(const SceneTexture& t) { return wp::add_texture(scene_, t); }

// `mapping`: {type: "uv"} (lookups at (u, v, 0)) or {type: "transform",
// transform: ...} (lookups at the hit point), either with an optional
// transform applied to the lookup point. Without one, the procedural
// textures are solid (the course's checker.json and marble.json references
// show patterns in world space) and images are looked up by UV.
void DartsImporter::parse_mapping(const JsonCursor& j, SceneTexture& t) {
  t.solid = t.kind == TEX_CHECKER || t.kind == TEX_MARBLE;
  if (!j.has("mapping")) return;
  JsonCursor m = j["mapping"].expect_object();
  m.allow_only({"type", "transform"});
  std::string type = m.has("type") ? m["type"].string() : "transform";
  t.solid = type == "transform";
  if (type != "transform" && type != "uv") m["type"].fail("unknown texture mapping \"" + type + "\" (expected uv or transform)");
  if (m.has("transform")) t.mapping = parse_transform(m["transform"]);
}

// A colour parameter: a number, [r, g, b] or a texture object. Returns the
// texture's index. `constant` receives the colour when it is one.
uint32_t DartsImporter::texture_param(const JsonCursor& j, int depth, glm::vec3* constant) {
  if (!j.is_object()) {
    glm::vec3 c = non_negative(j);
    if (constant) *constant = c;
    return add_texture(constant_texture(c));
  }
  std::string type = j["type"].string();
  SceneTexture t;
  if (type == "constant") {
    j.allow_only({"type", "color"});
    return texture_param(j["color"], depth, constant);
  }
  if (type == "checker") {
    j.allow_only({"type", "even", "odd", "scale", "mapping"});
    if (depth >= TEXTURE_MAX_NESTING - 1) j.fail("checker textures nest more than " + std::to_string(TEXTURE_MAX_NESTING - 1) + " deep");
    t.kind = TEX_CHECKER;
    parse_mapping(j, t);
    // darts: odd where sin(x / scale) sin(y / scale) sin(z / scale) < 0, so
    // cells are pi * scale wide (the course's checker.json reference).
    t.scale = 1.0f / (float(M_PI) * (j.has("scale") ? j["scale"].positive_number() : 1.0f));
    // Children first: their indices go into this texture.
    t.even = j.has("even") ? texture_param(j["even"], depth + 1) : add_texture(constant_texture(glm::vec3(1.0f)));
    t.odd = j.has("odd") ? texture_param(j["odd"], depth + 1) : add_texture(constant_texture(glm::vec3(0.0f)));
    return add_texture(t);
  }
  if (type == "marble") {
    j.allow_only({"type", "base", "veins", "scale", "mapping"});
    t.kind = TEX_MARBLE;
    parse_mapping(j, t);
    t.color = j.has("base") ? non_negative(j["base"]) : glm::vec3(0.8f);
    t.scale = j.has("scale") ? j["scale"].positive_number() : 1.0f;
    t.veins = j.has("veins") ? non_negative(j["veins"]) : glm::vec3(0.1f);
    return add_texture(t);
  }
  if (type == "image") {
    j.allow_only({"type", "filename", "mapping"});
    t = image_texture(scene_, resolve(j["filename"].string()), "loaded by " + file_ + " at " + j.path());
    parse_mapping(j, t);
    return add_texture(t);
  }
  if (type == "fresnel") j["type"].fail("a \"fresnel\" texture is only meaningful as a blend's amount");
  j["type"].fail("unknown texture type \"" + type + "\" (expected constant, checker, marble or image)");
}

// A colour, or {"type": "image", "filename": ...}: an equirectangular
// environment map (HDR or EXR for real lighting), importance-sampled.
void DartsImporter::parse_background(const JsonCursor& j) {
  if (!j.is_object()) {
    scene_.background = non_negative(j);
    return;
  }
  j.allow_only({"type", "filename"});
  std::string type = j["type"].string();
  if (type != "image") j["type"].fail("a background is a colour or {\"type\": \"image\", \"filename\": ...} (an environment map)");
  scene_.environment = add_image_texture(scene_, resolve(j["filename"].string()), "loaded by " + file_ + " at " + j.path());
}

// ---- materials -------------------------------------------------------------

// A material's keys are its kind's parameters (src/scene/materials/): a
// parameter "g.k" is key k of an object "g"; a number or colour may be a
// texture where its kind names one to stand for it.
Complaint DartsImporter::complaint_at(const JsonCursor& j) {
  return [j](const std::string& problem) { j.fail(problem); };
}

uint32_t DartsImporter::add_material(const JsonCursor& j, const std::string& name) {
  const std::string type = j["type"].string();
  const std::optional<uint32_t> kind = kind_named(material_kinds(), type);
  if (!kind) {
    std::vector<std::string> kinds;
    for (const KindInfo& k : material_kinds()) kinds.push_back(k.name);
    std::string hint = did_you_mean(type, kinds);
    j["type"].fail("unknown material type \"" + type + "\"" + (hint.empty() ? " (expected " + kind_list(material_kinds()) + ")" : hint));
  }
  const MaterialModule& module = material_module(*kind);
  // Each kind's keys, worked out from its schema once: its top-level names,
  // each group's keys, and where each parameter sits.
  struct Keys {
    std::vector<std::string> top = {"type", "name"};
    std::map<std::string, std::vector<std::string>> groups;
    std::vector<std::pair<std::string, std::string>> place;  // per parameter: (group or "", key)
  };
  static const std::vector<Keys> kindKeys = [] {
    std::vector<Keys> all;
    for (const MaterialModule* m : material_modules()) {
      Keys k;
      for (const ParamSpec& p : m->params) {
        const size_t dot = p.name.find('.');
        if (dot == std::string::npos) k.top.push_back(p.name);
        else k.groups[p.name.substr(0, dot)].push_back(p.name.substr(dot + 1));
        k.place.emplace_back(dot == std::string::npos ? "" : p.name.substr(0, dot), dot == std::string::npos ? p.name : p.name.substr(dot + 1));
      }
      all.push_back(std::move(k));
    }
    return all;
  }();
  const Keys& keys = kindKeys[*kind];
  j.allow_only(keys.top);
  MaterialParams params(*kind, name, complaint_at(j));
  for (size_t i = 0; i < module.params.size(); ++i) {
    const ParamSpec& p = module.params[i];
    const auto& [group, key] = keys.place[i];
    if (p.type == ParamType::Group) {
      if (!j.has(key.c_str())) continue;
      j[key.c_str()].expect_object().allow_only(keys.groups.at(key));
      params.flag(p.name, true, complaint_at(j[key.c_str()]));
      continue;
    }
    if (!group.empty() && !j.has(group.c_str())) continue;
    const JsonCursor parent = group.empty() ? j : j[group.c_str()];
    if (!parent.has(key.c_str())) continue;
    read_param(parent[key.c_str()], p, params, name + "/" + key);
  }
  return wp::add_material(scene_, params);
}

void DartsImporter::read_param(const JsonCursor& v, const ParamSpec& p, MaterialParams& params, const std::string& name) {
  const Complaint at = complaint_at(v);
  if (!p.textureName.empty() && v.is_object()) {
    params.texture(p.textureName, texture_param(v), at);
    return;
  }
  switch (p.type) {
    case ParamType::Number: params.number(p.name, v.number(), at); break;
    case ParamType::Colour: params.colour(p.name, v.vec3(), at); break;
    case ParamType::Texture:
      if (p.fresnelAllowed && v.is_object() && v.has("type") && v["type"].is_string() && v["type"].string() == "fresnel") {
        v.allow_only({"type", "ior"});
        SceneTexture t;
        t.kind = TEX_FRESNEL;
        t.ior = v.has("ior") ? v["ior"].positive_number() : 1.5f;
        params.texture(p.name, add_texture(t), at);
      } else {
        params.texture(p.name, texture_param(v), at);
      }
      break;
    case ParamType::Material: params.material(p.name, material_part(v, name), at); break;
    case ParamType::Choice: params.choice(p.name, v.string(), at); break;
    case ParamType::Flag:
      if (!v.json().is_boolean()) v.fail("expected true or false");
      params.flag(p.name, v.json().get<bool>(), at);
      break;
    case ParamType::Group: break;
  }
}

// A blend's part or a layer's base: a material's name or an inline material.
uint32_t DartsImporter::material_part(const JsonCursor& j, const std::string& name) {
  if (!j.is_string()) return add_material(j.expect_object(), name);
  auto it = named_.find(j.string());
  if (it == named_.end()) j.fail("no material named \"" + j.string() + "\" (materials must be defined before use)");
  return it->second;
}

uint32_t DartsImporter::material_of(const JsonCursor& surface) {
  JsonCursor j = surface["material"];
  if (j.json().is_null()) return with_media(surface, interface_material());  // no surface: only a boundary of media
  if (j.is_string()) {
    if (phases_.count(j.string())) j.fail("\"" + j.string() + "\" is a phase function, not a surface's material");
    auto it = named_.find(j.string());
    if (it == named_.end()) j.fail("no material named \"" + j.string() + "\"");
    return with_media(surface, it->second);
  }
  j.expect_object();
  return with_media(surface, add_material(j, surface.path() + "/material"));
}

uint32_t DartsImporter::interface_material() {
  if (interface_ == WP_INVALID) interface_ = wp::add_material(scene_, MaterialParams(MAT_INTERFACE, "interface", complaint_at(JsonCursor(doc_, "", file_))));
  return interface_;
}

}  // namespace wp::darts_import
