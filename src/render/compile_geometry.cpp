// compile_geometry.cpp — compile_scene's geometry and instances: the trees
// of both levels in the chosen layout, and the primitive records their
// leaves index, with the shading data beside them.
#include <glm/glm.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <chrono>
#include <utility>
#include <vector>

#include "bvh/wide_bvh.h"
#include "render/compile_parts.h"
#include "scene/transform.h"
#include "util/error.h"
#include "util/huge_pages.h"

namespace wp {

namespace {

Aabb triangle_bounds(const SceneTriangle& t) {
  Aabb b;
  for (const glm::vec3& v : t.v) b.grow(v);
  return b;
}

// Exact bounds of a transformed unit sphere: the half-extent along world axis i
// is the length of row i of the linear part.
Aabb sphere_bounds(const glm::mat4& m) {
  glm::vec3 c(m[3]);
  glm::vec3 e;
  for (int i = 0; i < 3; ++i) e[i] = glm::length(glm::vec3(m[0][i], m[1][i], m[2][i]));
  Aabb b;
  b.lo = c - e;
  b.hi = c + e;
  return b;
}

// A triangle's record without its shading data (compile_geometry adds that)
// and before the emitter table names it.
shader::Triangle triangle_record(const SceneTriangle& t) {
  shader::Triangle g{};
  g.v0 = t.v[0];
  g.v1 = t.v[1];
  g.v2 = t.v[2];
  g.material = t.material;
  g.emitter = WP_INVALID;
  g.shading = WP_INVALID;
  return g;
}

// bvh_input with the scene's material_radiance already at hand, and the
// instances' world boxes (placeholders after the spheres, which emit nothing).
BvhInput bvh_input(const Scene& scene, const std::vector<double>& radiance, const std::vector<Aabb>& instanceBoxes) {
  BvhInput input;
  const size_t count = scene.triangles.size() + scene.spheres.size() + instanceBoxes.size();
  reserve_huge(input.bounds, count);
  for (const SceneTriangle& t : scene.triangles) input.bounds.push_back(triangle_bounds(t));
  for (const SceneSphere& s : scene.spheres) input.bounds.push_back(sphere_bounds(s.toWorld));
  input.bounds.insert(input.bounds.end(), instanceBoxes.begin(), instanceBoxes.end());
  if (std::any_of(radiance.begin(), radiance.end(), [](double r) { return r > 0.0; })) {
    reserve_huge(input.emits, count);
    for (const SceneTriangle& t : scene.triangles) {
      const glm::vec3 front = glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);  // as surface_at's ng
      uint8_t sides = 0;
      for (int a = 0; a < 3; ++a) sides |= uint8_t((front[a] < 0.0f ? 1u : 0u) | (front[a] > 0.0f ? 2u : 0u)) << (2 * a);
      input.emits.push_back(radiance[t.material] > 0.0 ? sides : 0);
    }
    for (const SceneSphere& s : scene.spheres) input.emits.push_back(radiance[s.material] > 0.0 ? 0x3f : 0);
    input.emits.resize(count, 0);
  }
  return input;
}

// An instance's world box: the union of its mesh's top boxes (`parts`)
// placed by its transform, tighter than the mesh's whole box placed, grown by
// a few ulps of its coordinates against rounding in the walk's transform of
// the ray.
Aabb instance_box(const std::vector<Aabb>& parts, const glm::mat4& toWorld) {
  Aabb w;
  for (const Aabb& b : parts) {
    const auto [lo, hi] = placed_bounds(b.lo, b.hi, toWorld);
    w.grow(lo);
    w.grow(hi);
  }
  const glm::vec3 pad = 4e-7f * glm::max(glm::abs(w.lo), glm::abs(w.hi)) + glm::vec3(1e-30f);
  w.lo -= pad;
  w.hi += pad;
  return w;
}

// The boxes under the root of a tree: a wide root's children, or a binary
// tree's nodes two levels down (each box whole where it is a leaf).
std::vector<Aabb> top_boxes(const std::vector<shader::WideNode>& wide, const std::vector<shader::BvhNode>& binary) {
  std::vector<Aabb> parts;
  if (!wide.empty()) {
    const shader::WideNode& root = wide[0];
    for (int slot = 0; slot < 8; ++slot)
      if (((slot < 4 ? root.meta0123 : root.meta4567) >> ((slot & 3) * 8)) & 0xffu) parts.push_back(wide_child_box(root, slot));
    return parts;
  }
  std::vector<uint32_t> level{0u};
  for (int depth = 0; depth < 2; ++depth) {
    std::vector<uint32_t> next;
    for (uint32_t n : level) {
      if (binary[n].count != 0u) parts.push_back(node_box(binary[n]));
      else next.insert(next.end(), {binary[n].leftFirst, binary[n].leftFirst + 1u});
    }
    level = std::move(next);
  }
  for (uint32_t n : level) parts.push_back(node_box(binary[n]));
  return parts;
}

}  // namespace

BvhInput bvh_input(const Scene& scene) {
  std::vector<Aabb> boxes;
  for (const SceneInstance& i : scene.instances) {
    const SceneInstancedMesh& m = scene.instancedMeshes[i.mesh];
    Aabb b;
    b.lo = m.lo;
    b.hi = m.hi;
    boxes.push_back(instance_box({b}, i.toWorld));
  }
  return bvh_input(scene, material_radiance(scene, pack_textures(scene)), boxes);
}

CompiledGeometry compile_geometry(const Scene& scene, const RenderOptions& options, const std::vector<double>& materialRadiance,
                                  CompiledScene& out) {
  const size_t numTris = scene.triangles.size();
  const size_t numSpheres = scene.spheres.size();
  size_t records = numTris + numSpheres + scene.lightOnlyTriangles.size() + scene.instances.size();
  for (const SceneInstancedMesh& m : scene.instancedMeshes) records += m.triangles.size();
  // Fewer than 2^28 records: the wide walk's way back out of an instance
  // keeps a primitive index and the count of primitive groups set aside
  // (two bits) in one word (WIDE_RETURN_X, traverse_wide.glsl).
  static_assert(EMITTER_UNSEEN_BIT == 0x10000000u && WIDE_STACK_PRIM_GROUPS <= 3u, "WIDE_RETURN_X's word");
  if (records >= size_t(EMITTER_UNSEEN_BIT)) throw InputError(scene.sourcePath + ": too many primitives");

  const bool wide = options.bvhLayout == BvhLayout::Wide;
  out.bvhLayout = options.bvhLayout;
  const auto start = std::chrono::steady_clock::now();
  // The split method for a tree of `primitives` (Auto resolved by size).
  auto accel_for = [&](size_t primitives) {
    AcceleratorSettings accel = scene.accelerator;
    accel.split = split_for(accel, primitives);
    if (options.clusteredBuild && accel.split == SplitMethod::Sah) accel.split = SplitMethod::ClusteredSah;
    return accel;
  };
  // The trees of the instanced meshes first (bottom level): the top level's
  // boxes of their instances come from them.
  struct MeshTree {
    std::vector<shader::WideNode> wideNodes;
    std::vector<shader::BvhNode> nodes;
    std::vector<uint32_t> order;
    int depth = 0;
    std::vector<Aabb> topBoxes;
  };
  std::vector<MeshTree> meshTrees(scene.instancedMeshes.size());
  for (size_t m = 0; m < scene.instancedMeshes.size(); ++m) {
    BvhInput in;
    for (const SceneTriangle& t : scene.instancedMeshes[m].triangles) in.bounds.push_back(triangle_bounds(t));
    const AcceleratorSettings accel = accel_for(in.bounds.size());
    MeshTree& tree = meshTrees[m];
    if (wide) {
      WideBvh w = build_wide_bvh(in, accel, options.wideCollapse);
      tree.wideNodes = std::move(w.nodes);
      tree.order = std::move(w.order);
      tree.depth = w.depth;
    } else {
      Bvh b = build_bvh(in, accel);
      tree.nodes = std::move(b.nodes);
      tree.order = std::move(b.order);
      tree.depth = b.depth;
    }
    tree.topBoxes = top_boxes(tree.wideNodes, tree.nodes);
  }
  std::vector<Aabb> instanceBoxes;
  reserve_huge(instanceBoxes, scene.instances.size());
  for (const SceneInstance& i : scene.instances) instanceBoxes.push_back(instance_box(meshTrees[i.mesh].topBoxes, i.toWorld));
  const size_t numInstances = scene.instances.size();
  BvhInput input = bvh_input(scene, materialRadiance, instanceBoxes);
  Aabb sceneBounds;
  for (const Aabb& b : input.bounds) sceneBounds.grow(b);
  const AcceleratorSettings accel = accel_for(input.bounds.size());
  out.bvhSplit = accel.split;
  uint32_t stackSlots;
  std::vector<uint32_t> order;
  if (wide) {
    // Collapsed from the builder's arrays, without laying out the binary tree.
    WideBvh w = build_wide_bvh(input, accel, options.wideCollapse);
    out.wideNodes = std::move(w.nodes);
    order = std::move(w.order);
    out.bvhDepth = w.depth;
    stackSlots = uint32_t(std::max(w.depth, 1)) - 1u + WIDE_STACK_PRIM_GROUPS;  // a node group per level below the root, and the primitive groups
    out.nodes.push_back(shader::BvhNode{});
  } else {
    Bvh bvh = build_bvh(input, accel);
    out.binarySahCost = bvh.sahCost;
    out.nodes = std::move(bvh.nodes);
    order = std::move(bvh.order);
    out.bvhDepth = bvh.depth;
    stackSlots = uint32_t(bvh.depth) + 1u;
    out.wideNodes.push_back(shader::WideNode{});
  }
  out.bvhBuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();  // both levels' trees
  input = {};
  // The builder bounds the depth, and with it the kernels' traversal stacks.
  if (out.bvhDepth > BVH_MAX_DEPTH) throw RenderError("internal error: BVH deeper than BVH_MAX_DEPTH");
  // An instance's walk stacks on the top level's (traverse_*.glsl).
  uint32_t meshSlots = 0;
  for (const MeshTree& tree : meshTrees)
    meshSlots = std::max(meshSlots, wide ? uint32_t(std::max(tree.depth, 1)) - 1u + WIDE_STACK_PRIM_GROUPS : uint32_t(tree.depth) + 1u);
  if (numInstances > 0) stackSlots += INSTANCE_ENTRY_SLOTS + meshSlots;

  // Primitive records in leaf order (both layouts' leaves index them): each
  // triangle, and for each sphere and each instance a placeholder naming it;
  // then each instanced mesh's triangles in its tree's leaf order.
  size_t meshTriangles = 0;
  for (const MeshTree& tree : meshTrees) meshTriangles += tree.order.size();
  reserve_huge(out.triangles, order.size() + meshTriangles);
  reserve_huge(out.triangleShading, scene.triangleShading.size());
  // Tangents, colours and second UVs: a record beside every shading record
  // once any triangle has them.
  auto has_vertex_data = [](const std::vector<SceneTriangleShading>& shading) {
    return std::any_of(shading.begin(), shading.end(), [](const SceneTriangleShading& s) { return s.hasVertexData; });
  };
  const bool vertexData = has_vertex_data(scene.triangleShading) ||
                          std::any_of(scene.instancedMeshes.begin(), scene.instancedMeshes.end(),
                                      [&](const SceneInstancedMesh& m) { return has_vertex_data(m.shading); });
  if (vertexData) reserve_huge(out.triangleVertexData, scene.triangleShading.size());
  // A triangle's record, with its shading data (from `shading`) where it has any.
  auto add_triangle = [&](const SceneTriangle& t, const std::vector<SceneTriangleShading>& shading) {
    shader::Triangle g = triangle_record(t);
    if (t.shading != WP_INVALID) {
      const SceneTriangleShading& in = shading[t.shading];
      shader::TriangleShading sh{};
      g.shading = uint32_t(out.triangleShading.size());
      sh.flags = (in.hasNormals ? SHADING_NORMALS : 0u) | (in.hasVertexData ? SHADING_VERTEX_DATA : 0u);
      if (in.hasNormals) {
        sh.n0 = in.n[0];
        sh.n1 = in.n[1];
        sh.n2 = in.n[2];
      }
      // Without UVs the barycentrics serve, as for triangles without shading data.
      glm::vec2 uv[3] = {{0, 0}, {1, 0}, {0, 1}};
      if (in.hasUvs) std::copy(in.uv, in.uv + 3, uv);
      sh.u0 = uv[0].x;
      sh.v0 = uv[0].y;
      sh.uv12 = glm::vec4(uv[1], uv[2]);
      out.triangleShading.push_back(sh);
      if (vertexData) {
        shader::TriangleVertexData vd{};
        const glm::vec2* uv1 = in.hasUv1 ? in.uv1 : uv;
        vd.tangent0 = in.tangent[0];
        vd.tangent1 = in.tangent[1];
        vd.tangent2 = in.tangent[2];
        vd.color0 = in.color[0];
        vd.color1 = in.color[1];
        vd.color2 = in.color[2];
        vd.uv1_01 = glm::vec4(uv1[0], uv1[1]);
        vd.uv1_2 = glm::vec4(uv1[2], 0.0f, 0.0f);
        out.triangleVertexData.push_back(vd);
      }
    }
    out.triangles.push_back(g);
  };
  for (uint32_t id : order) {
    shader::Triangle g{};
    if (id >= numTris) {
      const bool sphere = id < numTris + numSpheres;
      g.material = sphere ? WP_INVALID : PRIM_INSTANCE;
      g.emitter = WP_INVALID;
      g.shading = id - uint32_t(sphere ? numTris : numTris + numSpheres);
      if (!sphere) {
        g.v0 = instanceBoxes[g.shading].lo;
        g.v1 = instanceBoxes[g.shading].hi;
      }
      out.triangles.push_back(g);
      continue;
    }
    add_triangle(scene.triangles[id], scene.triangleShading);
  }
  out.instancing.topLevelBytes = out.triangles.size() * sizeof(shader::Triangle) +
                                 (wide ? out.wideNodes.size() * sizeof(shader::WideNode) : out.nodes.size() * sizeof(shader::BvhNode)) +
                                 numInstances * sizeof(shader::Instance);
  // The instanced meshes' trees after the top level's, their node and
  // primitive indices moved by where they now start.
  std::vector<uint32_t> meshRoot(meshTrees.size());
  for (size_t m = 0; m < meshTrees.size(); ++m) {
    MeshTree& tree = meshTrees[m];
    const uint32_t nodeBase = uint32_t(wide ? out.wideNodes.size() : out.nodes.size());
    const uint32_t primBase = uint32_t(out.triangles.size());
    meshRoot[m] = nodeBase;
    for (shader::WideNode n : tree.wideNodes) {
      n.childBase += nodeBase;
      n.primBase += primBase;
      out.wideNodes.push_back(n);
    }
    for (shader::BvhNode n : tree.nodes) {
      n.leftFirst += n.count == 0u ? nodeBase : primBase;
      out.nodes.push_back(n);
    }
    const SceneInstancedMesh& mesh = scene.instancedMeshes[m];
    for (uint32_t id : tree.order) add_triangle(mesh.triangles[id], mesh.shading);
    out.instancing.bottomLevelBytes += (tree.wideNodes.size() * sizeof(shader::WideNode) + tree.nodes.size() * sizeof(shader::BvhNode)) +
                                       tree.order.size() * sizeof(shader::Triangle);
    out.instancing.uniqueTriangles += tree.order.size();
    tree = MeshTree{};
  }
  for (const SceneInstance& i : scene.instances) {
    shader::Instance g{};
    rows_3x4(i.toWorld, g.toWorld0, g.toWorld1, g.toWorld2);
    rows_3x4(glm::inverse(i.toWorld), g.toObject0, g.toObject1, g.toObject2);
    g.root = meshRoot[i.mesh];
    g.flags = glm::determinant(glm::mat3(i.toWorld)) < 0.0f ? INSTANCE_MIRRORED : 0u;
    g.mesh = i.mesh;
    out.instances.push_back(g);
  }
  out.instancing.meshes = meshTrees.size();
  out.instancing.instances = numInstances;
  out.instancing.instancedTriangles = instanced_triangle_count(scene);
  // Light-only triangles after the leaves' records, where no leaf reaches them.
  const size_t firstLightOnly = out.triangles.size();
  for (const SceneTriangle& t : scene.lightOnlyTriangles) out.triangles.push_back(triangle_record(t));
  for (const SceneSphere& s : scene.spheres) {
    shader::Sphere g{};
    rows_3x4(s.toWorld, g.toWorld0, g.toWorld1, g.toWorld2);
    rows_3x4(glm::inverse(s.toWorld), g.toObject0, g.toObject1, g.toObject2);
    g.material = s.material;
    g.emitter = WP_INVALID;
    float r = glm::length(glm::vec3(s.toWorld[0]));  // uniform scale (checked when emissive)
    g.area = 4.0f * WP_PI * r * r;
    out.spheres.push_back(g);
  }
  return CompiledGeometry{sceneBounds, firstLightOnly, stackSlots};
}

}  // namespace wp
