// textures.glsl — texture lookups at a surface point, for every texture kind
// (kinds.glsl): constant, checker (nested), marble, image.
#ifndef WP_TEXTURES_GLSL
#define WP_TEXTURES_GLSL

// Where texture t is looked up: its mapping applied to the hit point (solid
// textures) or to (u, v, 0).
vec3 texture_point(Texture t, vec2 uv, vec3 p) {
  vec3 q = (t.info.x & TEX_SOLID) != 0u ? p : vec3(uv.x, uv.y, 0.0f);
  return xform_point(t.map0, t.map1, t.map2, q);
}

vec3 texel_at(Texture t, uint x, uint y) {
  uvec4 packed = texelFetch(imageTexels, int(t.info.y + y * t.info.z + x));
  vec2 rg = unpackHalf2x16(packed.x);
  vec2 b = unpackHalf2x16(packed.y);
  return vec3(rg.x, rg.y, b.x);
}

// Bilinear lookup, repeating; v = 0 is the bottom row of the image.
vec3 image_lookup(Texture t, vec3 q) {
  uint w = t.info.z;
  uint h = t.info.w;
  float x = (q.x - floor(q.x)) * float(w) - 0.5f;
  float y = (1.0f - (q.y - floor(q.y))) * float(h) - 0.5f;
  float x0f = floor(x);
  float y0f = floor(y);
  float fx = x - x0f;
  float fy = y - y0f;
  // x0f lies in [-1, w - 1]: wrap without a (GLSL-undefined) negative modulo.
  uint x0 = x0f < 0.0f ? w - 1u : min(uint(x0f), w - 1u);
  uint y0 = y0f < 0.0f ? h - 1u : min(uint(y0f), h - 1u);
  uint x1 = x0 + 1u >= w ? 0u : x0 + 1u;
  uint y1 = y0 + 1u >= h ? 0u : y0 + 1u;
  vec3 top = mix(texel_at(t, x0, y0), texel_at(t, x1, y0), fx);
  vec3 bottom = mix(texel_at(t, x0, y1), texel_at(t, x1, y1), fx);
  return mix(top, bottom, fy);
}

// Colour of texture `index` at a surface point. Reads only the fields a
// texture's type needs: on lavapipe every 16 bytes loaded costs more than the
// arithmetic around them, and most textures are constants. A constant is what
// every lookup ends in, so it is never compiled out; a fresnel texture is a
// blend's amount, which material_at.glsl computes, never looked up here.
vec3 texture_eval(uint index, vec2 uv, vec3 p) {
  uvec4 info = load_texture(index).info;
  // A checker picks one of two textures; follow the picks (the loader bounds the nesting).
  for (uint depth = 0u; TEXTURE_COMPILED(TEX_CHECKER) && depth < TEXTURE_MAX_NESTING && (info.x & TEX_TYPE_MASK) == TEX_CHECKER; ++depth) {
    Texture t = load_texture(index);
    vec3 c = floor(texture_point(t, uv, p) * t.color0.w);
    int parity = (int(c.x) + int(c.y) + int(c.z)) & 1;
    index = parity == 0 ? info.y : info.z;
    info = load_texture(index).info;
  }
  uint type = info.x & TEX_TYPE_MASK;
  if (TEXTURE_COMPILED(TEX_MARBLE) && type == TEX_MARBLE) {
    Texture t = load_texture(index);
    float m = marble_pattern(texture_point(t, uv, p) * t.color0.w);
    return mix(vec3(t.color0.x, t.color0.y, t.color0.z), vec3(t.color1.x, t.color1.y, t.color1.z), m);
  }
  if (TEXTURE_COMPILED(TEX_IMAGE) && type == TEX_IMAGE) {
    Texture t = load_texture(index);
    return image_lookup(t, texture_point(t, uv, p)) * vec3(t.color0.x, t.color0.y, t.color0.z);
  }
  vec4 c = load_texture(index).color0;
  return vec3(c.x, c.y, c.z);
}

#endif  // WP_TEXTURES_GLSL
