// test_collada.cpp — CS184's COLLADA scenes: the reader against our own
// scenes in the course's dialect (tests/data/collada), the course's camera
// rule, its vertex normals, its lights against analytic answers, its PNG
// curve and camera settings files, bad input, and one scene written as
// COLLADA and as darts JSON rendering alike.
#include "test_support.h"

#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "image/image.h"
#include "scene/cs184_normals.h"
#include "scene/importers.h"
#include "stats/compare.h"

namespace wp::test {
namespace {

std::string collada_path(const std::string& name) {
  return source_path("tests/data/collada/" + name);
}

glm::vec3 sphere_centre(const SceneSphere& s) {
  return glm::vec3(s.toWorld[3]);
}

// Loads a COLLADA document and expects an InputError naming the file in one
// line that contains every part (a line:column among them).
void expect_dae_error(const std::string& text, std::initializer_list<const char*> parts) {
  expect_error(text, parts, "bad.dae");
}

// A COLLADA document around `body` (library elements and a visual scene of `nodes`).
std::string dae(const std::string& libraries, const std::string& nodes, const std::string& up = "Y_UP") {
  return "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
         "<asset><up_axis>" + up + "</up_axis></asset>\n" + libraries +
         "<library_visual_scenes><visual_scene id=\"s\">\n" + nodes +
         "</visual_scene></library_visual_scenes>\n<scene><instance_visual_scene url=\"#s\"/></scene>\n</COLLADA>\n";
}

// A 4x4 quad of albedo 0.5 at y = 0 wound so that the course's normals point
// up, seen from straight above by a camera node at (0, 1, 1) (its (0, 0, -1)
// lands on (0, 1, 0)), with `light` placed by `lightNode`.
std::string lit_plane(const std::string& light, const std::string& lightNode) {
  const std::string libs =
      "<library_cameras><camera id=\"c\"><optics><technique_common><perspective><xfov>40</xfov><yfov>30</yfov>"
      "</perspective></technique_common></optics></camera></library_cameras>\n"
      "<library_lights><light id=\"l\"><technique_common>" + light + "</technique_common></light></library_lights>\n"
      "<library_effects><effect id=\"fx\"><profile_COMMON><technique sid=\"common\"><phong><diffuse><color>0.5 0.5 0.5 1</color>"
      "</diffuse></phong></technique></profile_COMMON></effect></library_effects>\n"
      "<library_materials><material id=\"m\"><instance_effect url=\"#fx\"/></material></library_materials>\n"
      "<library_geometries><geometry id=\"g\"><mesh><source id=\"p\"><float_array id=\"pa\" count=\"12\">"
      "-2 0 -2 2 0 -2 2 0 2 -2 0 2</float_array></source><vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/>"
      "</vertices><polylist material=\"sym\" count=\"2\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/>"
      "<vcount>3 3</vcount><p>0 1 2 0 2 3</p></polylist></mesh></geometry></library_geometries>\n";
  const std::string nodes =
      "<node id=\"cn\"><translate>0 1 1</translate><instance_camera url=\"#c\"/></node>\n"
      "<node id=\"ln\">" + lightNode + "<instance_light url=\"#l\"/></node>\n"
      "<node id=\"gn\"><instance_geometry url=\"#g\"><bind_material><technique_common>"
      "<instance_material symbol=\"sym\" target=\"#m\"/></technique_common></bind_material></instance_geometry></node>\n";
  return dae(libs, nodes);
}

// The course's estimator on `scene` at its centre: 4x4 pixels cut from the
// middle of its frame (resizing keeps the focal length), direct light only.
ImageStats centre_pixels(const std::string& path, int spp) {
  Scene scene = load_scene(path);
  set_resolution(scene.camera, 4, 4);
  RenderOptions o;
  o.spp = spp;
  o.seed = 7;
  Progress quiet("", 0, false);
  return render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
}

}  // namespace

TEST(Collada, CornellSceneReadsEveryElement) {
  const Scene s = load_scene(collada_path("cornell.dae"));
  // Z up: (x, y, z) of the file is (-x, z, y) here. Six quads, one split in
  // two triangles in its polylist, the lamp two triangles.
  EXPECT_EQ(s.triangles.size(), 12u);
  ASSERT_EQ(s.spheres.size(), 2u);
  // The mirror ball by a <matrix> at (-0.45, -0.2, 0.3), the glass one by a <translate> at (0.45, 0.25, 0.3).
  EXPECT_NEAR(glm::distance(sphere_centre(s.spheres[0]), glm::vec3(0.45f, 0.3f, -0.2f)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(sphere_centre(s.spheres[1]), glm::vec3(-0.45f, 0.3f, 0.25f)), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(s.spheres[0].toWorld[0][0], 0.3f);
  const SceneMaterial& mirror = s.materials[s.spheres[0].material];
  const SceneMaterial& glass = s.materials[s.spheres[1].material];
  EXPECT_EQ(mirror.kind, uint32_t(MAT_METAL));
  EXPECT_EQ(mirror.record.params.x, 0.0f);  // roughness 0: a mirror
  EXPECT_EQ(s.textures[mirror.albedo()].color, glm::vec3(0.9f, 0.9f, 0.85f));
  EXPECT_EQ(glass.kind, uint32_t(MAT_CS184_GLASS));
  EXPECT_EQ(glass.record.params, glm::vec4(1.5f, 0.0f, 0.0f, 0.0f));
  // Diffuse colours from phong, lambert and blinn; the lamp's CGL emission.
  std::map<std::string, const SceneMaterial*> byName;
  for (const SceneMaterial& m : s.materials) byName[m.name] = &m;
  EXPECT_EQ(s.textures[byName.at("red")->albedo()].color, glm::vec3(0.6f, 0.1f, 0.1f));
  EXPECT_EQ(s.textures[byName.at("green")->albedo()].color, glm::vec3(0.1f, 0.5f, 0.15f));
  EXPECT_EQ(byName.at("lamp")->kind, uint32_t(MAT_LIGHT));
  EXPECT_EQ(s.textures[byName.at("lamp")->emission].color, glm::vec3(6.0f));
  // The CGL area light wins over the point light of technique_common: a
  // 0.5 x 0.5 quad at height 1.48 facing down, no geometry, no point light.
  EXPECT_TRUE(s.pointLights.empty());
  ASSERT_EQ(s.lightOnlyTriangles.size(), 2u);
  float area = 0.0f;
  for (const SceneTriangle& t : s.lightOnlyTriangles) {
    glm::vec3 n = glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
    area += 0.5f * glm::length(n);
    EXPECT_LT(glm::normalize(n).y, -0.999f);  // its front faces down
    for (const glm::vec3& v : t.v) EXPECT_NEAR(v.y, 1.48f, 1e-6f);
    EXPECT_EQ(s.textures[s.materials[t.material].emission].color, glm::vec3(6.0f));
  }
  EXPECT_NEAR(area, 0.25f, 1e-6f);
  // The course's conventions and defaults (-s 1, -m 1, 800x600).
  EXPECT_TRUE(s.cs184Estimator && s.cs184LatLong && s.eightBitCurve == EightBitCurve::Cs184);
  EXPECT_EQ(s.integrator.kind, IntegratorKind::PathNee);
  EXPECT_EQ(s.integrator.maxBounces, 1);
  EXPECT_EQ(s.samplesPerPixel, 1);
  EXPECT_EQ(s.camera.width, 800);
  EXPECT_EQ(s.camera.height, 600);
  // Every wall has the course's vertex normals, which the border walk turns
  // against the winding: the floor, wound to face up, gets normals facing down.
  for (const SceneTriangle& t : s.triangles) {
    ASSERT_NE(t.shading, WP_INVALID);
    const glm::vec3 ng = glm::normalize(glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]));
    for (const glm::vec3& n : s.triangleShading[t.shading].n) EXPECT_NEAR(glm::dot(n, ng), -1.0f, 1e-5f);
  }
}

// The 3-2 skeleton's reading (render --cs184 3-2): the lamp mesh emits
// nothing (collada.cpp:879), and the area light is also two triangles of
// geometry emitting radiance / area times the cosine, from the front only
// (light.cpp:77-105, bsdf.h:274-278), while light sampling stays as it was.
TEST(Collada, Cs184Skeleton32LightsAsThatSkeletonBuildsThem) {
  Scene s = load_scene(collada_path("cornell.dae"));
  EXPECT_EQ(s.cs184Skeleton, 31);
  use_cs184_3_2_skeleton(s);
  EXPECT_EQ(s.cs184Skeleton, 32);
  ASSERT_EQ(s.triangles.size(), 14u);
  ASSERT_EQ(s.lightOnlyTriangles.size(), 2u);
  for (const SceneMaterial& m : s.materials)
    if (m.name == "lamp") {
      EXPECT_EQ(m.emission, WP_INVALID) << "the lamp mesh still emits";
    }
  CompiledScene cs = compile_scene(s, RenderOptions{});
  EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(FEATURE_COSINE_EMISSION));
  for (uint32_t i = 12; i < 14; ++i) {
    const SceneTriangle& t = s.triangles[i];
    // The light's triangle, a hair behind its plane (above it: the light faces down).
    EXPECT_NEAR(glm::distance(t.v[0], s.lightOnlyTriangles[i - 12].v[0]), 4e-5f * 1.48f, 1e-6f);
    EXPECT_GT(t.v[0].y, s.lightOnlyTriangles[i - 12].v[0].y);
    const SceneMaterial& quad = s.materials[t.material];
    EXPECT_EQ(quad.kind, uint32_t(MAT_LIGHT));
    EXPECT_NEAR(glm::distance(s.textures[quad.emission].color, glm::vec3(6.0f / 0.25f)), 0.0f, 1e-4f);
  }
  // Seen from below along its normal, the full radiance over the area; at 60
  // degrees from it, half; from above nothing, under the course's both-sided
  // estimator too.
  shader::SceneView view = cs.view();
  std::set<uint32_t> quads;
  for (uint32_t i = 0; i < cs.triangles.size(); ++i) {
    const uint32_t material = cs.triangles[i].material;  // WP_INVALID: a sphere's placeholder
    if (material == WP_INVALID || cs.materials[material & TRIANGLE_MATERIAL_MASK].params.x != 1.0f) continue;
    quads.insert(i);
    const shader::SceneView::SurfaceHit hit = view.triangle_surface(i, 0.25f, 0.25f);
    const glm::vec3 down(0.0f, -1.0f, 0.0f), slant = glm::normalize(glm::vec3(std::sqrt(3.0f), -1.0f, 0.0f));
    EXPECT_NEAR(view.emitted_radiance(hit, down).x, 24.0f, 1e-3f);
    EXPECT_NEAR(view.emitted_radiance(hit, slant).x, 12.0f, 1e-3f);
    EXPECT_EQ(view.emitted_radiance(hit, -down).x, 0.0f);
  }
  EXPECT_EQ(quads.size(), 2u);
  // The quad does not shadow its own light: no shadow ray from the room to
  // a point sampled on the light meets it (it once did, moved in front of
  // the light's plane, and the room went black).
  uint32_t state = 5, blocked = 0, samples = 0;
  for (int i = 0; i < 400; ++i) {
    const glm::vec3 p(view.rng_next(state) * 1.6f - 0.8f, 0.02f + view.rng_next(state) * 1.2f, view.rng_next(state) * 1.6f - 0.8f);
    shader::SceneView::LightSample ls;
    if (!view.sample_emitter(p, glm::vec3(view.rng_next(state), view.rng_next(state), view.rng_next(state)), ls)) continue;
    glm::vec3 origin, dir;
    float tmax;
    view.aim_shadow_ray(p, glm::normalize(ls.wi), ls, origin, dir, tmax);
    shader::Hit h;
    ASSERT_EQ(view.trace_ray(origin, dir, tmax, true, h), TRACE_OK);
    blocked += quads.count(h.prim);
    ++samples;
  }
  EXPECT_GT(samples, 300u);
  EXPECT_EQ(blocked, 0u) << "of " << samples << " shadow rays to the area light met its quad";
}

// The lamp as the course's renderer shows it under the 3-2 skeleton: an
// emissive lamp mesh (black there) placed as Blender places it, within 5e-8
// of its area light's plane (one plane in floats), and the light's quad
// there too. The course meets whichever is nearer in double: the mesh's
// height above the light is 1.6e-7 z (its node's tilt) minus 9.5e-9 (1.49
// read as a float, collada.cpp:631-640, where the light's matrix reads it
// as a double), so the quad shows where z < 0.0596 and outside the mesh.
// Every camera ray of the lamp's pixels is classified by that rule here and
// the rendered pixel (-m 0: what the camera sees) must be its mean. The
// band 0 < z < 0.0596 is the float-read's: read as doubles, the mesh would
// hide the quad there.
TEST(Collada, Cs184Skeleton32ShowsTheLampAsTheCourseDoes) {
  const std::string libs =
      "<library_cameras><camera id=\"c\"><optics><technique_common><perspective><xfov>50</xfov><yfov>35</yfov>"
      "</perspective></technique_common></optics></camera></library_cameras>\n"
      "<library_lights><light id=\"l\"><technique_common><ambient><color>0 0 0</color></ambient></technique_common>"
      "<extra><technique profile=\"CGL\"><area><color>6 6 6</color></area></technique></extra></light></library_lights>\n"
      "<library_effects><effect id=\"fx\"><profile_COMMON><technique sid=\"common\"><phong/></technique></profile_COMMON>"
      "<extra><technique profile=\"CGL\"><emission><radiance>6 6 6</radiance></emission></technique></extra></effect></library_effects>\n"
      "<library_materials><material id=\"m\"><instance_effect url=\"#fx\"/></material></library_materials>\n"
      "<library_geometries><geometry id=\"g\"><mesh><source id=\"p\"><float_array id=\"pa\" count=\"12\">"
      "0.4 1.49 -0.3 0.4 1.49 0.3 -0.4 1.49 0.3 -0.4 1.49 -0.3</float_array></source><vertices id=\"v\"><input semantic=\"POSITION\" "
      "source=\"#p\"/></vertices><polylist material=\"sym\" count=\"1\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/>"
      "<vcount>4</vcount><p>0 1 2 3</p></polylist></mesh></geometry></library_geometries>\n";
  // The camera looks up at the lamp along (0, -0.8, 0.6) from 1.5 times the
  // lamp's diagonal (the orbit rule); the light faces down, 0.6 x 0.8.
  const std::string nodes =
      "<node id=\"cn\"><matrix>1 0 0 0 0 1 0 -0.8 0 0 1 1.6 0 0 0 1</matrix><instance_camera url=\"#c\"/></node>\n"
      "<node id=\"ln\"><matrix>0.6 0 0 0 0 0 1 1.49 0 -0.8 0 0 0 0 0 1</matrix><instance_light url=\"#l\"/></node>\n"
      "<node id=\"gn\"><matrix>1 0 0 0 0 1 -1.6e-7 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url=\"#g\"><bind_material>"
      "<technique_common><instance_material symbol=\"sym\" target=\"#m\"/></technique_common></bind_material></instance_geometry></node>\n";
  Scene s = load_scene(write_scene("lamp-plane.dae", dae(libs, nodes)));
  ASSERT_EQ(s.cs184LightPlaneContacts.size(), 2u) << "the lamp's two triangles lie in the light's plane";
  use_cs184_3_2_skeleton(s);
  s.integrator.maxBounces = 0;
  set_resolution(s.camera, 96, 72);
  RenderOptions o;
  o.spp = 8;
  CompiledScene cs = compile_scene(s, reference_options(o));
  Progress quiet("", 0, false);
  const ImageStats img = render_cpu(cs, 0, quiet);
  shader::SceneView view = cs.view();

  const double meshAbove = double(1.49f) - 1.49, tilt = 1.6e-7, split = meshAbove / tilt;  // z = 0.0596
  const double margin = 2e-3;  // rays this close to an edge or the split are left out (the quad sits 6e-5 back)
  int lit = 0, hidden = 0, band = 0, checked = 0, wrong = 0;
  std::string firstWrong;
  for (uint32_t pixel = 0; pixel < uint32_t(cs.width * cs.height); ++pixel) {
    double expected = 0.0;
    bool clear = true, allLit = true, allHidden = true, allInBand = true;
    for (uint32_t k = 0; k < uint32_t(o.spp); ++k) {
      shader::PathState ps;
      view.path_begin(ps, pixel, k);  // the render's own camera rays
      const glm::dvec3 origin(ps.origin), dir(ps.dir);
      const double t = (1.49 - origin.y) / dir.y;
      const glm::dvec3 p = origin + t * dir;
      const double ax = std::fabs(p.x), az = std::fabs(p.z);
      const bool inQuad = t > 0.0 && ax < 0.3 && az < 0.4, inMesh = t > 0.0 && ax < 0.4 && az < 0.3;
      for (double edge : {ax - 0.3, az - 0.4, ax - 0.4, az - 0.3, p.z - split}) clear = clear && std::fabs(edge) > margin;
      // The mesh's height above the light, along the light's facing (down).
      const bool meshInFront = inMesh && -(meshAbove - tilt * p.z) > 0.0;
      const bool seen = inQuad && !meshInFront;
      expected += seen ? 6.0 / (0.6 * 0.8) * dir.y : 0.0;  // radiance / area times the cosine (bsdf.h:274-278)
      allLit = allLit && seen;
      allHidden = allHidden && inQuad && meshInFront;
      allInBand = allInBand && seen && inMesh && p.z > 0.0;
    }
    if (!clear) continue;
    expected /= o.spp;
    const double got = img.mean(pixel).x;
    if (std::fabs(got - expected) > 1e-4 * expected + 1e-6 && wrong++ == 0)
      firstWrong = "pixel " + std::to_string(pixel % cs.width) + ", " + std::to_string(pixel / cs.width) + ": " + std::to_string(got) +
                   " where the course's rule gives " + std::to_string(expected);
    ++checked;
    lit += allLit;
    hidden += allHidden;
    band += allInBand;
  }
  EXPECT_EQ(wrong, 0) << "of " << checked << " pixels; the first, " << firstWrong;
  EXPECT_GT(lit, 1000);
  EXPECT_GT(hidden, 300);
  EXPECT_GT(band, 500) << "pixels where the course shows the quad over the lamp mesh only because it reads positions as floats";
  EXPECT_GT(checked, cs.width * cs.height / 2);
}

// The camera as application.cpp places it, computed here from the course's
// formulas: a known point lands on the pixel they give, in the 800x600 frame
// and in a -r 480 360 render, which is the frame's central crop.
TEST(Collada, CameraFollowsTheCoursesOrbitRule) {
  Scene s = load_scene(collada_path("cornell.dae"));
  // The objects' box (walls, lamp and balls; lights are not objects): the
  // room, x and z in [-1, 1], y in [0, 1.5].
  const glm::dvec3 lo(-1, 0, -1), hi(1, 1.5, 1), target = 0.5 * (lo + hi);
  const double r = 1.5 * glm::length(hi - lo);
  // The camera node: (0, 0, -1) goes to (0, -1 + 4, 0.5) + ... of the matrix; in Z up that is the direction below.
  const glm::dvec3 m = glm::dvec3(0.0, 0.5, 4.0 + 1.0);  // rows (1 0 0 0), (0 0 -1 4), (0 1 0 0.5) applied to (0, 0, -1, 1), axes swapped
  const glm::dvec3 dir = glm::normalize(glm::dvec3(-0.0, m.y, m.z));
  const double phi = std::acos(dir.y), theta = std::atan2(dir.x, dir.z);
  const glm::dvec3 pos = target + r * glm::dvec3(std::sin(phi) * std::sin(theta), std::cos(phi), std::sin(phi) * std::cos(theta));
  EXPECT_NEAR(glm::distance(glm::dvec3(s.camera.toWorld[3]), pos), 0.0, 1e-5);
  // Fields: xfov 45 and aspect 1.333333 give a yfov; fitted to 800x600.
  const double tanH = std::tan(glm::radians(45.0) / 2), tanV0 = tanH / 1.333333;
  const double tanV = tanH / tanV0 > 800.0 / 600.0 ? tanH / (800.0 / 600.0) : tanV0;
  EXPECT_NEAR(std::tan(glm::radians(double(s.camera.vfovDegrees)) / 2), tanV, 1e-6);
  // Project the glass ball's centre as the course's generate_ray would see it.
  const glm::dvec3 back = glm::normalize(pos - target);
  const glm::dvec3 x = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), back)), y = glm::cross(back, x);
  const glm::dvec3 p = glm::dvec3(-0.45, 0.3, 0.25) - pos;
  const double sx = glm::dot(p, x) / -glm::dot(p, back), sy = glm::dot(p, y) / -glm::dot(p, back);
  const double tanHFrame = tanV * 800.0 / 600.0;
  const double px = (sx / tanHFrame + 1.0) * 0.5 * 800.0, pyUp = (sy / tanV + 1.0) * 0.5 * 600.0;
  for (int crop = 0; crop < 2; ++crop) {
    if (crop) set_resolution(s.camera, 480, 360);
    const double cx = px - (crop ? 160.0 : 0.0), cy = (600.0 - pyUp) - (crop ? 120.0 : 0.0);  // rows from the top
    CompiledScene cs = compile_scene(s, RenderOptions{});
    shader::SceneView view = cs.view();
    const uint32_t pixel = uint32_t(std::floor(cy)) * uint32_t(cs.width) + uint32_t(std::floor(cx));
    // The pixel's rays pass within its footprint of the point.
    glm::dvec3 mean(0.0);
    for (uint32_t k = 0; k < 256; ++k) {
      shader::PathState ps;
      view.path_begin(ps, pixel, k);
      EXPECT_NEAR(glm::distance(glm::dvec3(ps.origin), pos), 0.0, 1e-4);
      mean += glm::dvec3(ps.dir);
    }
    const double angle = std::acos(std::clamp(glm::dot(glm::normalize(mean), glm::normalize(p)), -1.0, 1.0));
    const double pixelAngle = 2.0 * tanV / 600.0;  // at the centre; the ball is near it
    EXPECT_LT(angle, pixelAngle) << (crop ? "480x360 crop" : "800x600 frame");
  }
}

TEST(Collada, NodeTreeTransformsLightsAndPrimitives) {
  const Scene s = load_scene(collada_path("lights.dae"));
  // <triangles>: the ground's two; <polygons>: the tetrahedron's four, placed
  // by translate, rotate (30 degrees about y) and scale 1.5 through an <instance_node>.
  ASSERT_EQ(s.triangles.size(), 6u);
  const glm::mat4 gem = glm::translate(glm::mat4(1.0f), glm::vec3(-0.8f, 0, 0)) *
                        glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), glm::vec3(0, 1, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(1.5f));
  const glm::vec3 apex = glm::vec3(gem * glm::vec4(0, 0.8f, 0, 1));
  bool found = false;
  for (const SceneTriangle& t : s.triangles)
    for (const glm::vec3& v : t.v) found = found || glm::distance(v, apex) < 1e-5f;
  EXPECT_TRUE(found) << "the tetrahedron's apex at " << apex.x << " " << apex.y << " " << apex.z;
  // The ground's UVs (TEXCOORD), corner by corner.
  const SceneTriangleShading& ground = s.triangleShading.at(s.triangles[0].shading);
  ASSERT_TRUE(ground.hasUvs);
  EXPECT_EQ(ground.uv[0], glm::vec2(0, 0));
  EXPECT_EQ(ground.uv[1], glm::vec2(0, 1));
  EXPECT_EQ(ground.uv[2], glm::vec2(1, 1));
  EXPECT_FALSE(s.triangleShading.at(s.triangles[2].shading).hasUvs);
  const SceneMaterial& gold = s.materials[s.triangles[2].material];
  EXPECT_EQ(gold.kind, uint32_t(MAT_BECKMANN_CONDUCTOR));
  EXPECT_EQ(gold.record.params, glm::vec4(0.25f, 0.143119f, 0.374957f, 1.44248f));
  EXPECT_EQ(gold.record.params2.w, 1.0f);  // the 3-2 skeleton's shadowing term
  ASSERT_EQ(s.spheres.size(), 1u);
  const SceneMaterial& water = s.materials[s.spheres[0].material];
  EXPECT_EQ(water.kind, uint32_t(MAT_CS184_GLASS));
  EXPECT_EQ(water.record.params.y, 1.0f);  // refraction only
  // The point light (no falloff), the directional light from the rotated
  // (0, 0, -1), the ambient light from above; the spot light gives nothing.
  ASSERT_EQ(s.pointLights.size(), 3u);
  const ScenePointLight &bulb = s.pointLights[0], &sun = s.pointLights[1], &sky = s.pointLights[2];
  EXPECT_EQ(bulb.kind, ScenePointLight::Kind::Point);
  EXPECT_FALSE(bulb.falloff);
  EXPECT_EQ(bulb.position, glm::vec3(1, 2, 1));
  EXPECT_EQ(bulb.intensity, glm::vec3(0.8f, 0.7f, 0.6f));
  EXPECT_EQ(sun.kind, ScenePointLight::Kind::Directional);
  const glm::vec3 from = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(-60.0f), glm::vec3(1, 0, 0)) * glm::vec4(0, 0, -1, 1));
  EXPECT_NEAR(glm::distance(sun.direction, -glm::normalize(from)), 0.0f, 1e-6f);
  EXPECT_EQ(sky.kind, ScenePointLight::Kind::Hemisphere);
  EXPECT_EQ(sky.direction, glm::vec3(0, 1, 0));
  EXPECT_EQ(sky.intensity, glm::vec3(0.2f, 0.25f, 0.3f));
  EXPECT_TRUE(s.lightOnlyTriangles.empty());
  // yfov 30 alone: xfov is the course's 50, and the frame widens the narrower.
  const double tanV = std::max(std::tan(glm::radians(15.0)), std::tan(glm::radians(25.0)) / (800.0 / 600.0));
  EXPECT_NEAR(std::tan(glm::radians(double(s.camera.vfovDegrees)) / 2), tanV, 1e-6);
}

// The skeleton's half-edge walk: around an interior vertex the faces' edge
// cross products in order; at a border it walks next-then-twin, turning the
// normals of an open sheet against its winding (a Cornell wall's case).
TEST(Collada, VertexNormalsFollowTheSkeletonsHalfEdgeWalk) {
  const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};  // wound about +z
  for (const auto& polys : {std::vector<std::vector<uint32_t>>{{0, 1, 2}, {0, 2, 3}}, std::vector<std::vector<uint32_t>>{{0, 1, 2, 3}}}) {
    auto n = cs184_vertex_normals(polys, quad);
    ASSERT_TRUE(n);
    for (const glm::vec3& v : *n) EXPECT_EQ(v, glm::vec3(0, 0, -1));
  }
  // A closed tetrahedron wound outwards: interior walks, outward normals,
  // each the normalized sum of its faces' (twice area) normals.
  const std::vector<glm::vec3> t = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::vector<uint32_t>> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  auto n = cs184_vertex_normals(faces, t);
  ASSERT_TRUE(n);
  EXPECT_NEAR(glm::distance((*n)[0], glm::normalize(glm::vec3(-1, -1, -1))), 0.0f, 1e-6f);
  // Vertex 1's faces give (0, 0, -1), (0, -1, 0) and (1, 1, 1) from it.
  EXPECT_NEAR(glm::distance((*n)[1], glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
  // An edge used twice in one direction: the skeleton refuses it.
  EXPECT_FALSE(cs184_vertex_normals({{0, 1, 2}, {0, 1, 3}}, t));
}

// Direct light under the course's estimator against its formulas: a
// diffuse plane of albedo rho seen from above, lit by a point light (no
// falloff: rho I / pi), a directional light (rho E / pi), an ambient light
// (rho L), and an area light, whose density takes the unnormalised cosine
// (light.cpp), so that a square of half-side a at height h gives
// rho / pi * 4 L h atan(a^2 / (h sqrt(2 a^2 + h^2))).
TEST(Collada, LightsGiveTheCoursesAnalyticRadiance) {
  const double rho = 0.5;
  struct Case {
    const char* what;
    std::string light, node;
    double expected;
    int spp;
  };
  const double a = 0.25, h = 0.7, le = 3.0;
  const Case cases[] = {
      {"point", "<point><color>2 2 2</color><constant_attenuation>1</constant_attenuation><linear_attenuation>0</linear_attenuation>"
                "<quadratic_attenuation>0</quadratic_attenuation></point>",
       "<translate>0 3 0</translate>", rho * 2.0 / WP_PI, 16},
      {"directional", "<directional><color>1.5 1.5 1.5</color></directional>", "<rotate>1 0 0 90</rotate>",
       rho * 1.5 / WP_PI, 16},
      {"ambient", "<ambient><color>0.8 0.8 0.8</color></ambient>", "", rho * 0.8, 4096},
      {"area", "<area><color>3 3 3</color></area>", "<translate>0 0.7 0</translate><rotate>1 0 0 -90</rotate><scale>0.5 0.5 1</scale>",
       rho / WP_PI * 4.0 * le * h * std::atan(a * a / (h * std::sqrt(2 * a * a + h * h))), 4096},
  };
  for (const Case& c : cases) {
    // The area light needs its CGL technique (technique_common has no area kind).
    std::string light = c.light;
    std::string doc = lit_plane(light, c.node);
    if (std::string(c.what) == "area") {
      const std::string common = "<technique_common>" + light + "</technique_common>";
      doc.replace(doc.find(common), common.size(),
                  "<technique_common><ambient><color>0 0 0</color></ambient></technique_common><extra><technique profile=\"CGL\">" + light +
                      "</technique></extra>");
    }
    ImageStats img = centre_pixels(write_scene(std::string(c.what) + ".dae", doc), c.spp);
    auto [mean, se] = image_mean(img);
    EXPECT_NEAR(mean, c.expected, std::max(4.0 * se, 2e-4 * c.expected) + 1e-3 * c.expected) << c.what;
  }
}

// CS184's lat-long layout (environment_light.cpp): theta = acos(y) down the
// rows, phi = atan2(-z, x) + pi across the columns, u = phi / 2 pi.
TEST(Collada, EnvironmentMapInTheCoursesLatLongLayout) {
  Scene scene = load_scene(source_path("tests/data/features/environment.json"));
  for (bool cs184 : {false, true}) {
    scene.cs184LatLong = cs184;
    CompiledScene cs = compile_scene(scene, RenderOptions{});
    shader::SceneView view = cs.view();
    for (glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(-0.3f, 0.5f, 0.81f), glm::vec3(0.6f, -0.7f, -0.39f)}) {
      d = glm::normalize(d);
      glm::vec2 uv = view.environment_uv(d);
      double u = cs184 ? (std::atan2(-double(d.z), double(d.x)) + WP_PI) / (2.0 * WP_PI)
                       : 0.5 + std::atan2(double(d.x), -double(d.z)) / (2.0 * WP_PI);
      EXPECT_NEAR(uv.x, u, 1e-6) << cs184;
      EXPECT_NEAR(1.0 - uv.y, std::acos(double(d.y)) / WP_PI, 1e-6);  // rows from the top
    }
    // The course's +X at the centre column; wavepath's -Z.
    EXPECT_NEAR(view.environment_uv(cs184 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, -1)).x, 0.5f, 1e-6f);
  }
}

TEST(Collada, Cs184PngToneCurve) {
  // (sqrt(2) L)^(1 / 2.2), clamped to [0, 1], times 255, truncated.
  EXPECT_EQ(encode_8bit_value(-1.0, EightBitCurve::Cs184), 0);
  EXPECT_EQ(encode_8bit_value(0.0, EightBitCurve::Cs184), 0);
  EXPECT_EQ(encode_8bit_value(0.1, EightBitCurve::Cs184), 104);  // 0.1414^(1/2.2) = 0.4110: 104.8
  EXPECT_EQ(encode_8bit_value(0.5, EightBitCurve::Cs184), 217);  // 0.7071^(1/2.2) = 0.8543: 217.8
  EXPECT_EQ(encode_8bit_value(1.0, EightBitCurve::Cs184), 255);
  EXPECT_EQ(encode_8bit_value(7.0, EightBitCurve::Cs184), 255);
  EXPECT_EQ(encode_8bit_value(0.5), 188);  // against sRGB, rounded
  EXPECT_EQ(encode_8bit_value(0.5, EightBitCurve::DartsSrgb), 187);  // and truncated, as darts writes (0.7354 * 255 = 187.5)
  EXPECT_EQ(encode_8bit_value(1.0, EightBitCurve::DartsSrgb), 254);  // darts' float curve gives 1.0 as 0.99999994
  EXPECT_EQ(encode_8bit_value(1.0), 255);
}

TEST(Collada, BadInputNamesFileLineAndColumn) {
  expect_dae_error("<COLLADA><asset><up_axis>Z_UP</up_axis></asset>\n  <scene>\n</COLLADA>", {"malformed XML", ":3:"});
  expect_dae_error("<?xml version=\"1.0\"?>\n<collada/>", {"not a COLLADA document", "2:1"});
  expect_dae_error(dae("", "", "W_UP"), {"up_axis \"W_UP\"", ":3:"});
  expect_dae_error("<COLLADA><asset/></COLLADA>", {"no <up_axis>"});
  expect_dae_error("<COLLADA><asset><up_axis>Y_UP</up_axis></asset></COLLADA>", {"no <scene><instance_visual_scene>"});
  expect_dae_error(dae("", "<node><instance_geometry url=\"#nothing\"/></node>\n"), {"url \"#nothing\" names no element", ":5:"});
  expect_dae_error(dae("", "<node><instance_light url=\"other.dae#l\"/></node>\n"), {"not a reference into this file"});
  expect_dae_error(dae("<library_lights><light id=\"l\"/></library_lights>\n", "<node><instance_camera url=\"#l\"/></node>\n"),
                   {"names a <light>, not a <camera>"});
  expect_dae_error(dae("", "<node><skew>10 0 1 0 1 0 0</skew></node>\n"), {"<skew> is not supported", ":5:"});
  expect_dae_error(dae("", "<node><instance_controller url=\"#x\"/></node>\n"), {"<instance_controller> is not supported"});
  expect_dae_error(dae("", "<node><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 x</matrix></node>\n"), {"\"x\" is not a number"});
  expect_dae_error(dae("", "<node id=\"a\"/><node id=\"a\"/>\n"), {"a second element with id \"a\""});
  const std::string geo =
      "<library_geometries><geometry id=\"g\"><mesh><source id=\"p\"><float_array id=\"pa\" count=\"9\">0 0 0 1 0 0 0 1 0"
      "</float_array></source><vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/></vertices>PRIM</mesh></geometry>"
      "</library_geometries>\n";
  const std::string node = "<node><instance_geometry url=\"#g\"/></node>\n";
  auto with = [&](const std::string& prim) {
    std::string g = geo;
    return dae(g.replace(g.find("PRIM"), 4, prim), node);
  };
  const std::string in = "<input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/>";
  expect_dae_error(with("<triangles count=\"1\">" + in + "<p>0 1 3</p></triangles>"), {"vertex index 3 past the 3 positions"});
  expect_dae_error(with("<polylist count=\"1\">" + in + "<vcount>2</vcount><p>0 1</p></polylist>"), {"a polygon of 2 vertices"});
  expect_dae_error(with("<triangles count=\"2\">" + in + "<p>0 1 2</p></triangles>"), {"3 numbers where 6 belong"});
  expect_dae_error(with("<triangles count=\"99999999999\">" + in + "<p>0 1 2</p></triangles>"), {"past what wavepath reads"});
  expect_dae_error(with("<lines count=\"1\">" + in + "<p>0 1</p></lines>"), {"<lines> is not supported"});
  expect_dae_error(with("<triangles count=\"1\"><p>0 1 2</p></triangles>"), {"has no VERTEX input"});
  expect_dae_error(with("<triangles count=\"1\">" + in + "<input semantic=\"TEXCOORD\" source=\"#p\" offset=\"1\"/><p>0 0 1 1 2 5</p></triangles>"),
                   {"UV index 5 past the 4 UVs"});
  {
    std::string g = geo;
    g.replace(g.find("count=\"9\""), 9, "count=\"10\"");
    expect_dae_error(dae(g.replace(g.find("PRIM"), 4, "<triangles count=\"1\">" + in + "<p>0 1 2</p></triangles>"), node),
                     {"9 numbers where 10 belong"});
  }
  // Lights and materials: the course's required elements.
  expect_dae_error(dae("<library_lights><light id=\"l\"><technique_common><point><color>1 1 1</color></point></technique_common>"
                       "</light></library_lights>\n",
                       "<node><instance_light url=\"#l\"/></node>\n"),
                   {"<point> has no <constant_attenuation>"});
  expect_dae_error(dae("<library_lights><light id=\"l\"><technique_common><neon><color>1 1 1</color></neon></technique_common>"
                       "</light></library_lights>\n",
                       "<node><instance_light url=\"#l\"/></node>\n"),
                   {"<neon> is not supported"});
  expect_dae_error(dae("<library_effects><effect id=\"e\"><extra><technique profile=\"CGL\"><microfacet><alpha>0.3</alpha>"
                       "<eta>1 1 1</eta></microfacet></technique></extra></effect></library_effects>"
                       "<library_materials><material id=\"m\"><instance_effect url=\"#e\"/></material></library_materials>\n" +
                           geo.substr(0, geo.find("PRIM")) + "<triangles count=\"1\">" + in +
                           "<p>0 1 2</p></triangles></mesh></geometry></library_geometries>\n",
                       "<node><instance_geometry url=\"#g\"><bind_material><technique_common><instance_material symbol=\"x\" "
                       "target=\"#m\"/></technique_common></bind_material></instance_geometry></node>\n"),
                   {"<microfacet> has no <k>"});
  expect_dae_error(dae("<library_cameras><camera id=\"c\"><optics><technique_common><orthographic><xmag>1</xmag></orthographic>"
                       "</technique_common></optics></camera></library_cameras>\n",
                       "<node><instance_camera url=\"#c\"/></node>\n"),
                   {"<orthographic> is not supported"});
}

// A camera settings file, as the course's viewer writes it with D: the
// position, the orientation matrix (row by row) and both fields win.
TEST(Collada, CameraSettingsFileSetsPoseAndFields) {
  Scene s = load_scene(collada_path("cornell.dae"));
  const std::string path = write_scene("cam.txt",
                                       "60 40 1.33 0.1 100\n"
                                       "0.5 1 3 0 0.75 0\n"
                                       "1.4 0.1 3 0.3 60\n"
                                       "0 0 1 0 1 0 -1 0 0\n"
                                       "800 600 824.2\n"
                                       "4.7 0\n");
  apply_cs184_camera_settings(path, s.camera);
  // Columns of the file's matrix: x = (0, 0, -1), y = (0, 1, 0), back = (1, 0, 0).
  EXPECT_EQ(glm::vec3(s.camera.toWorld[0]), glm::vec3(0, 0, -1));
  EXPECT_EQ(glm::vec3(s.camera.toWorld[2]), glm::vec3(1, 0, 0));
  EXPECT_EQ(glm::vec3(s.camera.toWorld[3]), glm::vec3(0.5f, 1, 3));
  EXPECT_FLOAT_EQ(s.camera.vfovDegrees, 40.0f);
  EXPECT_NEAR(s.camera.aspect, std::tan(glm::radians(30.0)) / std::tan(glm::radians(20.0)), 1e-6);
  CompiledScene cs = compile_scene(s, RenderOptions{});
  EXPECT_FLOAT_EQ(cs.params.camLens.y, s.camera.aspect);
  // A binary file: one line naming the file, its bytes not echoed raw.
  try {
    std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
    apply_cs184_camera_settings(write_scene("cam.png", png), s.camera);
    ADD_FAILURE() << "a PNG read as camera settings";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find("\"?PNG\" is not a number"), std::string::npos) << msg;
  }
  for (const char* bad : {"60 40 1.33", "60 40 1.33 0.1 100 0.5 1 3 0 0.75 0 1.4 0.1 3 0.3 60 0 0 1 0 1 0 -1 0 0 800 600 824.2 4.7 nan",
                          "200 40 1.33 0.1 100 0.5 1 3 0 0.75 0 1.4 0.1 3 0.3 60 0 0 1 0 1 0 -1 0 0 800 600 824.2 4.7 0",
                          "60 40 1.33 0.1 100 0.5 1 3 0 0.75 0 1.4 0.1 3 0.3 60 0 0 0 0 0 0 0 0 0 800 600 824.2 4.7 0"}) {
    EXPECT_THROW(apply_cs184_camera_settings(write_scene("bad.txt", bad), s.camera), InputError) << bad;
  }
}

// One scene written twice, as CS184 COLLADA read physically
// (--consistent-lights) and as darts JSON with the camera the course's rule
// gives: the two renders estimate the same image.
TEST(Collada, SameSceneAsDartsJsonRendersTheSameImage) {
  Scene fromDae = load_scene(collada_path("room.dae"));
  use_consistent_lights(fromDae);
  fromDae.camera.width = 64;  // the whole frame, smaller (the fields stay)
  fromDae.camera.height = 48;
  Scene fromJson = load_scene(collada_path("room.json"));
  RenderOptions o;
  o.spp = 256;
  o.maxBounces = 3;
  Progress quiet("", 0, false);
  o.seed = 1;
  ImageStats a = render_cpu(compile_scene(fromDae, reference_options(o)), 0, quiet);
  o.seed = 2;
  ImageStats b = render_cpu(compile_scene(fromJson, reference_options(o)), 0, quiet);
  CompareResult r = compare_images(a, b);
  EXPECT_TRUE(r.passed()) << r.summary();
  EXPECT_GT(r.meanA, 0.02);  // lit, not black
}

}  // namespace wp::test
