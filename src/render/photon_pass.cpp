#include "render/photon_pass.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>


namespace wp {

void build_photon_map(CompiledScene& cs, uint32_t count, uint32_t seed) {
  shader::SceneView view = cs.view();  // read-only: shared by the threads
  // Each photon's records in its own list, so the map does not depend on
  // how the threads share the work; a block of photons at a time.
  constexpr uint32_t kBlock = 1u << 14;
  std::vector<std::vector<shader::Photon>> records(std::min(count, kBlock));
  PhotonMap map;
  for (uint32_t first = 0; first < count; first += kBlock) {
    const uint32_t n = std::min(kBlock, count - first);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 256), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        records[i].clear();
        shader::SceneView::PhotonPath path = view.photon_emit(first + i, count, seed);
        shader::Photon ph;
        while (path.alive != 0u)
          if (view.photon_bounce(path, ph)) records[i].push_back(ph);
      }
    });
    for (uint32_t i = 0; i < n; ++i)
      for (const shader::Photon& ph : records[i]) map.add(ph.position, ph.power, ph.from);
  }
  map.build();
  cs.photons = pack_photon_map(map);
  cs.params.photons.x = uint32_t(map.size());
}

std::vector<shader::Photon> pack_photon_map(const PhotonMap& map) {
  std::vector<shader::Photon> out(map.size());
  for (uint32_t i = 0; i < map.size(); ++i) {
    const PhotonMap::Photon& p = map.photon(i);
    out[i] = shader::Photon{p.position, map.axis(i), p.power, p.from};
  }
  return out;
}

}  // namespace wp
