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

// A new Embree scene of the triangles, built at the default quality on all
// cores; `buildSeconds` receives the time of rtcCommitScene alone (the
// vertex copy before it is not Embree's build).
RTCScene new_scene(RTCDevice device, const Scene& s, double* buildSeconds) {
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                        s.triangles.size() * 3));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                             s.triangles.size()));
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      v[9 * i + 3 * size_t(c)] = s.triangles[i].v[c].x;
      v[9 * i + 3 * size_t(c) + 1] = s.triangles[i].v[c].y;
      v[9 * i + 3 * size_t(c) + 2] = s.triangles[i].v[c].z;
      idx[3 * i + size_t(c)] = unsigned(3 * i + size_t(c));
    }
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(scene);
  *buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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

double EmbreeScene::trace(const std::vector<shader::ShadowRay>& rays, std::vector<float>* t) const {
  t->assign(rays.size(), WP_INF);
  RTCScene scene = static_cast<RTCScene>(scene_);
  auto t0 = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const shader::ShadowRay& ray = rays[i];
      RTCRayHit rh;
      rh.ray.org_x = ray.origin.x;
      rh.ray.org_y = ray.origin.y;
      rh.ray.org_z = ray.origin.z;
      rh.ray.dir_x = ray.dir.x;
      rh.ray.dir_y = ray.dir.y;
      rh.ray.dir_z = ray.dir.z;
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = ray.tmax;
      rh.ray.time = 0.0f;
      rh.ray.mask = ~0u;
      rh.ray.id = 0;
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) (*t)[i] = rh.ray.tfar;
    }
  });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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

#endif

double embree_build_seconds(const Scene& scene) {
  return EmbreeScene(scene).build_seconds();
}

}  // namespace wp
