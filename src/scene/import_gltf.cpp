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
//
// This file loads the model and checks its extensions; the importer's class
// is in gltf_importer.h, and its other parts are gltf_nodes.cpp,
// gltf_meshes.cpp, gltf_materials.cpp, gltf_textures.cpp and
// gltf_cameras_lights.cpp.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>

#include "scene/gltf_importer.h"
#include "scene/importers.h"

namespace wp {

namespace gltf_import {

bool Sandbox::inside(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::path(path), ec);
  if (ec) return false;
  const fs::path rel = p.lexically_relative(root);
  const bool ok = !rel.empty() && *rel.begin() != ".." && rel.is_relative();
  if (!ok && refused.empty()) refused = path;
  return ok;
}

namespace {

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

// The extensions wavepath reads beside its materials' (material_extensions,
// gltf_materials.cpp). Others are named once in a warning, or refused when
// the file requires them.
const std::set<std::string> kSupportedExtensions = {"EXT_mesh_gpu_instancing", "KHR_lights_punctual", "KHR_texture_transform"};

}  // namespace

Scene GltfImporter::run() {
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

void GltfImporter::fail(const std::string& where, const std::string& what) const {
  throw InputError(path_ + ": " + where + ": " + what);
}

void GltfImporter::load_model() {
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
void GltfImporter::check_what_tinygltf_passes(const std::vector<unsigned char>& bytes, bool binary) const {
  // The JSON's bytes, read where they lie (a GLB's first chunk).
  const unsigned char* first = bytes.data();
  const unsigned char* last = bytes.data() + bytes.size();
  if (binary) {
    uint32_t version = 0, length = 0;
    if (bytes.size() >= 8) std::memcpy(&version, bytes.data() + 4, 4);
    if (version == 1) fail("the binary header", "glTF 1.0 is not supported: wavepath reads glTF 2.0 (convert the model, e.g. with Blender)");
    if (bytes.size() < 20) return;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (size_t(length) > bytes.size() - 20) return;
    first = bytes.data() + 20;
    last = first + length;
  }
  // Only the asset and the meshes are looked at: the rest (a million nodes,
  // say) is read past without being stored.
  const nlohmann::json doc = nlohmann::json::parse(
      first, last,
      [](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        return depth != 1 || event != nlohmann::json::parse_event_t::key || parsed == "asset" || parsed == "meshes";
      },
      false);
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

std::string GltfImporter::first_line(const std::string& s) {
  const size_t end = s.find('\n');
  return end == std::string::npos ? s : s.substr(0, end);
}

void GltfImporter::check_extensions() {
  for (size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
    const std::string& e = model_.extensionsRequired[i];
    if (!kSupportedExtensions.count(e) && !material_extensions().count(e))
      fail("/extensionsRequired/" + std::to_string(i), "the model requires extension " + e + ", which wavepath does not support");
  }
  std::set<std::string> ignored;
  for (const std::string& e : model_.extensionsUsed)
    if (!kSupportedExtensions.count(e) && !material_extensions().count(e)) ignored.insert(e);
  if (!ignored.empty()) std::fprintf(stderr, "wavepath: warning: %s: ignoring extensions it uses: %s\n", path_.c_str(), joined(ignored).c_str());
}

}  // namespace gltf_import

using gltf_import::GltfImporter;

Scene import_gltf(const std::string& path) {
  return GltfImporter(path).run();
}

}  // namespace wp
