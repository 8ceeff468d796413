// import_darts.cpp — Dartmouth CS 87 "darts" JSON scenes, with OBJ meshes
// (docs/scene-format.md): the document, its settings (camera, sampler,
// accelerator, integrator) and the entry points of importers.h and
// darts_tests.h. The importer's class is in darts_importer.h; its other
// parts are darts_materials.cpp, darts_media.cpp, darts_surfaces.cpp and
// darts_test_files.cpp.
#include "scene/importers.h"

#include <cmath>
#include <filesystem>
#include <optional>

#include "scene/darts_importer.h"

namespace wp {

namespace darts_import {

namespace fs = std::filesystem;

void DartsImporter::parse_document() { doc_ = read_json_file(file_); }

bool DartsImporter::holds_tests(const nlohmann::json& doc) {
  return doc.is_object() && doc.contains("type") && doc["type"] == "tests";
}

Scene DartsImporter::load() {
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

glm::vec3 DartsImporter::non_negative(const JsonCursor& j) {
  glm::vec3 c = j.color();
  if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) j.fail("colour components must not be negative");
  return c;
}

// A path in the scene file, relative to the scene's folder.
std::string DartsImporter::resolve(const std::string& rel) const {
  fs::path path = fs::path(rel).is_absolute() ? fs::path(rel) : fs::path(file_).parent_path() / rel;
  return path.lexically_normal().string();
}

// ---- settings -------------------------------------------------------------

void DartsImporter::parse_camera(const JsonCursor& j) {
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

void DartsImporter::parse_sampler(const JsonCursor& j) {
  j.allow_only({"type", "samples"});
  if (j.has("type")) {
    std::string type = j["type"].string();
    std::optional<SamplerKind> kind = sampler_named(type);
    if (!kind) j["type"].fail("unknown sampler type \"" + type + "\" (expected independent or cmj)");
    scene_.sampler = *kind;
  }
  if (j.has("samples")) scene_.samplesPerPixel = j["samples"].integer(1, MAX_SAMPLES_PER_PIXEL);
}

void DartsImporter::parse_accelerator(const JsonCursor& j) {
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

void DartsImporter::parse_integrator(const JsonCursor& j) {
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
    j.allow_only({"type", "max bounces", "russian roulette", "recursive", "power", "photons", "search radius", "search count", "photon seed", "spectral"});
    s.photons = uint32_t(j.integer_or("photons", int(s.photons), 1, 1 << 22));
    s.searchRadius = j.number_or("search radius", s.searchRadius);
    if (!(s.searchRadius > 0.0f && std::isfinite(s.searchRadius))) j["search radius"].fail("the search radius must be positive");
    s.searchCount = uint32_t(j.integer_or("search count", int(s.searchCount), 0, int(PHOTON_SEARCH_MAX)));
    s.photonSeed = uint32_t(j.integer_or("photon seed", int(s.photonSeed), 0, 1 << 30));
  } else {
    j.allow_only({"type", "max bounces", "russian roulette", "recursive", "power", "spectral"});
  }
  // wavepath's own key: render spectrally (spectral.glsl).
  if (j.has("spectral")) s.spectral = j["spectral"].boolean();
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
  if (j.has("recursive")) j["recursive"].boolean();
}

}  // namespace darts_import

using darts_import::DartsImporter;

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
