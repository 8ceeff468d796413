// import_gltf.cpp — glTF 2.0 (.gltf with external or embedded buffers and
// images, and .glb) through Debian's tinygltf: the default scene's node
// tree, triangle meshes, metal-rough materials with their textures, cameras
// and KHR_lights_punctual lights (docs/scene-format.md, "glTF 2.0").
//
// tinygltf parses the JSON and the GLB container and resolves URIs; every
// index, count, offset and value it hands over is checked here before it is
// used, since tinygltf checks few of them. It reads files only through
// callbacks that keep them inside the model's folder (it would follow
// "../" and absolute URIs), and hands images over undecoded: the project's
// own decoder (texture_image.h) decodes each with its checks, in the colour
// space of the texture slot that uses it.
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>

#include "scene/gltf_accessors.h"
#include "scene/kinds.h"
#include "scene/importers.h"
#include "scene/materials/material_module.h"
#include "util/error.h"
#include "util/files.h"

namespace wp {

namespace {

namespace fs = std::filesystem;

// The files a model may read: those inside its folder.
struct Sandbox {
  fs::path root;  // canonical
  std::vector<std::string> read;
  std::string refused;  // the first path refused, for the error message

  bool inside(const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::path(path), ec);
    if (ec) return false;
    const fs::path rel = p.lexically_relative(root);
    const bool ok = !rel.empty() && *rel.begin() != ".." && rel.is_relative();
    if (!ok && refused.empty()) refused = path;
    return ok;
  }
};

bool sandbox_file_exists(const std::string& path, void* user) {
  Sandbox* box = static_cast<Sandbox*>(user);
  std::error_code ec;
  return box->inside(path) && fs::is_regular_file(path, ec);
}

std::string sandbox_expand(const std::string& path, void*) {
  return path;  // no "~" or environment variables: a path means what it says
}

bool sandbox_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  Sandbox* box = static_cast<Sandbox*>(user);
  if (!box->inside(path)) {
    if (err) *err += "refused " + path + ": it lies outside the model's folder\n";
    return false;
  }
  std::optional<std::vector<unsigned char>> bytes = read_file_bytes(path);
  if (!bytes) {
    if (err) *err += "cannot read " + path + "\n";
    return false;
  }
  *out = std::move(*bytes);
  box->read.push_back(path);
  return true;
}

bool sandbox_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "wavepath does not write files while reading a model\n";
  return false;
}

// Keeps an image's bytes as they are; the importer decodes them (above).
// An image in a buffer view is left alone: tinygltf hands over its bytes
// without checking that the view lies inside its buffer (the fuzzer found
// it reading freed memory), so the importer reads them through its checks.
bool keep_encoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0) image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

std::string joined(const std::set<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The extensions wavepath reads. Others are named once in a warning, or
// refused when the file requires them.
const std::set<std::string> kSupportedExtensions = {"EXT_mesh_gpu_instancing", "KHR_lights_punctual",      "KHR_materials_anisotropy",      "KHR_materials_clearcoat",    "KHR_materials_dispersion", "KHR_materials_emissive_strength",
                                                    "KHR_materials_ior",        "KHR_materials_iridescence",  "KHR_materials_sheen",        "KHR_materials_specular",
                                                    "KHR_materials_transmission", "KHR_materials_volume",     "KHR_texture_transform"};

// The most nodes a scene's tree may visit (a DAG can share subtrees, which
// multiplies what a walk visits).
constexpr size_t kMaxNodeVisits = 1u << 20;

// The most instances a file may place (nodes and EXT_mesh_gpu_instancing's
// together): each costs the GPU 160 bytes.
constexpr size_t kMaxInstances = size_t(1) << 24;

// Default image width; the height follows the camera's aspect ratio.
constexpr int kDefaultWidth = 800;

class GltfImporter {
 public:
  explicit GltfImporter(const std::string& path) : path_(path) {}

  Scene run() {
    scene_.sourcePath = path_;
    load_model();
    check_extensions();
    if (!model_.animations.empty()) unread_.insert("animations (the model renders at rest)");
    scene_.integrator.maxBounces = 16;
    scene_.samplesPerPixel = 64;
    scene_.background = glm::vec3(0.0f);
    const int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (!model_.scenes.empty()) {
      if (sceneIndex >= int(model_.scenes.size())) fail("/scene", "names scene " + std::to_string(sceneIndex) + ", which does not exist");
      const tinygltf::Scene& s = model_.scenes[size_t(sceneIndex)];
      std::vector<int> ancestors;
      for (size_t i = 0; i < s.nodes.size(); ++i)
        visit(s.nodes[i], glm::mat4(1.0f), "/scenes/" + std::to_string(sceneIndex) + "/nodes/" + std::to_string(i), ancestors);
    }
    settle_instances(scene_);
    if (scene_.triangles.empty() && scene_.instances.empty()) fail("/scenes", "the default scene holds no triangles");
    default_camera();
    if (!unread_.empty())
      std::fprintf(stderr, "wavepath: warning: %s: not read yet, rendered without: %s\n", path_.c_str(), joined(unread_).c_str());
    // A model without a light worth the name is lit by a white sky, as
    // viewers light every model; a file whose emitters light it renders by
    // them alone, as Blender renders what its importer reads
    // (default_sky_wanted). `--env none` takes the sky away, `--env MAP`
    // replaces it, `--env sky` asks for it.
    if (scene_.pointLights.empty() && default_sky_wanted(scene_)) {
      scene_.background = glm::vec3(1.0f);
      scene_.defaultSky = true;
    }
    for (const std::string& f : sandbox_.read) scene_.inputFiles.push_back(f);
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(path_ + ": " + where + ": " + what);
  }

  void load_model() {
    std::error_code ec;
    sandbox_.root = fs::weakly_canonical(fs::absolute(fs::path(path_)).parent_path(), ec);
    const std::optional<std::vector<unsigned char>> file = read_file_bytes(path_);
    if (!file) throw InputError(path_ + ": cannot read scene file");
    const std::vector<unsigned char>& bytes = *file;
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks fs{&sandbox_file_exists, &sandbox_expand, &sandbox_read, &sandbox_write, &sandbox_};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&keep_encoded, nullptr);
    std::string err, warn;
    const std::string base = sandbox_.root.string();
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    check_what_tinygltf_passes(bytes, binary);
    bool ok;
    if (binary) {
      ok = loader.LoadBinaryFromMemory(&model_, &err, &warn, bytes.data(), unsigned(std::min<size_t>(bytes.size(), UINT32_MAX)), base);
    } else {
      if (lower_extension(path_) == ".glb") throw InputError(path_ + ": not a binary glTF file (it does not start with \"glTF\")");
      ok = loader.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(bytes.data()), unsigned(bytes.size()), base);
    }
    if (!ok || !sandbox_.refused.empty()) {
      if (!sandbox_.refused.empty()) throw InputError(path_ + ": refused " + sandbox_.refused + ": a model may only read files inside its own folder");
      std::string reason = first_line(err.empty() ? warn : err);
      throw InputError(path_ + ": cannot read glTF: " + (reason.empty() ? "unknown error" : reason));
    }
  }

  // What tinygltf reads without a word, so that the model would render
  // empty or wrong further on: a glTF 1.0 file, a mesh whose primitives are
  // not an array. Anything else wrong with the JSON, tinygltf names.
  void check_what_tinygltf_passes(const std::vector<unsigned char>& bytes, bool binary) const {
    std::string text;
    if (binary) {
      uint32_t version = 0, length = 0;
      if (bytes.size() >= 8) std::memcpy(&version, bytes.data() + 4, 4);
      if (version == 1) fail("the binary header", "glTF 1.0 is not supported: wavepath reads glTF 2.0 (convert the model, e.g. with Blender)");
      if (bytes.size() < 20) return;
      std::memcpy(&length, bytes.data() + 12, 4);
      if (size_t(length) > bytes.size() - 20) return;
      text.assign(reinterpret_cast<const char*>(bytes.data() + 20), length);
    } else {
      text.assign(bytes.begin(), bytes.end());
    }
    const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return;
    const auto asset = doc.find("asset");
    if (asset != doc.end() && asset->is_object()) {
      const auto version = asset->find("version");
      if (version != asset->end() && version->is_string() && version->get<std::string>().rfind("1.", 0) == 0)
        fail("/asset/version", "glTF " + version->get<std::string>() + " is not supported: wavepath reads glTF 2.0 (convert the model, e.g. with Blender)");
    }
    const auto meshes = doc.find("meshes");
    if (meshes == doc.end() || !meshes->is_array()) return;
    for (size_t i = 0; i < meshes->size(); ++i) {
      const nlohmann::json& mesh = (*meshes)[i];
      if (!mesh.is_object()) continue;
      const auto primitives = mesh.find("primitives");
      if (primitives != mesh.end() && !primitives->is_array())
        fail("/meshes/" + std::to_string(i) + "/primitives", std::string("must be an array of primitives, not ") + primitives->type_name());
    }
  }

  static std::string first_line(const std::string& s) {
    const size_t end = s.find('\n');
    return end == std::string::npos ? s : s.substr(0, end);
  }

  void check_extensions() {
    for (size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
      const std::string& e = model_.extensionsRequired[i];
      if (!kSupportedExtensions.count(e))
        fail("/extensionsRequired/" + std::to_string(i), "the model requires extension " + e + ", which wavepath does not support");
    }
    std::set<std::string> ignored;
    for (const std::string& e : model_.extensionsUsed)
      if (!kSupportedExtensions.count(e)) ignored.insert(e);
    if (!ignored.empty()) std::fprintf(stderr, "wavepath: warning: %s: ignoring extensions it uses: %s\n", path_.c_str(), joined(ignored).c_str());
  }

  // ---- nodes ---------------------------------------------------------------

  glm::mat4 local_transform(const tinygltf::Node& n, const std::string& where) const {
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16) fail(where + "/matrix", "expected 16 numbers");
      glm::mat4 m;
      for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = float(n.matrix[size_t(i)]);  // column-major, as glTF stores it
      return m;
    }
    glm::mat4 m(1.0f);
    if (!n.translation.empty()) {
      if (n.translation.size() != 3) fail(where + "/translation", "expected 3 numbers");
      m = glm::translate(m, glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
    }
    if (!n.rotation.empty()) {
      if (n.rotation.size() != 4) fail(where + "/rotation", "expected a quaternion of 4 numbers");
      glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));  // glTF: x, y, z, w
      const float len = glm::length(q);
      if (!(len > 0.0f) || !std::isfinite(len)) fail(where + "/rotation", "is not a rotation (its length is " + std::to_string(len) + ")");
      m = m * glm::mat4_cast(q / len);
    }
    if (!n.scale.empty()) {
      if (n.scale.size() != 3) fail(where + "/scale", "expected 3 numbers");
      m = glm::scale(m, glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
    }
    return m;
  }

  // Places node `index` and its subtree. `path` holds the nodes above it: a
  // node met again on its own path is a cycle.
  void visit(int index, const glm::mat4& parent, const std::string& where, std::vector<int>& path) {
    if (index < 0 || index >= int(model_.nodes.size())) fail(where, "names node " + std::to_string(index) + ", which does not exist");
    if (std::find(path.begin(), path.end(), index) != path.end()) fail(where, "node " + std::to_string(index) + " is its own ancestor (a cycle)");
    if (++visits_ > kMaxNodeVisits) fail(where, "the node tree visits more than " + std::to_string(kMaxNodeVisits) + " nodes");
    const std::string at = "/nodes/" + std::to_string(index);
    const tinygltf::Node& n = model_.nodes[size_t(index)];
    const glm::mat4 toWorld = parent * local_transform(n, at);
    if (n.skin >= 0) unread_.insert("skins (meshes in their bind pose)");
    auto instancing = n.extensions.find("EXT_mesh_gpu_instancing");
    if (n.mesh >= 0 && instancing != n.extensions.end()) {
      add_gpu_instances(n.mesh, toWorld, instancing->second, at + "/extensions/EXT_mesh_gpu_instancing");
    } else if (n.mesh >= 0) {
      add_mesh_instance(n.mesh, toWorld, at + "/mesh");
    }
    if (n.camera >= 0) add_camera(n.camera, toWorld, at + "/camera");
    auto light = n.extensions.find("KHR_lights_punctual");
    if (light != n.extensions.end()) add_light(light->second, toWorld, at + "/extensions/KHR_lights_punctual");
    path.push_back(index);
    for (size_t c = 0; c < n.children.size(); ++c) visit(n.children[c], toWorld, at + "/children/" + std::to_string(c), path);
    path.pop_back();
  }

  // ---- meshes --------------------------------------------------------------

  // A primitive of a mesh, as read from the file.
  struct Primitive {
    SceneMesh mesh;
    uint32_t material;
    std::string where;  // its JSON path
  };

  // Every node that places a mesh makes an instance of it; settle_instances
  // flattens the meshes that gain nothing from instancing (placed once).
  void add_mesh_instance(int meshIndex, const glm::mat4& toWorld, const std::string& where) {
    if (scene_.instances.size() >= kMaxInstances) fail(where, "the scene places more than " + std::to_string(kMaxInstances) + " instances");
    add_instance(scene_, instanced_mesh_of(meshIndex, where), toWorld, [&](const std::string& problem) { fail(where, problem); });
  }

  // EXT_mesh_gpu_instancing: the node places its mesh once per element of
  // its attribute accessors, each placement the node's transform times the
  // element's translation, rotation and scale (the extension's
  // specification, "Instancing").
  void add_gpu_instances(int meshIndex, const glm::mat4& toWorld, const tinygltf::Value& ext, const std::string& where) {
    if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject()) fail(where, "has no attributes object");
    const tinygltf::Value& attributes = ext.Get("attributes");
    AccessorReader reader(model_, path_);
    std::vector<glm::vec4> columns[3];
    const char* const kNames[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    size_t count = std::numeric_limits<size_t>::max();
    for (int a = 0; a < 3; ++a) {
      if (!attributes.Has(kNames[a])) continue;
      const tinygltf::Value& index = attributes.Get(kNames[a]);
      const std::string at = where + "/attributes/" + kNames[a];
      if (!index.IsInt()) fail(at, "must be an accessor index");
      columns[a] = reader.read(index.GetNumberAsInt(), {a == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3}, at, count);
      count = columns[a].size();
    }
    if (count == std::numeric_limits<size_t>::max()) fail(where + "/attributes", "has none of TRANSLATION, ROTATION and SCALE");
    if (scene_.instances.size() + count > kMaxInstances) fail(where, "the scene places more than " + std::to_string(kMaxInstances) + " instances");
    const uint32_t mesh = instanced_mesh_of(meshIndex, where);
    for (size_t i = 0; i < count; ++i) {
      const std::string at = where + "/attributes (instance " + std::to_string(i) + ")";
      glm::mat4 m(1.0f);
      if (!columns[0].empty()) m = glm::translate(m, glm::vec3(columns[0][i]));
      if (!columns[1].empty()) {
        const glm::vec4 r = columns[1][i];
        glm::quat q(r.w, r.x, r.y, r.z);
        const float len = glm::length(q);
        if (!(len > 0.0f) || !std::isfinite(len)) fail(at, "its ROTATION is not a rotation (its length is " + std::to_string(len) + ")");
        m = m * glm::mat4_cast(q / len);
      }
      if (!columns[2].empty()) m = glm::scale(m, glm::vec3(columns[2][i]));
      add_instance(scene_, mesh, toWorld * m, [&](const std::string& problem) { fail(at, problem); });
    }
  }

  // The instanced mesh (Scene::instancedMeshes) of glTF mesh `meshIndex`,
  // made on first use from all its primitives.
  uint32_t instanced_mesh_of(int meshIndex, const std::string& where) {
    auto found = instancedMeshes_.find(meshIndex);
    if (found != instancedMeshes_.end()) return found->second;
    const std::vector<Primitive> primitives = primitives_of(meshIndex, where);
    const uint32_t index = add_instanced_mesh(scene_);
    for (const Primitive& p : primitives)
      add_to_instanced_mesh(scene_, index, p.mesh, {p.material}, WP_INVALID, [&](const std::string& problem) { fail(p.where, problem); });
    instancedMeshes_[meshIndex] = index;
    return index;
  }

  // A mesh's primitives, read once (instanced_mesh_of keeps what they hold).
  std::vector<Primitive> primitives_of(int meshIndex, const std::string& where) {
    if (meshIndex < 0 || meshIndex >= int(model_.meshes.size())) fail(where, "names mesh " + std::to_string(meshIndex) + ", which does not exist");
    std::vector<Primitive> out;
    const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
    const std::string at = "/meshes/" + std::to_string(meshIndex);
    AccessorReader reader(model_, path_);
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const std::string pat = at + "/primitives/" + std::to_string(p);
      if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
        static const char* const kModes[] = {"points", "lines", "line loops", "line strips", "triangles", "triangle strips", "triangle fans"};
        const std::string mode = prim.mode >= 0 && prim.mode <= 6 ? kModes[prim.mode] : "mode " + std::to_string(prim.mode);
        fail(pat + "/mode", "wavepath renders triangles only, not " + mode);
      }
      if (!prim.targets.empty()) unread_.insert("morph targets");
      auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) fail(pat + "/attributes", "has no POSITION");
      SceneMesh m;
      for (const glm::vec4& v : reader.read(pos->second, {TINYGLTF_TYPE_VEC3}, pat + "/attributes/POSITION")) {
        glm::vec3 q(v);
        if (!is_finite(q)) fail(pat + "/attributes/POSITION", "holds a position that is not a finite number");
        m.positions.push_back(q);
      }
      const size_t vertices = m.positions.size();
      auto normal = prim.attributes.find("NORMAL");
      if (normal != prim.attributes.end())
        for (const glm::vec4& v : reader.read(normal->second, {TINYGLTF_TYPE_VEC3}, pat + "/attributes/NORMAL", vertices))
          m.normals.push_back(glm::vec3(v));
      for (int set = 0; set < 2; ++set) {
        auto uv = prim.attributes.find("TEXCOORD_" + std::to_string(set));
        if (uv == prim.attributes.end()) continue;
        std::vector<glm::vec2>& uvs = set == 0 ? m.uvs : m.uvs1;
        for (const glm::vec4& v : reader.read(uv->second, {TINYGLTF_TYPE_VEC2}, pat + "/attributes/TEXCOORD_" + std::to_string(set), vertices))
          uvs.push_back(glm::vec2(v.x, 1.0f - v.y));  // glTF's v runs down the image; wavepath's up
      }
      auto tangent = prim.attributes.find("TANGENT");
      if (tangent != prim.attributes.end())
        for (const glm::vec4& v : reader.read(tangent->second, {TINYGLTF_TYPE_VEC4}, pat + "/attributes/TANGENT", vertices)) {
          // A tangent that is not a finite direction is derived from the UVs instead.
          const bool usable = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
          m.tangents.push_back(usable ? v : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        }
      auto color = prim.attributes.find("COLOR_0");
      if (color != prim.attributes.end()) {
        const std::vector<glm::vec4> colors = reader.read(color->second, {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, pat + "/attributes/COLOR_0", vertices);
        const bool rgb = model_.accessors[size_t(color->second)].type == TINYGLTF_TYPE_VEC3;  // read() checked the index
        for (const glm::vec4& v : colors) {
          const glm::vec4 c(v.x, v.y, v.z, rgb ? 1.0f : v.w);
          if (!(glm::all(glm::greaterThanEqual(c, glm::vec4(0.0f))) && glm::all(glm::lessThanEqual(c, glm::vec4(1.0f)))))
            fail(pat + "/attributes/COLOR_0", "holds a colour outside [0, 1]");
          m.colors.push_back(c);
        }
      }
      std::vector<uint32_t> corners;
      if (prim.indices >= 0) {
        corners = reader.indices(prim.indices, pat + "/indices", vertices);
      } else {
        corners.resize(vertices);
        for (size_t i = 0; i < vertices; ++i) corners[i] = uint32_t(i);
      }
      if (corners.size() % 3 != 0) fail(prim.indices >= 0 ? pat + "/indices" : pat + "/attributes/POSITION", "holds " + std::to_string(corners.size()) + " corners, not a whole number of triangles");
      m.positionIndices = corners;
      m.normalIndices = m.normals.empty() ? std::vector<uint32_t>(corners.size(), WP_INVALID) : corners;
      m.uvIndices = m.uvs.empty() ? std::vector<uint32_t>(corners.size(), WP_INVALID) : corners;
      m.materials.assign(corners.size() / 3, 0u);
      const uint32_t material = material_for(prim.material, pat + "/material");
      // A normal map or anisotropy without TANGENT: smooth tangents from its UV set.
      const int uvSet = uv_set_needing_tangents(material);
      if (uvSet >= 0 && m.tangents.empty()) m.tangents = smooth_tangents(m, uvSet == 1 ? m.uvs1 : m.uvs);
      out.push_back(Primitive{std::move(m), material, pat});
    }
    return out;
  }

  // ---- materials -----------------------------------------------------------

  uint32_t material_for(int index, const std::string& where) {
    if (index < 0) {  // the specification's default material
      // The module's defaults are the specification's: white, metallic 1, roughness 1, ior 1.5.
      if (defaultMaterial_ == WP_INVALID)
        defaultMaterial_ = add_material(scene_, MaterialParams(MAT_METAL_ROUGH, "glTF default material", complaint(where)));
      return defaultMaterial_;
    }
    if (index >= int(model_.materials.size())) fail(where, "names material " + std::to_string(index) + ", which does not exist");
    auto found = materials_.find(index);
    if (found != materials_.end()) return found->second;
    const tinygltf::Material& g = model_.materials[size_t(index)];
    const std::string at = "/materials/" + std::to_string(index);
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    if (g.occlusionTexture.index >= 0) unread_.insert("occlusion maps (a path tracer computes occlusion)");
    const std::string name = g.name.empty() ? "material " + std::to_string(index) : g.name;
    MaterialParams m(MAT_METAL_ROUGH, name, complaint(at));
    const glm::vec3 base = factor3(pbr.baseColorFactor, glm::vec3(1.0f), at + "/pbrMetallicRoughness/baseColorFactor");
    const std::vector<double>& baseFactor = pbr.baseColorFactor;
    const float alpha = baseFactor.size() == 4 ? unit(baseFactor[3], at + "/pbrMetallicRoughness/baseColorFactor/3") : 1.0f;
    m.texture("base_color",
              texture_times(TextureRef(pbr.baseColorTexture), glm::vec4(base, alpha), ColorEncoding::Srgb, at + "/pbrMetallicRoughness/baseColorTexture"),
              complaint(at + "/pbrMetallicRoughness/baseColorFactor"));
    uint32_t normalMap = WP_INVALID;
    if (g.normalTexture.index >= 0) {
      const float scale = float(g.normalTexture.scale);
      if (!std::isfinite(scale) || std::fabs(scale) > 1e3f) fail(at + "/normalTexture/scale", "must be a finite number of at most 1000");
      normalMap = texture_times(TextureRef(g.normalTexture), glm::vec4(scale, scale, 1.0f, 1.0f), ColorEncoding::Linear, at + "/normalTexture");
    }
    m.number("metallic", unit(pbr.metallicFactor, at + "/pbrMetallicRoughness/metallicFactor"), complaint(at + "/pbrMetallicRoughness/metallicFactor"));
    m.number("roughness", unit(pbr.roughnessFactor, at + "/pbrMetallicRoughness/roughnessFactor"),
             complaint(at + "/pbrMetallicRoughness/roughnessFactor"));
    if (pbr.metallicRoughnessTexture.index >= 0)
      m.texture("metallic_roughness", texture_times(TextureRef(pbr.metallicRoughnessTexture), glm::vec4(1.0f), ColorEncoding::Linear,
                                                    at + "/pbrMetallicRoughness/metallicRoughnessTexture"));
    auto iorExt = g.extensions.find("KHR_materials_ior");
    if (iorExt != g.extensions.end() && iorExt->second.Has("ior")) {
      const float ior = float(iorExt->second.Get("ior").GetNumberAsDouble());
      if (!(ior >= 1.0f && ior <= 10.0f)) fail(at + "/extensions/KHR_materials_ior/ior", "must lie in [1, 10]");
      m.number("ior", ior, complaint(at + "/extensions/KHR_materials_ior/ior"));
    }
    auto transmissionExt = g.extensions.find("KHR_materials_transmission");
    if (transmissionExt != g.extensions.end()) {
      const tinygltf::Value& t = transmissionExt->second;
      const std::string tat = at + "/extensions/KHR_materials_transmission";
      if (t.Has("transmissionFactor")) {
        if (!t.Get("transmissionFactor").IsNumber()) fail(tat + "/transmissionFactor", "expected a number");
        m.number("transmission", unit(t.Get("transmissionFactor").GetNumberAsDouble(), tat + "/transmissionFactor"),
                 complaint(tat + "/transmissionFactor"));
      }
      if (t.Has("transmissionTexture"))
        m.texture("transmission_texture", extension_texture(t, "transmissionTexture", glm::vec4(1.0f), ColorEncoding::Linear, tat));
    }
    // Surface properties, not the kind's parameters: on the top layer (below).
    bool doubleSided = g.doubleSided;
    float alphaCutoff = 0.0f;
    // MASK cuts out where alpha < cutoff; BLEND is rendered as stochastic
    // transparency (a ray passes with probability 1 - alpha), which a path
    // tracer converges to the blend a rasterizer draws.
    if (g.alphaMode == "MASK") {
      if (!(g.alphaCutoff >= 0.0 && g.alphaCutoff <= 1.0)) fail(at + "/alphaCutoff", "must lie in [0, 1]");
      alphaCutoff = float(g.alphaCutoff);
    } else if (g.alphaMode == "BLEND") {
      alphaCutoff = -1.0f;
    } else if (g.alphaMode != "OPAQUE") {
      fail(at + "/alphaMode", "is \"" + g.alphaMode + "\", not OPAQUE, MASK or BLEND");
    }
    float strength = 1.0f;
    auto strengthExt = g.extensions.find("KHR_materials_emissive_strength");
    if (strengthExt != g.extensions.end() && strengthExt->second.Has("emissiveStrength")) {
      strength = float(strengthExt->second.Get("emissiveStrength").GetNumberAsDouble());
      if (!(strength >= 0.0f && strength < 1e6f))
        fail(at + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "must be a number from 0 to 1e6");
    }
    const glm::vec3 emissive = factor3(g.emissiveFactor, glm::vec3(0.0f), at + "/emissiveFactor") * strength;
    const uint32_t emission = emissive == glm::vec3(0.0f) ? WP_INVALID
        : texture_times(TextureRef(g.emissiveTexture), glm::vec4(emissive, 1.0f), ColorEncoding::Srgb, at + "/emissiveTexture");
    read_specular(g, at, m);
    if (read_volume(g, at, m)) doubleSided = true;
    read_iridescence(g, at, m);
    read_anisotropy(g, at, m);
    // The layers, each over what lies below (the extensions' order): the
    // base, a sheen, a clear coat. The top carries the surface's emission,
    // sidedness and cut-out; the base its alpha texture and normal map.
    uint32_t coatNormalMap = WP_INVALID;
    std::optional<MaterialParams> sheen = sheen_layer(g, at, name), coat = clearcoat_layer(g, at, name, coatNormalMap);
    MaterialParams& top = coat ? *coat : sheen ? *sheen : m;
    if (emission != WP_INVALID) top.texture("emit", emission, complaint(at + "/emissiveTexture"));
    uint32_t id = add_material(scene_, m);
    scene_.materials[id].normalMap = normalMap;
    for (std::optional<MaterialParams>* layer : {&sheen, &coat}) {
      if (!*layer) continue;
      (*layer)->material("base", id);
      id = add_material(scene_, **layer);
      if (layer == &coat) scene_.materials[id].normalMap = coatNormalMap;
    }
    scene_.materials[id].doubleSided = doubleSided;
    scene_.materials[id].alphaCutoff = alphaCutoff;
    materials_[index] = id;
    return id;
  }

  Complaint complaint(const std::string& where) const {
    return [this, where](const std::string& problem) { fail(where, problem); };
  }

  // The UV set (0 or 1) a mesh of material m needs tangents in: that of a
  // normal map of its surface or of a coat over it, or of its anisotropy's
  // texture (the first found; an anisotropy without a texture takes the
  // first set); -1 where nothing needs tangents.
  int uv_set_needing_tangents(uint32_t m) const {
    for (int depth = 0; depth <= LAYERS_MAX; ++depth) {
      const SceneMaterial& mat = scene_.materials[m];
      if (mat.normalMap != WP_INVALID) return scene_.textures[mat.normalMap].secondUvSet ? 1 : 0;
      if (mat.kind == MAT_METAL_ROUGH && mat.record.anisotropy.x > 0.0f) {
        const uint32_t t = glm::floatBitsToUint(mat.record.anisotropy.w);  // metal_rough.cpp's record
        return t != WP_INVALID && scene_.textures[t].secondUvSet ? 1 : 0;
      }
      if (!is_layer(mat.kind)) break;
      m = mat.part(0);
    }
    return -1;
  }

  // A number of an extension's object in [lo, hi], or `fallback` if absent.
  float extension_number(const tinygltf::Value& ext, const char* key, float fallback, float lo, float hi, const std::string& at) const {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsNumber()) fail(at + "/" + key, "expected a number");
    const double x = v.GetNumberAsDouble();
    if (!(x >= lo && x <= hi)) fail(at + "/" + key, "must lie in [" + number_text(lo) + ", " + number_text(hi) + "]");
    return float(x);
  }

  // A colour of an extension's object (3 numbers in [0, hi]), or `fallback`.
  glm::vec3 extension_color(const tinygltf::Value& ext, const char* key, glm::vec3 fallback, float hi, const std::string& at) const {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) fail(at + "/" + key, "expected 3 numbers");
    glm::vec3 c;
    for (int i = 0; i < 3; ++i) {
      if (!v.Get(i).IsNumber()) fail(at + "/" + key + "/" + std::to_string(i), "expected a number");
      c[i] = float(v.Get(i).GetNumberAsDouble());
      if (!(c[i] >= 0.0f && c[i] <= hi)) fail(at + "/" + key + "/" + std::to_string(i), "must lie in [0, " + number_text(hi) + "]");
    }
    return c;
  }

  static std::string number_text(float v) {
    if (v > 1e30f) return "infinity";
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return text;
  }

  // An extension's texture (a textureInfo, or a normalTextureInfo, whose
  // scale multiplies the factor's first two channels) times `factor`.
  uint32_t extension_texture(const tinygltf::Value& ext, const char* key, glm::vec4 factor, ColorEncoding encoding, const std::string& at,
                             bool normal = false) {
    const std::string where = at + "/" + key;
    const tinygltf::Value& ti = ext.Get(key);
    if (!ti.IsObject() || !ti.Has("index") || !ti.Get("index").IsInt()) fail(where, "expected a textureInfo with an index");
    tinygltf::TextureInfo info;
    info.index = ti.Get("index").GetNumberAsInt();
    if (ti.Has("texCoord")) info.texCoord = ti.Get("texCoord").IsInt() ? ti.Get("texCoord").GetNumberAsInt() : -1;
    if (ti.Has("extensions") && ti.Get("extensions").IsObject() && ti.Get("extensions").Has("KHR_texture_transform"))
      info.extensions["KHR_texture_transform"] = ti.Get("extensions").Get("KHR_texture_transform");
    if (normal && ti.Has("scale")) {
      if (!ti.Get("scale").IsNumber()) fail(where + "/scale", "expected a number");
      const float scale = float(ti.Get("scale").GetNumberAsDouble());
      if (!std::isfinite(scale) || std::fabs(scale) > 1e3f) fail(where + "/scale", "must be a finite number of at most 1000");
      factor.x *= scale;
      factor.y *= scale;
    }
    return texture_times(TextureRef(info), factor, encoding, where);
  }

  // KHR_materials_specular on metal-rough m: params2 holds the factor and
  // colour less 1 (metal_rough.glsl), the textures scale them.
  void read_specular(const tinygltf::Material& g, const std::string& at, MaterialParams& m) {
    auto found = g.extensions.find("KHR_materials_specular");
    if (found == g.extensions.end()) return;
    const tinygltf::Value& e = found->second;
    const std::string eat = at + "/extensions/KHR_materials_specular";
    if (!e.IsObject()) fail(eat, "expected an object");
    const float specular = extension_number(e, "specularFactor", 1.0f, 0.0f, 1.0f, eat);
    const glm::vec3 color = extension_color(e, "specularColorFactor", glm::vec3(1.0f), 1e3f, eat);
    m.number("specular", specular, complaint(eat + "/specularFactor"));
    m.colour("specular_color", color, complaint(eat + "/specularColorFactor"));
    if (e.Has("specularTexture"))
      m.texture("specular_texture", extension_texture(e, "specularTexture", glm::vec4(1.0f), ColorEncoding::AlphaAsGrey, eat));
    if (e.Has("specularColorTexture"))
      m.texture("specular_color_texture", extension_texture(e, "specularColorTexture", glm::vec4(1.0f), ColorEncoding::Srgb, eat));
  }

  // KHR_materials_volume on metal-rough m: a thickness above 0 makes its
  // transmission refract into a volume (0, the default, is thin-walled);
  // the attenuation colour c reached after attenuationDistance d gives the
  // absorption coefficient -ln(c) / d (README.md:150). The thickness
  // texture is a rasterizer's stand-in for the distance a path tracer
  // traces, and is not read (README.md:125).
  // Whether the material is a volume's boundary.
  bool read_volume(const tinygltf::Material& g, const std::string& at, MaterialParams& m) const {
    auto found = g.extensions.find("KHR_materials_volume");
    if (found == g.extensions.end()) return false;
    const tinygltf::Value& e = found->second;
    const std::string eat = at + "/extensions/KHR_materials_volume";
    if (!e.IsObject()) fail(eat, "expected an object");
    const float thickness = extension_number(e, "thicknessFactor", 0.0f, 0.0f, 1e30f, eat);
    const float distance = extension_number(e, "attenuationDistance", 1e30f, 0.0f, 1e30f, eat);
    if (!(distance > 0.0f)) fail(eat + "/attenuationDistance", "must be above 0");
    const glm::vec3 color = extension_color(e, "attenuationColor", glm::vec3(1.0f), 1.0f, eat);
    m.flag("volume", thickness > 0.0f, complaint(eat + "/thicknessFactor"));
    m.colour("volume.attenuation_color", color, complaint(eat + "/attenuationColor"));
    m.number("volume.attenuation_distance", distance, complaint(eat + "/attenuationDistance"));
    // KHR_materials_dispersion (20 / Abbe number) spreads the volume's index
    // over the colours; a thin-walled surface does not disperse (README.md).
    auto dispersion = g.extensions.find("KHR_materials_dispersion");
    if (dispersion != g.extensions.end()) {
      const std::string dat = at + "/extensions/KHR_materials_dispersion";
      if (!dispersion->second.IsObject()) fail(dat, "expected an object");
      m.number("volume.dispersion", extension_number(dispersion->second, "dispersion", 0.0f, 0.0f, 1000.0f, dat), complaint(dat + "/dispersion"));
    }
    // "doubleSided has no effect on volume boundaries" (README.md:110-115):
    // paths inside meet the boundary from behind.
    return thickness > 0.0f;
  }

  // KHR_materials_iridescence on metal-rough m: a thin film's factor (times
  // the red of its texture), ior and thickness range (nm; its texture's green
  // picks within it, the maximum without one; README.md:61-88).
  void read_iridescence(const tinygltf::Material& g, const std::string& at, MaterialParams& m) {
    auto found = g.extensions.find("KHR_materials_iridescence");
    if (found == g.extensions.end()) return;
    const tinygltf::Value& e = found->second;
    const std::string eat = at + "/extensions/KHR_materials_iridescence";
    if (!e.IsObject()) fail(eat, "expected an object");
    m.flag("iridescence", true, complaint(eat));
    m.number("iridescence.factor", extension_number(e, "iridescenceFactor", 0.0f, 0.0f, 1.0f, eat), complaint(eat + "/iridescenceFactor"));
    m.number("iridescence.ior", extension_number(e, "iridescenceIor", 1.3f, 1.0f, 10.0f, eat), complaint(eat + "/iridescenceIor"));
    m.number("iridescence.thickness_minimum", extension_number(e, "iridescenceThicknessMinimum", 100.0f, 0.0f, 1e5f, eat),
             complaint(eat + "/iridescenceThicknessMinimum"));
    m.number("iridescence.thickness_maximum", extension_number(e, "iridescenceThicknessMaximum", 400.0f, 0.0f, 1e5f, eat),
             complaint(eat + "/iridescenceThicknessMaximum"));
    if (e.Has("iridescenceTexture"))
      m.texture("iridescence.factor_texture", extension_texture(e, "iridescenceTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat));
    if (e.Has("iridescenceThicknessTexture"))
      m.texture("iridescence.thickness_texture", extension_texture(e, "iridescenceThicknessTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat));
  }

  // KHR_materials_anisotropy on metal-rough m: strength, rotation (radians)
  // and a texture of directions (red, green: 2 c - 1 in the tangent frame)
  // and strengths (blue), linear (README.md:65-90).
  void read_anisotropy(const tinygltf::Material& g, const std::string& at, MaterialParams& m) {
    auto found = g.extensions.find("KHR_materials_anisotropy");
    if (found == g.extensions.end()) return;
    const tinygltf::Value& e = found->second;
    const std::string eat = at + "/extensions/KHR_materials_anisotropy";
    if (!e.IsObject()) fail(eat, "expected an object");
    m.flag("anisotropy", true, complaint(eat));
    m.number("anisotropy.strength", extension_number(e, "anisotropyStrength", 0.0f, 0.0f, 1.0f, eat), complaint(eat + "/anisotropyStrength"));
    m.number("anisotropy.rotation", extension_number(e, "anisotropyRotation", 0.0f, -1e4f, 1e4f, eat), complaint(eat + "/anisotropyRotation"));
    if (e.Has("anisotropyTexture"))
      m.texture("anisotropy.texture", extension_texture(e, "anisotropyTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat));
  }

  // KHR_materials_sheen, to lie over the base; none where the sheen is black.
  std::optional<MaterialParams> sheen_layer(const tinygltf::Material& g, const std::string& at, const std::string& name) {
    auto found = g.extensions.find("KHR_materials_sheen");
    if (found == g.extensions.end()) return std::nullopt;
    const tinygltf::Value& e = found->second;
    const std::string eat = at + "/extensions/KHR_materials_sheen";
    if (!e.IsObject()) fail(eat, "expected an object");
    const glm::vec3 color = extension_color(e, "sheenColorFactor", glm::vec3(0.0f), 1.0f, eat);
    const float roughness = extension_number(e, "sheenRoughnessFactor", 0.0f, 0.0f, 1.0f, eat);
    if (color == glm::vec3(0.0f)) return std::nullopt;  // "If sheenColorFactor is zero, the whole sheen layer is disabled."
    MaterialParams sheen(MAT_SHEEN, name + " (sheen)", complaint(eat));
    sheen.texture("color", e.Has("sheenColorTexture") ? extension_texture(e, "sheenColorTexture", glm::vec4(color, 1.0f), ColorEncoding::Srgb, eat)
                                                     : add_texture(scene_, constant_texture(color)));
    sheen.texture("roughness", e.Has("sheenRoughnessTexture")
                                   ? extension_texture(e, "sheenRoughnessTexture", glm::vec4(roughness), ColorEncoding::AlphaAsGrey, eat)
                                   : add_texture(scene_, constant_texture(glm::vec3(roughness))));
    return sheen;
  }

  // KHR_materials_clearcoat, to lie over the base (and its own normal map in
  // `normalMap`); none where the coat is 0.
  std::optional<MaterialParams> clearcoat_layer(const tinygltf::Material& g, const std::string& at, const std::string& name, uint32_t& normalMap) {
    auto found = g.extensions.find("KHR_materials_clearcoat");
    if (found == g.extensions.end()) return std::nullopt;
    const tinygltf::Value& e = found->second;
    const std::string eat = at + "/extensions/KHR_materials_clearcoat";
    if (!e.IsObject()) fail(eat, "expected an object");
    const float factor = extension_number(e, "clearcoatFactor", 0.0f, 0.0f, 1.0f, eat);
    const float roughness = extension_number(e, "clearcoatRoughnessFactor", 0.0f, 0.0f, 1.0f, eat);
    if (factor == 0.0f) return std::nullopt;  // "If clearcoatFactor = 0, the clearcoat layer is disabled."
    MaterialParams coat(MAT_CLEARCOAT, name + " (clear coat)", complaint(eat));  // the module's ior is the extension's, 1.5
    coat.texture("factor", e.Has("clearcoatTexture") ? extension_texture(e, "clearcoatTexture", glm::vec4(factor), ColorEncoding::Linear, eat)
                                                     : add_texture(scene_, constant_texture(glm::vec3(factor))));
    coat.texture("roughness", e.Has("clearcoatRoughnessTexture")
                                  ? extension_texture(e, "clearcoatRoughnessTexture", glm::vec4(roughness), ColorEncoding::Linear, eat)
                                  : add_texture(scene_, constant_texture(glm::vec3(roughness))));
    if (e.Has("clearcoatNormalTexture"))
      normalMap = extension_texture(e, "clearcoatNormalTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat, true);
    return coat;
  }

  // A colour factor (its first three numbers; a fourth, alpha, is not used).
  glm::vec3 factor3(const std::vector<double>& v, glm::vec3 fallback, const std::string& where) const {
    if (v.empty()) return fallback;
    if (v.size() < 3) fail(where, "expected 3 or 4 numbers");
    const glm::vec3 c{float(v[0]), float(v[1]), float(v[2])};
    if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f && c.x <= 1.0f && c.y <= 1.0f && c.z <= 1.0f)) fail(where, "must lie in [0, 1]");
    return c;
  }

  float unit(double v, const std::string& where) const {
    if (!(v >= 0.0 && v <= 1.0)) fail(where, "must lie in [0, 1]");
    return float(v);
  }

  // What a material says of one of its textures (glTF's textureInfo, and
  // the normal texture's, which adds a scale).
  struct TextureRef {
    int index;
    int texCoord;
    const tinygltf::ExtensionMap& extensions;
    template <typename Info>
    explicit TextureRef(const Info& info) : index(info.index), texCoord(info.texCoord), extensions(info.extensions) {}
  };

  // A texture scaled by a constant factor (RGB and alpha), or the factor
  // alone without one.
  uint32_t texture_times(const TextureRef& info, glm::vec4 factor, ColorEncoding encoding, const std::string& where) {
    const int textureIndex = info.index;
    if (textureIndex < 0) {
      SceneTexture constant = constant_texture(glm::vec3(factor));
      constant.alpha = factor.w;
      return add_texture(scene_, constant);
    }
    if (info.texCoord < 0 || info.texCoord > 1) fail(where + "/texCoord", "wavepath reads TEXCOORD_0 and TEXCOORD_1, not set " + std::to_string(info.texCoord));
    if (textureIndex >= int(model_.textures.size()))
      fail(where + "/index", "names texture " + std::to_string(textureIndex) + ", which does not exist");
    const tinygltf::Texture& t = model_.textures[size_t(textureIndex)];
    const int image = t.source;
    if (image < 0 || image >= int(model_.images.size()))
      fail("/textures/" + std::to_string(textureIndex) + "/source", "names image " + std::to_string(image) + ", which does not exist");
    SceneTexture tex;
    tex.kind = TEX_IMAGE;
    tex.color = glm::vec3(factor);
    tex.alpha = factor.w;
    tex.secondUvSet = info.texCoord == 1;
    if (t.sampler >= 0) {
      if (t.sampler >= int(model_.samplers.size()))
        fail("/textures/" + std::to_string(textureIndex) + "/sampler", "names sampler " + std::to_string(t.sampler) + ", which does not exist");
      const tinygltf::Sampler& s = model_.samplers[size_t(t.sampler)];
      const std::string sat = "/samplers/" + std::to_string(t.sampler);
      tex.wrapU = wrap_mode(s.wrapS, sat + "/wrapS");
      tex.wrapV = wrap_mode(s.wrapT, sat + "/wrapT");
    }
    tex.image = decoded_image(image, encoding);
    auto transform = info.extensions.find("KHR_texture_transform");
    if (transform != info.extensions.end()) {
      const std::string tat = where + "/extensions/KHR_texture_transform";
      tex.mapping = uv_transform(transform->second, tat);
      if (transform->second.Has("texCoord")) {  // overrides the textureInfo's set
        const tinygltf::Value& set = transform->second.Get("texCoord");
        if (!set.IsInt() || set.GetNumberAsInt() < 0 || set.GetNumberAsInt() > 1) fail(tat + "/texCoord", "wavepath reads TEXCOORD_0 and TEXCOORD_1 only");
        tex.secondUvSet = set.GetNumberAsInt() == 1;
      }
    }
    return add_texture(scene_, tex);
  }

  // A sampler's wrap mode (the OpenGL enum glTF uses) as TEX_WRAP_*.
  uint32_t wrap_mode(int mode, const std::string& where) const {
    switch (mode) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT: return TEX_WRAP_REPEAT;
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TEX_WRAP_CLAMP;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TEX_WRAP_MIRROR;
      default: fail(where, "is " + std::to_string(mode) + ", not a wrap mode (10497, 33071 or 33648)");
    }
  }

  // KHR_texture_transform's offset x rotation x scale of glTF's UVs, as a
  // mapping of wavepath's (whose v is glTF's 1 - v): flip, transform, flip back.
  glm::mat4 uv_transform(const tinygltf::Value& t, const std::string& where) const {
    auto pair = [&](const char* key, glm::vec2 fallback) {
      if (!t.Has(key)) return fallback;
      const tinygltf::Value& v = t.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber()) fail(where + "/" + key, "expected 2 numbers");
      const glm::vec2 r(float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()));
      if (!std::isfinite(r.x) || !std::isfinite(r.y)) fail(where + "/" + key, "expected finite numbers");
      return r;
    };
    const glm::vec2 offset = pair("offset", glm::vec2(0.0f)), scale = pair("scale", glm::vec2(1.0f));
    float rotation = 0.0f;
    if (t.Has("rotation")) {
      if (!t.Get("rotation").IsNumber() || !std::isfinite(t.Get("rotation").GetNumberAsDouble())) fail(where + "/rotation", "expected a number");
      rotation = float(t.Get("rotation").GetNumberAsDouble());
    }
    const float c = std::cos(rotation), s = std::sin(rotation);
    glm::mat4 m(1.0f);  // the specification's matrix: (u, v) -> (c u + s v + ox, -s u + c v + oy) after scaling
    m[0] = glm::vec4(c * scale.x, -s * scale.x, 0.0f, 0.0f);
    m[1] = glm::vec4(s * scale.y, c * scale.y, 0.0f, 0.0f);
    m[3] = glm::vec4(offset.x, offset.y, 0.0f, 1.0f);
    const glm::mat4 flip = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)) * glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f));
    return flip * m * flip;
  }

  uint32_t decoded_image(int index, ColorEncoding encoding) {
    const auto key = std::make_pair(index, encoding);
    auto found = images_.find(key);
    if (found != images_.end()) return found->second;
    const tinygltf::Image& img = model_.images[size_t(index)];
    const std::string where = path_ + ": /images/" + std::to_string(index) + (img.uri.empty() || img.uri.rfind("data:", 0) == 0 ? "" : " (" + img.uri + ")");
    std::vector<unsigned char> bytes = img.bufferView >= 0 ? AccessorReader(model_, path_).view_bytes(img.bufferView, "/images/" + std::to_string(index) + "/bufferView") : img.image;
    if (bytes.empty()) throw InputError(where + ": holds no image data");
    const std::string ext = img.uri.rfind("data:", 0) == 0 ? std::string() : lower_extension(img.uri);
    scene_.images.push_back(decode_linear_image(bytes, where, ext, encoding));
    const uint32_t id = uint32_t(scene_.images.size() - 1);
    images_[key] = id;
    return id;
  }

  // ---- cameras and lights --------------------------------------------------

  void add_camera(int index, const glm::mat4& toWorld, const std::string& where) {
    if (index >= int(model_.cameras.size())) fail(where, "names camera " + std::to_string(index) + ", which does not exist");
    const tinygltf::Camera& c = model_.cameras[size_t(index)];
    const std::string at = "/cameras/" + std::to_string(index);
    NamedCamera nc;
    nc.name = c.name.empty() ? std::to_string(index) : c.name;
    nc.index = index;
    if (c.type != "perspective" && c.type != "orthographic") {
      nc.problem = at + "/type: wavepath renders perspective and orthographic cameras, not \"" + c.type + "\"";
    } else {
      double aspect = 4.0 / 3.0;
      if (c.type == "perspective") {
        const double yfov = c.perspective.yfov;
        if (!(yfov > 0.0 && yfov < M_PI)) fail(at + "/perspective/yfov", "must lie between 0 and pi radians");
        if (c.perspective.aspectRatio > 0.0) aspect = c.perspective.aspectRatio;
        nc.camera.vfovDegrees = float(glm::degrees(yfov));
      } else {
        // xmag and ymag: half the width and height it sees (the image's
        // aspect follows them).
        const double xmag = c.orthographic.xmag, ymag = c.orthographic.ymag;
        if (!(xmag > 0.0 && xmag < 1e9)) fail(at + "/orthographic/xmag", "must be a positive number");
        if (!(ymag > 0.0 && ymag < 1e9)) fail(at + "/orthographic/ymag", "must be a positive number");
        nc.camera.orthoHalfHeight = float(ymag);
        aspect = xmag / ymag;
      }
      if (!(aspect > 1e-3 && aspect < 1e3)) fail(at + "/" + c.type + (c.type == "perspective" ? "/aspectRatio" : "/xmag"), "gives an aspect ratio outside 0.001 to 1000");
      nc.camera.width = kDefaultWidth;
      nc.camera.height = std::max(1, int(std::lround(kDefaultWidth / aspect)));
      // The node's rotation and translation; a camera ignores scale.
      glm::vec3 x = glm::normalize(glm::vec3(toWorld[0])), y = glm::vec3(toWorld[1]);
      glm::vec3 z = glm::normalize(glm::cross(x, y));
      y = glm::cross(z, x);
      if (!is_finite(x) || !is_finite(z) || !is_finite(glm::vec3(toWorld[3])))
        fail(where, "the node's transform does not place the camera (it is singular or not finite)");
      nc.camera.toWorld = glm::mat4(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(z, 0.0f), toWorld[3]);
      nc.camera.focusDistance = 1.0f;
    }
    nc.camera.name = nc.name;
    scene_.cameras.push_back(nc);
  }

  void add_light(const tinygltf::Value& ext, const glm::mat4& toWorld, const std::string& where) {
    if (!ext.Has("light") || !ext.Get("light").IsInt()) fail(where, "names no light");
    const int index = ext.Get("light").GetNumberAsInt();
    if (index < 0 || index >= int(model_.lights.size())) fail(where + "/light", "names light " + std::to_string(index) + ", which does not exist");
    const tinygltf::Light& l = model_.lights[size_t(index)];
    const std::string at = "/extensions/KHR_lights_punctual/lights/" + std::to_string(index);
    ScenePointLight p;
    if (l.type == "spot") p.kind = ScenePointLight::Kind::Spot;
    else if (l.type == "directional") p.kind = ScenePointLight::Kind::Directional;
    else if (l.type != "point") fail(at + "/type", "unknown light type \"" + l.type + "\" (expected point, spot or directional)");
    const glm::vec3 color = factor3(l.color, glm::vec3(1.0f), at + "/color");
    if (!(l.intensity >= 0.0 && l.intensity < 1e9)) fail(at + "/intensity", "must be a number from 0 to 1e9");
    // Candela (lm/sr) to W/sr, lux (lm/m^2) to W/m^2, at the luminous
    // efficacy of 555 nm light.
    p.intensity = color * float(l.intensity / kLumensPerWatt);
    p.position = glm::vec3(toWorld[3]);
    // Spot and directional lights shine down their node's -Z axis.
    p.direction = glm::normalize(glm::vec3(toWorld * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
    if (!is_finite(p.position) || !is_finite(p.direction)) fail(where, "the node's transform does not place the light (it is singular or not finite)");
    if (p.kind == ScenePointLight::Kind::Spot) {
      const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
      if (!(inner >= 0.0 && inner < outer && outer <= M_PI / 2))
        fail(at + "/spot", "needs 0 <= innerConeAngle < outerConeAngle <= pi / 2 (it has " + std::to_string(inner) + " and " +
                               std::to_string(outer) + ")");
      p.cosInner = float(std::cos(inner));
      p.cosOuter = float(std::cos(outer));
    }
    scene_.pointLights.push_back(p);
  }

  // The camera the render uses: the first camera of the tree,
  // or one framing the scene's bounds (the command line may pick another).
  void default_camera() {
    for (const NamedCamera& c : scene_.cameras)
      if (c.problem.empty()) {
        scene_.camera = c.camera;
        return;
      }
    scene_.camera = framing_camera(scene_);
  }

  std::string path_;
  Sandbox sandbox_;
  tinygltf::Model model_;
  Scene scene_;
  size_t visits_ = 0;
  uint32_t defaultMaterial_ = WP_INVALID;
  std::map<int, uint32_t> materials_;
  std::map<int, uint32_t> instancedMeshes_;  // glTF mesh -> Scene::instancedMeshes
  std::map<std::pair<int, ColorEncoding>, uint32_t> images_;
  std::set<std::string> unread_;  // features of the model wavepath renders without, for one warning
};

}  // namespace

Scene import_gltf(const std::string& path) {
  return GltfImporter(path).run();
}

}  // namespace wp
