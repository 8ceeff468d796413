// collada_materials.cpp — the COLLADA reader's materials: the course's BSDFs
// from an effect's CGL technique, profile_COMMON's diffuse colour, and the
// bindings of material symbols by instances (collada_reader.h).
#include <optional>

#include "scene/collada_reader.h"

namespace wp::collada_import {

// ---- materials ---------------------------------------------------------------

// The technique of profile CGL among an element's <extra>s, or null.
pugi::xml_node ColladaReader::cgl_technique(pugi::xml_node e) {
  for (pugi::xml_node extra : e.children("extra"))
    for (pugi::xml_node t : extra.children("technique"))
      if (std::string(t.attribute("profile").value()) == "CGL") return t;
  return {};
}

uint32_t ColladaReader::constant(glm::dvec3 c) { return add_texture(scene_, constant_texture(glm::vec3(c))); }

// A material's BSDF as the course builds it (collada.cpp, parse_material):
// the last BSDF element of the effect's CGL technique, or else profile
// COMMON's diffuse colour, or else 0.5 grey.
uint32_t ColladaReader::material(pugi::xml_node mat) {
  auto known = materials_.find(mat.internal_object());
  if (known != materials_.end()) return known->second;
  pugi::xml_node effect = resolve(required(mat, "instance_effect"), "url", "effect");
  const std::string name = mat.attribute("name") ? mat.attribute("name").value() : mat.attribute("id").value();
  // The course's BSDFs in wavepath's kinds and their parameters' names.
  std::optional<MaterialParams> m;
  for (pugi::xml_node b : cgl_technique(effect).children()) {
    if (b.type() != pugi::node_element) continue;
    const std::string type = b.name();
    const auto at = [this](pugi::xml_node n) { return Complaint([this, n](const std::string& problem) { fail(n, problem); }); };
    if (type == "emission") {
      m.emplace(MAT_LIGHT, name, at(b));
      m->texture("emit", constant(color(required(b, "radiance"), "<radiance>")), at(b.child("radiance")));
    } else if (type == "mirror") {
      m.emplace(MAT_METAL, name, at(b));  // roughness 0: a mirror tinted by the reflectance
      m->texture("albedo", constant(color(required(b, "reflectance"), "<reflectance>")), at(b.child("reflectance")));
    } else if (type == "microfacet") {
      m.emplace(MAT_BECKMANN_CONDUCTOR, name, at(b));
      m->number("alpha", float(number(required(b, "alpha"), "<alpha>")), at(b.child("alpha")));
      m->colour("eta", glm::vec3(color(required(b, "eta"), "<eta>")), at(b.child("eta")));
      m->colour("k", glm::vec3(color(required(b, "k"), "<k>")), at(b.child("k")));
      m->choice("shadowing", "cs184");  // the 3-2 skeleton's shadowing term
    } else if (type == "glass" || type == "refraction") {
      m.emplace(MAT_CS184_GLASS, name, at(b));
      m->texture("transmittance", constant(color(required(b, "transmittance"), "<transmittance>")), at(b.child("transmittance")));
      if (type == "glass") m->colour("reflectance", glm::vec3(color(required(b, "reflectance"), "<reflectance>")), at(b.child("reflectance")));
      number(required(b, "roughness"), "<roughness>");  // read, not used: both BSDFs are smooth in the course
      const double ior = number(required(b, "ior"), "<ior>");
      if (!(ior > 0.0 && ior < 100.0)) fail(b.child("ior"), "ior must lie between 0 and 100");
      m->number("ior", float(ior), at(b.child("ior")));
      m->flag("refraction_only", type == "refraction");
    } else {
      unsupported(b);
    }
  }
  if (!m) {
    // profile_COMMON: the technique of sid "common"; its shading model's diffuse colour.
    glm::dvec3 diffuse(0.5);
    for (pugi::xml_node t : effect.child("profile_COMMON").children("technique")) {
      for (pugi::xml_node model : t.children()) {
        const std::string shading = model.name();
        if (shading != "phong" && shading != "lambert" && shading != "blinn") continue;
        pugi::xml_node d = model.child("diffuse");
        if (!d) continue;
        if (d.child("texture")) fail(d, "a diffuse <texture> is not supported (colours only)");
        if (pugi::xml_node c = d.child("color")) diffuse = color(c, "<color>");
      }
    }
    m.emplace(MAT_LAMBERTIAN, name, [this, effect](const std::string& problem) { fail(effect, problem); });
    m->texture("albedo", constant(diffuse));
  }
  const uint32_t id = add_material(scene_, *m);
  materials_.emplace(mat.internal_object(), id);
  return id;
}

uint32_t ColladaReader::default_material() {
  if (defaultMaterial_ == WP_INVALID) defaultMaterial_ = add_lambertian(scene_, glm::vec3(0.5f), "default (0.5 grey)");
  return defaultMaterial_;
}

// The material bound to `symbol` by an instance's <bind_material>; with no
// binding at all, the course's 0.5 grey.
uint32_t ColladaReader::bound_material(pugi::xml_node instance, const std::string& symbol) {
  pugi::xml_node common = instance.child("bind_material").child("technique_common");
  pugi::xml_node first;
  for (pugi::xml_node im : common.children("instance_material")) {
    if (!first) first = im;
    if (symbol.empty() || symbol == im.attribute("symbol").value()) return material(resolve(im, "target", "material"));
  }
  if (!first) return default_material();
  fail(instance, "no <instance_material> binds the material symbol \"" + symbol + "\"");
}

}  // namespace wp::collada_import
