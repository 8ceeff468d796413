// The darts scene loader: the default scene, every transform form, and clear
// errors (file, place, problem) for bad input.
#include "test_support.h"

#include <glm/gtc/matrix_transform.hpp>

#include <fstream>

#include "scene/kinds.h"
#include "scene/transform.h"
#include "util/error.h"

namespace wp::test {
namespace {

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) {
  return glm::vec3(m * glm::vec4(p, 1.0f));
}

TEST(Scene, CornellBoxLoads) {
  Scene s = load_scene(source_path("scenes/cornell-box.json"));
  EXPECT_EQ(s.triangles.size(), 32u);
  EXPECT_EQ(s.camera.width, 512);
  EXPECT_NEAR(s.camera.vfovDegrees, 39.3f, 1e-5f);
  glm::vec3 eye = apply(s.camera.toWorld, glm::vec3(0));
  EXPECT_NEAR(glm::distance(eye, glm::vec3(278, 273, -800)), 0.0f, 1e-3f);
  glm::vec3 forward = glm::vec3(s.camera.toWorld * glm::vec4(0, 0, -1, 0));
  EXPECT_NEAR(forward.z, 1.0f, 1e-6f);  // looks down -Z in camera space, +Z in the world
  int lights = 0;
  for (const auto& m : s.materials) lights += m.emission != WP_INVALID;
  EXPECT_EQ(lights, 1);
}

TEST(Transform, EveryFormMapsPointsAsDartsDoes) {
  std::string file = "t.json";
  auto parse = [&](const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text);
    return parse_transform(JsonCursor(j, "/transform", file));
  };
  EXPECT_NEAR(glm::distance(apply(parse(R"({"translate": [1, 2, 3]})"), glm::vec3(1)), glm::vec3(2, 3, 4)), 0, 1e-6);
  EXPECT_NEAR(glm::distance(apply(parse(R"({"scale": 2})"), glm::vec3(1, 2, 3)), glm::vec3(2, 4, 6)), 0, 1e-6);
  EXPECT_NEAR(glm::distance(apply(parse(R"({"scale": [1, 2, 3]})"), glm::vec3(1)), glm::vec3(1, 2, 3)), 0, 1e-6);
  EXPECT_NEAR(glm::distance(apply(parse(R"({"rotate": [90, 0, 0, 1]})"), glm::vec3(1, 0, 0)), glm::vec3(0, 1, 0)), 0, 1e-6);
  EXPECT_NEAR(glm::distance(apply(parse(R"({"matrix": [1,0,0,5, 0,1,0,6, 0,0,1,7, 0,0,0,1]})"), glm::vec3(0)),
                            glm::vec3(5, 6, 7)), 0, 1e-6);
  EXPECT_NEAR(glm::distance(apply(parse(R"({"o": [1,1,1], "x": [0,1,0], "y": [-1,0,0], "z": [0,0,1]})"), glm::vec3(1, 0, 0)),
                            glm::vec3(1, 2, 1)), 0, 1e-6);
  // Arrays apply in order: scale first, then translate.
  EXPECT_NEAR(glm::distance(apply(parse(R"([{"scale": 2}, {"translate": [1, 0, 0]}])"), glm::vec3(1, 0, 0)),
                            glm::vec3(3, 0, 0)), 0, 1e-6);
  glm::mat4 look = parse(R"({"from": [0, 0, 5], "to": [0, 0, 0], "up": [0, 1, 0]})");
  EXPECT_NEAR(glm::distance(apply(look, glm::vec3(0, 0, -5)), glm::vec3(0)), 0, 1e-5);  // -Z looks at the target
  EXPECT_NEAR(glm::distance(apply(look, glm::vec3(1, 0, 0)), glm::vec3(1, 0, 5)), 0, 1e-5);
}

// Vertex normals and UVs sit apart from the triangles that have them; they
// must reach those triangles' records, and only theirs, in the compiled scene.
TEST(Scene, PerVertexDataReachesItsTrianglesOnly) {
  Scene s = load_scene(write_scene("shading.json", R"({"surfaces": [
    {"type": "triangle", "positions": [[0,0,0],[1,0,0],[0,1,0]], "normals": [[0,0,2],[0,0,1],[0,1,1]], "material": {"type": "lambertian"}},
    {"type": "quad", "size": 2, "transform": {"translate": [0, 0, 5]}, "material": {"type": "lambertian"}},
    {"type": "triangle", "positions": [[0,0,-3],[1,0,-3],[0,1,-3]], "material": {"type": "lambertian"}}]})"));
  ASSERT_EQ(s.triangles.size(), 4u);
  ASSERT_EQ(s.triangleShading.size(), 3u);
  EXPECT_EQ(s.triangles[3].shading, WP_INVALID);
  const SceneTriangleShading& smooth = s.triangleShading.at(s.triangles[0].shading);
  EXPECT_TRUE(smooth.hasNormals);
  EXPECT_FALSE(smooth.hasUvs);
  EXPECT_NEAR(glm::distance(smooth.n[2], glm::normalize(glm::vec3(0, 1, 1))), 0.0f, 1e-6f);
  for (int q : {1, 2}) {
    const SceneTriangleShading& quad = s.triangleShading.at(s.triangles[size_t(q)].shading);
    EXPECT_TRUE(quad.hasUvs && !quad.hasNormals);
    for (glm::vec2 uv : quad.uv) EXPECT_TRUE((uv.x == 0.0f || uv.x == 1.0f) && (uv.y == 0.0f || uv.y == 1.0f));
  }

  CompiledScene cs = compile_scene(s, RenderOptions{});
  ASSERT_EQ(cs.triangleShading.size(), 3u);
  int smoothRecords = 0, plainRecords = 0;
  for (const shader::Triangle& t : cs.triangles) {
    if (t.v0.z == -3.0f) {
      EXPECT_EQ(t.shading, WP_INVALID);
      ++plainRecords;
    } else if (t.v0.z == 0.0f) {
      const shader::TriangleShading& sh = cs.triangleShading.at(t.shading);
      EXPECT_EQ(sh.flags, SHADING_NORMALS);
      EXPECT_NEAR(glm::distance(sh.n2, glm::normalize(glm::vec3(0, 1, 1))), 0.0f, 1e-6f);
      EXPECT_EQ(glm::vec2(sh.u0, sh.v0), glm::vec2(0.0f));  // no UVs: the barycentrics
      ++smoothRecords;
    } else {
      EXPECT_EQ(cs.triangleShading.at(t.shading).flags, 0u);
    }
  }
  EXPECT_EQ(smoothRecords, 1);
  EXPECT_EQ(plainRecords, 1);
}

TEST(Scene, QuadFrontIsTheTransformedZAxisEvenWhenMirrored) {
  for (const char* xf : {R"({"rotate": [90, 1, 0, 0]})", R"([{"scale": [-1, 1, 1]}, {"rotate": [90, 1, 0, 0]}])"}) {
    std::string text = std::string(R"({"surfaces": [{"type": "quad", "size": [2, 3], "material": {"type": "lambertian"}, "transform": )") + xf + "}]}";
    Scene s = load_scene(write_scene("quad.json", text));
    ASSERT_EQ(s.triangles.size(), 2u);
    for (const SceneTriangle& t : s.triangles) {
      glm::vec3 n = glm::normalize(glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]));
      EXPECT_NEAR(n.y, -1.0f, 1e-5f) << xf;  // +Z rotated by 90 degrees about X is -Y
    }
  }
}

// The kernels compile out what a scene does not use (SceneParams.kinds,
// specialization constants): the masks must name every kind a scene uses,
// and nothing it does not.
TEST(Scene, KindMasksNameWhatTheSceneUses) {
  auto kinds = [](const char* path, RenderOptions o = RenderOptions{}) { return compile_scene(load_scene(source_path(path)), o).params.kinds; };
  auto bits = [](std::initializer_list<uint32_t> ids) {
    uint32_t m = 0;
    for (uint32_t id : ids) m |= KIND_BIT(id);
    return m;
  };
  const glm::uvec4 box = kinds("scenes/cornell-box.json");
  EXPECT_EQ(box, glm::uvec4(bits({MAT_LAMBERTIAN, MAT_LIGHT}), bits({TEX_CONSTANT}), bits({LIGHT_AREA}), 0u));
  const glm::uvec4 materials = kinds("tests/data/features/materials.json");
  EXPECT_EQ(materials.x, bits({MAT_LAMBERTIAN, MAT_LIGHT, MAT_METAL, MAT_DIELECTRIC, MAT_PHONG, MAT_BLINN_PHONG, MAT_BLEND}));
  EXPECT_EQ(materials.y, bits({TEX_CONSTANT, TEX_CHECKER, TEX_FRESNEL}));
  EXPECT_EQ(materials.z, bits({LIGHT_AREA, LIGHT_SPHERE, LIGHT_POINT}));
  EXPECT_EQ(materials.w, bits({FEATURE_SPHERES, FEATURE_SHADING_DATA}));  // quads carry planar UVs
  const glm::uvec4 textures = kinds("tests/data/features/textures.json");
  EXPECT_EQ(textures.y & bits({TEX_CHECKER, TEX_MARBLE, TEX_IMAGE}), bits({TEX_CHECKER, TEX_MARBLE, TEX_IMAGE}));
  // Emission: a checker-textured lamp there; in materials.json checkers, but
  // every light one colour.
  EXPECT_TRUE(textures.w & KIND_BIT(FEATURE_EMISSION_TEXTURES));
  EXPECT_TRUE(kinds("tests/data/features/smooth-mesh.json").w & KIND_BIT(FEATURE_SHADING_DATA));
  const glm::uvec4 environment = kinds("tests/data/features/environment.json");
  EXPECT_TRUE(environment.z & KIND_BIT(LIGHT_ENVIRONMENT));
  EXPECT_TRUE(environment.y & KIND_BIT(TEX_IMAGE));
  // The sampler counts too: the camera kernel compiles CMJ out for others.
  EXPECT_TRUE(kinds("tests/data/features/camera.json").w & KIND_BIT(FEATURE_CMJ));
  EXPECT_FALSE(materials.w & KIND_BIT(FEATURE_CMJ));
  RenderOptions independent;
  independent.sampler = SamplerKind::Independent;
  EXPECT_FALSE(kinds("tests/data/features/camera.json", independent).w & KIND_BIT(FEATURE_CMJ));
  // So does CS184's -H, whose sampling is otherwise compiled out (and the
  // BSDF's, unbiased too, would take its place unnoticed by comparisons).
  RenderOptions hemisphere;
  hemisphere.integrator = IntegratorKind::PathHemisphere;
  EXPECT_TRUE(kinds("tests/data/features/integrators.json", hemisphere).w & KIND_BIT(FEATURE_UNIFORM_HEMISPHERE));
  EXPECT_FALSE(kinds("tests/data/features/integrators.json").w & KIND_BIT(FEATURE_UNIFORM_HEMISPHERE));
  // wavepath info names them.
  EXPECT_EQ(kinds_description(glm::uvec4(0u)), "materials none; textures none; lights none; features none");
  EXPECT_EQ(kinds_description(box), "materials lambertian, diffuse_light; textures constant; lights area lights; features none");
}

// Each kind table lists ids 0, 1, 2, ... (an id is a bit of a 32-bit mask),
// and names each kind once.
TEST(Scene, KindTablesHaveConsecutiveIdsAndDistinctNames) {
  for (const std::vector<KindInfo>* table : {&material_kinds(), &texture_kinds(), &light_kinds(), &feature_kinds()}) {
    ASSERT_LE(table->size(), 32u);
    for (size_t i = 0; i < table->size(); ++i) {
      EXPECT_EQ((*table)[i].id, uint32_t(i)) << (*table)[i].name;
      for (size_t j = 0; j < i; ++j) EXPECT_STRNE((*table)[i].name, (*table)[j].name);
      EXPECT_EQ(kind_named(*table, (*table)[i].name), std::optional<uint32_t>(uint32_t(i)));
    }
  }
  EXPECT_EQ(kind_named(material_kinds(), "glass"), std::nullopt);
  EXPECT_EQ(kind_list(light_kinds(), KIND_BIT(LIGHT_POINT) | KIND_BIT(LIGHT_AREA)), "area lights or point lights");
}

// Sorting by material class (gpu-sort) shades each class with a kernel that
// holds only its kinds: a material in a class without its kinds would be
// shaded as something else. Every material that primitives use must land in
// a class that has its material and texture kinds; classes must differ; and
// beyond SHADE_CLASSES_MAX they share the last, which has all their kinds.
TEST(Scene, ShadeClassesHoldTheKindsOfTheirMaterials) {
  auto check = [](const CompiledScene& cs, const Scene& scene, const std::string& what) {
    ASSERT_LE(cs.shadeClasses.size(), size_t(SHADE_CLASSES_MAX)) << what;
    for (size_t a = 0; a + 1 < cs.shadeClasses.size(); ++a)
      for (size_t b = a + 1; b < cs.shadeClasses.size(); ++b) EXPECT_TRUE(cs.shadeClasses[a] != cs.shadeClasses[b]) << what;
    for (size_t m = 0; m < cs.materials.size(); ++m) {
      const shader::Material& mat = cs.materials[m];
      const bool used = std::any_of(scene.triangles.begin(), scene.triangles.end(), [&](const SceneTriangle& t) { return t.material == m; }) ||
                        std::any_of(scene.spheres.begin(), scene.spheres.end(), [&](const SceneSphere& sp) { return sp.material == m; });
      if (!used) continue;
      ASSERT_NE(mat.children.w, SORT_KEY_MISS) << what << ", material " << m;  // sort key: class + 1
      ASSERT_LE(mat.children.w, cs.shadeClasses.size()) << what << ", material " << m;
      const glm::uvec4 kernel = cs.shade_key_kinds(mat.children.w);
      EXPECT_TRUE(kernel.x & KIND_BIT(mat.info.x)) << what << ", material " << m;
      if (mat.info.y != WP_INVALID) {
        const uint32_t tex = KIND_BIT(cs.textures[mat.info.y].info.x & TEX_TYPE_MASK);
        EXPECT_EQ(kernel.y & tex, tex) << what << ", material " << m;
      }
    }
  };
  for (const char* path : {"tests/data/features/materials.json", "tests/data/features/textures.json", "tests/data/features/environment.json"}) {
    Scene scene = load_scene(source_path(path));
    CompiledScene cs = compile_scene(scene, RenderOptions{});
    check(cs, scene, path);
    // Only the kinds a class needs: the first class's kernel lacks some.
    EXPECT_TRUE(cs.shade_key_kinds(1) != cs.params.kinds) << path;
  }
  {
    Scene scene = load_scene(source_path("tests/data/features/materials.json"));
    CompiledScene cs = compile_scene(scene, RenderOptions{});
    const glm::uvec4 misses = cs.shade_key_kinds(SORT_KEY_MISS);
    EXPECT_EQ(misses.x, 0u);
    EXPECT_EQ(glm::uvec2(misses.z, misses.w), glm::uvec2(cs.params.kinds.z, cs.params.kinds.w));
  }
  // Emission and the environment are looked up by every kernel: the
  // checker-textured lamp's kind, and the environment's image, stay in the
  // misses' kernel.
  EXPECT_TRUE(compile_scene(load_scene(source_path("tests/data/features/textures.json")), RenderOptions{}).shade_key_kinds(SORT_KEY_MISS).y &
              KIND_BIT(TEX_CHECKER));
  EXPECT_TRUE(compile_scene(load_scene(source_path("tests/data/features/environment.json")), RenderOptions{}).shade_key_kinds(SORT_KEY_MISS).y &
              KIND_BIT(TEX_IMAGE));
  // 20 kinds of material (5 lobe kinds by 4 kinds of albedo texture), one
  // sphere each: more than SHADE_CLASSES_MAX classes.
  Scene scene;
  scene.camera = Camera{};
  SceneTexture marble = constant_texture(glm::vec3(0.5f));
  marble.kind = TEX_MARBLE;
  const uint32_t plain = add_texture(scene, constant_texture(glm::vec3(0.5f))), marbled = add_texture(scene, marble);
  SceneTexture checker;
  checker.kind = TEX_CHECKER;
  checker.even = checker.odd = plain;
  const uint32_t checkered = add_texture(scene, checker);
  checker.odd = marbled;
  const uint32_t both = add_texture(scene, checker);
  for (uint32_t type : {MAT_LAMBERTIAN, MAT_METAL, MAT_DIELECTRIC, MAT_PHONG, MAT_BLINN_PHONG}) {
    for (uint32_t albedo : {plain, checkered, marbled, both}) {
      SceneMaterial m;
      m.kind = type;
      m.record.info.y = albedo;  // packed by hand: every kind with every albedo, dielectrics too
      m.record.params.x = type == MAT_DIELECTRIC ? 1.5f : 10.0f;
      scene.materials.push_back(m);
      SceneSphere sp;
      sp.toWorld = glm::translate(glm::mat4(1.0f), glm::vec3(float(scene.spheres.size()) * 3.0f, 0.0f, 0.0f));
      sp.material = uint32_t(scene.materials.size() - 1);
      scene.spheres.push_back(sp);
    }
  }
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  EXPECT_EQ(cs.shadeClasses.size(), size_t(SHADE_CLASSES_MAX));
  check(cs, scene, "20 kinds of material");
}

// Every split method by its scene-file name (bvh.h).
TEST(Scene, AcceleratorSplitMethodsByName) {
  for (auto [name, split] : {std::pair<const char*, SplitMethod>{"sah", SplitMethod::Sah},
                             {"clustered sah", SplitMethod::ClusteredSah},
                             {"middle", SplitMethod::Middle},
                             {"equal", SplitMethod::Equal}}) {
    const std::string path =
        write_scene("accel.json", std::string(R"({"accelerator": {"type": "bbh", "max_leaf_size": 2, "split_method": ")") + name + "\"}}");
    const Scene scene = load_scene(path);
    EXPECT_EQ(scene.accelerator.split, split) << name;
    EXPECT_EQ(scene.accelerator.maxLeafSize, 2) << name;
  }
  // Without a method the builder picks one of the SAH builds by size.
  EXPECT_EQ(load_scene(write_scene("accel.json", R"({"accelerator": {"type": "bbh"}})")).accelerator.split, SplitMethod::Auto);
}

// darts' integrator "power", the MIS exponent: 2 (the power heuristic) by
// default, as given otherwise; it reaches the kernels' parameters.
TEST(Scene, IntegratorPowerIsTheMisExponent) {
  EXPECT_EQ(load_scene(write_scene("p.json", R"({"integrator": {"type": "path tracer mis"}})")).integrator.misPower, 2.0f);
  Scene balance = load_scene(write_scene("p.json", R"({"integrator": {"type": "path tracer mis", "power": 1}})"));
  EXPECT_EQ(balance.integrator.misPower, 1.0f);
  EXPECT_EQ(compile_scene(balance, RenderOptions{}).params.mis.x, 1.0f);
  expect_error(R"({"integrator": {"power": -1}})", {"/integrator/power", "from 0 to 16"});
  expect_error(R"({"integrator": {"power": "two"}})", {"/integrator/power"});
}

// add_mesh, which every importer places its meshes with: triangles in world
// space, degenerate ones dropped, material slots mapped, vertex normals through
// the normal matrix where every corner has one, UVs where every corner has one,
// and problems reported through the importer's callback.
TEST(Scene, MeshesArePlacedInWorldSpaceWithTheirVertexData) {
  SceneMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.normals = {{0, 0, 1}, {1, 0, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}};
  // A triangle with a normal and a UV at every corner; one with a corner
  // lacking its normal; a degenerate one (on a line); one without a material.
  mesh.positionIndices = {0, 1, 2, 0, 2, 3, 0, 1, 4, 1, 2, 3};
  mesh.normalIndices = {0, 0, 1, 0, WP_INVALID, 0, 0, 0, 0, 0, 0, 0};
  mesh.uvIndices = {0, 1, 2, 0, 2, 1, 0, 1, 2, 0, 1, WP_INVALID};
  mesh.materials = {1, 0, 0, WP_INVALID};
  auto fail = [](const std::string& problem) { throw InputError(problem); };
  const glm::mat4 toWorld = glm::translate(glm::mat4(1.0f), glm::vec3(5, 0, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(2, 1, 1));
  Scene scene;
  add_mesh(scene, mesh, toWorld, {7, 8}, 9, fail);
  ASSERT_EQ(scene.triangles.size(), 3u);  // the degenerate one dropped
  const SceneTriangle& a = scene.triangles[0];
  EXPECT_EQ(a.v[1], glm::vec3(7, 0, 0));
  EXPECT_EQ(a.material, 8u);               // slot 1
  EXPECT_EQ(scene.triangles[2].material, 9u);  // no slot: the fallback
  ASSERT_NE(a.shading, WP_INVALID);
  const SceneTriangleShading& sa = scene.triangleShading[a.shading];
  EXPECT_TRUE(sa.hasNormals && sa.hasUvs);
  // (1, 0, 1) through the inverse transpose of scale (2, 1, 1): (0.5, 0, 1), normalised.
  EXPECT_NEAR(glm::distance(sa.n[2], glm::normalize(glm::vec3(0.5f, 0, 1))), 0.0f, 1e-6f);
  EXPECT_EQ(sa.uv[2], glm::vec2(1, 1));
  const SceneTriangleShading& sb = scene.triangleShading.at(scene.triangles[1].shading);
  EXPECT_FALSE(sb.hasNormals);  // one corner lacks its normal: flat
  EXPECT_TRUE(sb.hasUvs);
  // The last lacks a UV at one corner and has the face's normal only where
  // given: with neither whole, no shading record at all.
  mesh.normalIndices[9] = WP_INVALID;
  Scene flat;
  add_mesh(flat, mesh, toWorld, {7, 8}, 9, fail);
  EXPECT_EQ(flat.triangles.back().shading, WP_INVALID);
  // No fallback for a triangle without a material, and geometry past floats:
  // each named by its triangle.
  Scene other;
  EXPECT_THROW(
      try { add_mesh(other, mesh, toWorld, {7, 8}, WP_INVALID, fail); } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "triangle 4 has no material");
        throw;
      },
      InputError);
  mesh.materials = {0, 0, 0, 0};
  EXPECT_THROW(
      try { add_mesh(other, mesh, glm::scale(glm::mat4(1.0f), glm::vec3(3e38f)), {7}, WP_INVALID, fail); } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "triangle 3: the transforms place it past the range of floats");  // its corner at x = 2
        throw;
      },
      InputError);
}

// load_scene picks the importer by content where it is telling, else by
// extension; a file of no format it reads is refused, naming the file.
TEST(Scene, TheImporterIsPickedByContentThenExtension) {
  EXPECT_EQ(scene_format("a.json", "{\"camera\": {}}"), SceneFormat::Darts);
  EXPECT_EQ(scene_format("a.scene", "  \n{\"camera\": {}}"), SceneFormat::Darts);
  EXPECT_EQ(scene_format("a.JSON", "not json"), SceneFormat::Darts);  // its importer names the syntax error
  EXPECT_EQ(scene_format("a.png", "\x89PNG\r\n"), SceneFormat::Unknown);
  EXPECT_EQ(scene_format("a", ""), SceneFormat::Unknown);
  // A darts scene under another name loads.
  EXPECT_EQ(load_scene(write_scene("renamed.scene", R"({"camera": {"vfov": 30}})")).camera.vfovDegrees, 30.0f);
  try {
    load_scene(source_path("tests/data/bad-image.png"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad-image.png: not a scene file wavepath reads"), std::string::npos) << e.what();
  }
}

TEST(SceneErrors, SyntaxErrorsGiveLineAndColumn) {
  expect_error("{\n  \"camera\": {\n    \"vfov\": 40,\n    \"resolution\": [16 16]\n  }\n}\n", {":4:", "JSON syntax error"});
  expect_error("{\n  \"camera\": {\n", {":3:", "JSON syntax error"});
}

TEST(SceneErrors, UnknownKeysAndTypesAreNamed) {
  expect_error(R"({"camera": {"fov": 40}})", {"/camera/fov", "unknown key \"fov\""});
  expect_error(R"({"lights": []})", {"unknown key \"lights\""});
  expect_error(R"({"surfaces": [{"type": "cone"}]})", {"/surfaces/0/type", "unknown surface type \"cone\""});
  expect_error(R"({"surfaces": [{"type": "sphere", "material": {"type": "velvet"}}]})", {"/surfaces/0/material/type", "velvet"});
  expect_error(R"({"surfaces": [{"type": "sphere", "material": "nope"}]})", {"/surfaces/0/material", "no material named \"nope\""});
  expect_error(R"({"surfaces": [{"type": "sphere", "radius": 1, "colour": 1, "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/colour", "unknown key"});
  expect_error(R"({"integrator": {"type": "bidirectional"}})", {"/integrator/type", "unknown integrator type"});
  expect_error(R"({"sampler": {"type": "sobol"}})", {"/sampler/type", "sobol"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": {"type": "wood"}}]})",
               {"/materials/0/albedo/type", "unknown texture type \"wood\""});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": {"type": "checker", "even": {"type": "plaid"}}}]})",
               {"/materials/0/albedo/even/type", "plaid"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": {"type": "fresnel", "ior": 1.5}}]})",
               {"/materials/0/albedo/type", "only meaningful as a blend"});
  expect_error(R"({"materials": [{"type": "metal", "name": "a", "roughness": 0.1, "shininess": 3}]})",
               {"/materials/0/shininess", "unknown key"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": {"type": "marble", "mapping": {"type": "cube"}}}]})",
               {"/materials/0/albedo/mapping/type", "unknown texture mapping"});
}

TEST(SceneErrors, BadMaterialsAndTexturesAreNamed) {
  expect_error(R"({"materials": [{"type": "dielectric", "name": "g", "ior": -1.5}]})", {"/materials/0/ior", "positive"});
  expect_error(R"({"materials": [{"type": "dielectric", "name": "g", "ior": 0}]})", {"/materials/0/ior", "positive"});
  expect_error(R"({"materials": [{"type": "phong", "name": "p", "exponent": -2}]})", {"/materials/0/exponent"});
  expect_error(R"({"materials": [{"type": "metal", "name": "m", "albedo": [0.5, 0.5]}]})", {"/materials/0/albedo", "array of 2"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": {"type": "checker", "scale": 0}}]})",
               {"/materials/0/albedo/scale", "positive"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": {"type": "image", "filename": "no-such.png"}}]})",
               {"no-such.png", "no such file", "/materials/0/albedo"});
  expect_error(R"({"materials": [{"type": "blend", "name": "b", "a": "x", "b": {"type": "lambertian"}}]})",
               {"/materials/0/a", "no material named \"x\""});
  expect_error(R"({"materials": [{"type": "blend", "name": "b", "amount": 2, "a": {"type": "lambertian"}, "b": {"type": "metal"}}]})",
               {"/materials/0/amount", "[0, 1]"});
  expect_error(R"({"materials": [{"type": "blend", "name": "b", "a": {"type": "diffuse_light", "emit": 1}, "b": {"type": "metal"}}]})",
               {"/materials/0/a", "cannot contain a diffuse_light"});
  // Five materials in one blend tree exceed the lobes a BSDF holds.
  expect_error(R"({"materials": [
      {"type": "blend", "name": "ab", "a": {"type": "lambertian"}, "b": {"type": "metal"}},
      {"type": "blend", "name": "cd", "a": {"type": "phong"}, "b": {"type": "metal"}},
      {"type": "blend", "name": "abcd", "a": "ab", "b": "cd"},
      {"type": "blend", "name": "all", "a": "abcd", "b": {"type": "lambertian"}}]})",
               {"/materials/3", "at most 4 materials"});
  expect_error(R"({"surfaces": [{"type": "triangle", "positions": [[0,0,0],[1,0,0],[0,1,0]], "normals": [[0,0,1],[0,0,1]], "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/normals", "expected 3 vertex normals"});
  expect_error(R"({"surfaces": [{"type": "triangle", "positions": [[0,0,0],[1,0,0],[0,1,0]], "normals": [[0,0,1],[0,0,1],[0,0,0]], "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/normals/2", "must not be zero"});
  expect_error(R"({"surfaces": [{"type": "point_light", "position": [0, 1, 0]}]})", {"/surfaces/0", "intensity"});
  expect_error(R"({"background": {"type": "sky"}})", {"/background/type", "environment map"});
  expect_error(R"({"background": {"type": "image", "filename": "no-such-sky.hdr"}})", {"no-such-sky.hdr", "no such file", "/background"});
  expect_error(R"({"background": {"type": "image", "filename": "sky.hdr", "strength": 2}})", {"/background/strength", "unknown key"});
  expect_error(R"({"surfaces": [{"type": "point_light", "position": [0, 1], "intensity": 1}]})", {"/surfaces/0/position"});
}

TEST(SceneErrors, BadValuesAreNamed) {
  expect_error(R"({"surfaces": [{"type": "sphere", "radius": -1, "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/radius", "positive"});
  expect_error(R"({"surfaces": [{"type": "quad", "size": [1, 0], "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/size", "zero-area"});
  expect_error(R"({"accelerator": {"split_method": "sha"}})",
               {"/accelerator/split_method", "unknown split method \"sha\"", "clustered sah"});
  expect_error(R"({"accelerator": {"max_leaf_size": 0}})", {"/accelerator/max_leaf_size"});
  expect_error(R"({"camera": {"resolution": [16]}})", {"/camera/resolution", "[width, height]"});
  expect_error(R"({"camera": {"resolution": [16, "x"]}})", {"/camera/resolution/1", "expected an integer"});
  expect_error(R"({"camera": {"vfov": 180}})", {"/camera/vfov"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": [1, 2]}]})", {"/materials/0/albedo", "array of 2"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a", "albedo": -0.5}]})", {"/materials/0/albedo", "negative"});
  expect_error(R"({"materials": [{"type": "lambertian", "name": "a"}, {"type": "lambertian", "name": "a"}]})",
               {"/materials/1/name", "defined twice"});
  expect_error(R"({"surfaces": [{"type": "sphere", "material": {"type": "lambertian"}, "transform": {"scale": [1, 0, 1]}}]})",
               {"/surfaces/0/transform/scale", "non-zero"});
  expect_error(R"({"surfaces": [{"type": "sphere", "material": {"type": "lambertian"}, "transform": {"translate": [1, 0, 0], "scale": 2}}]})",
               {"/surfaces/0/transform", "exactly one"});
  expect_error(R"({"surfaces": [{"type": "triangle", "positions": [[0,0,0],[1,0,0],[2,0,0]], "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/positions", "zero area"});
  expect_error(R"({"surfaces": [{"type": "sphere", "material": {"type": "diffuse_light", "emit": 1}, "transform": {"scale": [1, 2, 1]}}]})",
               {"/surfaces/0", "uniform scale"});
  // Meshes are opened before the surfaces are read (to size the triangle
  // array): a missing one inside a group still names its place, and a
  // malformed mesh surface is left to the reading, which names the problem.
  expect_error(R"({"surfaces": [{"type": "group", "children": [{"type": "mesh", "filename": "no-such.obj"}]}]})",
               {"/surfaces/0/children/0", "no-such.obj"});
  expect_error(R"({"surfaces": [{"type": "mesh", "filename": 7}]})", {"/surfaces/0/filename"});
  expect_error(R"({"surfaces": [{"type": "group", "children": 7}]})", {"/surfaces/0/children"});
  // Each transform is finite, their product is not: the geometry is refused
  // where it is placed.
  const std::string huge = R"("transform": {"scale": 1e30})";
  const std::string lambertian = R"("material": {"type": "lambertian"})";
  for (const std::string& shape : {R"({"type": "quad", )" + huge + ", " + lambertian + "}",
                                   R"({"type": "sphere", )" + huge + ", " + lambertian + "}",
                                   R"({"type": "triangle", "positions": [[0,0,0],[1,0,0],[0,1,0]], )" + huge + ", " + lambertian + "}",
                                   R"({"type": "point_light", "position": [1, 1, 1], "intensity": 1, )" + huge + "}",
                                   R"({"type": "mesh", "filename": ")" + source_path("tests/data/furnace-box.obj") + R"(", )" +
                                       huge + ", " + lambertian + "}"}) {
    expect_error(R"({"surfaces": [{"type": "group", )" + huge + R"(, "children": [)" + shape + "]}]}",
                 {"/surfaces/0/children/0", "past the range of floats"});
  }
}

TEST(SceneErrors, MissingFilesAndBadMeshesNameTheFile) {
  try {
    load_scene("/no/such/scene.json");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/scene.json: cannot open scene file (no such file)"), std::string::npos) << e.what();
  }
  for (auto [scene, parts] : std::vector<std::pair<const char*, std::vector<const char*>>>{
           {"mesh-bad-index.json", {"bad-index.obj:4", "vertex 99"}},
           {"mesh-bad-negative.json", {"bad-negative.obj:4", "vertex -7"}},
           {"mesh-bad-token.json", {"bad-token.obj:4", "not a vertex index"}},
           {"mesh-missing.json", {"no-such-mesh.obj", "no such file", "/surfaces/0"}}}) {
    try {
      load_scene(source_path(std::string("tests/data/") + scene));
      ADD_FAILURE() << scene;
    } catch (const InputError& e) {
      for (const char* p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace wp::test
