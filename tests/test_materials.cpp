// Material modules (src/scene/materials/): each kind's schema, the checks
// add_material makes against it, and its errors at the importer's place.
#include <set>
#include <stdexcept>

#include "render/spectra.h"
#include "test_support.h"

namespace wp::test {

namespace {

// A complaint that throws the problem, as an importer's would.
Complaint thrower(const std::string& where) {
  return [where](const std::string& problem) { throw InputError(where + ": " + problem); };
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// One module per row of kinds.glsl, in id order, each schema well formed: a
// parameter "g.k" has its group g, a number's stand-in texture is declared
// as a texture, a choice has words, and no name is declared twice.
TEST(MaterialModules, EveryKindHasOneWellFormedModule) {
  const auto& modules = material_modules();
  ASSERT_EQ(modules.size(), material_kinds().size());
  for (const KindInfo& k : material_kinds()) {
    const MaterialModule& m = *modules[k.id];
    SCOPED_TRACE(k.name);
    EXPECT_EQ(m.kind, k.id);
    EXPECT_NE(m.pack, nullptr);
    std::set<std::string> names;
    for (const ParamSpec& p : m.params) {
      EXPECT_TRUE(names.insert(p.name).second) << p.name << " declared twice";
      const size_t dot = p.name.find('.');
      if (dot != std::string::npos) {
        const ParamSpec* group = find_param(m, p.name.substr(0, dot));
        ASSERT_NE(group, nullptr) << p.name;
        EXPECT_EQ(group->type, ParamType::Group) << p.name;
      }
      if (!p.textureName.empty()) {
        const ParamSpec* t = find_param(m, p.textureName);
        ASSERT_NE(t, nullptr) << p.textureName;
        EXPECT_EQ(t->type, ParamType::Texture);
      }
      if (p.type == ParamType::Choice) {
        EXPECT_FALSE(p.choices.empty());
      }
      if (p.type == ParamType::Number && p.presence == Presence::Defaulted && !p.clamp) {
        EXPECT_TRUE(p.range.contains(p.fallback.x)) << p.name << "'s default lies outside its range";
      }
    }
  }
}

// Defaults fill what the importer leaves out (a texture's as a constant
// texture), and a kind's pack reads them.
TEST(MaterialModules, DefaultsFillWhatIsNotGiven) {
  Scene s;
  const uint32_t m = add_material(s, MaterialParams(MAT_ROUGH_DIELECTRIC, "glass", thrower("glass")));
  EXPECT_EQ(s.materials[m].record.params, glm::vec4(1.5f, 0.3f * 0.3f, 0.0f, 0.0f));
  ASSERT_NE(s.materials[m].albedo(), WP_INVALID);
  EXPECT_EQ(s.textures[s.materials[m].albedo()].color, glm::vec3(1.0f));
  const uint32_t beckmann = add_material(s, MaterialParams(MAT_BECKMANN_CONDUCTOR, "b", thrower("b"))
                                                .number("alpha", 0.5f)
                                                .colour("eta", glm::vec3(0.2f))
                                                .colour("k", glm::vec3(3.0f)));
  EXPECT_EQ(s.materials[beckmann].record.params2.w, 0.0f) << "Smith's shadowing is the default";
}

// A conductor's "metal" names a measured metal (metal_spectra.glsl): an RGB
// render takes its eta and k as their spectra's sRGB projections, and
// params2.w names it for the spectral mode (CONDUCTOR_NAMED), beside CS184's
// shadowing choice. A dielectric's "glass" names a glass (glasses.glsl).
TEST(MaterialModules, NamedMetalsAndGlassesBringTheirMeasuredIndices) {
  Scene s;
  const uint32_t gold = add_material(s, MaterialParams(MAT_ROUGH_CONDUCTOR, "gold", thrower("gold")).choice("metal", "Au"));
  const shader::Material& g = s.materials[gold].record;
  EXPECT_EQ(g.params2.w, CONDUCTOR_NAMED * float(METAL_AU + 1u));
  glm::vec3 eta, k;
  metal_rgb(METAL_AU, eta, k);
  EXPECT_EQ(glm::vec3(g.params.y, g.params.z, g.params.w), eta);
  EXPECT_EQ(glm::vec3(g.params2), k);
  EXPECT_LT(eta.x, 0.5f) << "gold's index is low in the red";
  EXPECT_GT(eta.z, 1.0f) << "and above 1 in the blue";
  EXPECT_GT(k.x, k.z);
  const uint32_t copper = add_material(s, MaterialParams(MAT_BECKMANN_CONDUCTOR, "copper", thrower("copper"))
                                              .number("alpha", 0.3f)
                                              .choice("metal", "Cu")
                                              .choice("shadowing", "cs184"));
  EXPECT_EQ(s.materials[copper].record.params2.w, CONDUCTOR_NAMED * float(METAL_CU + 1u) + 1.0f);
  // A named glass: its index at the d line, its name in params.w, dispersion compiled in.
  const uint32_t bk7 = add_material(s, MaterialParams(MAT_DIELECTRIC, "bk7", thrower("bk7")).choice("glass", "BK7"));
  EXPECT_NEAR(s.materials[bk7].record.params.x, 1.5168f, 1e-4f);
  EXPECT_EQ(s.materials[bk7].record.params.w, float(GLASS_BK7 + 1u));
  EXPECT_EQ(material_module(MAT_DIELECTRIC).features(s.materials[bk7].record), KIND_BIT(FEATURE_DISPERSION));
  const uint32_t water = add_material(s, MaterialParams(MAT_ROUGH_DIELECTRIC, "water", thrower("water")).choice("glass", "water").number("roughness", 0.1f));
  EXPECT_NEAR(s.materials[water].record.params.x, 1.3333f, 2e-4f);
  EXPECT_EQ(s.materials[water].record.params.w, float(GLASS_WATER + 1u));
  EXPECT_EQ(error_of([&] { add_material(s, MaterialParams(MAT_DIELECTRIC, "g", thrower("g")).number("ior", 1.6f).choice("glass", "BK7", thrower("g/glass"))); }),
            "g/glass: a named glass brings its own index of refraction: give \"glass\" or \"ior\", not both");
  EXPECT_EQ(error_of([&] { add_material(s, MaterialParams(MAT_ROUGH_CONDUCTOR, "x", thrower("x")).choice("metal", "Zn", thrower("x/metal"))); }),
            "x/metal: metal must be \"none\", \"Au\", \"Ag\", \"Cu\", \"Al\", \"Cr\", \"Ni\", \"Ti\", \"W\" or \"Pt\"");
}

// Each problem is reported at the place the importer gave for the value, or
// for the whole material where the value is missing.
TEST(MaterialModules, ProblemsAreReportedWhereTheValueCameFrom) {
  Scene s;
  auto conductor = [&] {
    return MaterialParams(MAT_ROUGH_CONDUCTOR, "c", thrower("/materials/0")).colour("eta", glm::vec3(1.0f), thrower("/materials/0/eta"));
  };
  EXPECT_EQ(error_of([&] { add_material(s, conductor()); }),
            "/materials/0: a conductor needs \"eta\" and \"k\", or \"metal\": one of Au, Ag, Cu, Al, Cr, Ni, Ti, W, Pt");
  EXPECT_EQ(error_of([&] { add_material(s, conductor().choice("metal", "Au", thrower("/materials/0/metal"))); }),
            "/materials/0/metal: a named metal brings its measured eta and k: give \"metal\" or \"eta\" and \"k\", not both");
  EXPECT_EQ(error_of([&] { add_material(s, conductor().colour("k", glm::vec3(0.0f, -1.0f, 0.0f), thrower("/materials/0/k"))); }),
            "/materials/0/k: k must lie in [0, 1000) in every channel");
  EXPECT_EQ(error_of([&] { add_material(s, conductor().colour("k", glm::vec3(1.0f)).number("roughness", 2.0f, thrower("<roughness>"))); }),
            "<roughness>: roughness must lie in [0, 1]");
  EXPECT_EQ(error_of([&] { add_material(s, conductor().colour("k", glm::vec3(1.0f)).colour("roughness", glm::vec3(0.5f), thrower("<r>"))); }),
            "<r>: roughness: expected a number, not a colour");
  EXPECT_EQ(error_of([&] {
              add_material(s, MaterialParams(MAT_BECKMANN_CONDUCTOR, "b", thrower("b"))
                                  .number("alpha", 0.5f)
                                  .colour("eta", glm::vec3(1.0f))
                                  .colour("k", glm::vec3(1.0f))
                                  .choice("shadowing", "walter", thrower("b/shadowing")));
            }),
            "b/shadowing: shadowing must be \"smith\" or \"cs184\"");
  // A constant texture's colour is checked; a clamped number is clamped.
  const uint32_t bright = add_texture(s, constant_texture(glm::vec3(1.5f)));
  EXPECT_EQ(error_of([&] { add_material(s, MaterialParams(MAT_LAMBERTIAN, "l", thrower("l")).texture("albedo", bright, thrower("l/albedo"))); }),
            "l/albedo: albedo above 1 would create energy");
  const uint32_t metal = add_material(s, MaterialParams(MAT_METAL, "m", thrower("m")).number("roughness", 3.0f));
  EXPECT_EQ(s.materials[metal].record.params.x, 1.0f);
  // A name the schema lacks is the importer's bug, not the file's.
  EXPECT_THROW(add_material(s, MaterialParams(MAT_METAL, "m", thrower("m")).number("shininess", 3.0f)), std::logic_error);
}

// A layer over a light or an emitting base, or past the kernels' limits, is
// refused at the base or at the material.
TEST(MaterialModules, PartsAndLayersStayWithinTheKernelsLimits) {
  Scene s;
  const uint32_t light = add_material(s, MaterialParams(MAT_LIGHT, "light", thrower("light")).texture("emit", add_texture(s, constant_texture(glm::vec3(1.0f)))));
  EXPECT_NE(error_of([&] { add_material(s, MaterialParams(MAT_SHEEN, "s", thrower("s")).material("base", light, thrower("s/base"))); })
                .find("s/base: a blend or a layer cannot contain a diffuse_light"),
            std::string::npos);
  uint32_t base = add_lambertian(s, glm::vec3(0.5f));
  base = add_material(s, MaterialParams(MAT_SHEEN, "s1", thrower("s1")).material("base", base));
  EXPECT_NE(error_of([&] { add_material(s, MaterialParams(MAT_SHEEN, "s2", thrower("s2")).material("base", base)); }).find("at most one sheen"),
            std::string::npos);
  base = add_material(s, MaterialParams(MAT_CLEARCOAT, "c1", thrower("c1")).material("base", base));
  EXPECT_EQ(material_layers(s, base), 2);
  EXPECT_NE(error_of([&] { add_material(s, MaterialParams(MAT_CLEARCOAT, "c2", thrower("c2")).material("base", base)); }).find("at most 2 deep"),
            std::string::npos);
}
}  // namespace wp::test
