// darts_test_files.cpp — darts' test files (darts_tests.h): material
// scattering and sampling, surface sampling, intersection and photon map
// tests, each read into a scene of its own (darts_importer.h).
#include <cmath>

#include "scene/darts_importer.h"

namespace wp::darts_import {

// ---- test files (darts_tests.h) ---------------------------------------------

bool DartsImporter::is_test_file() {
  parse_document();
  return holds_tests(doc_);
}

std::vector<DartsTest> DartsImporter::load_tests() {
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

// Sizes as darts' ScatterTest and SampleTest read them (test.cpp).
void DartsImporter::parse_sampling_options(const JsonCursor& j, DartsTest& t) {
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

glm::vec3 DartsImporter::unit_vector(const JsonCursor& j) {
  glm::vec3 v = j.vec3();
  if (!(glm::length(v) > 0.0f) || !is_finite(v)) j.fail("expected a non-zero direction");
  return glm::normalize(v);
}

void DartsImporter::parse_test(const JsonCursor& j, DartsTest& t) {
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
void DartsImporter::parse_test_surfaces(const JsonCursor& j, DartsTest& t, bool sampling) {
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

}  // namespace wp::darts_import
