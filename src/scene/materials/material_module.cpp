#include "scene/materials/material_module.h"

#include <cstdio>
#include <stdexcept>

namespace wp {

namespace {

std::string number_text(float v) {
  if (std::isinf(v)) return v > 0.0f ? "infinity" : "-infinity";
  char text[32];
  std::snprintf(text, sizeof text, "%g", double(v));
  return text;
}

const char* type_name(ParamType t) {
  switch (t) {
    case ParamType::Number: return "a number";
    case ParamType::Colour: return "a colour";
    case ParamType::Texture: return "a texture";
    case ParamType::Material: return "a material";
    case ParamType::Choice: return "a word";
    case ParamType::Flag: return "true or false";
    case ParamType::Group: return "a group";
  }
  return "?";
}

bool is_choice(const std::string& choices, const std::string& word) {
  size_t start = 0;
  while (start <= choices.size()) {
    const size_t bar = std::min(choices.find('|', start), choices.size());
    if (choices.compare(start, bar - start, word) == 0 && bar - start == word.size()) return true;
    start = bar + 1;
  }
  return false;
}

std::string first_choice(const std::string& choices) { return choices.substr(0, choices.find('|')); }

// "\"a\" or \"b\"" for messages.
std::string choice_list(const std::string& choices) {
  std::string out;
  size_t start = 0;
  while (start <= choices.size()) {
    const size_t bar = std::min(choices.find('|', start), choices.size());
    const bool last = bar == choices.size();
    if (!out.empty()) out += last ? " or " : ", ";
    out += "\"" + choices.substr(start, bar - start) + "\"";
    start = bar + 1;
  }
  return out;
}

}  // namespace

std::string Range::describe() const {
  if (lo == 0.0f && std::isinf(hi) && hi > 0.0f) return loOpen ? "must be positive" : "must not be negative";
  return "must lie in " + std::string(loOpen ? "(" : "[") + number_text(lo) + ", " + number_text(hi) + (hiOpen ? ")" : "]");
}

Range unit_range() { return Range{0.0f, 1.0f}; }
Range positive_range() { return Range{0.0f, INFINITY, true, false}; }
Range non_negative_range() { return Range{0.0f, INFINITY}; }
Range closed_range(float lo, float hi) { return Range{lo, hi}; }

ParamSpec ParamSpec::number(std::string name, float fallback, Range range) {
  ParamSpec s;
  s.name = std::move(name);
  s.fallback = glm::vec3(fallback);
  s.range = range;
  return s;
}

ParamSpec ParamSpec::required_number(std::string name, Range range) {
  ParamSpec s = number(std::move(name), 0.0f, range);
  s.presence = Presence::Required;
  return s;
}

ParamSpec ParamSpec::colour(std::string name, glm::vec3 fallback, Range range) {
  ParamSpec s = number(std::move(name), 0.0f, range);
  s.type = ParamType::Colour;
  s.fallback = fallback;
  return s;
}

ParamSpec ParamSpec::required_colour(std::string name, Range range) {
  ParamSpec s = colour(std::move(name), glm::vec3(0.0f), range);
  s.presence = Presence::Required;
  return s;
}

ParamSpec ParamSpec::texture(std::string name, glm::vec3 fallback, Range range) {
  ParamSpec s = colour(std::move(name), fallback, range);
  s.type = ParamType::Texture;
  return s;
}

ParamSpec ParamSpec::optional_texture(std::string name) {
  ParamSpec s = texture(std::move(name), glm::vec3(0.0f));
  s.presence = Presence::Optional;
  return s;
}

ParamSpec ParamSpec::material(std::string name) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Material;
  s.presence = Presence::Required;
  return s;
}

ParamSpec ParamSpec::choice(std::string name, std::string choices) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Choice;
  s.choices = std::move(choices);
  return s;
}

ParamSpec ParamSpec::flag(std::string name, bool fallback) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Flag;
  s.fallback = glm::vec3(fallback ? 1.0f : 0.0f);
  return s;
}

ParamSpec ParamSpec::group(std::string name) {
  ParamSpec s = flag(std::move(name));
  s.type = ParamType::Group;
  return s;
}

ParamSpec ParamSpec::clamped() const {
  ParamSpec s = *this;
  s.clamp = true;
  return s;
}

ParamSpec ParamSpec::or_texture(std::string texture) const {
  ParamSpec s = *this;
  s.textureName = std::move(texture);
  return s;
}

ParamSpec ParamSpec::with_problem(std::string message) const {
  ParamSpec s = *this;
  s.problem = std::move(message);
  return s;
}

ParamSpec ParamSpec::allowing_fresnel() const {
  ParamSpec s = *this;
  s.fresnelAllowed = true;
  return s;
}

MaterialParams::MaterialParams(uint32_t kind, std::string name, Complaint whole)
    : kind_(kind), name_(std::move(name)), whole_(std::move(whole)) {}

MaterialParams& MaterialParams::set(const std::string& key, Value v) {
  if (!v.at) v.at = whole_;
  values_[key] = std::move(v);
  return *this;
}

MaterialParams& MaterialParams::number(const std::string& key, float v, Complaint at) {
  return set(key, Value{ParamType::Number, glm::vec3(v), WP_INVALID, {}, std::move(at)});
}
MaterialParams& MaterialParams::colour(const std::string& key, glm::vec3 v, Complaint at) {
  return set(key, Value{ParamType::Colour, v, WP_INVALID, {}, std::move(at)});
}
MaterialParams& MaterialParams::texture(const std::string& key, uint32_t texture, Complaint at) {
  return set(key, Value{ParamType::Texture, glm::vec3(0.0f), texture, {}, std::move(at)});
}
MaterialParams& MaterialParams::material(const std::string& key, uint32_t material, Complaint at) {
  return set(key, Value{ParamType::Material, glm::vec3(0.0f), material, {}, std::move(at)});
}
MaterialParams& MaterialParams::choice(const std::string& key, std::string word, Complaint at) {
  return set(key, Value{ParamType::Choice, glm::vec3(0.0f), WP_INVALID, std::move(word), std::move(at)});
}
MaterialParams& MaterialParams::flag(const std::string& key, bool v, Complaint at) {
  return set(key, Value{ParamType::Flag, glm::vec3(v ? 1.0f : 0.0f), WP_INVALID, {}, std::move(at)});
}

const MaterialInputs::Slot& MaterialInputs::slot(const std::string& key, ParamType type) const {
  const auto& specs = module_->params;
  for (size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].name != key) continue;
    const ParamType declared = specs[i].type == ParamType::Group ? ParamType::Flag : specs[i].type;
    if (declared != type) break;
    return slots_[i];
  }
  // A pack reading a name its schema lacks, or as another type, is a bug here, not in the file.
  throw std::logic_error("material pack reads undeclared parameter \"" + key + "\"");
}

float MaterialInputs::number(const std::string& key) const { return slot(key, ParamType::Number).v.x; }
glm::vec3 MaterialInputs::colour(const std::string& key) const { return slot(key, ParamType::Colour).v; }
uint32_t MaterialInputs::texture(const std::string& key) const { return slot(key, ParamType::Texture).index; }
uint32_t MaterialInputs::material(const std::string& key) const { return slot(key, ParamType::Material).index; }
const std::string& MaterialInputs::choice(const std::string& key) const { return slot(key, ParamType::Choice).word; }
bool MaterialInputs::flag(const std::string& key) const { return slot(key, ParamType::Flag).v.x != 0.0f; }
bool MaterialInputs::given(const std::string& key) const {
  for (size_t i = 0; i < module_->params.size(); ++i)
    if (module_->params[i].name == key) return slots_[i].given != nullptr;
  throw std::logic_error("material pack asks after undeclared parameter \"" + key + "\"");
}

void MaterialInputs::fail(const std::string& key, const std::string& problem) const {
  auto it = params_->values().find(key);
  const Complaint& at = it != params_->values().end() && it->second.at ? it->second.at : params_->whole();
  at(problem);
  throw std::logic_error("a complaint returned: " + problem);  // complaints throw
}

void MaterialInputs::fail(const std::string& problem) const {
  params_->whole()(problem);
  throw std::logic_error("a complaint returned: " + problem);
}

const ParamSpec* find_param(const MaterialModule& module, const std::string& name) {
  for (const ParamSpec& p : module.params)
    if (p.name == name) return &p;
  return nullptr;
}

const MaterialModule& material_module(uint32_t kind) {
  const auto& all = material_modules();
  if (kind >= all.size()) throw std::logic_error("no material module for kind " + std::to_string(kind));
  return *all[kind];
}

uint32_t MaterialInputs::add_medium(SceneMedium medium) const {
  if (medium.name.empty()) medium.name = params_->name() + " (inside)";
  scene_->media.push_back(std::move(medium));
  return uint32_t(scene_->media.size() - 1);
}

uint32_t add_material(Scene& scene, const MaterialParams& params) {
  const MaterialModule& module = material_module(params.kind());
  MaterialInputs in;
  in.module_ = &module;
  in.params_ = &params;
  in.scene_ = &scene;
  auto complain = [](const Complaint& at, const std::string& problem) {
    at(problem);
    throw std::logic_error("a complaint returned: " + problem);
  };
  for (const auto& [key, v] : params.values()) {
    const ParamSpec* spec = find_param(module, key);
    if (!spec) throw std::logic_error("an importer gave material kind " + std::to_string(module.kind) + " an undeclared parameter \"" + key + "\"");
    const ParamType expected = spec->type == ParamType::Group ? ParamType::Flag : spec->type;
    if (v.type != expected) complain(v.at, key + ": expected " + std::string(type_name(expected)) + ", not " + type_name(v.type));
  }
  in.slots_.resize(module.params.size());
  for (size_t i = 0; i < module.params.size(); ++i) {
    const ParamSpec& spec = module.params[i];
    MaterialInputs::Slot& slot = in.slots_[i];
    auto found = params.values().find(spec.name);
    if (found == params.values().end()) {
      if (spec.presence == Presence::Required) complain(params.whole(), "needs \"" + spec.name + "\"");
      slot.v = spec.fallback;
      if (spec.type == ParamType::Choice) slot.word = first_choice(spec.choices);
      if (spec.type == ParamType::Texture && spec.presence == Presence::Defaulted) slot.index = add_texture(scene, constant_texture(spec.fallback));
      continue;
    }
    const MaterialParams::Value& v = found->second;
    slot.given = &v;
    slot.v = v.v;
    slot.index = v.index;
    slot.word = v.word;
    auto problem = [&spec] { return spec.problem.empty() ? spec.name + " " + spec.range.describe() : spec.problem; };
    const bool colour = spec.type == ParamType::Colour;
    if (spec.type == ParamType::Number || colour) {
      for (int c = 0; c < (colour ? 3 : 1); ++c) {
        if (spec.range.contains(slot.v[c])) continue;
        if (spec.clamp && !std::isnan(slot.v[c])) slot.v[c] = std::clamp(slot.v[c], spec.range.lo, spec.range.hi);
        else complain(v.at, colour ? problem() + " in every channel" : problem());
      }
    } else if (spec.type == ParamType::Texture) {
      const SceneTexture& t = scene.textures.at(v.index);
      if (t.kind == TEX_FRESNEL && !spec.fresnelAllowed) complain(v.at, "a \"fresnel\" texture is only meaningful as a blend's amount");
      if (t.kind == TEX_CONSTANT && !(spec.range.contains(t.color.x) && spec.range.contains(t.color.y) && spec.range.contains(t.color.z)))
        complain(v.at, problem());
    } else if (spec.type == ParamType::Choice) {
      if (!is_choice(spec.choices, v.word)) complain(v.at, spec.name + " must be " + choice_list(spec.choices));
    } else if (spec.type == ParamType::Material) {
      if (v.index >= scene.materials.size()) throw std::logic_error("material parameter \"" + spec.name + "\" names no material");
    }
  }
  SceneMaterial m;
  m.kind = module.kind;
  m.record.info.x = module.kind;
  m.name = params.name();
  module.pack(in, m);
  scene.materials.push_back(std::move(m));
  return uint32_t(scene.materials.size() - 1);
}

uint32_t add_lambertian(Scene& scene, glm::vec3 albedo, const std::string& name) {
  return add_material(scene, MaterialParams(MAT_LAMBERTIAN, name, [name](const std::string& problem) {
                               throw std::invalid_argument("material " + name + ": " + problem);
                             }).texture("albedo", add_texture(scene, constant_texture(albedo))));
}

int material_lobes(const Scene& scene, uint32_t m) {
  const SceneMaterial& mat = scene.materials.at(m);
  if (mat.kind == MAT_BLEND) return material_lobes(scene, mat.part(0)) + material_lobes(scene, mat.part(1));
  if (is_layer(mat.kind)) return material_lobes(scene, mat.part(0)) + 1;
  return 1;
}

int material_layers(const Scene& scene, uint32_t m) {
  const SceneMaterial& mat = scene.materials.at(m);
  return is_layer(mat.kind) ? material_layers(scene, mat.part(0)) + 1 : 0;
}

int material_sheens(const Scene& scene, uint32_t m) {
  const SceneMaterial& mat = scene.materials.at(m);
  if (mat.kind == MAT_BLEND) return material_sheens(scene, mat.part(0)) + material_sheens(scene, mat.part(1));
  if (is_layer(mat.kind)) return material_sheens(scene, mat.part(0)) + (mat.kind == MAT_SHEEN ? 1 : 0);
  return 0;
}

}  // namespace wp
