// darts_media.cpp — the darts importer's participating media and phase
// functions (darts' final project), and the materials of surfaces that
// bound media (darts_importer.h).
#include <cmath>
#include <memory>
#include <tuple>

#include "scene/darts_importer.h"

namespace wp::darts_import {

// ---- participating media (darts' final project) ----------------------------

bool DartsImporter::is_phase_type(const std::string& type) { return type == "isotropic" || type == "henyey-greenstein"; }

// A phase function: its Henyey-Greenstein asymmetry g (0: isotropic).
float DartsImporter::parse_phase(const JsonCursor& j) {
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
glm::vec3 DartsImporter::coefficient(const JsonCursor& j, const char* key, glm::vec3 fallback) {
  if (!j.has(key)) return fallback;
  glm::vec3 c = j[key].color();
  if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f) || !is_finite(c)) j[key].fail("medium coefficients must be finite and not negative");
  return c;
}

// One medium of "media", or one given inline where a surface or the
// camera names it: src/media/*.cpp of darts-2022 (docs/scene-format.md).
uint32_t DartsImporter::add_medium(const JsonCursor& j, const std::string& name) {
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

void DartsImporter::parse_media(const JsonCursor& j) {
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
uint32_t DartsImporter::medium_of(const JsonCursor& j) {
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
uint32_t DartsImporter::with_media(const JsonCursor& surface, uint32_t material) {
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

}  // namespace wp::darts_import
