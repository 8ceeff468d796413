// metal_rough.glsl — glTF 2.0's metal-rough material (the specification's
// Appendix B) with KHR_materials_transmission: a GGX specular layer (D,
// height-correlated G2) over a base of the base colour for the dielectric
// part, whose Fresnel term is Schlick's with f0 = ((ior - 1) / (ior + 1))^2
// (0.04 at ior 1.5), mixed by `metallic` with a metal whose Schlick f0 is the
// base colour. The dielectric's base is Lambertian, or by the transmission
// factor t a thin-walled specular transmission (the extension without
// KHR_materials_volume): the GGX lobe mirrored through the surface, tinted
// by the base colour:
//   reflection:   f = (1 - m) [(1 - max3 F_d)(1 - t) base / pi + F_d S] + m F_m S,
//   transmission: f = (1 - m)(1 - max3 F_d) t base S(wo, wi'),  wi' = wi mirrored to wo's side,
// S = D G2 / (4 cos_o cos_i), both F at wo.h, h the half vector of wo and
// wi (wi'). The mirrored lobe keeps S's reciprocity: f(wo, wi) = f(wi, wo).
// KHR_materials_specular scales and tints F_d (metal_rough_dielectric_fresnel:
// params2, FEATURE_SPECULAR_TINT), which is why the base takes 1 - max3 F_d.
// With KHR_materials_volume (FEATURE_VOLUME; params.w negated) the
// transmission refracts instead, through the GGX microfacets into a volume
// of index ior (Walter et al. 2007):
//   transmission: f = (1 - m)(1 - max3 F_d) t base BTDF(wo, wi),
// F_d taken at the transmitted angle on the way out, 1 beyond the critical
// angle; the volume's absorption is the integrator's (volume_transmittance).
// KHR_materials_diffuse_transmission (FEATURE_DIFFUSE_TRANSMISSION) lets a
// fraction dt of the diffuse base through the surface, as a Lambertian lobe
// of its own colour dtColor on wi's other side (README.md:183-240 at
// 603619ef; a thin surface, whatever a volume behind it does):
//   reflection:   the base's term above times (1 - dt),
//   transmission: + (1 - m)(1 - max3 F_d)(1 - t) dt dtColor |cos_i| / pi,
// F_d at wo.h with h the half vector of wo and wi mirrored to wo's side, as
// the reflection takes it; KHR_materials_transmission's t takes its share
// first (README.md:338-357).
// KHR_materials_iridescence (FEATURE_IRIDESCENCE) lays a thin film
// over both surfaces: metal_rough_iridescence; KHR_materials_anisotropy
// (FEATURE_ANISOTROPY) stretches the specular layer's microfacets
// along a direction (metal_rough_specular_*); the refraction into a volume
// stays isotropic.
// color is the base colour, params at the hit: x alpha (roughness squared,
// at least GGX_MIN_ALPHA), y metallic, z ior, w transmission; params2 and
// extra as metal_rough_at, at the end of this file, resolves them from the
// material's factors and its textures. The specular layer and the transmission are sampled through the
// visible normals, the diffuse base by cosine, picked by their estimated
// reflectance at wo. Lobe functions as no_lobe.glsl describes them.
#ifndef WP_METAL_ROUGH_GLSL
#define WP_METAL_ROUGH_GLSL

// The dielectric layer's reflectance at normal incidence, from its ior.
float metal_rough_f0(Lobe l) {
  float r = (l.params.z - 1.0f) / (l.params.z + 1.0f);
  return r * r;
}

// The dielectric's Fresnel term at Schlick weight w (KHR_materials_specular):
// mix(f0, f90, w) with f0 = min(f0(ior) specularColor, 1) specular and
// f90 = specular. Without the extension (specular and its colour 1) it is
// Schlick's f0 + (1 - f0) w. params2 holds specularColor - 1 and
// specular - 1, so that a material without the extension has zeros there.
Spectrum metal_rough_dielectric_fresnel(Lobe l, float w) {
  float f0 = metal_rough_f0(l);
  if (!FEATURE_COMPILED(FEATURE_SPECULAR_TINT)) return Spectrum(f0 + (1.0f - f0) * w);
  float specular = 1.0f + l.params2.w;
  Spectrum tint = lobe_spectrum(l, vec3(l.params2.x, l.params2.y, l.params2.z), LOBE_FOURTH_PARAMS2) + Spectrum(1.0f);
  Spectrum tinted = min(f0 * tint, Spectrum(1.0f)) * specular;
  return tinted + (Spectrum(specular) - tinted) * w;
}

// A thin film over the dielectric's and the metal's surfaces
// (KHR_materials_iridescence, extra[MR_LOBE_FILM]: factor, ior, thickness): each Fresnel
// term mixed by the factor with the film's reflectance over it at c = wo.h
// (README.md:124-245 at acfcbe6; the specification leaves the angle open,
// and wo.h is where the microfacet model takes its Fresnel terms).
void metal_rough_iridescence(Lobe l, float c, INOUT(Spectrum) fd, INOUT(Spectrum) fm) {
  if (!FEATURE_COMPILED(FEATURE_IRIDESCENCE) || !(l.extra[MR_LOBE_FILM].x > 0.0f)) return;
  vec4 film = l.extra[MR_LOBE_FILM];
  Spectrum filmD = thin_film_fresnel(film.y, film.z, metal_rough_dielectric_fresnel(l, 0.0f), c, film.w);
  Spectrum filmM = thin_film_fresnel(film.y, film.z, l.color, c, film.w);
  fd = fd + (filmD - fd) * l.extra[MR_LOBE_FILM].x;
  fm = fm + (filmM - fm) * l.extra[MR_LOBE_FILM].x;
}

// Whether the transmission refracts into a volume (KHR_materials_volume),
// which bsdf_at says by storing it negated; its magnitude is the factor.
bool metal_rough_refracts(Lobe l) {
  return FEATURE_COMPILED(FEATURE_VOLUME) && l.params.w < 0.0f;
}

float metal_rough_transmission(Lobe l) {
  return abs(l.params.w);
}

// The ratio of indices, wi's side over wo's, where wi refracts (the
// volume's inside is the back side).
float metal_rough_eta(Lobe l) {
  return l.front ? l.params.z : 1.0f / l.params.z;
}

// Schlick's weight of the dielectric's Fresnel term at c = wo.h. Leaving a
// volume it is taken at the transmitted angle, and is 1 beyond the critical
// angle (KHR_materials_volume's README.md:206-218 at acfcbe6).
float metal_rough_fresnel_weight(Lobe l, float c) {
  if (metal_rough_refracts(l) && !l.front) {
    float sin2 = l.params.z * l.params.z * max(1.0f - c * c, 0.0f);
    return sin2 >= 1.0f ? 1.0f : schlick_weight(sqrt(1.0f - sin2));
  }
  return schlick_weight(c);
}

// The microfacet normal that refracts wo into wi (facing ns), or a zero
// vector where none does.
vec3 metal_rough_refraction_normal(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  vec3 h = wo + wi * metal_rough_eta(l);
  float len = length(h);
  if (!(len > 0.0f)) return vec3(0.0f);
  h = h / len;
  if (dot(h, ns) < 0.0f) h = -h;
  return dot(wo, h) > 0.0f && dot(wi, h) < 0.0f ? h : vec3(0.0f);
}

// The specular layer's microfacets: isotropic GGX of width alpha
// (params.x), or with KHR_materials_anisotropy (FEATURE_ANISOTROPY)
// alpha_t (extra[MR_LOBE_ANISOTROPY].w) along the direction in its xyz and alpha across it
// (README.md:90-105 at acfcbe6). Its reflection term S |cos_i|, the density
// of its samples and a sample, as ggx_reflection_* give them.
bool metal_rough_anisotropic(Lobe l) {
  return FEATURE_COMPILED(FEATURE_ANISOTROPY) && l.extra[MR_LOBE_ANISOTROPY].w > 0.0f;
}

// w in the frame of the anisotropy's direction t, cross(ns, t) and ns.
vec3 metal_rough_local(Lobe l, vec3 ns, vec3 w) {
  vec3 t = vec3(l.extra[MR_LOBE_ANISOTROPY].x, l.extra[MR_LOBE_ANISOTROPY].y, l.extra[MR_LOBE_ANISOTROPY].z);
  return vec3(dot(w, t), dot(w, cross(ns, t)), dot(w, ns));
}

// The anisotropic lobe at (wo, wi): x its reflection term S |cos_i|
// (D G2 / 4 cos_o), y the density of its visible-normal samples
// (D G1(wo) / 4 cos_o); zero where either direction is below the surface.
vec2 metal_rough_anisotropic_terms(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  vec3 o = metal_rough_local(l, ns, wo);
  vec3 i = metal_rough_local(l, ns, wi);
  if (o.z <= 0.0f || i.z <= 0.0f) return vec2(0.0f);
  float at = l.extra[MR_LOBE_ANISOTROPY].w;
  float ab = l.params.x;
  float lambdaO = ggx_anisotropic_lambda(o, at, ab);
  float d = ggx_anisotropic_d(normalize(o + i), at, ab) / (4.0f * o.z);
  return vec2(d / (1.0f + lambdaO + ggx_anisotropic_lambda(i, at, ab)), d / (1.0f + lambdaO));
}

float metal_rough_specular_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  if (!metal_rough_anisotropic(l)) return ggx_reflection_eval(l.params.x, ns, wo, wi);
  return metal_rough_anisotropic_terms(l, ns, wo, wi).x;
}

float metal_rough_specular_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  if (!metal_rough_anisotropic(l)) return ggx_reflection_pdf(l.params.x, ns, wo, wi);
  return metal_rough_anisotropic_terms(l, ns, wo, wi).y;
}

vec3 metal_rough_specular_sample(Lobe l, vec3 ns, vec3 wo, vec2 u) {
  if (!metal_rough_anisotropic(l)) return ggx_reflection_sample(l.params.x, ns, wo, u);
  vec3 t = vec3(l.extra[MR_LOBE_ANISOTROPY].x, l.extra[MR_LOBE_ANISOTROPY].y, l.extra[MR_LOBE_ANISOTROPY].z);
  vec3 b = cross(ns, t);
  vec3 o = metal_rough_local(l, ns, wo);
  if (o.z <= 0.0f) return vec3(0.0f);
  vec3 hl = ggx_sample_visible_anisotropic(o, l.extra[MR_LOBE_ANISOTROPY].w, l.params.x, u);
  vec3 h = t * hl.x + b * hl.y + ns * hl.z;
  vec3 wi = reflect_about(wo, h);
  return hl.z > 0.0f && dot(wi, ns) > 0.0f ? wi : vec3(0.0f);
}

// The diffuse transmission at the hit: xyz its colour, w its factor dt (0
// where the feature is not compiled).
vec4 metal_rough_diffuse_transmission(Lobe l) {
  return FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION) ? l.extra[MR_LOBE_DIFFUSE_TRANSMISSION] : vec4(0.0f);
}

// The diffuse transmission's colour.
Spectrum metal_rough_diffuse_transmission_colour(Lobe l) {
  vec4 dt = metal_rough_diffuse_transmission(l);
  return lobe_spectrum(l, vec3(dt.x, dt.y, dt.z), LOBE_FOURTH_TRANSMISSION);
}

// The share of the diffuse base's samples sent through the surface: by the
// two lobes' mean colours.
float metal_rough_diffuse_transmitted_share(Lobe l) {
  float dt = metal_rough_diffuse_transmission(l).w;
  float through = dt * spectrum_sum(metal_rough_diffuse_transmission_colour(l));
  float back = (1.0f - dt) * spectrum_sum(l.color);
  return through + back > 0.0f ? through / (through + back) : dt;
}

// Probabilities of sampling the specular layer (x) and the transmission (y)
// rather than the diffuse base, by their estimated reflectance at wo. The
// Fresnel weight is the one eval takes (inside a volume, total internal
// reflection past the critical angle): with Schlick's at wo there, internal
// reflections were picked seldom and weighed up to ten times over, and
// light trapped in a glass ball piled up into fireflies.
vec2 metal_rough_probabilities(Lobe l, float cosO) {
  float metallic = l.params.y;
  float transmission = metal_rough_transmission(l);
  float fd = spectrum_max(metal_rough_dielectric_fresnel(l, metal_rough_fresnel_weight(l, cosO)));
  float specular = (1.0f - metallic) * fd + metallic;
  float base = (1.0f - metallic) * (1.0f - fd) * clamp(spectrum_average(l.color), 0.0f, 1.0f);
  if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) {
    // The diffuse base reflects (1 - dt) of the base colour and transmits dt of its own.
    float dt = metal_rough_diffuse_transmission(l).w;
    Spectrum mixed = l.color * (1.0f - dt) + metal_rough_diffuse_transmission_colour(l) * dt;
    float diffuse = (1.0f - metallic) * (1.0f - fd) * (1.0f - transmission) * clamp(spectrum_average(mixed), 0.0f, 1.0f);
    float all = specular + diffuse + base * transmission;
    if (!(all > 0.0f)) return vec2(1.0f, 0.0f);
    return vec2(specular, base * transmission) / all;
  }
  float total = specular + base;
  if (!(total > 0.0f)) return vec2(1.0f, 0.0f);
  return vec2(specular, base * transmission) / total;
}

// wi mirrored through the surface of normal ns.
vec3 metal_rough_mirrored(vec3 ns, vec3 wi) {
  return wi - ns * (2.0f * dot(wi, ns));
}

// The density of the diffuse transmission's samples at wi below the
// surface, where p are the lobe's probabilities (metal_rough_probabilities).
float metal_rough_diffuse_transmitted_pdf(Lobe l, vec2 p, vec3 ns, vec3 wo, vec3 wi) {
  if (!FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) return 0.0f;
  return (1.0f - p.x - p.y) * metal_rough_diffuse_transmitted_share(l) * lambertian_pdf(l, ns, wo, -wi);
}

// The diffuse transmission's term f |cos_i| at wi below the surface, where
// the base under the specular layer keeps `base` (1 - max3 F_d).
Spectrum metal_rough_diffuse_transmitted_under(Lobe l, float base, vec3 ns, vec3 wi) {
  float weight = (1.0f - l.params.y) * base * (1.0f - metal_rough_transmission(l)) * metal_rough_diffuse_transmission(l).w;
  return metal_rough_diffuse_transmission_colour(l) * (weight * max(-dot(wi, ns), 0.0f) * WP_INV_PI);
}

// The same where the caller has no F_d at wo and wi mirrored (the refraction branch).
Spectrum metal_rough_diffuse_transmitted(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  if (!(metal_rough_diffuse_transmission(l).w > 0.0f)) return Spectrum(0.0f);
  vec3 wr = metal_rough_mirrored(ns, wi);
  float c = dot(wo, normalize(wo + wr));
  Spectrum fd = metal_rough_dielectric_fresnel(l, metal_rough_fresnel_weight(l, c));
  Spectrum fm = Spectrum(0.0f);
  metal_rough_iridescence(l, c, fd, fm);
  return metal_rough_diffuse_transmitted_under(l, 1.0f - spectrum_max(fd), ns, wi);
}

float metal_rough_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  if (cosO <= 0.0f) return 0.0f;
  vec2 p = metal_rough_probabilities(l, cosO);
  if (dot(wi, ns) < 0.0f && metal_rough_refracts(l)) {
    vec3 h = metal_rough_refraction_normal(l, ns, wo, wi);
    if (h == vec3(0.0f)) return metal_rough_diffuse_transmitted_pdf(l, p, ns, wo, wi);
    float eta = metal_rough_eta(l);
    float denom = dot(wo, h) + eta * dot(wi, h);
    float pdf = p.y * ggx_visible_pdf(wo, h, ns, l.params.x) * eta * eta * abs(dot(wi, h)) / (denom * denom);
    if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) pdf += metal_rough_diffuse_transmitted_pdf(l, p, ns, wo, wi);
    return pdf;
  }
  if (dot(wi, ns) < 0.0f) {
    float pdf = p.y * metal_rough_specular_pdf(l, ns, wo, metal_rough_mirrored(ns, wi));
    if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) pdf += metal_rough_diffuse_transmitted_pdf(l, p, ns, wo, wi);
    return pdf;
  }
  float diffuse = 1.0f - p.x - p.y;
  if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) diffuse *= 1.0f - metal_rough_diffuse_transmitted_share(l);
  return p.x * metal_rough_specular_pdf(l, ns, wo, wi) + diffuse * lambertian_pdf(l, ns, wo, wi);
}

Spectrum metal_rough_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosI = dot(wi, ns);
  float cosO = dot(wo, ns);
  if (cosO <= 0.0f || cosI == 0.0f) return Spectrum(0.0f);
  float metallic = l.params.y;
  float transmission = metal_rough_transmission(l);
  if (cosI < 0.0f && metal_rough_refracts(l)) {
    // Walter et al.'s BTDF through the GGX microfacets, its (1 - F) the
    // base's weight under the specular layer; as rough_dielectric.glsl,
    // radiance is not scaled by eta^2 on crossing.
    vec3 h = metal_rough_refraction_normal(l, ns, wo, wi);
    if (h == vec3(0.0f)) return metal_rough_diffuse_transmitted(l, ns, wo, wi);
    float eta = metal_rough_eta(l);
    float woH = dot(wo, h);
    float wiH = dot(wi, h);
    Spectrum fd = metal_rough_dielectric_fresnel(l, metal_rough_fresnel_weight(l, woH));
    Spectrum fm = Spectrum(0.0f);
    metal_rough_iridescence(l, woH, fd, fm);
    float base = 1.0f - spectrum_max(fd);
    float denom = woH + eta * wiH;
    float btdf = ggx_d(h, ns, l.params.x) * ggx_g2(cosO, -cosI, l.params.x) * eta * eta * woH * abs(wiH) / (cosO * denom * denom);
    Spectrum f = l.color * ((1.0f - metallic) * base * transmission * btdf);
    if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) f += metal_rough_diffuse_transmitted(l, ns, wo, wi);
    return f;
  }
  vec3 wr = cosI > 0.0f ? wi : metal_rough_mirrored(ns, wi);
  float c = dot(wo, normalize(wo + wr));
  float w = schlick_weight(c);
  Spectrum fd = metal_rough_dielectric_fresnel(l, metal_rough_fresnel_weight(l, c));
  Spectrum fm = l.color + (Spectrum(1.0f) - l.color) * w;
  metal_rough_iridescence(l, c, fd, fm);
  float base = 1.0f - spectrum_max(fd);  // the base's weight under the specular layer
  float specular = metal_rough_specular_eval(l, ns, wo, wr);  // S |cos_i|
  if (cosI < 0.0f) {
    Spectrum f = l.color * ((1.0f - metallic) * base * transmission * specular);
    if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) f += metal_rough_diffuse_transmitted_under(l, base, ns, wi);
    return f;
  }
  float diffuse = 1.0f - transmission;
  if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) diffuse *= 1.0f - metal_rough_diffuse_transmission(l).w;
  Spectrum dielectric = l.color * (base * diffuse * cosI * WP_INV_PI) + fd * specular;
  return dielectric * (1.0f - metallic) + fm * (metallic * specular);
}

vec3 metal_rough_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec2 p = metal_rough_probabilities(l, dot(wo, ns));
  if (u.z < p.x) return metal_rough_specular_sample(l, ns, wo, vec2(u.x, u.y));
  if (u.z < p.x + p.y && metal_rough_refracts(l)) {
    vec3 h = ggx_visible_normal(l.params.x, ns, wo, vec2(u.x, u.y));
    if (dot(h, ns) <= 0.0f) return vec3(0.0f);
    float eta = metal_rough_eta(l);
    float woH = dot(wo, h);
    float sin2 = (1.0f - woH * woH) / (eta * eta);
    if (sin2 >= 1.0f) return vec3(0.0f);  // beyond the critical angle: nothing refracts
    vec3 wi = normalize(h * (woH / eta - sqrt(1.0f - sin2)) - wo / eta);
    return dot(wi, ns) < 0.0f ? wi : vec3(0.0f);
  }
  if (u.z < p.x + p.y) {
    vec3 wr = metal_rough_specular_sample(l, ns, wo, vec2(u.x, u.y));
    return wr == vec3(0.0f) ? wr : metal_rough_mirrored(ns, wr);
  }
  // The diffuse base: through the surface for its transmitted share.
  if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION) && u.z - p.x - p.y < (1.0f - p.x - p.y) * metal_rough_diffuse_transmitted_share(l))
    return metal_rough_mirrored(ns, lambertian_sample(l, ns, wo, u));
  return lambertian_sample(l, ns, wo, u);
}

WP_NO_DELTA_LOBE(metal_rough)

#endif  // WP_METAL_ROUGH_GLSL

// ---- The material at a hit: its record's factors and textures resolved into
// the lobe's parameters. material_at.glsl includes this file a second time,
// after textures.glsl, with WP_MATERIAL_AT_HIT defined, for this half. ----
#if defined(WP_MATERIAL_AT_HIT) && !defined(WP_METAL_ROUGH_AT_HIT)
#define WP_METAL_ROUGH_AT_HIT

// The record (Material; metal_rough.cpp packs it):
//   params: x roughness, y metallic, z ior, w transmission; info.y the base
//     colour, info.w the metallic-roughness texture (G roughness, B
//     metallic), children.y the transmission texture (R);
//   params2: the specular colour less 1 (xyz) and the specular factor less 1
//     (w), so that zeros are glTF's default (KHR_materials_specular);
//   extra[MR_TEXTURES]: the textures of x the specular factor (A, as grey in
//     R), y the specular colour, z the film's factor (R), w its thickness (G);
//   extra[MR_VOLUME]: xyz the absorption coefficient inside, w 0 where
//     thin-walled, else 1 + the dispersion (20 / Abbe number);
//   extra[MR_IRIDESCENCE]: the film's factor, ior, and thickness (nm) where
//     its texture is 0 and 1;
//   extra[MR_ANISOTROPY]: strength, the cosine and sine of the direction's
//     rotation from the tangent, its texture (uint bits);
//   extra[MR_DIFFUSE_TRANSMISSION]: xyz the diffuse transmission's colour,
//     w its factor; extra[MR_DIFFUSE_TRANSMISSION_TEXTURES]: x the factor's
//     texture (R: glTF's alpha, as grey), y the colour's.
// A texture slot holds WP_INVALID where the material has none.

// The anisotropy of metal-rough m at s (KHR_materials_anisotropy,
// README.md:82-181 at acfcbe6): its texture's red and green give a direction
// in the tangent frame (2 c - 1; the tangent without a texture) and its blue
// scales the strength; the direction turns by the material's rotation, and
// alpha_t = mix(alpha, 1, strength^2) along it (alpha across it). Returns the
// direction made orthogonal to the shading normal ns, and alpha_t; zero
// (isotropic) where the surface has no tangent.
vec4 metal_rough_anisotropy_at(Material m, SurfaceHit s, vec3 ns, float alpha) {
  vec4 a = m.extra[MR_ANISOTROPY];
  float strength = a.x;
  vec2 d = vec2(1.0f, 0.0f);
  uint tex = floatBitsToUint(a.w);
  if (tex != WP_INVALID) {
    vec3 c = texture_eval(tex, s.uv, s.p);
    d = vec2(2.0f * c.x - 1.0f, 2.0f * c.y - 1.0f);
    strength *= c.z;
    float len = length(d);
    d = len > 0.0f ? d / len : vec2(1.0f, 0.0f);
  }
  vec2 r = vec2(a.y * d.x - a.z * d.y, a.z * d.x + a.y * d.y);
  vec3 t = vec3(s.tangent.x, s.tangent.y, s.tangent.z);
  t -= s.ns * dot(s.ns, t);
  float tl = length(t);
  if (!(tl > 0.0f) || !(strength > 0.0f)) return vec4(0.0f);
  t /= tl;
  vec3 dir = t * r.x + cross(s.ns, t) * (s.tangent.w * r.y);
  dir -= ns * dot(ns, dir);
  float dl = length(dir);
  if (!(dl > 0.0f)) return vec4(0.0f);
  dir /= dl;
  strength = clamp(strength, 0.0f, 1.0f);
  return vec4(dir.x, dir.y, dir.z, alpha + (1.0f - alpha) * strength * strength);
}

// Texture `tex` of m's extensions at s (stored as bits), which scales
// `value`: by its red where `red`, else by its colour. (An if, not a
// select: both sides of a select run.)
vec3 metal_rough_scaled(float tex, SurfaceHit s, vec3 value, bool red) {
  uint t = floatBitsToUint(tex);
  if (t != WP_INVALID) {
    vec3 c = texture_eval(t, s.uv, s.p);
    value *= red ? vec3(c.x) : c;
  }
  return value;
}

// The lobe's parameters of metal-rough m at s (shading normal ns), its
// factors scaled by their textures; and its dispersion (0: none).
void metal_rough_at(INOUT(Lobe) l, OUT(float) dispersion, Material m, SurfaceHit s, vec3 ns) {
  vec3 mr = m.info.w != WP_INVALID ? texture_eval(m.info.w, s.uv, s.p) : vec3(1.0f);
  float roughness = clamp(m.params.x * mr.y, 0.0f, 1.0f);
  float transmission = m.children.y != WP_INVALID ? m.params.w * texture_eval(m.children.y, s.uv, s.p).x : m.params.w;
  l.params = vec4(max(roughness * roughness, GGX_MIN_ALPHA), clamp(m.params.y * mr.z, 0.0f, 1.0f), max(m.params.z, METAL_ROUGH_MIN_IOR),
                  clamp(transmission, 0.0f, 1.0f));
  vec4 volume = m.extra[MR_VOLUME];
  // A transmission that refracts into a volume is stored negated (metal_rough_refracts).
  if (FEATURE_COMPILED(FEATURE_VOLUME) && volume.w > 0.0f) l.params.w = -l.params.w;
  if (FEATURE_COMPILED(FEATURE_SPECULAR_TINT)) {
    vec4 textures = m.extra[MR_TEXTURES];
    float weight = metal_rough_scaled(textures.x, s, vec3(1.0f + m.params2.w), true).x;
    vec3 tint = metal_rough_scaled(textures.y, s, vec3(1.0f + m.params2.x, 1.0f + m.params2.y, 1.0f + m.params2.z), false);
    l.params2 = vec4(tint.x - 1.0f, tint.y - 1.0f, tint.z - 1.0f, clamp(weight, 0.0f, 1.0f) - 1.0f);
  }
  vec4 film = m.extra[MR_IRIDESCENCE];
  if (FEATURE_COMPILED(FEATURE_IRIDESCENCE) && film.x > 0.0f) {
    // The film's factor (times its texture's red) and thickness (between
    // its two bounds by its texture's green; the upper without one).
    vec4 textures = m.extra[MR_TEXTURES];
    float factor = metal_rough_scaled(textures.z, s, vec3(film.x), true).x;
    float along = 1.0f;
    if (floatBitsToUint(textures.w) != WP_INVALID) along = texture_eval(floatBitsToUint(textures.w), s.uv, s.p).y;
    l.extra[MR_LOBE_FILM] = vec4(clamp(factor, 0.0f, 1.0f), film.y, film.z + (film.w - film.z) * along, 0.0f);
  }
  if (FEATURE_COMPILED(FEATURE_ANISOTROPY) && m.extra[MR_ANISOTROPY].x > 0.0f)
    l.extra[MR_LOBE_ANISOTROPY] = metal_rough_anisotropy_at(m, s, ns, l.params.x);
  vec4 dt = m.extra[MR_DIFFUSE_TRANSMISSION];
  if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION) && dt.w > 0.0f) {
    vec4 textures = m.extra[MR_DIFFUSE_TRANSMISSION_TEXTURES];
    float factor = metal_rough_scaled(textures.x, s, vec3(dt.w), true).x;
    vec3 color = metal_rough_scaled(textures.y, s, vec3(dt.x, dt.y, dt.z), false);
    l.extra[MR_LOBE_DIFFUSE_TRANSMISSION] = vec4(color.x, color.y, color.z, clamp(factor, 0.0f, 1.0f));
  }
  dispersion = volume.w > 1.0f ? volume.w - 1.0f : 0.0f;
}

#endif  // WP_METAL_ROUGH_AT_HIT
