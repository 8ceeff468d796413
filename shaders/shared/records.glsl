// records.glsl — the scene's records, decoded from the RGBA32UI texels they
// are read through (bindings.glsl), field by field as the structs in
// types.glsl lay them out (the walks' nodes and primitives through walk_node_texel
// and its kin: a texel fetch, or a storage-buffer load); on the host the same
// code reads the uploaded arrays through texelFetch on plain pointers. Unused
// fields cost nothing: a texel fetch whose result is not used is removed by
// the compiler.
#ifndef WP_RECORDS_GLSL
#define WP_RECORDS_GLSL

vec3 texel_xyz(uvec4 t) {
  return vec3(uintBitsToFloat(t.x), uintBitsToFloat(t.y), uintBitsToFloat(t.z));
}

BvhNode load_node(uint i) {
  int at = int(i) * BVH_NODE_TEXELS;
  uvec4 a = walk_node_texel(at);
  uvec4 b = walk_node_texel(at + 1);
  BvhNode n;
  n.bmin = texel_xyz(a);
  n.leftFirst = a.w;
  n.bmax = texel_xyz(b);
  n.count = b.w;
  return n;
}

WideNode load_wide_node(uint i) {
  int at = int(i) * WIDE_NODE_TEXELS;
  uvec4 a = walk_wide_node_texel(at);
  uvec4 b = walk_wide_node_texel(at + 1);
  WideNode n;
  n.origin = texel_xyz(a);
  n.exyzImask = a.w;
  n.childBase = b.x;
  n.primBase = b.y;
  n.meta0123 = b.z;
  n.meta4567 = b.w;
  n.qlo = walk_wide_node_texel(at + 2);
  n.qloZqhiX = walk_wide_node_texel(at + 3);
  n.qhi = walk_wide_node_texel(at + 4);
  return n;
}

Triangle load_triangle(uint i) {
  int at = int(i) * TRIANGLE_TEXELS;
  uvec4 a = walk_triangle_texel(at);
  uvec4 b = walk_triangle_texel(at + 1);
  uvec4 c = walk_triangle_texel(at + 2);
  Triangle t;
  t.v0 = texel_xyz(a);
  t.material = a.w;
  t.v1 = texel_xyz(b);
  t.emitter = b.w;
  t.v2 = texel_xyz(c);
  t.shading = c.w;
  return t;
}

TriangleShading load_shading(uint i) {
  int at = int(i) * TRIANGLE_SHADING_TEXELS;
  uvec4 a = texelFetch(shadingTexels, at);
  uvec4 b = texelFetch(shadingTexels, at + 1);
  uvec4 c = texelFetch(shadingTexels, at + 2);
  uvec4 d = texelFetch(shadingTexels, at + 3);
  TriangleShading sh;
  sh.n0 = texel_xyz(a);
  sh.u0 = uintBitsToFloat(a.w);
  sh.n1 = texel_xyz(b);
  sh.v0 = uintBitsToFloat(b.w);
  sh.n2 = texel_xyz(c);
  sh.flags = c.w;
  sh.uv12 = vec4(uintBitsToFloat(d.x), uintBitsToFloat(d.y), uintBitsToFloat(d.z), uintBitsToFloat(d.w));
  return sh;
}

vec4 texel_vec4(uvec4 t) {
  return vec4(uintBitsToFloat(t.x), uintBitsToFloat(t.y), uintBitsToFloat(t.z), uintBitsToFloat(t.w));
}

TriangleVertexData load_vertex_data(uint i) {
  int at = int(i) * TRIANGLE_VERTEX_DATA_TEXELS;
  TriangleVertexData vd;
  vd.tangent0 = texel_vec4(texelFetch(vertexDataTexels, at));
  vd.tangent1 = texel_vec4(texelFetch(vertexDataTexels, at + 1));
  vd.tangent2 = texel_vec4(texelFetch(vertexDataTexels, at + 2));
  vd.color0 = texel_vec4(texelFetch(vertexDataTexels, at + 3));
  vd.color1 = texel_vec4(texelFetch(vertexDataTexels, at + 4));
  vd.color2 = texel_vec4(texelFetch(vertexDataTexels, at + 5));
  vd.uv1_01 = texel_vec4(texelFetch(vertexDataTexels, at + 6));
  vd.uv1_2 = texel_vec4(texelFetch(vertexDataTexels, at + 7));
  return vd;
}

Instance load_instance(uint i) {
  int at = int(i) * INSTANCE_TEXELS;
  Instance inst;
  inst.toWorld0 = texel_vec4(texelFetch(instanceTexels, at));
  inst.toWorld1 = texel_vec4(texelFetch(instanceTexels, at + 1));
  inst.toWorld2 = texel_vec4(texelFetch(instanceTexels, at + 2));
  inst.toObject0 = texel_vec4(texelFetch(instanceTexels, at + 3));
  inst.toObject1 = texel_vec4(texelFetch(instanceTexels, at + 4));
  inst.toObject2 = texel_vec4(texelFetch(instanceTexels, at + 5));
  uvec4 g = texelFetch(instanceTexels, at + 6);
  inst.root = g.x;
  inst.flags = g.y;
  inst.mesh = g.z;
  inst.pad = g.w;
  return inst;
}

Sphere load_sphere(uint i) {
  int at = int(i) * SPHERE_TEXELS;
  Sphere sp;
  sp.toWorld0 = texel_vec4(texelFetch(sphereTexels, at));
  sp.toWorld1 = texel_vec4(texelFetch(sphereTexels, at + 1));
  sp.toWorld2 = texel_vec4(texelFetch(sphereTexels, at + 2));
  sp.toObject0 = texel_vec4(texelFetch(sphereTexels, at + 3));
  sp.toObject1 = texel_vec4(texelFetch(sphereTexels, at + 4));
  sp.toObject2 = texel_vec4(texelFetch(sphereTexels, at + 5));
  uvec4 g = texelFetch(sphereTexels, at + 6);
  sp.material = g.x;
  sp.emitter = g.y;
  sp.area = uintBitsToFloat(g.z);
  sp.pad = g.w;
  return sp;
}

// Whether a compiled feature reads slot `slot` of Material.extra (the
// features' table, kinds.glsl). The CPU reference compiles every feature
// and reads every slot.
bool material_extra_compiled(uint slot) {
#ifdef __cplusplus
  return true;
#else
  return (FEATURES_OF_SCENE & (0u WP_FEATURES(WP_READS_MATERIAL_EXTRA))) != 0u;
#endif
}

Material load_material(uint i) {
  int at = int(i) * MATERIAL_TEXELS;
  Material m;
  m.info = texelFetch(materialTexels, at);
  m.children = texelFetch(materialTexels, at + 1);
  m.params = texel_vec4(texelFetch(materialTexels, at + 2));
  m.params2 = MATERIAL_PARAMS2_COMPILED ? texel_vec4(texelFetch(materialTexels, at + 3)) : vec4(0.0f);
  for (uint k = 0u; k < uint(MATERIAL_EXTRA_SLOTS); ++k)
    m.extra[k] = material_extra_compiled(k) ? texel_vec4(texelFetch(materialTexels, at + 4 + int(k))) : vec4(0.0f);
  m.media = FEATURE_COMPILED(FEATURE_MEDIA) ? texelFetch(materialTexels, at + MATERIAL_MEDIA_TEXEL) : uvec4(WP_INVALID);
  return m;
}

// The material whose surface a layer (clearcoat, sheen) covers: its base,
// followed down through at most LAYERS_MAX layers; any other material is
// its own. The surface's alpha (its albedo texture's) and normal map are
// this material's.
Material surface_material(Material m) {
  uint layers = LAYER_MATERIALS_COMPILED ? (0u WP_MATERIAL_KINDS(WP_IS_LAYER)) : 0u;
  for (uint k = 0u; k < LAYERS_MAX; ++k) {
    if (LAYER_MATERIALS_COMPILED && m.info.x < 32u && (KIND_BIT(m.info.x) & layers) != 0u) m = load_material(m.children.x);
  }
  return m;
}

Texture load_texture(uint i) {
  int at = int(i) * TEXTURE_TEXELS;
  Texture t;
  t.info = texelFetch(textureTexels, at);
  t.color0 = texel_vec4(texelFetch(textureTexels, at + 1));
  t.color1 = texel_vec4(texelFetch(textureTexels, at + 2));
  t.map0 = texel_vec4(texelFetch(textureTexels, at + 3));
  t.map1 = texel_vec4(texelFetch(textureTexels, at + 4));
  t.map2 = texel_vec4(texelFetch(textureTexels, at + 5));
  return t;
}

Photon load_photon(uint i) {
  int at = int(i) * PHOTON_TEXELS;
  uvec4 a = texelFetch(photonTexels, at);
  uvec4 b = texelFetch(photonTexels, at + 1);
  Photon ph;
  ph.position = vec3(uintBitsToFloat(a.x), uintBitsToFloat(a.y), uintBitsToFloat(a.z));
  ph.axis = a.w;
  ph.power = vec3(uintBitsToFloat(b.x), uintBitsToFloat(b.y), uintBitsToFloat(b.z));
  ph.from = b.w;
  return ph;
}

PointLight load_point_light(uint i) {
  int at = int(i) * POINT_LIGHT_TEXELS;
  PointLight l;
  l.position = texel_vec4(texelFetch(pointLightTexels, at));
  l.intensity = texel_vec4(texelFetch(pointLightTexels, at + 1));
  l.direction = ANY_LIGHT_COMPILED(LIGHTS_READING_DIRECTION) ? texel_vec4(texelFetch(pointLightTexels, at + 2)) : vec4(0.0f);
  return l;
}

Emitter load_emitter(uint i) {
  uvec4 t = texelFetch(emitterTexels, int(i) * EMITTER_TEXELS);
  Emitter e;
  e.prim = t.x;
  e.alias = t.y;
  e.threshold = uintBitsToFloat(t.z);
  e.pmf = uintBitsToFloat(t.w);
  return e;
}

// Entry i of the environment map's sampling distribution.
float cdf_at(uint i) {
  return texelFetch(floatTables, FLOAT_TABLE_ENVIRONMENT + int(i)).x;
}

#endif  // WP_RECORDS_GLSL
