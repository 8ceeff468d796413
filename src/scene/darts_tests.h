// darts_tests.h — a darts file of "type": "tests": the course's checks of
// materials, surfaces and intersections (darts-2022 src/tests/*.cpp), read
// into plain descriptions. `wavepath test` (src/cli/test.cpp) runs them.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace wp {

enum class DartsTestKind {
  ScatterMaterial,  // "scatter material": histogram of a material's sampled directions
  SampleMaterial,   // "sample material": the same, against the material's pdf
  SampleSurface,    // "sample surface": directions to points sampled on surfaces, against their pdf
  Intersection,     // "intersection": one ray against the surfaces, hit compared with the file's
  PhotonMap,        // "photon map": photons on a transformed disk, their density estimate against the disk's pdf
};

struct DartsTest {
  DartsTestKind kind = DartsTestKind::ScatterMaterial;
  std::string name;       // output files are NAME-sampled.png and so on ("intersection" tests have none)
  std::string where;      // "FILE: at /tests/N", for messages
  std::string loadError;  // set where this test could not be read; the others still run
  Scene scene;            // the material (material tests) or the surfaces

  // Sampling tests (darts' ScatterTest and SampleTest, with their defaults).
  glm::ivec2 imageSize{256, 128};  // the lat-long histogram
  uint64_t samplesPerPixel = 1000;  // "spp": samples = spp x pixels
  uint32_t upSamples = 4;           // each histogram cell written as up x up pixels
  uint32_t superSamples = 32;       // pdf evaluated at super x super points per cell
  // Material tests: the hit's normal and the incoming ray's direction (towards the surface).
  uint32_t material = 0;
  glm::vec3 normal{0, 0, 1};
  glm::vec3 incoming{0, 0, -1};
  // Surface tests: the surfaces of each child of the group darts samples (a
  // child is picked uniformly, then a point on it) emit through a material
  // of the child's own, listed here.
  std::vector<uint32_t> childMaterials;

  // Photon map tests (darts' PhotonMapTest): a k-nearest search of "search
  // count" photons within "search radius", or a fixed-radius one where the
  // count is 0; the unit disk placed by "transform".
  float searchRadius = 0.1f;
  int searchCount = 50;
  glm::mat4 transform{1.0f};

  // Intersection tests.
  glm::vec3 rayOrigin{0.0f}, rayDirection{0, 0, 1};  // the direction as given: t is in its units
  float t = 0.0f;
  glm::vec3 p{0.0f}, gn{0.0f}, sn{0.0f};
  bool shouldHit = true;
  float threshold = 1e-5f;
};

// Whether `path` is a darts JSON file of "type": "tests".
bool is_darts_test_file(const std::string& path);

// The tests of a darts test file. A problem with the file as a whole (JSON
// syntax, keys at its top) is thrown as an InputError; a problem with one
// test (an unknown key, a mesh that cannot be opened) is left in its
// loadError, so that the others still run, as in darts.
std::vector<DartsTest> import_darts_tests(const std::string& path);

}  // namespace wp
