// gltf_textures.cpp — the glTF importer's textures: a material's texture
// slots, their samplers' wrap modes, KHR_texture_transform, and the images
// they decode, each once per colour space (gltf_importer.h).
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "scene/gltf_importer.h"

namespace wp::gltf_import {

// ---- textures ---------------------------------------------------------------

// A texture scaled by a constant factor (RGB and alpha), or the factor
// alone without one.
uint32_t GltfImporter::texture_times(const TextureRef& info, glm::vec4 factor, ColorEncoding encoding, const std::string& where) {
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
uint32_t GltfImporter::wrap_mode(int mode, const std::string& where) const {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return TEX_WRAP_REPEAT;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TEX_WRAP_CLAMP;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TEX_WRAP_MIRROR;
    default: fail(where, "is " + std::to_string(mode) + ", not a wrap mode (10497, 33071 or 33648)");
  }
}

// KHR_texture_transform's offset x rotation x scale of glTF's UVs, as a
// mapping of wavepath's (whose v is glTF's 1 - v): flip, transform, flip back.
glm::mat4 GltfImporter::uv_transform(const tinygltf::Value& t, const std::string& where) const {
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

uint32_t GltfImporter::decoded_image(int index, ColorEncoding encoding) {
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

}  // namespace wp::gltf_import
