// material_module.h — a material kind as one module: the parameters it takes
// (names, types, defaults, valid ranges, which may be textures) and how it
// packs them into the kernels' record, beside its lobe functions in
// shaders/shared/materials/NAME.glsl.
//
// An importer never packs: it translates its format's vocabulary into named
// parameters (MaterialParams), each with a way to complain at the place in
// its file the value came from, and hands them to add_material, which checks
// them against the kind's schema, fills in defaults and calls the kind's
// pack. pbrt-v4's Material::Create(parameters) and Mitsuba 3's
// src/bsdfs/ plugins take the same shape. The names are the darts
// vocabulary's (docs/scene-format.md), which wavepath extends: its JSON
// reader needs no table of its own.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace wp {

struct MaterialModule;

// Throws the importer's error for the place a value came from (a JSON
// pointer, an XML element, a glTF path); never returns.
using Complaint = std::function<void(const std::string& problem)>;

enum class ParamType : uint8_t {
  Number,    // one float
  Colour,    // three floats (a scalar given for all three)
  Texture,   // a texture's index; a constant texture's colour is range-checked
  Material,  // another material's index: a blend's parts, a layer's base
  Choice,    // one of a few words (ParamSpec::choices)
  Flag,      // true or false
  Group,     // present or not; its parameters are named "group.key" (darts nests them in an object "group")
};

// A closed, open or half-open interval of valid values (each channel).
struct Range {
  float lo = -INFINITY, hi = INFINITY;
  bool loOpen = false, hiOpen = false;
  bool contains(float v) const { return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi); }
  std::string describe() const;  // "must be positive", "must lie in [0, 1]", ...
};
Range unit_range();                    // [0, 1]
Range positive_range();                // (0, inf)
Range non_negative_range();            // [0, inf)
Range closed_range(float lo, float hi);  // [lo, hi]

enum class Presence : uint8_t {
  Defaulted,  // absent: `fallback` (a texture: a constant one of that colour)
  Optional,   // absent: none (a texture or material: WP_INVALID)
  Required,   // absent: an error
};

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::Number;
  Presence presence = Presence::Defaulted;
  glm::vec3 fallback{0.0f};  // Number: x; Colour, Texture: all three; Flag: x != 0
  Range range;               // Number, Colour, and a Texture's constant colour
  bool clamp = false;        // out of range: clamped, not refused (darts clamps metal roughness)
  std::string choices;       // Choice: the words, "|"-separated, the first the default
  std::string textureName;   // Number, Colour: the texture that may stand for the value in darts' files
  bool fresnelAllowed = false;  // Texture: may be a fresnel texture (a blend's amount)
  std::string problem;       // overrides the range's message ("albedo above 1 would create energy")

  // Builders, so that a schema reads as a list.
  static ParamSpec number(std::string name, float fallback, Range range = {});
  static ParamSpec required_number(std::string name, Range range = {});
  static ParamSpec colour(std::string name, glm::vec3 fallback, Range range = {});
  static ParamSpec required_colour(std::string name, Range range = {});
  static ParamSpec texture(std::string name, glm::vec3 fallback, Range range = {});
  static ParamSpec optional_texture(std::string name);
  static ParamSpec material(std::string name);
  static ParamSpec choice(std::string name, std::string choices);
  static ParamSpec flag(std::string name, bool fallback = false);
  static ParamSpec group(std::string name);
  ParamSpec clamped() const;
  ParamSpec or_texture(std::string texture) const;
  ParamSpec with_problem(std::string message) const;
  ParamSpec allowing_fresnel() const;
};

// What an importer hands over: named values, each with where it came from.
class MaterialParams {
 public:
  MaterialParams(uint32_t kind, std::string name, Complaint whole);
  MaterialParams& number(const std::string& key, float v, Complaint at = {});
  MaterialParams& colour(const std::string& key, glm::vec3 v, Complaint at = {});
  MaterialParams& texture(const std::string& key, uint32_t texture, Complaint at = {});
  MaterialParams& material(const std::string& key, uint32_t material, Complaint at = {});
  MaterialParams& choice(const std::string& key, std::string word, Complaint at = {});
  MaterialParams& flag(const std::string& key, bool v, Complaint at = {});

  struct Value {
    ParamType type;
    glm::vec3 v{0.0f};     // Number (x), Colour, Flag (x)
    uint32_t index = WP_INVALID;  // Texture, Material
    std::string word;      // Choice
    Complaint at;
  };
  uint32_t kind() const { return kind_; }
  const std::string& name() const { return name_; }
  const Complaint& whole() const { return whole_; }
  const std::map<std::string, Value>& values() const { return values_; }

 private:
  MaterialParams& set(const std::string& key, Value v);
  uint32_t kind_;
  std::string name_;
  Complaint whole_;
  std::map<std::string, Value> values_;
};

// The parameters as a kind's pack reads them: checked, defaults filled in.
class MaterialInputs {
 public:
  float number(const std::string& key) const;
  glm::vec3 colour(const std::string& key) const;
  uint32_t texture(const std::string& key) const;   // WP_INVALID: an optional texture not given
  uint32_t material(const std::string& key) const;  // WP_INVALID: not given
  const std::string& choice(const std::string& key) const;
  bool flag(const std::string& key) const;
  bool given(const std::string& key) const;  // by the importer, not by default
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;  // at the value's place
  [[noreturn]] void fail(const std::string& problem) const;                          // at the material's
  const Scene& scene() const { return *scene_; }
  // Adds a medium the material bounds to the scene (glTF's volumes, whose
  // material holds their inside); its index into Scene::media.
  uint32_t add_medium(SceneMedium medium) const;

 private:
  friend uint32_t add_material(Scene&, const MaterialParams&);
  // One per schema entry, in the schema's order: the value given (or null)
  // and the default's where none was.
  struct Slot {
    const MaterialParams::Value* given = nullptr;
    glm::vec3 v{0.0f};
    uint32_t index = WP_INVALID;
    std::string word;  // a choice's
  };
  const Slot& slot(const std::string& key, ParamType type) const;
  const MaterialModule* module_ = nullptr;
  const MaterialParams* params_ = nullptr;
  Scene* scene_ = nullptr;
  std::vector<Slot> slots_;
};

struct MaterialModule {
  uint32_t kind;  // MAT_*: its row in kinds.glsl
  std::vector<ParamSpec> params;
  // Fills the kind's share of the record (kind and name are set).
  void (*pack)(const MaterialInputs& in, SceneMaterial& out);
  // The FEATURE_* bits a packed record needs compiled into the kernels
  // (none if null).
  uint32_t (*features)(const shader::Material& record) = nullptr;
  // The textures its lobes read at a hit besides the record's albedo and
  // amount (info.y, info.w) and normal map, whose kinds the shade kernels
  // compile in (none if null; WP_INVALID entries are skipped).
  std::vector<uint32_t> (*lookups)(const shader::Material& record) = nullptr;
};

// Every kind's module, in id order (one per row of WP_MATERIAL_KINDS; tested).
const std::vector<const MaterialModule*>& material_modules();
const MaterialModule& material_module(uint32_t kind);
const ParamSpec* find_param(const MaterialModule& module, const std::string& name);

// Checks `params` against its kind's schema, packs it and appends it to the
// scene's materials; its index. Errors go to the importer's complaints.
uint32_t add_material(Scene& scene, const MaterialParams& params);

// A Lambertian of constant albedo (the courses' default materials, tests).
uint32_t add_lambertian(Scene& scene, glm::vec3 albedo, const std::string& name = "lambertian");

// What a material combines, counted through blends and layers (the kernels'
// limits: BSDF_MAX_LOBES lobes, LAYERS_MAX layers, one sheen).
int material_lobes(const Scene& scene, uint32_t m);
int material_layers(const Scene& scene, uint32_t m);
int material_sheens(const Scene& scene, uint32_t m);

}  // namespace wp
