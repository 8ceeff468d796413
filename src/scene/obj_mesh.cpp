#include "scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/error.h"

namespace wp {

namespace {

// tinyobjloader's messages may span several lines; keep the first, which names
// the problem (and often the line number).
std::string first_line(const std::string& s) {
  std::string line = s.substr(0, s.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// tinyobjloader accepts faces whose indices it cannot resolve and silently
// skips some malformed ones. Scan the face lines ourselves first so that a bad
// file is reported with its line number instead of rendering a partial mesh.
// Returns the material libraries the file names (mtllib), as written.
std::vector<std::string> check_face_lines(const std::string& path) {
  std::vector<std::string> libraries;
  std::ifstream in(path);
  std::string line;
  long vertexCount = 0;
  for (int lineNo = 1; std::getline(in, line); ++lineNo) {
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag)) continue;
    if (tag == "v") {
      ++vertexCount;
      continue;
    }
    if (tag == "mtllib") {
      for (std::string name; ls >> name;) libraries.push_back(name);
      continue;
    }
    if (tag != "f") continue;
    std::string token;
    int corners = 0;
    while (ls >> token) {
      ++corners;
      const char* s = token.c_str();
      char* end = nullptr;
      long idx = std::strtol(s, &end, 10);
      if (end == s || (*end != '\0' && *end != '/')) {
        throw InputError(path + ":" + std::to_string(lineNo) + ": face corner \"" + token + "\" is not a vertex index");
      }
      long resolved = idx > 0 ? idx : vertexCount + idx + 1;  // negative indices count back
      if (idx == 0 || resolved < 1 || resolved > vertexCount) {
        throw InputError(path + ":" + std::to_string(lineNo) + ": face refers to vertex " + std::to_string(idx) +
                         " but only " + std::to_string(vertexCount) + " vertices are defined before it");
      }
    }
    if (corners < 3) {
      throw InputError(path + ":" + std::to_string(lineNo) + ": a face needs at least 3 vertices, got " +
                       std::to_string(corners));
    }
  }
  return libraries;
}

}  // namespace

ObjFile load_obj(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": cannot open OBJ file (no such file)");
  std::vector<std::string> libraries = check_face_lines(path);

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = std::filesystem::path(path).parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    std::string msg = first_line(reader.Error());
    throw InputError(path + ": OBJ parse error: " + (msg.empty() ? "unknown error" : msg));
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  ObjFile file;
  file.files.push_back(path);
  for (const std::string& name : libraries) {
    std::string library = (std::filesystem::path(config.mtl_search_path) / name).string();
    if (std::filesystem::is_regular_file(library, ec)) file.files.push_back(library);
  }
  SceneMesh& mesh = file.mesh;
  size_t vertexCount = attrib.vertices.size() / 3;
  mesh.positions.reserve(vertexCount);
  for (size_t i = 0; i < vertexCount; ++i) {
    glm::vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InputError(path + ": vertex " + std::to_string(i + 1) + " is not finite");
    }
    mesh.positions.push_back(p);
  }
  for (size_t i = 0; i < attrib.normals.size() / 3; ++i) {
    glm::vec3 n(attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]);
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) {
      throw InputError(path + ": normal " + std::to_string(i + 1) + " is not finite");
    }
    mesh.normals.push_back(n);
  }
  for (size_t i = 0; i < attrib.texcoords.size() / 2; ++i) {
    glm::vec2 t(attrib.texcoords[2 * i], attrib.texcoords[2 * i + 1]);
    if (!std::isfinite(t.x) || !std::isfinite(t.y)) throw InputError(path + ": texture coordinate " + std::to_string(i + 1) + " is not finite");
    mesh.uvs.push_back(t);
  }
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    ObjMaterial om;
    om.name = m.name;
    om.diffuse = glm::vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    om.emission = glm::vec3(m.emission[0], m.emission[1], m.emission[2]);
    if (!m.diffuse_texname.empty()) om.diffuseMap = (std::filesystem::path(config.mtl_search_path) / m.diffuse_texname).string();
    file.materials.push_back(om);
  }
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const tinyobj::mesh_t& m = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      size_t corners = m.num_face_vertices[f];
      if (corners != 3 || offset + 3 > m.indices.size()) {
        throw InputError(path + ": shape \"" + shape.name + "\": face " + std::to_string(f + 1) +
                         " could not be triangulated");
      }
      for (size_t c = 0; c < 3; ++c) {
        int vi = m.indices[offset + c].vertex_index;
        if (vi < 0 || size_t(vi) >= vertexCount) {
          throw InputError(path + ": shape \"" + shape.name + "\": face " + std::to_string(f + 1) +
                           " refers to a vertex that does not exist");
        }
        mesh.positionIndices.push_back(uint32_t(vi));
        // Normal and UV indices are optional; one out of range is an error, not a crash.
        int ni = m.indices[offset + c].normal_index;
        int ti = m.indices[offset + c].texcoord_index;
        if (ni >= int(mesh.normals.size()) || ti >= int(mesh.uvs.size())) {
          throw InputError(path + ": shape \"" + shape.name + "\": face " + std::to_string(f + 1) +
                           " refers to a normal or texture coordinate that does not exist");
        }
        mesh.normalIndices.push_back(ni < 0 ? WP_INVALID : uint32_t(ni));
        mesh.uvIndices.push_back(ti < 0 ? WP_INVALID : uint32_t(ti));
      }
      int mat = f < m.material_ids.size() ? m.material_ids[f] : -1;
      mesh.materials.push_back(mat < 0 || mat >= int(file.materials.size()) ? WP_INVALID : uint32_t(mat));
      offset += corners;
    }
  }
  return file;
}

}  // namespace wp
