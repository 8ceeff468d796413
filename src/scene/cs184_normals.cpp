#include "scene/cs184_normals.h"

#include <cmath>
#include <unordered_map>

namespace wp {

namespace {

constexpr uint32_t kNone = 0xffffffffu;

// A half-edge: `vertex` is its tail, as in the skeleton.
struct HalfEdge {
  uint32_t vertex;
  uint32_t next = kNone;
  uint32_t twin = kNone;
  bool boundary = false;  // on a boundary loop's virtual face
};

uint64_t edge_key(uint32_t a, uint32_t b) {
  return (uint64_t(a) << 32) | b;
}

}  // namespace

std::optional<std::vector<glm::vec3>> cs184_vertex_normals(const std::vector<std::vector<uint32_t>>& polygons,
                                                           const std::vector<glm::vec3>& positions) {
  std::vector<HalfEdge> h;
  std::unordered_map<uint64_t, uint32_t> byEdge;
  std::vector<uint32_t> vertexEdge(positions.size(), kNone);  // the last half-edge leaving each vertex
  // One half-edge per polygon side, twinned with the opposite side once both exist.
  for (const std::vector<uint32_t>& poly : polygons) {
    const size_t first = h.size();
    for (size_t i = 0; i < poly.size(); ++i) {
      uint32_t a = poly[i], b = poly[(i + 1) % poly.size()];
      uint32_t id = uint32_t(h.size());
      if (!byEdge.emplace(edge_key(a, b), id).second) return std::nullopt;
      h.push_back(HalfEdge{a});
      vertexEdge[a] = id;
      auto opposite = byEdge.find(edge_key(b, a));
      if (opposite != byEdge.end()) {
        h[id].twin = opposite->second;
        h[opposite->second].twin = id;
      }
    }
    for (size_t i = 0; i < poly.size(); ++i) h[first + i].next = uint32_t(first + (i + 1) % poly.size());
  }
  const size_t walkLimit = 4 * h.size() + 8;
  // A border vertex starts from its border half-edge.
  for (uint32_t& start : vertexEdge) {
    if (start == kNone) continue;
    uint32_t e = start;
    for (size_t steps = 0; steps < walkLimit; ++steps) {
      if (h[e].twin == kNone) {
        start = e;
        break;
      }
      e = h[h[e].twin].next;
      if (e == start) break;
    }
  }
  // Each border loop gets virtual half-edges, linked against its direction.
  for (size_t k = 0; k < h.size(); ++k) {
    if (h[k].twin != kNone) continue;
    std::vector<uint32_t> loop;
    uint32_t i = uint32_t(k);
    do {
      uint32_t t = uint32_t(h.size());
      if (loop.size() > walkLimit) return std::nullopt;
      h.push_back(HalfEdge{h[h[i].next].vertex});
      h[t].twin = i;
      h[t].boundary = true;
      h[i].twin = t;
      loop.push_back(t);
      i = h[i].next;
      size_t steps = 0;
      while (i != k && h[i].twin != kNone) {
        i = h[h[i].twin].next;
        if (++steps > walkLimit) return std::nullopt;
      }
    } while (i != k);
    for (size_t p = 0; p < loop.size(); ++p) h[loop[p]].next = loop[(p + loop.size() - 1) % loop.size()];
  }
  for (uint32_t& start : vertexEdge)
    if (start != kNone) start = h[h[start].twin].next;

  std::vector<glm::vec3> normals(positions.size(), glm::vec3(0.0f));
  for (size_t v = 0; v < positions.size(); ++v) {
    const uint32_t start = vertexEdge[v];
    if (start == kNone) continue;
    bool border = false;
    uint32_t e = start;
    for (size_t steps = 0; steps < walkLimit; ++steps) {
      if (h[e].boundary) {
        border = true;
        break;
      }
      e = h[h[e].twin].next;
      if (e == start) break;
    }
    // Double precision, as the skeleton's Vector3D.
    const glm::dvec3 pi(positions[v]);
    glm::dvec3 n(0.0);
    e = start;
    for (size_t steps = 0; steps < walkLimit; ++steps) {
      const glm::dvec3 pj(positions[h[h[e].next].vertex]);
      const glm::dvec3 pk(positions[h[h[h[e].next].next].vertex]);
      n += glm::cross(pj - pi, pk - pi);
      e = border ? h[h[e].next].twin : h[h[e].twin].next;
      if (e == start) break;
    }
    const double len = glm::length(n);
    if (len > 0.0 && std::isfinite(len)) normals[v] = glm::vec3(n / len);
  }
  return normals;
}

}  // namespace wp
