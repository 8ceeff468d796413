#include "bvh/photon_map.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace wp {

void PhotonMap::build() {
  axis_.assign(photons_.size(), 0);
  build(0, photons_.size());
}

void PhotonMap::build(size_t lo, size_t hi) {
  if (hi - lo < 2) return;
  glm::vec3 a(INFINITY), b(-INFINITY);
  for (size_t i = lo; i < hi; ++i) {
    a = glm::min(a, photons_[i].position);
    b = glm::max(b, photons_[i].position);
  }
  const glm::vec3 extent = b - a;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const size_t mid = lo + (hi - lo) / 2;
  std::nth_element(photons_.begin() + lo, photons_.begin() + mid, photons_.begin() + hi,
                   [axis](const Photon& p, const Photon& q) { return p.position[axis] < q.position[axis]; });
  axis_[mid] = uint8_t(axis);
  build(lo, mid);
  build(mid + 1, hi);
}

// Visits the nodes of [lo, hi) that may lie within sqrt(radius2) of q, the
// nearer half first; radius2 may shrink as the visit goes (k nearest).
template <class Visit>
void PhotonMap::search(size_t lo, size_t hi, glm::vec3 q, const float& radius2, Visit& visit) const {
  if (lo >= hi) return;
  const size_t mid = lo + (hi - lo) / 2;
  const Photon& p = photons_[mid];
  const float d = q[axis_[mid]] - p.position[axis_[mid]];
  const bool leftFirst = d < 0.0f;
  search(leftFirst ? lo : mid + 1, leftFirst ? mid : hi, q, radius2, visit);
  const glm::vec3 v = p.position - q;
  const float dist2 = glm::dot(v, v);
  if (dist2 <= radius2) visit(uint32_t(mid), dist2);
  if (d * d <= radius2) search(leftFirst ? mid + 1 : lo, leftFirst ? hi : mid, q, radius2, visit);
}

void PhotonMap::within(glm::vec3 q, float radius2, const std::function<void(const Photon&, float)>& visit) const {
  auto each = [&](uint32_t i, float dist2) { visit(photons_[i], dist2); };
  search(0, photons_.size(), q, radius2, each);
}

PhotonMap::Nearest PhotonMap::nearest(glm::vec3 q, float radius2, size_t k) const {
  Nearest out;
  out.radius2 = radius2;
  if (k == 0) return out;
  std::priority_queue<std::pair<float, uint32_t>> heap;  // the farthest kept on top
  auto keep = [&](uint32_t i, float dist2) {
    if (heap.size() == k) {
      if (dist2 >= heap.top().first) return;
      heap.pop();
    }
    heap.push({dist2, i});
    if (heap.size() == k) out.radius2 = heap.top().first;  // only nearer ones may join now
  };
  search(0, photons_.size(), q, out.radius2, keep);
  out.photons.reserve(heap.size());
  for (; !heap.empty(); heap.pop()) out.photons.push_back(heap.top());
  return out;
}

PhotonMap::Gathered PhotonMap::gather_nearest(glm::vec3 q, float radius2, size_t k) const {
  Nearest found = nearest(q, radius2, k + 1);
  Gathered g;
  g.area = float(M_PI) * found.radius2;
  // Farthest first: the (k+1)-th, where k+1 were found, only bounds the disc.
  const size_t skip = found.photons.size() > k ? 1 : 0;
  for (size_t i = skip; i < found.photons.size(); ++i) g.power += photons_[found.photons[i].second].power;
  return g;
}

PhotonMap::Gathered PhotonMap::gather_within(glm::vec3 q, float radius2) const {
  // Summed in double: a wide disc holds thousands of photons.
  glm::dvec3 sum(0.0);
  auto add = [&](uint32_t i, float) { sum += glm::dvec3(photons_[i].power); };
  search(0, photons_.size(), q, radius2, add);
  Gathered g;
  g.power = glm::vec3(sum);
  g.area = float(M_PI) * radius2;
  return g;
}

}  // namespace wp
