// textures.glsl — texture lookups at a surface point, for every texture kind
// (kinds.glsl): constant, checker (nested), marble, image.
#ifndef WP_TEXTURES_GLSL
#define WP_TEXTURES_GLSL

// Where texture t is looked up: its mapping applied to the hit point (solid
// textures) or to the UV set it reads, (u, v, 0).
vec3 texture_point(Texture t, vec4 uv, vec3 p) {
  vec2 set = (t.info.x & TEX_UV1) != 0u ? vec2(uv.z, uv.w) : vec2(uv.x, uv.y);
  vec3 q = (t.info.x & TEX_SOLID) != 0u ? p : vec3(set.x, set.y, 0.0f);
  return xform_point(t.map0, t.map1, t.map2, q);
}

vec4 texel_at(Texture t, uint x, uint y) {
  uvec4 packed = texelFetch(imageTexels, int(t.info.y + y * t.info.z + x));
  vec2 rg = unpackHalf2x16(packed.x);
  vec2 ba = unpackHalf2x16(packed.y);
  return vec4(rg.x, rg.y, ba.x, ba.y);
}

// The two texels (i0, i1) along one axis of `size` texels between which
// coordinate c (0 to 1 across the image) falls, and the weight f of i1, as
// wrap mode `mode` extends the image beyond [0, 1].
void wrap_texels(float c, uint mode, uint size, OUT(uint) i0, OUT(uint) i1, OUT(float) f) {
  float m = c - floor(c);  // repeat
  if (mode == TEX_WRAP_CLAMP) m = clamp(c, 0.0f, 1.0f);
  if (mode == TEX_WRAP_MIRROR) {
    float r = c - 2.0f * floor(0.5f * c);  // [0, 2)
    m = r <= 1.0f ? r : 2.0f - r;
  }
  float x = m * float(size) - 0.5f;
  float x0f = floor(x);
  f = x - x0f;
  // x0f lies in [-1, size - 1]: wrap without a (GLSL-undefined) negative modulo.
  bool repeat = mode == TEX_WRAP_REPEAT;
  i0 = x0f < 0.0f ? (repeat ? size - 1u : 0u) : min(uint(x0f), size - 1u);
  i1 = i0 + 1u < size ? i0 + 1u : (repeat ? 0u : size - 1u);
  if (x0f < 0.0f && !repeat) i1 = 0u;
}

// Bilinear lookup, RGBA; v = 0 is the bottom row of the image.
vec4 image_lookup(Texture t, vec3 q) {
  uint x0;
  uint x1;
  uint y0;
  uint y1;
  float fx;
  float fy;
  wrap_texels(q.x, (t.info.x >> TEX_WRAP_U_SHIFT) & 3u, t.info.z, x0, x1, fx);
  wrap_texels(1.0f - q.y, (t.info.x >> TEX_WRAP_V_SHIFT) & 3u, t.info.w, y0, y1, fy);
  vec4 top = mix(texel_at(t, x0, y0), texel_at(t, x1, y0), fx);
  vec4 bottom = mix(texel_at(t, x0, y1), texel_at(t, x1, y1), fx);
  return mix(top, bottom, fy);
}

// Colour of texture `index` at a surface point. Reads only the fields a
// texture's type needs: on lavapipe every 16 bytes loaded costs more than the
// arithmetic around them, and most textures are constants. A constant is what
// every lookup ends in, so it is never compiled out; a fresnel texture is a
// blend's amount, which material_at.glsl computes, never looked up here.
vec3 texture_eval(uint index, vec4 uv, vec3 p) {
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
    vec4 c = image_lookup(t, texture_point(t, uv, p));
    return vec3(c.x, c.y, c.z) * vec3(t.color0.x, t.color0.y, t.color0.z);
  }
  vec4 c = load_texture(index).color0;
  return vec3(c.x, c.y, c.z);
}

// Opacity of texture `index` at a surface point (glTF's alpha): a constant's
// color0.w, an image's alpha times it; other kinds are opaque.
float texture_alpha(uint index, vec4 uv, vec3 p) {
  Texture t = load_texture(index);
  uint type = t.info.x & TEX_TYPE_MASK;
  if (TEXTURE_COMPILED(TEX_IMAGE) && type == TEX_IMAGE) return image_lookup(t, texture_point(t, uv, p)).w * t.color0.w;
  return type == TEX_CONSTANT ? t.color0.w : 1.0f;
}

// The alpha below which a cut-out material (TRIANGLE_CUTOUT) is not there;
// negative for stochastic transparency.
float material_alpha_cutoff(Material m) {
  return uintBitsToFloat(m.children.x);
}

#endif  // WP_TEXTURES_GLSL
