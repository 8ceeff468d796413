#include "scene/load_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "scene/json_cursor.h"
#include "scene/obj_mesh.h"
#include "scene/transform.h"
#include "util/error.h"

namespace wp {

namespace {

namespace fs = std::filesystem;

bool is_nonzero(glm::vec3 c) {
  return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f;
}

class SceneLoader {
 public:
  explicit SceneLoader(std::string path) : file_(std::move(path)) {}

  Scene load() {
    std::ifstream in(file_, std::ios::binary);
    if (!in) throw InputError(file_ + ": cannot open scene file (" + (fs::exists(file_) ? "permission denied" : "no such file") + ")");
    std::stringstream text;
    text << in.rdbuf();
    try {
      doc_ = nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(file_ + ":" + location_of(text.str(), e.byte) + ": JSON syntax error: " + describe(e));
    }
    scene_.sourcePath = file_;
    JsonCursor root(doc_, "", file_);
    root.expect_object();
    root.allow_only({"camera", "sampler", "background", "accelerator", "integrator", "materials", "surfaces", "media"});
    if (root.has("media")) root["media"].fail("participating media are not supported yet");
    if (root.has("camera")) parse_camera(root["camera"]);
    if (root.has("sampler")) parse_sampler(root["sampler"]);
    if (root.has("background")) scene_.background = non_negative(root["background"]);
    if (root.has("accelerator")) parse_accelerator(root["accelerator"]);
    if (root.has("integrator")) parse_integrator(root["integrator"]);
    if (root.has("materials")) {
      JsonCursor mats = root["materials"].expect_array();
      for (size_t i = 0; i < mats.size(); ++i) {
        JsonCursor m = mats[i].expect_object();
        std::string name = m["name"].string();
        if (named_.count(name)) m["name"].fail("material \"" + name + "\" is defined twice");
        named_[name] = add_material(m, name);
      }
    }
    if (root.has("surfaces")) {
      JsonCursor surfs = root["surfaces"].expect_array();
      for (size_t i = 0; i < surfs.size(); ++i) parse_surface(surfs[i], glm::mat4(1.0f));
    }
    return std::move(scene_);
  }

 private:
  static std::string location_of(const std::string& text, size_t byte) {
    // nlohmann reports the byte after the offending token; count lines up to it.
    size_t end = std::min(byte == 0 ? 0 : byte - 1, text.size());
    int line = 1;
    int column = 1;
    for (size_t i = 0; i < end; ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    return std::to_string(line) + ":" + std::to_string(column);
  }

  static std::string describe(const nlohmann::json::parse_error& e) {
    // what() is "[json.exception.parse_error.101] parse error at line L, column C: MESSAGE".
    std::string w = e.what();
    size_t colon = w.find(": ");
    return colon == std::string::npos ? w : w.substr(colon + 2);
  }

  glm::vec3 non_negative(const JsonCursor& j) {
    glm::vec3 c = j.color();
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) j.fail("colour components must not be negative");
    return c;
  }

  // Colour parameters may later be textures; only constants for now.
  glm::vec3 color_param(const JsonCursor& j) {
    if (!j.is_object()) return non_negative(j);
    j.allow_only({"type", "color"});
    std::string type = j["type"].string();
    if (type == "constant") return non_negative(j["color"]);
    if (type == "checker" || type == "marble" || type == "image" || type == "fresnel")
      j["type"].fail("texture type \"" + type + "\" is not supported yet");
    j["type"].fail("unknown texture type \"" + type + "\"");
  }

  void parse_camera(const JsonCursor& j) {
    j.allow_only({"transform", "vfov", "resolution", "fdist", "aperture"});
    Camera& c = scene_.camera;
    if (j.has("transform")) c.toWorld = parse_transform(j["transform"]);
    if (j.has("vfov")) {
      c.vfovDegrees = j["vfov"].number();
      if (!(c.vfovDegrees > 0.0f && c.vfovDegrees < 180.0f)) j["vfov"].fail("vfov must lie strictly between 0 and 180 degrees");
    }
    if (j.has("resolution")) {
      JsonCursor r = j["resolution"].expect_array();
      if (r.size() != 2) r.fail("expected [width, height]");
      c.width = r[size_t(0)].integer(1, 16384);
      c.height = r[size_t(1)].integer(1, 16384);
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
      if (type == "cmj") j["type"].fail("sampler \"cmj\" is not supported yet (use \"independent\")");
      if (type != "independent") j["type"].fail("unknown sampler type \"" + type + "\"");
    }
    if (j.has("samples")) scene_.samplesPerPixel = j["samples"].integer(1, 1 << 24);
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
      else j["split_method"].fail("unknown split method \"" + s + "\" (expected sah, middle or equal)");
    }
  }

  void parse_integrator(const JsonCursor& j) {
    j.allow_only({"type", "max bounces", "russian roulette", "recursive"});
    IntegratorSettings& s = scene_.integrator;
    if (j.has("type")) {
      std::string type = j["type"].string();
      if (type == "path tracer mis") s.kind = IntegratorKind::PathMis;
      else if (type == "path tracer nee") s.kind = IntegratorKind::PathNee;
      else if (type == "path tracer mats") s.kind = IntegratorKind::PathMats;
      else if (type == "normals" || type == "ao" || type == "path tracer mixture")
        j["type"].fail("integrator \"" + type + "\" is not supported yet");
      else j["type"].fail("unknown integrator type \"" + type + "\"");
    }
    s.maxBounces = j.integer_or("max bounces", s.maxBounces, 0, 1024);
    if (j.has("russian roulette")) {
      const nlohmann::json& rr = j["russian roulette"].json();
      if (rr.is_boolean()) s.russianRouletteDepth = rr.get<bool>() ? 3 : 1 << 30;
      else s.russianRouletteDepth = j["russian roulette"].integer(1, 1 << 30);
    }
    // "recursive" picks darts' recursive or iterative implementation; both
    // estimate the same image, and wavepath is always iterative.
    if (j.has("recursive") && !j["recursive"].json().is_boolean()) j["recursive"].fail("expected true or false");
  }

  uint32_t add_material(const JsonCursor& j, const std::string& name) {
    std::string type = j["type"].string();
    shader::Material m{};
    if (type == "lambertian") {
      j.allow_only({"type", "name", "albedo"});
      glm::vec3 a = j.has("albedo") ? color_param(j["albedo"]) : glm::vec3(0.8f);
      if (a.x > 1.0f || a.y > 1.0f || a.z > 1.0f) j["albedo"].fail("albedo above 1 would create energy");
      m.albedo = glm::vec4(a, 0.0f);
      m.info.x = MAT_LAMBERTIAN;
    } else if (type == "diffuse_light") {
      j.allow_only({"type", "name", "emit"});
      m.emission = glm::vec4(color_param(j["emit"]), 0.0f);
      m.info.x = MAT_LIGHT;
    } else if (type == "metal" || type == "dielectric" || type == "phong" || type == "blinn-phong" || type == "blend") {
      j["type"].fail("material type \"" + type + "\" is not supported yet");
    } else {
      j["type"].fail("unknown material type \"" + type + "\"");
    }
    scene_.materials.push_back(m);
    scene_.materialNames.push_back(name);
    return uint32_t(scene_.materials.size() - 1);
  }

  uint32_t material_of(const JsonCursor& surface) {
    JsonCursor j = surface["material"];
    if (j.is_string()) {
      auto it = named_.find(j.string());
      if (it == named_.end()) j.fail("no material named \"" + j.string() + "\"");
      return it->second;
    }
    j.expect_object();
    return add_material(j, surface.path() + "/material");
  }

  void parse_surface(const JsonCursor& j, const glm::mat4& parent) {
    j.expect_object();
    std::string type = j["type"].string();
    glm::mat4 xform = parent * (j.has("transform") ? parse_transform(j["transform"]) : glm::mat4(1.0f));
    if (type == "sphere") {
      j.allow_only({"type", "radius", "transform", "material"});
      float radius = j.has("radius") ? j["radius"].positive_number() : 1.0f;
      SceneSphere s;
      s.toWorld = xform * glm::scale(glm::mat4(1.0f), glm::vec3(radius));
      s.material = material_of(j);
      if (is_nonzero(glm::vec3(scene_.materials[s.material].emission)) && !is_similarity(glm::mat3(s.toWorld)))
        j.fail("emissive spheres must keep their shape (uniform scale): an emissive ellipsoid cannot be sampled yet");
      scene_.spheres.push_back(s);
    } else if (type == "quad") {
      j.allow_only({"type", "size", "transform", "material"});
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
      for (const auto& t : kWinding[mirrored ? 1 : 0]) add_triangle(j, c[t[0]], c[t[1]], c[t[2]], mat);
    } else if (type == "triangle") {
      j.allow_only({"type", "positions", "normals", "transform", "material"});
      JsonCursor pos = j["positions"].expect_array();
      if (pos.size() != 3) pos.fail("expected 3 vertex positions, got " + std::to_string(pos.size()));
      if (j.has("normals")) {
        JsonCursor nrm = j["normals"].expect_array();
        if (nrm.size() != 3) nrm.fail("expected 3 vertex normals, got " + std::to_string(nrm.size()));
        for (size_t i = 0; i < 3; ++i) nrm[i].vec3();  // validated; shading normals arrive with smooth shading
      }
      glm::vec3 v[3];
      for (size_t i = 0; i < 3; ++i) v[i] = glm::vec3(xform * glm::vec4(pos[i].vec3(), 1.0f));
      add_triangle(pos, v[0], v[1], v[2], material_of(j));
    } else if (type == "mesh") {
      j.allow_only({"type", "filename", "transform", "material", "material prefix"});
      load_mesh(j, xform);
    } else if (type == "group") {
      j.allow_only({"type", "children", "transform"});
      JsonCursor children = j["children"].expect_array();
      for (size_t i = 0; i < children.size(); ++i) parse_surface(children[i], xform);
    } else {
      j["type"].fail("unknown surface type \"" + type + "\" (expected sphere, quad, triangle, mesh or group)");
    }
  }

  static bool is_similarity(const glm::mat3& m) {
    float a = glm::length(m[0]), b = glm::length(m[1]), c = glm::length(m[2]);
    auto close = [](float x, float y) { return std::fabs(x - y) <= 1e-4f * std::max(x, y); };
    return close(a, b) && close(b, c) && std::fabs(glm::dot(m[0], m[1])) <= 1e-4f * a * b &&
           std::fabs(glm::dot(m[1], m[2])) <= 1e-4f * b * c && std::fabs(glm::dot(m[0], m[2])) <= 1e-4f * a * c;
  }

  void add_triangle(const JsonCursor& where, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
    if (glm::length(glm::cross(b - a, c - a)) == 0.0f) where.fail("triangle has zero area");
    scene_.triangles.push_back(SceneTriangle{{a, b, c}, material});
  }

  void load_mesh(const JsonCursor& j, const glm::mat4& xform) {
    std::string rel = j["filename"].string();
    fs::path objPath = fs::path(rel).is_absolute() ? fs::path(rel) : fs::path(file_).parent_path() / rel;
    ObjMesh mesh;
    try {
      mesh = load_obj(objPath.lexically_normal().string());
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) + " (loaded by " + file_ + " at " + j.path() + ")");
    }
    bool override = j.has("material");
    uint32_t fixed = override ? material_of(j) : 0;
    std::string prefix = j.has("material prefix") ? j["material prefix"].string() : "";
    std::vector<uint32_t> mtlToScene(mesh.materials.size());
    for (size_t i = 0; i < mesh.materials.size() && !override; ++i) {
      const ObjMaterial& om = mesh.materials[i];
      auto named = named_.find(prefix + om.name);
      if (named != named_.end()) {  // a scene material of that name overrides the MTL
        mtlToScene[i] = named->second;
        continue;
      }
      shader::Material m{};
      m.albedo = glm::vec4(glm::clamp(om.diffuse, 0.0f, 1.0f), 0.0f);
      m.emission = glm::vec4(glm::max(om.emission, 0.0f), 0.0f);
      m.info.x = is_nonzero(om.emission) && !is_nonzero(om.diffuse) ? MAT_LIGHT : MAT_LAMBERTIAN;
      scene_.materials.push_back(m);
      scene_.materialNames.push_back(prefix + om.name);
      mtlToScene[i] = uint32_t(scene_.materials.size() - 1);
    }
    glm::mat4 x = xform;
    for (size_t t = 0; t < mesh.triangleMaterials.size(); ++t) {
      int mm = mesh.triangleMaterials[t];
      if (!override && mm < 0) {
        j.fail("mesh " + rel + " has faces without a material: give the surface a \"material\"");
      }
      glm::vec3 v[3];
      for (int c = 0; c < 3; ++c) v[c] = glm::vec3(x * glm::vec4(mesh.positions[mesh.indices[3 * t + c]], 1.0f));
      // Degenerate triangles are common in scanned meshes; they can never be
      // hit, so they are dropped rather than rejected.
      if (glm::length(glm::cross(v[1] - v[0], v[2] - v[0])) == 0.0f) continue;
      scene_.triangles.push_back(SceneTriangle{{v[0], v[1], v[2]}, override ? fixed : mtlToScene[size_t(mm)]});
    }
  }

  std::string file_;
  nlohmann::json doc_;
  Scene scene_;
  std::map<std::string, uint32_t> named_;
};

}  // namespace

Scene load_scene(const std::string& path) {
  return SceneLoader(path).load();
}

}  // namespace wp
