#include "scene/importers.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "scene/json_cursor.h"
#include "scene/kinds.h"
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

  Scene load() {
    std::ifstream in(file_, std::ios::binary);
    if (!in) throw InputError(file_ + ": cannot open scene file (" + (fs::exists(file_) ? "permission denied" : "no such file") + ")");
    std::stringstream text;
    text << in.rdbuf();
    try {
      doc_ = nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(file_ + ":" + location_of(text.str(), e.byte) + ": JSON syntax error: " + describe(e));
    } catch (const nlohmann::json::out_of_range& e) {
      throw InputError(file_ + ": " + number_out_of_range(text.str(), e));
    }
    scene_.sourcePath = file_;
    JsonCursor root(doc_, "", file_);
    root.expect_object();
    root.allow_only({"camera", "sampler", "background", "accelerator", "integrator", "materials", "surfaces", "media"});
    if (root.has("media")) root["media"].fail("participating media are not supported yet");
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
        if (named_.count(name)) m["name"].fail("material \"" + name + "\" is defined twice");
        named_[name] = add_material(m, name);
      }
    }
    if (root.has("surfaces")) {
      JsonCursor surfs = root["surfaces"].expect_array();
      reserve_huge(scene_.triangles, mesh_triangles(surfs) + 2 * surfs.size());
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

  // A number too large for a double (nlohmann: "number overflow parsing
  // 'TOKEN'"), which the parser reports without a position: the place is
  // that of the token's first appearance in the text.
  static std::string number_out_of_range(const std::string& text, const nlohmann::json::out_of_range& e) {
    const std::string w = e.what();
    const size_t open = w.find('\''), close = w.rfind('\'');
    if (open == std::string::npos || close <= open) return "JSON number out of range (" + w + ")";
    std::string token = w.substr(open + 1, close - open - 1);
    const size_t at = text.find(token);
    if (token.size() > 40) token = token.substr(0, 37) + "...";
    const std::string problem = "JSON number " + token + " is out of the range of double-precision numbers";
    return at == std::string::npos ? problem : location_of(text, at + 1) + ": " + problem;
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

  // ---- textures ------------------------------------------------------------

  uint32_t add_texture(const SceneTexture& t) { return wp::add_texture(scene_, t); }

  // `mapping`: {type: "uv"} (the default: lookups at (u, v, 0)) or
  // {type: "transform", transform: ...} (lookups at the hit point), either
  // with an optional transform applied to the lookup point.
  void parse_mapping(const JsonCursor& j, SceneTexture& t) {
    if (!j.has("mapping")) return;
    JsonCursor m = j["mapping"].expect_object();
    m.allow_only({"type", "transform"});
    std::string type = m.has("type") ? m["type"].string() : "transform";
    if (type == "transform") t.solid = true;
    else if (type != "uv") m["type"].fail("unknown texture mapping \"" + type + "\" (expected uv or transform)");
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
      t.scale = j.has("scale") ? j["scale"].positive_number() : 1.0f;
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
    j.allow_only({"type", "max bounces", "russian roulette", "recursive", "power"});
    IntegratorSettings& s = scene_.integrator;
    if (j.has("type")) {
      std::string type = j["type"].string();
      std::optional<IntegratorKind> kind = integrator_named(type);
      if (!kind) j["type"].fail("unknown integrator type \"" + type + "\" (expected " + kIntegratorNames + ")");
      s.kind = *kind;
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

  // An albedo: a colour or texture whose constant values must not exceed 1.
  uint32_t albedo_param(const JsonCursor& j, const char* key) {
    if (!j.has(key)) return add_texture(constant_texture(glm::vec3(0.8f)));
    glm::vec3 c(0.0f);
    uint32_t tex = texture_param(j[key], 0, &c);
    if (c.x > 1.0f || c.y > 1.0f || c.z > 1.0f) j[key].fail("albedo above 1 would create energy");
    return tex;
  }

  uint32_t add_material(const JsonCursor& j, const std::string& name) {
    std::string type = j["type"].string();
    SceneMaterial m;
    m.name = name;
    if (type == "lambertian") {
      j.allow_only({"type", "name", "albedo"});
      m.albedo = albedo_param(j, "albedo");
    } else if (type == "diffuse_light") {
      j.allow_only({"type", "name", "emit"});
      m.kind = MAT_LIGHT;
      m.emission = texture_param(j["emit"]);
    } else if (type == "metal") {
      j.allow_only({"type", "name", "albedo", "roughness"});
      m.kind = MAT_METAL;
      m.albedo = albedo_param(j, "albedo");
      m.param = j.number_or("roughness", 0.0f);
      if (!(m.param >= 0.0f)) j["roughness"].fail("roughness must not be negative");
    } else if (type == "dielectric") {
      j.allow_only({"type", "name", "ior"});
      m.kind = MAT_DIELECTRIC;
      m.param = j.has("ior") ? j["ior"].positive_number() : 1.5f;
    } else if (type == "phong" || type == "blinn-phong") {
      j.allow_only({"type", "name", "albedo", "exponent"});
      m.kind = type == "phong" ? MAT_PHONG : MAT_BLINN_PHONG;
      m.albedo = albedo_param(j, "albedo");
      m.param = j.number_or("exponent", 20.0f);
      if (!(m.param >= 0.0f && m.param <= 1e6f)) j["exponent"].fail("exponent must lie in [0, 1e6]");
    } else if (type == "blend") {
      j.allow_only({"type", "name", "amount", "a", "b"});
      m.kind = MAT_BLEND;
      m.amount = blend_amount(j);
      m.a = blend_child(j["a"], name + "/a");
      m.b = blend_child(j["b"], name + "/b");
      if (leaves_[m.a] + leaves_[m.b] > BSDF_MAX_LOBES) {
        j.fail("a blend may combine at most " + std::to_string(BSDF_MAX_LOBES) + " materials in all");
      }
    } else {
      j["type"].fail("unknown material type \"" + type + "\" (expected " + kind_list(material_kinds()) + ")");
    }
    scene_.materials.push_back(m);
    leaves_.push_back(m.kind == MAT_BLEND ? leaves_[m.a] + leaves_[m.b] : 1);
    return uint32_t(scene_.materials.size() - 1);
  }

  uint32_t blend_amount(const JsonCursor& j) {
    if (!j.has("amount")) return add_texture(constant_texture(glm::vec3(0.5f)));
    JsonCursor a = j["amount"];
    if (a.is_object() && a.has("type") && a["type"].is_string() && a["type"].string() == "fresnel") {
      a.allow_only({"type", "ior"});
      SceneTexture t;
      t.kind = TEX_FRESNEL;
      t.ior = a.has("ior") ? a["ior"].positive_number() : 1.5f;
      return add_texture(t);
    }
    glm::vec3 c(0.0f);
    uint32_t tex = texture_param(a, 0, &c);
    if (c.x > 1.0f || c.y > 1.0f || c.z > 1.0f) a.fail("blend amount must lie in [0, 1]");
    return tex;
  }

  // A blend's a or b: a material name or an inline material; never a light
  // (emission belongs to the surface's own material).
  uint32_t blend_child(const JsonCursor& j, const std::string& name) {
    uint32_t m;
    if (j.is_string()) {
      auto it = named_.find(j.string());
      if (it == named_.end()) j.fail("no material named \"" + j.string() + "\" (materials must be defined before use)");
      m = it->second;
    } else {
      m = add_material(j.expect_object(), name);
    }
    if (scene_.materials[m].kind == MAT_LIGHT) j.fail("a blend cannot contain a diffuse_light");
    return m;
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
      // Its bounds (centre +- the rows' lengths) must be finite too.
      const glm::mat3 rows = glm::transpose(glm::mat3(s.toWorld));
      const glm::vec3 centre(s.toWorld[3]), extent(glm::length(rows[0]), glm::length(rows[1]), glm::length(rows[2]));
      if (!is_finite(centre + extent) || !is_finite(centre - extent)) j.fail(std::string("sphere: ") + kPastFloatRange);
      s.material = material_of(j);
      if (scene_.materials[s.material].emission != WP_INVALID && !is_similarity(glm::mat3(s.toWorld)))
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
      static const glm::vec2 kCornerUv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // planar UVs over the quad
      for (const auto& t : kWinding[mirrored ? 1 : 0]) {
        SceneTriangleShading& sh = add_shading(add_triangle(j, c[t[0]], c[t[1]], c[t[2]], mat));
        sh.hasUvs = true;
        for (int k = 0; k < 3; ++k) sh.uv[k] = kCornerUv[t[k]];
      }
    } else if (type == "triangle") {
      j.allow_only({"type", "positions", "normals", "transform", "material"});
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
    } else if (type == "mesh") {
      j.allow_only({"type", "filename", "transform", "material", "material prefix"});
      load_mesh(j, xform);
    } else if (type == "point_light") {
      // wavepath extension (CS184's point lights): radiant intensity in W/sr.
      j.allow_only({"type", "position", "intensity", "transform"});
      ScenePointLight l;
      l.position = glm::vec3(xform * glm::vec4(j.vec3_or("position", glm::vec3(0.0f)), 1.0f));
      if (!is_finite(l.position)) j.fail(std::string("point light: ") + kPastFloatRange);
      l.intensity = non_negative(j["intensity"]);
      scene_.pointLights.push_back(l);
    } else if (type == "group") {
      j.allow_only({"type", "children", "transform"});
      JsonCursor children = j["children"].expect_array();
      for (size_t i = 0; i < children.size(); ++i) parse_surface(children[i], xform);
    } else {
      j["type"].fail("unknown surface type \"" + type + "\" (expected sphere, quad, triangle, mesh, group or point_light)");
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
      SceneMaterial m;
      m.name = prefix + om.name;
      if (!om.diffuseMap.empty()) {
        m.albedo = add_image_texture(scene_, om.diffuseMap, "map_Kd of " + om.name + ", loaded by " + file_ + " at " + j.path());
      } else {
        m.albedo = add_texture(constant_texture(glm::clamp(om.diffuse, 0.0f, 1.0f)));
      }
      if (is_nonzero(om.emission)) m.emission = add_texture(constant_texture(glm::max(om.emission, 0.0f)));
      if (is_nonzero(om.emission) && !is_nonzero(om.diffuse)) m.kind = MAT_LIGHT;
      scene_.materials.push_back(m);
      leaves_.push_back(1);
      mtlToScene[i] = uint32_t(scene_.materials.size() - 1);
    }
    if (!override && std::find(mesh.materials.begin(), mesh.materials.end(), WP_INVALID) != mesh.materials.end())
      j.fail("mesh " + rel + " has faces without a material: give the surface a \"material\"");
    add_mesh(scene_, mesh, xform, mtlToScene, override ? fixed : WP_INVALID,
             [&](const std::string& problem) { j.fail("mesh " + rel + ", " + problem); });
  }

  std::string file_;
  nlohmann::json doc_;
  Scene scene_;
  std::map<std::string, ObjFile> meshes_;  // parsed OBJ files by path
  std::map<std::string, uint32_t> named_;
  std::vector<int> leaves_;  // per material: the lobes it flattens to (blends: the sum of their children's)
};

}  // namespace

Scene import_darts(const std::string& path) {
  return DartsImporter(path).load();
}

}  // namespace wp
