// cs184_normals.h — vertex normals as the CS184 skeleton computes them: its
// half-edge mesh (src/util/halfEdgeMesh.cpp, build and Vertex::computeNormal)
// sums, around each vertex, the cross products of the edges to the next two
// vertices of each face. Around a vertex on an open border it walks the
// faces by next-then-twin instead of twin-then-next, which turns the
// normals of open meshes (the Cornell box's single-sided walls) to the
// other side. CS184 scenes are shaded with these normals, so wavepath
// reproduces the walk exactly.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace wp {

// The unit normal of every position (zero where the sum vanishes or the
// vertex is on no polygon), or nullopt where the skeleton's half-edge mesh
// refuses the polygons (an edge used twice in one direction: non-manifold
// or inconsistently oriented), so that the caller can fall back.
std::optional<std::vector<glm::vec3>> cs184_vertex_normals(const std::vector<std::vector<uint32_t>>& polygons,
                                                           const std::vector<glm::vec3>& positions);

}  // namespace wp
