// photon_map.h — photons in a balanced kd-tree, with the two searches of
// density estimation: every photon within a radius, and the k nearest
// within it (darts-2022 include/darts/photon.h and point_kdtree.h define
// the same two; photon mapping gathers with them).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace wp {

class PhotonMap {
 public:
  struct Photon {
    glm::vec3 position;
    glm::vec3 power;
    uint32_t from = 0;  // the direction it arrived from, packed (photons.glsl); carried, not searched
  };

  void reserve(size_t n) { photons_.reserve(n); }
  void add(glm::vec3 position, glm::vec3 power, uint32_t from = 0) { photons_.push_back({position, power, from}); }
  // Orders the photons as an implicit balanced kd-tree: each range's median
  // on its widest axis is its node, the halves its subtrees. Call after the
  // last add and before searching.
  void build();
  size_t size() const { return photons_.size(); }

  // Calls visit(photon, squared distance) for every photon within
  // sqrt(radius2) of q.
  void within(glm::vec3 q, float radius2, const std::function<void(const Photon&, float)>& visit) const;

  // The k nearest photons within sqrt(radius2) of q (fewer where fewer lie
  // there), and the squared radius they fill: the k-th one's distance when k
  // were found, else radius2 (darts' KNNSearch::max_dist2).
  struct Nearest {
    std::vector<std::pair<float, uint32_t>> photons;  // squared distance, index into photon()
    float radius2 = 0.0f;
  };
  Nearest nearest(glm::vec3 q, float radius2, size_t k) const;
  const Photon& photon(uint32_t i) const { return photons_[i]; }
  // The axis the node at index i splits (after build).
  uint32_t axis(uint32_t i) const { return axis_[i]; }

  // The parts of the k-nearest density estimate at q, power / area: the
  // power of the k nearest photons within sqrt(radius2), and the area of the
  // disc out to the (k+1)-th nearest, or of the search disc where no more
  // than k lie in it. The (k+1)-th photon's disc rather than the k-th's makes
  // the estimate unbiased where photons are spread uniformly: for a Poisson
  // process of density d, pi r^2 d at the j-th nearest is Gamma(j)-distributed,
  // so k / (pi r^2) averages d at the (k+1)-th and d k / (k - 1) at the k-th.
  // darts' KNNSearch (include/darts/photon.h) ends on the (k+1)-th's disc
  // too whenever the farthest of the first k photons it meets is among the k
  // nearest, since it lets the next one in unconditionally.
  struct Gathered {
    glm::vec3 power{0.0f};
    float area = 0.0f;
  };
  Gathered gather_nearest(glm::vec3 q, float radius2, size_t k) const;
  // The fixed-radius estimate's parts: every photon within sqrt(radius2)
  // over the search disc.
  Gathered gather_within(glm::vec3 q, float radius2) const;

 private:
  void build(size_t lo, size_t hi);
  template <class Visit>
  void search(size_t lo, size_t hi, glm::vec3 q, const float& radius2, Visit& visit) const;

  std::vector<Photon> photons_;
  std::vector<uint8_t> axis_;  // the splitting axis of the node at each index
};

}  // namespace wp
