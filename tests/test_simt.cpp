// The SIMT model of the walks (src/bench/simt_model.h): its counts against
// what they must be for warps whose rays are known.
#include "test_support.h"

#include "bench/ray_sets.h"
#include "bench/simt_model.h"
#include "gpu/wavefront.h"

namespace wp::test {
namespace {

struct RayCase {
  CompiledScene cs;
  bench::RaySets sets;
};

RayCase ray_case(const std::string& variant, int size = 24) {
  Scene scene = load_scene(source_path("scenes/cornell-box.json"));
  scene.camera.width = size;
  scene.camera.height = size;
  RayCase s{compile_scene(scene, variant_options(RenderOptions{}, variant)), {}};
  s.sets = bench::make_rays(s.cs);
  return s;
}

// The walk's iterations for one ray, counted by the CPU traversal itself.
uint64_t steps_of(const CompiledScene& cs, const shader::ShadowRay& r, bool anyHit) {
  shader::SceneView view = cs.view();
  uint64_t steps = 0;
  view.stepsTaken = &steps;
  shader::Hit h;
  view.trace_ray(r.origin, r.dir, r.tmax, anyHit, h);
  return steps;
}

// A warp of 32 copies of one ray runs in lockstep: every lane takes every
// iteration and every phase, and the lanes read the same node and primitive
// sectors as one lane alone (the stack is each lane's own).
TEST(Simt, IdenticalRaysRunInLockstepAndShareTheirSectors) {
  for (const char* variant : {"gpu", "gpu-bvh2", "gpu-regstack"}) {
    SCOPED_TRACE(variant);
    RayCase s = ray_case(variant);
    const shader::ShadowRay ray = s.sets.bounce[s.sets.bounce.size() / 2];
    const std::vector<shader::ShadowRay> one{ray}, copies(32, ray);
    const SimtWalk walk = simt_walk(variant, s.cs);
    const GpuModel& gpu = gpu_model("h200");
    const SimtFigures alone = simulate_walks(s.cs, one, false, walk, gpu, 32);
    const SimtFigures warp = simulate_walks(s.cs, copies, false, walk, gpu, 32);
    EXPECT_EQ(warp.warps, 1u);
    EXPECT_EQ(warp.warpIterations, steps_of(s.cs, ray, false));
    EXPECT_DOUBLE_EQ(warp.simdEfficiency, 1.0);
    EXPECT_DOUBLE_EQ(warp.phaseEfficiency, 1.0);
    EXPECT_DOUBLE_EQ(warp.nodeSectors, alone.nodeSectors);
    EXPECT_DOUBLE_EQ(warp.primSectors, alone.primSectors);
    // A lane alone in its warp keeps 1/32 of the lanes busy.
    EXPECT_DOUBLE_EQ(alone.simdEfficiency, 1.0 / 32.0);
  }
}

// The model's iterations are the walk's own, ray by ray; a warp runs as long
// as its longest walk, so its efficiency is the mean walk over the longest.
TEST(Simt, WarpsRunAsLongAsTheirLongestWalk) {
  for (const char* variant : {"gpu", "gpu-bvh2"}) {
    SCOPED_TRACE(variant);
    RayCase s = ray_case(variant);
    std::vector<shader::ShadowRay> rays(s.sets.bounce.begin(), s.sets.bounce.begin() + 64);
    const SimtFigures f = simulate_walks(s.cs, rays, false, simt_walk(variant, s.cs), gpu_model("h200"), 32);
    uint64_t lanes = 0, warpIterations = 0;
    for (size_t w = 0; w < 2; ++w) {
      uint64_t longest = 0;
      for (size_t l = 0; l < 32; ++l) {
        const uint64_t n = steps_of(s.cs, rays[w * 32 + l], false);
        lanes += n;
        longest = std::max(longest, n);
      }
      warpIterations += longest;
    }
    EXPECT_EQ(f.rays, 64u);
    EXPECT_EQ(f.laneIterations, lanes);
    EXPECT_EQ(f.warpIterations, warpIterations);
    EXPECT_DOUBLE_EQ(f.simdEfficiency, double(lanes) / double(warpIterations * 32));
    // Warps of 64 lanes: one warp as long as the longest of all 64.
    const SimtFigures wide = simulate_walks(s.cs, rays, false, simt_walk(variant, s.cs), gpu_model("h200"), 64);
    EXPECT_EQ(wide.warps, 1u);
    EXPECT_LE(wide.simdEfficiency, f.simdEfficiency);
  }
}

// Several rays a lane (trace_items.glsl): the same walks, the same lane
// iterations, but lanes refilled as their rays end keep more of them busy,
// once the rays outnumber a GPU dispatch's fill.
TEST(Simt, LanesThatTakeTheNextRayKeepTheWarpBusier) {
  RayCase s = ray_case("gpu-multiray", 48);
  const GpuModel& gpu = gpu_model("h200");
  SimtWalk one = simt_walk("gpu", s.cs);
  SimtWalk many = simt_walk("gpu-multiray", s.cs);
  ASSERT_EQ(many.raysPerLane, 16u);
  const SimtFigures a = simulate_walks(s.cs, s.sets.bounce, false, one, gpu, 32);
  const SimtFigures b = simulate_walks(s.cs, s.sets.bounce, false, many, gpu, 32);
  EXPECT_EQ(a.rays, s.sets.bounce.size());
  EXPECT_EQ(b.rays, s.sets.bounce.size());
  EXPECT_EQ(a.laneIterations, b.laneIterations);
  // A GPU's dispatch has at least TRACING_INVOCATIONS_ON_GPUS invocations:
  // these few rays get one each, as `gpu` gives them.
  EXPECT_DOUBLE_EQ(b.simdEfficiency, a.simdEfficiency);
  // Sixteen rays to a lane, the lanes busier.
  many.fillInvocations = 0;
  const SimtFigures c = simulate_walks(s.cs, s.sets.bounce, false, many, gpu, 32);
  EXPECT_EQ(a.laneIterations, c.laneIterations);
  EXPECT_GT(c.simdEfficiency, a.simdEfficiency + 0.05);
}

// Identical rays through one SM's L1: after the first warp, every record's
// sector is there (each warp's stack is its own, written before it is read).
TEST(Simt, TheL1KeepsWhatAWarpReadForTheNext) {
  RayCase s = ray_case("gpu-bvh2");
  GpuModel oneSm = gpu_model("h200");
  oneSm.sms = 1;
  const std::vector<shader::ShadowRay> copies(32 * 16, s.sets.primary[s.sets.primary.size() / 2]);
  const SimtFigures f = simulate_walks(s.cs, copies, false, simt_walk("gpu-bvh2", s.cs), oneSm, 32);
  EXPECT_EQ(f.warps, 16u);
  EXPECT_GT(f.l1HitRate, 0.9);
  EXPECT_LT(f.l2BytesPerRay, f.bytesPerRay * 0.1);
  // Spread over 16 SMs, the 8 workgroups (of two warps) meet 8 cold L1s,
  // and each reads the records' sectors from L2 once.
  oneSm.sms = 16;
  const SimtFigures spread = simulate_walks(s.cs, copies, false, simt_walk("gpu-bvh2", s.cs), oneSm, 32);
  EXPECT_DOUBLE_EQ(spread.l2BytesPerRay, f.l2BytesPerRay * 8.0);
}

// Node visits, split between the top level and the instances' trees: an
// iteration visits at most one node; a flat scene has no instance's tree,
// and rays into a scene of instances walk both levels.
TEST(Simt, NodeVisitsAreSplitBetweenTheTopLevelAndTheInstances) {
  for (const char* variant : {"gpu", "gpu-bvh2"}) {
    SCOPED_TRACE(variant);
    Scene scene = load_scene(source_path("tests/data/gltf/instances.gltf"));
    scene.camera.width = scene.camera.height = 24;
    Scene flat = scene;
    flatten_instances(flat);
    for (const Scene* sc : {&scene, &flat}) {
      const CompiledScene cs = compile_scene(*sc, variant_options(RenderOptions{}, variant));
      const bench::RaySets sets = bench::make_rays(cs);
      const SimtFigures f = simulate_walks(cs, sets.bounce, false, simt_walk(variant, cs), gpu_model("h200"), 32);
      EXPECT_GT(f.nodeVisitsPerRay, 0.0);
      EXPECT_LE(f.nodeVisitsPerRay, f.stepsPerRay);
      if (sc == &flat) {
        EXPECT_EQ(f.instanceNodeVisitsPerRay, 0.0);
      } else {
        EXPECT_GT(f.instanceNodeVisitsPerRay, 0.0);
        EXPECT_LT(f.instanceNodeVisitsPerRay, f.nodeVisitsPerRay);
      }
    }
  }
}

// Nodes modelled a cache line apart (--node-stride 128): every 80-byte wide
// node lies in one line, in its first three sectors; back to back, some
// straddle two lines. A warp of one ray's copies loads one node an iteration.
TEST(Simt, NodesACacheLineApartTakeOneLineEach) {
  RayCase s = ray_case("gpu");
  const std::vector<shader::ShadowRay> copies(32, s.sets.bounce[s.sets.bounce.size() / 3]);
  SimtWalk walk = simt_walk("gpu", s.cs);
  const SimtFigures plain = simulate_walks(s.cs, copies, false, walk, gpu_model("h200"), 32);
  walk.nodeStrideBytes = 128;
  const SimtFigures padded = simulate_walks(s.cs, copies, false, walk, gpu_model("h200"), 32);
  EXPECT_EQ(padded.warpIterations, plain.warpIterations);
  EXPECT_DOUBLE_EQ(padded.nodeLines, 1.0);
  EXPECT_DOUBLE_EQ(padded.nodeSectors, 3.0);
  EXPECT_GE(plain.nodeSectors, 3.0);
  EXPECT_GE(plain.nodeLines, 1.0);
}

TEST(Simt, UnknownModelsAndWidthsAreRefused) {
  EXPECT_THROW(gpu_model("h300"), InputError);
  RayCase s = ray_case("gpu", 4);
  EXPECT_THROW(simulate_walks(s.cs, s.sets.primary, false, simt_walk("gpu", s.cs), gpu_model("h200"), 48), InputError);
}

// Nodes and primitives read by loads (the *-loads variants) skip the texture
// unit's quads: 32 lanes reading one texel take one L1 wavefront, not eight.
// The walk, its sectors and its lines are the same.
TEST(Simt, LoadsTakeALineAClockWhereTexelFetchesTakeAQuad) {
  RayCase s = ray_case("gpu-bvh2");
  GpuModel oneSm = gpu_model("h200");
  oneSm.sms = 1;
  const std::vector<shader::ShadowRay> copies(32 * 96, s.sets.bounce[s.sets.bounce.size() / 2]);
  const SimtWalk texels = simt_walk("gpu-bvh2", s.cs);
  const SimtWalk loads = simt_walk("gpu-bvh2-loads", s.cs);
  ASSERT_FALSE(texels.walkLoads);
  ASSERT_TRUE(loads.walkLoads);
  const SimtFigures a = simulate_walks(s.cs, copies, false, texels, oneSm, 32);
  const SimtFigures b = simulate_walks(s.cs, copies, false, loads, oneSm, 32);
  EXPECT_EQ(a.warpIterations, b.warpIterations);
  EXPECT_DOUBLE_EQ(a.nodeLines, b.nodeLines);
  EXPECT_DOUBLE_EQ(a.bytesPerRay, b.bytesPerRay);
  EXPECT_EQ(a.bound, "L1");
  EXPECT_GT(b.predictedRaysPerSecond, a.predictedRaysPerSecond * 1.5);
}

// The fused binary walk (a primitive and a node an iteration) takes warps
// through fewer iterations than the plain one on the same rays, each issuing
// more of the lanes' work: the same rays and nodes, so about the same bytes.
TEST(Simt, TheFusedBinaryWalkTakesWarpsThroughFewerIterations) {
  RayCase plain = ray_case("gpu-bvh2", 48);
  RayCase fused = ray_case("gpu-bvh2-fused", 48);
  const SimtWalk a = simt_walk("gpu-bvh2", plain.cs);
  const SimtWalk b = simt_walk("gpu-bvh2-fused", fused.cs);
  ASSERT_FALSE(a.binaryFused);
  ASSERT_TRUE(b.binaryFused);
  const GpuModel& h200 = gpu_model("h200");
  const SimtFigures pa = simulate_walks(plain.cs, plain.sets.bounce, false, a, h200, 32);
  const SimtFigures pb = simulate_walks(fused.cs, fused.sets.bounce, false, b, h200, 32);
  EXPECT_EQ(pa.rays, pb.rays);
  EXPECT_LT(double(pb.warpIterations), 0.9 * double(pa.warpIterations));
  EXPECT_GT(pb.phaseEfficiency, pa.phaseEfficiency);
  EXPECT_NEAR(pb.bytesPerRay, pa.bytesPerRay, 0.1 * pa.bytesPerRay);
}

// SM balance, the most that dynamic fetch across SMs could gain: 1 where
// every SM takes the same workgroups of the same rays (two rounds of
// resident warps each); below 1 where one more workgroup goes to the first
// SM, which then takes a third round (latency) or 1/24 more issue slots.
TEST(Simt, SmBalanceSaysWhatDynamicFetchCouldGain) {
  RayCase s = ray_case("gpu-bvh2");
  const GpuModel& h200 = gpu_model("h200");
  const SimtWalk walk = simt_walk("gpu-bvh2", s.cs);
  const shader::ShadowRay ray = s.sets.bounce[s.sets.bounce.size() / 2];
  const size_t groups = size_t(h200.sms) * size_t(h200.residentWarps) * 32 / WORKGROUP_SIZE * 2;
  const SimtFigures even = simulate_walks(s.cs, std::vector<shader::ShadowRay>(groups * WORKGROUP_SIZE, ray), false, walk, h200, 32);
  EXPECT_DOUBLE_EQ(even.smBalance, 1.0);
  const SimtFigures uneven = simulate_walks(s.cs, std::vector<shader::ShadowRay>((groups + 1) * WORKGROUP_SIZE, ray), false, walk, h200, 32);
  EXPECT_LT(uneven.smBalance, 0.99);
  EXPECT_GT(uneven.smBalance, 0.6);
}

// The invocations of a dispatch of several rays a lane (limits.glsl, used by
// prepare.comp, the host and the model): every ray its own lane below the
// fill, the fill up to fill x rays, then the rays over rays a lane.
TEST(Simt, TracingDispatchesFillTheGpuBeforeTheyShareLanes) {
  const uint64_t fill = TRACING_INVOCATIONS_ON_GPUS;
  EXPECT_EQ(TRACING_INVOCATIONS(uint64_t(0), uint64_t(16), fill), 0u);
  EXPECT_EQ(TRACING_INVOCATIONS(uint64_t(1000), uint64_t(16), fill), 1000u);
  EXPECT_EQ(TRACING_INVOCATIONS(fill + 1, uint64_t(16), fill), fill);
  EXPECT_EQ(TRACING_INVOCATIONS(fill * 16, uint64_t(16), fill), fill);
  EXPECT_EQ(TRACING_INVOCATIONS(fill * 16 + 1, uint64_t(16), fill), fill + 1);
  // Without a fill (CPU devices), the rays over rays a lane, rounded up.
  EXPECT_EQ(TRACING_INVOCATIONS(uint64_t(1000), uint64_t(16), uint64_t(0)), 63u);
}

}  // namespace
}  // namespace wp::test
