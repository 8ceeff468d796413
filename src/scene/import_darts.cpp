#include "scene/importers.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <tuple>
#include <sstream>

#include "scene/darts_tests.h"
#include "scene/json_cursor.h"
#include "scene/kinds.h"
#include "scene/materials/material_module.h"
#include "scene/obj_mesh.h"
#include "scene/transform.h"
#include "util/error.h"
#include "util/huge_pages.h"

namespace wp {

namespace {

namespace fs = std::filesystem;

bool is_nonzero(glm::vec3 c) {
  return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f;
}

class DartsImporter {
 public:
  explicit DartsImporter(std::string path) : file_(std::move(path)) {}

  void parse_document() { doc_ = read_json_file(file_); }

  static bool holds_tests(const nlohmann::json& doc) {
    return doc.is_object() && doc.contains("type") && doc["type"] == "tests";
  }

  Scene load() {
    parse_document();
    scene_.sourcePath = file_;
    scene_.background = glm::vec3(0.2f);  // darts' default (scene.h of darts-2022)
    scene_.eightBitCurve = EightBitCurve::DartsSrgb;  // darts truncates to 8 bits (src/image.cpp:250)
    JsonCursor root(doc_, "", file_);
    root.expect_object();
    if (holds_tests(doc_)) root["type"].fail("this file holds darts tests (\"type\": \"tests\"), not a scene: run it with wavepath test");
    root.allow_only({"camera", "sampler", "background", "accelerator", "integrator", "materials", "surfaces", "media"});
    // Phase functions are darts materials (include/darts/medium.h:21), so
    // named ones sit among the materials; the media come before the camera
    // and the surfaces that name them.
    if (root.has("materials")) {
      JsonCursor mats = root["materials"].expect_array();
      for (size_t i = 0; i < mats.size(); ++i) {
        JsonCursor m = mats[i].expect_object();
        if (m.has("type") && m["type"].is_string() && is_phase_type(m["type"].string())) phases_[m["name"].string()] = parse_phase(m);
      }
    }
    if (root.has("media")) parse_media(root["media"]);
    if (root.has("camera")) parse_camera(root["camera"]);
    if (root.has("sampler")) parse_sampler(root["sampler"]);
    if (root.has("background")) parse_background(root["background"]);
    if (root.has("accelerator")) parse_accelerator(root["accelerator"]);
    if (root.has("integrator")) parse_integrator(root["integrator"]);
    if (root.has("materials")) {
      JsonCursor mats = root["materials"].expect_array();
      for (size_t i = 0; i < mats.size(); ++i) {
        JsonCursor m = mats[i].expect_object();
        std::string name = m["name"].string();
        if (is_phase_type(m["type"].string())) continue;  // read above
        if (named_.count(name) || phases_.count(name)) m["name"].fail("material \"" + name + "\" is defined twice");
        named_[name] = add_material(m, name);
      }
    }
    if (root.has("surfaces")) {
      JsonCursor surfs = root["surfaces"].expect_array();
      reserve_huge(scene_.triangles, mesh_triangles(surfs) + 2 * surfs.size());
      for (size_t i = 0; i < surfs.size(); ++i) parse_surface(surfs[i], glm::mat4(1.0f));
    }
    if (!unused_media_.empty()) {
      // Likely a misspelt name on the surface meant to bound it.
      JsonCursor media = root["media"];
      for (size_t i = 0; i < media.size(); ++i) {
        if (unused_media_.count(media[i]["name"].string()))
          media[i]["name"].fail("medium \"" + media[i]["name"].string() + "\" is named by no surface and not by the camera");
      }
    }
    return std::move(scene_);
  }

 private:
  glm::vec3 non_negative(const JsonCursor& j) {
    glm::vec3 c = j.color();
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) j.fail("colour components must not be negative");
    return c;
  }

  // ---- textures ------------------------------------------------------------

  uint32_t add_texture(const SceneTexture& t) { return wp::add_texture(scene_, t); }

  // `mapping`: {type: "uv"} (lookups at (u, v, 0)) or {type: "transform",
  // transform: ...} (lookups at the hit point), either with an optional
  // transform applied to the lookup point. Without one, the procedural
  // textures are solid (the course's checker.json and marble.json references
  // show patterns in world space) and images are looked up by UV.
  void parse_mapping(const JsonCursor& j, SceneTexture& t) {
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
  uint32_t texture_param(const JsonCursor& j, int depth = 0, glm::vec3* constant = nullptr) {
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
  void parse_background(const JsonCursor& j) {
    if (!j.is_object()) {
      scene_.background = non_negative(j);
      return;
    }
    j.allow_only({"type", "filename"});
    std::string type = j["type"].string();
    if (type != "image") j["type"].fail("a background is a colour or {\"type\": \"image\", \"filename\": ...} (an environment map)");
    scene_.environment = add_image_texture(scene_, resolve(j["filename"].string()), "loaded by " + file_ + " at " + j.path());
  }

  // A path in the scene file, relative to the scene's folder.
  std::string resolve(const std::string& rel) const {
    fs::path path = fs::path(rel).is_absolute() ? fs::path(rel) : fs::path(file_).parent_path() / rel;
    return path.lexically_normal().string();
  }

  // ---- participating media (darts' final project) ----------------------------

  static bool is_phase_type(const std::string& type) { return type == "isotropic" || type == "henyey-greenstein"; }

  // A phase function: its Henyey-Greenstein asymmetry g (0: isotropic).
  float parse_phase(const JsonCursor& j) {
    j.expect_object();
    std::string type = j["type"].string();
    if (type == "isotropic") {
      j.allow_only({"type", "name"});
      return 0.0f;
    }
    if (type == "henyey-greenstein") {
      j.allow_only({"type", "name", "g"});
      float g = j.number_or("g", 0.0f);
      if (!(g > -1.0f && g < 1.0f)) j["g"].fail("a Henyey-Greenstein g must lie strictly between -1 and 1");
      return g;
    }
    std::string hint = did_you_mean(type, {"isotropic", "henyey-greenstein"});
    j["type"].fail("unknown phase function type \"" + type + "\"" + (hint.empty() ? " (expected isotropic or henyey-greenstein)" : hint));
    return 0.0f;
  }

  // A medium's coefficient colour: a number or [r, g, b], none negative.
  glm::vec3 coefficient(const JsonCursor& j, const char* key, glm::vec3 fallback) {
    if (!j.has(key)) return fallback;
    glm::vec3 c = j[key].color();
    if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f) || !is_finite(c)) j[key].fail("medium coefficients must be finite and not negative");
    return c;
  }

  // One medium of "media", or one given inline where a surface or the
  // camera names it: src/media/*.cpp of darts-2022 (docs/scene-format.md).
  uint32_t add_medium(const JsonCursor& j, const std::string& name) {
    j.expect_object();
    std::string type = j["type"].string();
    SceneMedium m;
    m.name = name;
    if (type == "vacuum") {
      j.allow_only({"type", "name", "phase function"});
      m.kind = MEDIUM_VACUUM;
    } else if (type == "homogeneous") {
      j.allow_only({"type", "name", "phase function", "albedo", "total", "real fraction"});
      // darts' HomogeneousMedium::coeffs (src/media/homogeneous.cpp:45-50).
      const glm::vec3 albedo = coefficient(j, "albedo", glm::vec3(0.8f)), total = coefficient(j, "total", glm::vec3(1.0f)),
                      real = coefficient(j, "real fraction", glm::vec3(1.0f));
      if (!(albedo.x <= 1.0f && albedo.y <= 1.0f && albedo.z <= 1.0f)) j["albedo"].fail("a medium's albedo must lie in [0, 1]");
      if (!(real.x <= 1.0f && real.y <= 1.0f && real.z <= 1.0f)) j["real fraction"].fail("the real fraction must lie in [0, 1]");
      m.sigmaA = total * (1.0f - albedo) * real;
      m.sigmaS = total * albedo * real;
      m.sigmaN = total * (1.0f - real);
    } else if (type == "nanovdb") {
      // darts' NanoVDBMedium (src/media/nanovdb_medium.cpp:43-105).
      j.allow_only({"type", "name", "phase function", "filename", "gridname", "transform", "sigma_a", "sigma_s", "majorant grid"});
      m.kind = MEDIUM_NANOVDB;
      m.sigmaA = coefficient(j, "sigma_a", glm::vec3(0.2f));
      m.sigmaS = coefficient(j, "sigma_s", glm::vec3(0.8f));
      const std::string path = resolve(j["filename"].string());
      const std::string gridName = j.has("gridname") ? j["gridname"].string() : "density";
      auto& grid = grids_[path + '\n' + gridName];
      if (!grid) grid = std::make_shared<const DensityGrid>(read_nanovdb(path, gridName, "read by " + file_ + " at " + j.path()));
      m.grid = grid;
      if (j.has("transform")) m.gridToScene = parse_transform(j["transform"]);
      if (j.has("majorant grid")) {
        // wavepath's: the majorant cells along each axis (1: one majorant
        // for the whole grid), in place of default_majorant_cells.
        const JsonCursor cells = j["majorant grid"];
        const float n = cells.number();
        if (!(n >= 1.0f && n <= float(MAJORANT_GRID_CELLS_MAX) && n == std::floor(n)))
          cells.fail("the majorant grid's cells per axis must be a whole number from 1 to " + std::to_string(MAJORANT_GRID_CELLS_MAX));
        m.majorantCells = glm::uvec3(uint32_t(n));
      }
    } else {
      std::vector<std::string> kinds;
      for (const KindInfo& k : medium_kinds()) kinds.push_back(k.name);
      std::string hint = did_you_mean(type, kinds);
      j["type"].fail("unknown medium type \"" + type + "\"" + (hint.empty() ? " (expected " + kind_list(medium_kinds()) + ")" : hint));
    }
    if (j.has("phase function")) {
      JsonCursor ph = j["phase function"];
      if (ph.is_string()) {
        auto it = phases_.find(ph.string());
        if (it == phases_.end()) ph.fail("no phase function named \"" + ph.string() + "\"");
        m.g = it->second;
      } else {
        m.g = parse_phase(ph);
      }
    }
    scene_.media.push_back(m);
    return uint32_t(scene_.media.size() - 1);
  }

  void parse_media(const JsonCursor& j) {
    j.expect_array();
    for (size_t i = 0; i < j.size(); ++i) {
      JsonCursor m = j[i].expect_object();
      std::string name = m["name"].string();
      if (media_.count(name)) m["name"].fail("medium \"" + name + "\" is defined twice");
      media_[name] = add_medium(m, name);
      unused_media_.insert(name);
    }
  }

  // A medium a surface or the camera names: a name from "media" or an
  // inline medium. WP_INVALID is the vacuum.
  uint32_t medium_of(const JsonCursor& j) {
    if (j.is_string()) {
      auto it = media_.find(j.string());
      if (it == media_.end()) {
        std::vector<std::string> names;
        for (const auto& [n, index] : media_) names.push_back(n);
        j.fail("no medium named \"" + j.string() + "\"" + did_you_mean(j.string(), names));
      }
      unused_media_.erase(j.string());
      return it->second;
    }
    return add_medium(j, j.path());
  }

  // The surface's material with the media its "interior" and "exterior"
  // name (either missing: the vacuum); one material per combination.
  uint32_t with_media(const JsonCursor& surface, uint32_t material) {
    if (!surface.has("interior") && !surface.has("exterior")) return material;
    const uint32_t in = surface.has("interior") ? medium_of(surface["interior"]) : WP_INVALID;
    const uint32_t out = surface.has("exterior") ? medium_of(surface["exterior"]) : WP_INVALID;
    const auto key = std::make_tuple(material, in, out);
    auto it = bounding_.find(key);
    if (it != bounding_.end()) return it->second;
    SceneMaterial m = scene_.materials[material];
    m.boundsMedia = true;
    m.interior = in;
    m.exterior = out;
    scene_.materials.push_back(m);
    return bounding_[key] = uint32_t(scene_.materials.size() - 1);
  }

  void parse_camera(const JsonCursor& j) {
    j.allow_only({"transform", "vfov", "resolution", "fdist", "aperture", "medium"});
    Camera& c = scene_.camera;
    if (j.has("medium")) scene_.cameraMedium = medium_of(j["medium"]);
    if (j.has("transform")) c.toWorld = parse_transform(j["transform"]);
    if (j.has("vfov")) {
      c.vfovDegrees = j["vfov"].number();
      if (!(c.vfovDegrees > 0.0f && c.vfovDegrees < 180.0f)) j["vfov"].fail("vfov must lie strictly between 0 and 180 degrees");
    }
    if (j.has("resolution")) {
      JsonCursor r = j["resolution"].expect_array();
      if (r.size() != 2) r.fail("expected [width, height]");
      c.width = r[size_t(0)].integer(1, MAX_IMAGE_SIZE);
      c.height = r[size_t(1)].integer(1, MAX_IMAGE_SIZE);
    }
    if (j.has("fdist")) c.focusDistance = j["fdist"].positive_number();
    if (j.has("aperture")) {
      c.apertureRadius = j["aperture"].number();
      if (c.apertureRadius < 0.0f) j["aperture"].fail("aperture radius must not be negative");
    }
  }

  void parse_sampler(const JsonCursor& j) {
    j.allow_only({"type", "samples"});
    if (j.has("type")) {
      std::string type = j["type"].string();
      std::optional<SamplerKind> kind = sampler_named(type);
      if (!kind) j["type"].fail("unknown sampler type \"" + type + "\" (expected independent or cmj)");
      scene_.sampler = *kind;
    }
    if (j.has("samples")) scene_.samplesPerPixel = j["samples"].integer(1, MAX_SAMPLES_PER_PIXEL);
  }

  void parse_accelerator(const JsonCursor& j) {
    j.allow_only({"type", "max_leaf_size", "split_method"});
    if (j.has("type")) {
      std::string type = j["type"].string();
      if (type != "bbh" && type != "bvh") j["type"].fail("unknown accelerator type \"" + type + "\" (expected \"bbh\")");
    }
    scene_.accelerator.maxLeafSize = j.integer_or("max_leaf_size", scene_.accelerator.maxLeafSize, 1, BVH_MAX_LEAF_SIZE);
    if (j.has("split_method")) {
      std::string s = j["split_method"].string();
      if (s == "sah") scene_.accelerator.split = SplitMethod::Sah;
      else if (s == "middle") scene_.accelerator.split = SplitMethod::Middle;
      else if (s == "equal") scene_.accelerator.split = SplitMethod::Equal;
      else if (s == "clustered sah") scene_.accelerator.split = SplitMethod::ClusteredSah;
      else j["split_method"].fail("unknown split method \"" + s + "\" (expected sah, clustered sah, middle or equal)");
    }
  }

  void parse_integrator(const JsonCursor& j) {
    IntegratorSettings& s = scene_.integrator;
    if (j.has("type")) {
      std::string type = j["type"].string();
      std::optional<IntegratorKind> kind = integrator_named(type);
      if (!kind) j["type"].fail("unknown integrator type \"" + type + "\" (expected " + kIntegratorNames + ")");
      s.kind = *kind;
    }
    if (s.kind == IntegratorKind::PhotonMapper) {
      // wavepath's photon mapper (darts leaves the integrator to the final
      // project); the search keys are those of darts' photon map test.
      j.allow_only({"type", "max bounces", "russian roulette", "recursive", "power", "photons", "search radius", "search count", "photon seed"});
      s.photons = uint32_t(j.integer_or("photons", int(s.photons), 1, 1 << 22));
      s.searchRadius = j.number_or("search radius", s.searchRadius);
      if (!(s.searchRadius > 0.0f && std::isfinite(s.searchRadius))) j["search radius"].fail("the search radius must be positive");
      s.searchCount = uint32_t(j.integer_or("search count", int(s.searchCount), 0, int(PHOTON_SEARCH_MAX)));
      s.photonSeed = uint32_t(j.integer_or("photon seed", int(s.photonSeed), 0, 1 << 30));
    } else {
      j.allow_only({"type", "max bounces", "russian roulette", "recursive", "power"});
    }
    s.maxBounces = j.integer_or("max bounces", s.maxBounces, 0, 1024);
    if (j.has("russian roulette")) {
      const nlohmann::json& rr = j["russian roulette"].json();
      if (rr.is_boolean()) s.russianRouletteDepth = rr.get<bool>() ? 3 : 1 << 30;
      else s.russianRouletteDepth = j["russian roulette"].integer(1, 1 << 30);
    }
    // The MIS heuristic's exponent: any makes the weights sum to one; past
    // 16 it is the maximum heuristic in all but name.
    if (j.has("power")) {
      s.misPower = j["power"].number();
      if (!(s.misPower >= 0.0f && s.misPower <= 16.0f)) j["power"].fail("the MIS exponent must be from 0 to 16");
    }
    // "recursive" picks darts' recursive or iterative implementation; both
    // estimate the same image, and wavepath is always iterative.
    if (j.has("recursive") && !j["recursive"].json().is_boolean()) j["recursive"].fail("expected true or false");
  }

  // ---- materials -------------------------------------------------------------
  // A material's keys are its kind's parameters (src/scene/materials/): a
  // parameter "g.k" is key k of an object "g"; a number or colour may be a
  // texture where its kind names one to stand for it.

  static Complaint complaint_at(const JsonCursor& j) {
    return [j](const std::string& problem) { j.fail(problem); };
  }

  uint32_t add_material(const JsonCursor& j, const std::string& name) {
    const std::string type = j["type"].string();
    const std::optional<uint32_t> kind = kind_named(material_kinds(), type);
    if (!kind) {
      std::vector<std::string> kinds;
      for (const KindInfo& k : material_kinds()) kinds.push_back(k.name);
      std::string hint = did_you_mean(type, kinds);
      j["type"].fail("unknown material type \"" + type + "\"" + (hint.empty() ? " (expected " + kind_list(material_kinds()) + ")" : hint));
    }
    const MaterialModule& module = material_module(*kind);
    std::vector<std::string> keys = {"type", "name"};
    std::map<std::string, std::vector<std::string>> groups;
    for (const ParamSpec& p : module.params) {
      const size_t dot = p.name.find('.');
      if (dot == std::string::npos) keys.push_back(p.name);
      else groups[p.name.substr(0, dot)].push_back(p.name.substr(dot + 1));
    }
    j.allow_only(keys);
    MaterialParams params(*kind, name, complaint_at(j));
    for (const ParamSpec& p : module.params) {
      const size_t dot = p.name.find('.');
      if (p.type == ParamType::Group) {
        if (!j.has(p.name.c_str())) continue;
        j[p.name.c_str()].expect_object().allow_only(groups[p.name]);
        params.flag(p.name, true, complaint_at(j[p.name.c_str()]));
        continue;
      }
      const std::string group = dot == std::string::npos ? "" : p.name.substr(0, dot);
      const std::string key = dot == std::string::npos ? p.name : p.name.substr(dot + 1);
      if (!group.empty() && !j.has(group.c_str())) continue;
      const JsonCursor parent = group.empty() ? j : j[group.c_str()];
      if (!parent.has(key.c_str())) continue;
      read_param(parent[key.c_str()], p, params, name + "/" + key);
    }
    return wp::add_material(scene_, params);
  }

  void read_param(const JsonCursor& v, const ParamSpec& p, MaterialParams& params, const std::string& name) {
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
  uint32_t material_part(const JsonCursor& j, const std::string& name) {
    if (!j.is_string()) return add_material(j.expect_object(), name);
    auto it = named_.find(j.string());
    if (it == named_.end()) j.fail("no material named \"" + j.string() + "\" (materials must be defined before use)");
    return it->second;
  }

  uint32_t material_of(const JsonCursor& surface) {
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

  uint32_t interface_material() {
    if (interface_ == WP_INVALID) interface_ = wp::add_material(scene_, MaterialParams(MAT_INTERFACE, "interface", complaint_at(JsonCursor(doc_, "", file_))));
    return interface_;
  }

  void parse_surface(const JsonCursor& j, const glm::mat4& parent) {
    j.expect_object();
    std::string type = j["type"].string();
    glm::mat4 xform = parent * (j.has("transform") ? parse_transform(j["transform"]) : glm::mat4(1.0f));
    if (type == "sphere") {
      j.allow_only({"type", "name", "radius", "transform", "material", "interior", "exterior"});
      float radius = j.has("radius") ? j["radius"].positive_number() : 1.0f;
      SceneSphere s;
      s.toWorld = xform * glm::scale(glm::mat4(1.0f), glm::vec3(radius));
      // Its bounds (centre +- the rows' lengths) must be finite too.
      const glm::mat3 rows = glm::transpose(glm::mat3(s.toWorld));
      const glm::vec3 centre(s.toWorld[3]), extent(glm::length(rows[0]), glm::length(rows[1]), glm::length(rows[2]));
      if (!is_finite(centre + extent) || !is_finite(centre - extent)) j.fail(std::string("sphere: ") + kPastFloatRange);
      s.material = material_of(j);
      if (scene_.materials[s.material].emission != WP_INVALID && !is_similarity(glm::mat3(s.toWorld)))
        j.fail("emissive spheres must keep their shape (uniform scale): an emissive ellipsoid cannot be sampled yet");
      scene_.spheres.push_back(s);
    } else if (type == "quad") {
      j.allow_only({"type", "name", "size", "transform", "material", "interior", "exterior"});
      glm::vec2 size(1.0f);
      if (j.has("size")) {
        JsonCursor sz = j["size"];
        if (sz.is_number()) size = glm::vec2(sz.number());
        else if (sz.is_array() && sz.size() == 2) size = glm::vec2(sz[size_t(0)].number(), sz[size_t(1)].number());
        else sz.fail("expected a number or [width, height]");
        if (!(size.x > 0.0f && size.y > 0.0f)) sz.fail("quad size must be positive (a zero-area quad cannot be rendered)");
      }
      uint32_t mat = material_of(j);
      glm::vec3 c[4] = {{-0.5f * size.x, -0.5f * size.y, 0}, {0.5f * size.x, -0.5f * size.y, 0},
                        {0.5f * size.x, 0.5f * size.y, 0}, {-0.5f * size.x, 0.5f * size.y, 0}};
      for (glm::vec3& p : c) p = glm::vec3(xform * glm::vec4(p, 1.0f));
      // The quad's front is its transformed +Z normal, as in darts; a mirroring
      // transform reverses the winding, so restore it.
      bool mirrored = glm::determinant(glm::mat3(xform)) < 0.0f;
      static const int kWinding[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 2, 1}, {0, 3, 2}}};
      static const glm::vec2 kCornerUv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // planar UVs over the quad
      for (const auto& t : kWinding[mirrored ? 1 : 0]) {
        SceneTriangleShading& sh = add_shading(add_triangle(j, c[t[0]], c[t[1]], c[t[2]], mat));
        sh.hasUvs = true;
        for (int k = 0; k < 3; ++k) sh.uv[k] = kCornerUv[t[k]];
      }
    } else if (type == "triangle") {
      j.allow_only({"type", "name", "positions", "normals", "uvs", "transform", "material", "interior", "exterior"});
      JsonCursor pos = j["positions"].expect_array();
      if (pos.size() != 3) pos.fail("expected 3 vertex positions, got " + std::to_string(pos.size()));
      glm::vec3 v[3];
      for (size_t i = 0; i < 3; ++i) v[i] = glm::vec3(xform * glm::vec4(pos[i].vec3(), 1.0f));
      SceneTriangle& tri = add_triangle(pos, v[0], v[1], v[2], material_of(j));
      if (j.has("normals")) {
        JsonCursor nrm = j["normals"].expect_array();
        if (nrm.size() != 3) nrm.fail("expected 3 vertex normals, got " + std::to_string(nrm.size()));
        glm::mat3 normalXform = normal_matrix(xform);
        SceneTriangleShading& sh = add_shading(tri);
        for (size_t i = 0; i < 3; ++i) {
          glm::vec3 n = normalXform * nrm[i].vec3();
          if (!(glm::length(n) > 0.0f)) nrm[i].fail("a vertex normal must not be zero");
          sh.n[i] = glm::normalize(n);
        }
        sh.hasNormals = true;
      }
      if (j.has("uvs")) {
        JsonCursor uvs = j["uvs"].expect_array();
        if (uvs.size() != 3) uvs.fail("expected 3 vertex UVs, got " + std::to_string(uvs.size()));
        SceneTriangleShading& sh = tri.shading == WP_INVALID ? add_shading(tri) : scene_.triangleShading[tri.shading];
        for (size_t i = 0; i < 3; ++i) {
          JsonCursor uv = uvs[i].expect_array();
          if (uv.size() != 2) uv.fail("expected [u, v]");
          sh.uv[i] = glm::vec2(uv[size_t(0)].number(), uv[size_t(1)].number());
        }
        sh.hasUvs = true;
      }
    } else if (type == "mesh") {
      j.allow_only({"type", "name", "filename", "transform", "material", "material prefix", "interior", "exterior"});
      load_mesh(j, xform);
    } else if (type == "point_light") {
      // wavepath extension (CS184's point lights): radiant intensity in W/sr.
      j.allow_only({"type", "name", "position", "intensity", "transform"});
      ScenePointLight l;
      l.position = glm::vec3(xform * glm::vec4(j.vec3_or("position", glm::vec3(0.0f)), 1.0f));
      if (!is_finite(l.position)) j.fail(std::string("point light: ") + kPastFloatRange);
      l.intensity = non_negative(j["intensity"]);
      scene_.pointLights.push_back(l);
    } else if (type == "spot_light" || type == "directional_light") {
      // wavepath extensions (glTF's KHR_lights_punctual): a spot's intensity
      // in W/sr within its cone, a directional light's irradiance in W/m^2.
      const bool spot = type == "spot_light";
      if (spot) j.allow_only({"type", "name", "position", "direction", "intensity", "inner_angle", "outer_angle", "transform"});
      else j.allow_only({"type", "name", "direction", "irradiance", "transform"});
      ScenePointLight l;
      l.kind = spot ? ScenePointLight::Kind::Spot : ScenePointLight::Kind::Directional;
      l.position = glm::vec3(xform * glm::vec4(j.vec3_or("position", glm::vec3(0.0f)), 1.0f));
      const glm::vec3 d = glm::vec3(xform * glm::vec4(j["direction"].vec3(), 0.0f));
      if (!(glm::length(d) > 0.0f) || !is_finite(d)) j["direction"].fail("the direction must be a nonzero vector");
      l.direction = glm::normalize(d);
      if (!is_finite(l.position)) j.fail(std::string("light: ") + kPastFloatRange);
      l.intensity = non_negative(j[spot ? "intensity" : "irradiance"]);
      if (spot) {
        const float inner = j.number_or("inner_angle", 0.0f), outer = j.number_or("outer_angle", 45.0f);
        if (!(inner >= 0.0f && inner < outer && outer <= 90.0f))
          j.fail("a spot light needs 0 <= inner_angle < outer_angle <= 90 (degrees)");
        l.cosInner = std::cos(glm::radians(inner));
        l.cosOuter = std::cos(glm::radians(outer));
      }
      scene_.pointLights.push_back(l);
    } else if (type == "group") {
      j.allow_only({"type", "name", "children", "transform"});
      JsonCursor children = j["children"].expect_array();
      for (size_t i = 0; i < children.size(); ++i) parse_surface(children[i], xform);
    } else {
      const std::vector<std::string> kinds = {"sphere", "quad", "triangle", "mesh", "group", "point_light", "spot_light", "directional_light"};
      std::string hint = did_you_mean(type, kinds);
      j["type"].fail("unknown surface type \"" + type + "\"" +
                     (hint.empty() ? " (expected sphere, quad, triangle, mesh, group, point_light, spot_light or directional_light)" : hint));
    }
  }

  static bool is_similarity(const glm::mat3& m) {
    float a = glm::length(m[0]), b = glm::length(m[1]), c = glm::length(m[2]);
    auto close = [](float x, float y) { return std::fabs(x - y) <= 1e-4f * std::max(x, y); };
    return close(a, b) && close(b, c) && std::fabs(glm::dot(m[0], m[1])) <= 1e-4f * a * b &&
           std::fabs(glm::dot(m[1], m[2])) <= 1e-4f * b * c && std::fabs(glm::dot(m[0], m[2])) <= 1e-4f * a * c;
  }

  SceneTriangle& add_triangle(const JsonCursor& where, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
    if (!is_finite(a) || !is_finite(b) || !is_finite(c)) where.fail(std::string("triangle: ") + kPastFloatRange);
    if (glm::length(glm::cross(b - a, c - a)) == 0.0f) where.fail("triangle has zero area");
    SceneTriangle t;
    t.v[0] = a;
    t.v[1] = b;
    t.v[2] = c;
    t.material = material;
    scene_.triangles.push_back(t);
    return scene_.triangles.back();
  }

  // Per-vertex data for triangle t, which has none yet.
  SceneTriangleShading& add_shading(SceneTriangle& t) {
    t.shading = uint32_t(scene_.triangleShading.size());
    return scene_.triangleShading.emplace_back();
  }

  // The OBJ file of mesh surface j. A mesh placed many times (a grid of
  // dragons) is parsed once.
  const ObjFile& mesh_of(const JsonCursor& j) {
    std::string path = resolve(j["filename"].string());
    auto cached = meshes_.find(path);
    if (cached == meshes_.end()) {
      try {
        cached = meshes_.emplace(path, load_obj(path)).first;
        for (const std::string& f : cached->second.files) scene_.inputFiles.push_back(f);
        // A file of no OBJ statements (not an OBJ at all: a typo in the name,
        // a path past the scene's folder) parses as an empty mesh; say so
        // rather than render an image without it.
        if (cached->second.mesh.triangle_count() == 0) {
          std::fprintf(stderr, "wavepath: warning: %s: no triangles (is it an OBJ file?), loaded by %s at %s\n", path.c_str(),
                       file_.c_str(), j["filename"].path().c_str());
        }
      } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + " (loaded by " + file_ + " at " + j.path() + ")");
      }
    }
    return cached->second;
  }

  // The triangles the meshes among `surfaces` (groups included) will add, so
  // that the triangle array is allocated once: 100 dragons are 10M triangles
  // of 104 bytes, and growing the array by doubling copied it and faulted its
  // pages in several times over. Surfaces that are not well formed are
  // skipped here; parse_surface reports them.
  size_t mesh_triangles(const JsonCursor& surfaces) {
    size_t n = 0;
    for (size_t i = 0; i < surfaces.size(); ++i) {
      JsonCursor s = surfaces[i];
      if (!s.is_object() || !s.has("type") || !s["type"].is_string()) continue;
      std::string type = s["type"].string();
      if (type == "mesh" && s.has("filename") && s["filename"].is_string()) {
        n += mesh_of(s).mesh.triangle_count();
      } else if (type == "group" && s.has("children") && s["children"].is_array()) {
        n += mesh_triangles(s["children"]);
      }
    }
    return n;
  }

  void load_mesh(const JsonCursor& j, const glm::mat4& xform) {
    std::string rel = j["filename"].string();
    const ObjFile& obj = mesh_of(j);
    const SceneMesh& mesh = obj.mesh;
    bool override = j.has("material");
    uint32_t fixed = override ? material_of(j) : 0;
    std::string prefix = j.has("material prefix") ? j["material prefix"].string() : "";
    std::vector<uint32_t> mtlToScene(obj.materials.size(), fixed);
    for (size_t i = 0; i < obj.materials.size() && !override; ++i) {
      const ObjMaterial& om = obj.materials[i];
      auto named = named_.find(prefix + om.name);
      if (named != named_.end()) {  // a scene material of that name overrides the MTL
        mtlToScene[i] = named->second;
        continue;
      }
      // Kd (or map_Kd) and Ke as a Lambertian that may emit; Ke without Kd a light.
      const bool light = is_nonzero(om.emission) && !is_nonzero(om.diffuse);
      MaterialParams m(light ? MAT_LIGHT : MAT_LAMBERTIAN, prefix + om.name, complaint_at(j));
      if (is_nonzero(om.emission)) m.texture("emit", add_texture(constant_texture(glm::max(om.emission, 0.0f))));
      if (light) {
      } else if (!om.diffuseMap.empty()) {
        m.texture("albedo", add_image_texture(scene_, om.diffuseMap, "map_Kd of " + om.name + ", loaded by " + file_ + " at " + j.path()));
      } else {
        m.texture("albedo", add_texture(constant_texture(glm::clamp(om.diffuse, 0.0f, 1.0f))));
      }
      mtlToScene[i] = wp::add_material(scene_, m);
    }
    if (!override)
      for (uint32_t& m : mtlToScene) m = with_media(j, m);
    if (!override && std::find(mesh.materials.begin(), mesh.materials.end(), WP_INVALID) != mesh.materials.end())
      j.fail("mesh " + rel + " has faces without a material: give the surface a \"material\"");
    add_mesh(scene_, mesh, xform, mtlToScene, override ? fixed : WP_INVALID,
             [&](const std::string& problem) { j.fail("mesh " + rel + ", " + problem); });
  }

  // ---- test files (darts_tests.h) ---------------------------------------------

 public:
  bool is_test_file() {
    parse_document();
    return holds_tests(doc_);
  }

  std::vector<DartsTest> load_tests() {
    parse_document();
    JsonCursor root(doc_, "", file_);
    root.expect_object();
    if (!holds_tests(doc_)) root.fail("this file holds no darts tests (\"type\": \"tests\"): render it with wavepath render");
    root.allow_only({"type", "tests"});
    JsonCursor tests = root["tests"].expect_array();
    std::vector<DartsTest> out(tests.size());
    for (size_t i = 0; i < tests.size(); ++i) {
      out[i].where = file_ + ": at " + tests[i].path();
      const nlohmann::json& raw = tests[i].json();
      if (raw.is_object() && raw.contains("name") && raw["name"].is_string()) out[i].name = raw["name"].get<std::string>();
      try {
        DartsImporter reader(file_);  // each test has its own materials, as darts makes each anew
        reader.parse_test(tests[i], out[i]);
        out[i].scene = std::move(reader.scene_);
        out[i].scene.sourcePath = file_;
      } catch (const InputError& e) {
        out[i].loadError = e.what();
      }
    }
    return out;
  }

 private:
  // Sizes as darts' ScatterTest and SampleTest read them (test.cpp).
  static void parse_sampling_options(const JsonCursor& j, DartsTest& t) {
    t.name = j["name"].string();
    if (t.name.empty() || t.name.find('/') != std::string::npos) j["name"].fail("a test's name names its output files: not empty, no '/'");
    if (j.has("image size")) {
      JsonCursor size = j["image size"].expect_array();
      if (size.size() != 2) size.fail("expected [width, height]");
      t.imageSize = glm::ivec2(size[size_t(0)].integer(1, 8192), size[size_t(1)].integer(1, 8192));
    }
    if (uint64_t(t.imageSize.x) * uint64_t(t.imageSize.y) > (uint64_t(1) << 23))
      j["image size"].fail("more than 2^23 cells (4096 x 2048): the histogram and the pdf would need gigabytes");
    t.samplesPerPixel = uint64_t(j.integer_or("spp", 1000, 1, 1 << 24));
    t.upSamples = uint32_t(j.integer_or("up samples", 4, 1, 64));
    t.superSamples = uint32_t(j.integer_or("super samples", 32, 1, 256));
    if (t.samplesPerPixel * uint64_t(t.imageSize.x) * uint64_t(t.imageSize.y) > (uint64_t(1) << 34))
      j.fail("spp x image size asks for more than 2^34 samples");
    if (uint64_t(t.imageSize.x) * t.upSamples > 16384 || uint64_t(t.imageSize.y) * t.upSamples > 16384)
      j.fail("image size x up samples must stay within 16384 pixels");
  }

  static glm::vec3 unit_vector(const JsonCursor& j) {
    glm::vec3 v = j.vec3();
    if (!(glm::length(v) > 0.0f) || !is_finite(v)) j.fail("expected a non-zero direction");
    return glm::normalize(v);
  }

  void parse_test(const JsonCursor& j, DartsTest& t) {
    j.expect_object();
    std::string type = j["type"].string();
    if (type == "scatter material" || type == "sample material") {
      bool sampling = type == "sample material";
      if (sampling) j.allow_only({"type", "name", "material", "normal", "incoming", "image size", "spp", "up samples", "super samples"});
      else j.allow_only({"type", "name", "material", "normal", "incoming", "image size", "spp", "up samples"});
      t.kind = sampling ? DartsTestKind::SampleMaterial : DartsTestKind::ScatterMaterial;
      parse_sampling_options(j, t);
      t.material = add_material(j["material"].expect_object(), t.name);
      if (scene_.materials[t.material].kind == MAT_LIGHT) j["material"].fail("a diffuse_light scatters nothing to test");
      if (scene_.materials[t.material].kind == MAT_INTERFACE) j["material"].fail("an interface scatters nothing to test");
      t.normal = unit_vector(j["normal"]);
      t.incoming = j.has("incoming") ? unit_vector(j["incoming"]) : sampling ? glm::normalize(glm::vec3(0.25f, 0.0f, -1.0f))
                                                                               : glm::normalize(glm::vec3(0.0f, 0.25f, -1.0f));
    } else if (type == "sample surface") {
      j.allow_only({"type", "name", "surface", "surfaces", "image size", "spp", "up samples", "super samples"});
      t.kind = DartsTestKind::SampleSurface;
      parse_sampling_options(j, t);
      parse_test_surfaces(j, t, true);
    } else if (type == "intersection") {
      j.allow_only({"type", "surface", "surfaces", "ray", "t", "p", "gn", "sn", "should_hit", "threshold"});
      t.kind = DartsTestKind::Intersection;
      t.name = "intersection";
      parse_test_surfaces(j, t, false);
      JsonCursor ray = j["ray"].expect_object();
      ray.allow_only({"origin", "direction"});
      t.rayOrigin = ray["origin"].vec3();
      t.rayDirection = ray["direction"].vec3();
      if (!(glm::length(t.rayDirection) > 0.0f)) ray["direction"].fail("expected a non-zero direction");
      t.t = j["t"].number();
      t.p = j["p"].vec3();
      t.gn = j["gn"].vec3();
      t.sn = j["sn"].vec3();
      if (j.has("should_hit")) {
        if (!j["should_hit"].json().is_boolean()) j["should_hit"].fail("expected true or false");
        t.shouldHit = j["should_hit"].json().get<bool>();
      }
      t.threshold = j.number_or("threshold", 1e-5f);
    } else if (type == "photon map") {
      // darts-2022 src/tests/photon_map_test.cpp: its keys and defaults.
      j.allow_only({"type", "name", "image size", "spp", "up samples", "super samples", "search radius", "search count", "transform"});
      t.kind = DartsTestKind::PhotonMap;
      parse_sampling_options(j, t);
      t.searchRadius = j.number_or("search radius", 0.1f);
      if (!(t.searchRadius > 0.0f) || !std::isfinite(t.searchRadius)) j["search radius"].fail("expected a positive radius");
      t.searchCount = int(j.integer_or("search count", 50, 0, 1 << 20));
      if (j.has("transform")) t.transform = parse_transform(j["transform"]);
      if (!(std::abs(glm::determinant(t.transform)) > 1e-12f)) j["transform"].fail("the disk's transform is singular: it has no density");
    } else {
      const std::vector<std::string> kinds = {"scatter material", "sample material", "sample surface", "intersection", "photon map"};
      std::string hint = did_you_mean(type, kinds);
      j["type"].fail("unknown test type \"" + type + "\"" +
                     (hint.empty() ? " (expected scatter material, sample material, sample surface, intersection or photon map)" : hint));
    }
  }

  // A test's "surface", or its "surfaces" (a group, or one surface). For
  // sampling, each child of the group gets an emitting material of its own,
  // so that the runner can pick children uniformly, as darts' group does.
  void parse_test_surfaces(const JsonCursor& j, DartsTest& t, bool sampling) {
    if (j.has("surface") == j.has("surfaces")) j.fail("a surface test needs \"surface\" or \"surfaces\" (one of them)");
    JsonCursor top = j.has("surface") ? j["surface"] : j["surfaces"];
    top.expect_object();
    std::vector<JsonCursor> children;
    glm::mat4 xform(1.0f);
    if (top.has("type") && top["type"].is_string() && top["type"].string() == "group") {
      top.allow_only({"type", "name", "children", "transform"});
      if (top.has("transform")) xform = parse_transform(top["transform"]);
      JsonCursor list = top["children"].expect_array();
      for (size_t i = 0; i < list.size(); ++i) children.push_back(list[i]);
      if (children.empty()) list.fail("a group to sample needs at least one child");
    } else {
      children.push_back(top);
    }
    for (const JsonCursor& child : children) {
      const size_t triangles = scene_.triangles.size(), spheres = scene_.spheres.size(), points = scene_.pointLights.size();
      parse_surface(child, xform);
      if (!sampling) continue;
      if (scene_.pointLights.size() != points) child.fail("a point light has no surface to sample");
      MaterialParams m(MAT_LIGHT, "child " + std::to_string(t.childMaterials.size()), complaint_at(child));
      m.texture("emit", add_texture(constant_texture(glm::vec3(1.0f))));
      // Materials defined inside children come first; this one goes last.
      for (size_t i = triangles; i < scene_.triangles.size(); ++i) scene_.triangles[i].material = uint32_t(scene_.materials.size());
      for (size_t i = spheres; i < scene_.spheres.size(); ++i) {
        if (!is_similarity(glm::mat3(scene_.spheres[i].toWorld)))
          child.fail("spheres are sampled by the cone they subtend: an ellipsoid (non-uniform scale) cannot be");
        scene_.spheres[i].material = uint32_t(scene_.materials.size());
      }
      t.childMaterials.push_back(wp::add_material(scene_, m));
    }
  }

  std::string file_;
  nlohmann::json doc_;
  Scene scene_;
  std::map<std::string, ObjFile> meshes_;  // parsed OBJ files by path
  std::map<std::string, uint32_t> named_;
  std::map<std::string, float> phases_;     // named phase functions: their g
  std::map<std::string, uint32_t> media_;   // named media
  std::set<std::string> unused_media_;      // named media no surface or camera names yet
  std::map<std::string, std::shared_ptr<const DensityGrid>> grids_;  // by file and grid name: each read once
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> bounding_;  // (material, interior, exterior): its copy bounding them
  uint32_t interface_ = WP_INVALID;         // the material of surfaces with "material": null
};

}  // namespace

Scene import_darts(const std::string& path) {
  return DartsImporter(path).load();
}

bool is_darts_test_file(const std::string& path) {
  try {
    return DartsImporter(path).is_test_file();
  } catch (const InputError&) {
    return false;  // not JSON, or unreadable: the scene loader says what is wrong
  }
}

std::vector<DartsTest> import_darts_tests(const std::string& path) {
  return DartsImporter(path).load_tests();
}

}  // namespace wp
