#include "bench/embree_baseline.h"

#include <chrono>

#include "util/error.h"

#ifdef WAVEPATH_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#endif

namespace wp {

#ifdef WAVEPATH_HAVE_EMBREE

bool embree_available() {
  return true;
}

namespace {

RTCDevice new_device(const Scene& s) {
  if (!s.spheres.empty()) throw RenderError("the Embree baseline takes triangle scenes only");
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw RenderError("Embree: cannot create a device");
  return device;
}

// Attaches the triangles to the scene as one triangle geometry.
void attach_triangles(RTCDevice device, RTCScene scene, const std::vector<SceneTriangle>& triangles) {
  if (triangles.empty()) return;
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                        triangles.size() * 3));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                             triangles.size()));
  for (size_t i = 0; i < triangles.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      v[9 * i + 3 * size_t(c)] = triangles[i].v[c].x;
      v[9 * i + 3 * size_t(c) + 1] = triangles[i].v[c].y;
      v[9 * i + 3 * size_t(c) + 2] = triangles[i].v[c].z;
      idx[3 * i + size_t(c)] = unsigned(3 * i + size_t(c));
    }
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
}

double commit(RTCScene scene) {
  auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(scene);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A new Embree scene of the triangles, built at the default quality on all
// cores; `buildSeconds` receives the time of the rtcCommitScene calls alone
// (the vertex copies before them are not Embree's build). Instanced meshes
// become scenes of their own, each placed by one instance geometry per
// SceneInstance in the top scene: Embree's two levels, as the kernels'.
RTCScene new_scene(RTCDevice device, const Scene& s, double* buildSeconds) {
  *buildSeconds = 0.0;
  std::vector<RTCScene> meshes;
  for (const SceneInstancedMesh& m : s.instancedMeshes) {
    meshes.push_back(rtcNewScene(device));
    attach_triangles(device, meshes.back(), m.triangles);
    *buildSeconds += commit(meshes.back());
  }
  RTCScene scene = rtcNewScene(device);
  attach_triangles(device, scene, s.triangles);
  for (const SceneInstance& inst : s.instances) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geom, meshes[inst.mesh]);
    rtcSetGeometryTimeStepCount(geom, 1);
    rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &inst.toWorld[0][0]);  // glm is column-major
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
  }
  for (RTCScene m : meshes) rtcReleaseScene(m);  // the instances hold them
  *buildSeconds += commit(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
    rtcReleaseScene(scene);
    throw RenderError("Embree: building the scene failed");
  }
  return scene;
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& s) {
  RTCDevice device = new_device(s);
  try {
    scene_ = new_scene(device, s, &buildSeconds_);
  } catch (...) {
    rtcReleaseDevice(device);
    throw;
  }
  device_ = device;
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

namespace {

RTCRay embree_ray(const shader::ShadowRay& ray) {
  RTCRay r;
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.dir.x;
  r.dir_y = ray.dir.y;
  r.dir_z = ray.dir.z;
  r.tnear = 0.0f;
  r.tfar = ray.tmax;
  r.time = 0.0f;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
  return r;
}

// Runs query(i, context) for every ray on all cores; returns the seconds.
template <typename Query>
double on_all_cores(size_t count, Query query) {
  auto t0 = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = r.begin(); i != r.end(); ++i) query(i, context);
  });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

double EmbreeScene::trace(const std::vector<shader::ShadowRay>& rays, std::vector<float>* t) const {
  t->assign(rays.size(), WP_INF);
  RTCScene scene = static_cast<RTCScene>(scene_);
  return on_all_cores(rays.size(), [&](size_t i, RTCIntersectContext& context) {
    RTCRayHit rh;
    rh.ray = embree_ray(rays[i]);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) (*t)[i] = rh.ray.tfar;
  });
}

double EmbreeScene::occluded(const std::vector<shader::ShadowRay>& rays, std::vector<uint8_t>* blocked) const {
  blocked->assign(rays.size(), 0);
  RTCScene scene = static_cast<RTCScene>(scene_);
  return on_all_cores(rays.size(), [&](size_t i, RTCIntersectContext& context) {
    RTCRay r = embree_ray(rays[i]);
    rtcOccluded1(scene, &context, &r);
    (*blocked)[i] = r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
  });
}

#else

bool embree_available() {
  return false;
}
EmbreeScene::EmbreeScene(const Scene&) {
  throw RenderError("wavepath was built without Embree (install libembree-dev and rebuild)");
}
EmbreeScene::~EmbreeScene() = default;
double EmbreeScene::trace(const std::vector<shader::ShadowRay>&, std::vector<float>*) const {
  return 0.0;
}
double EmbreeScene::occluded(const std::vector<shader::ShadowRay>&, std::vector<uint8_t>*) const {
  return 0.0;
}

#endif

double embree_build_seconds(const Scene& scene) {
  return EmbreeScene(scene).build_seconds();
}

}  // namespace wp
