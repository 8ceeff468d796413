// media.glsl — participating media (FEATURE_MEDIA): the medium records, the
// media a surface bounds, free-flight sampling, transmittance and the phase
// function. The integrator (integrator.glsl) calls these between a ray's
// trace and its surface: the wavefront kernels, the megakernel and the CPU
// reference share every line.
//
// Conventions (pbrt-v4's and Mitsuba 3's): a path carries the medium its ray
// travels in (PathState.medium; the camera's from SceneParams.media.x). A
// surface whose material holds media (Material.media) bounds them: a ray
// leaving it against its geometric normal enters the inside one, along it
// the outside one; a surface without them leaves a ray in its medium. An
// interface material (MAT_INTERFACE) has no surface at all: rays pass it
// without scattering and without counting a bounce.
//
// Chromatic coefficients: collisions are sampled against one majorant for
// all of a path's channels (Medium.sigmaS.w), and each collision is absorbed,
// scattered or null with probabilities proportional to the coefficients
// weighted by the path's throughput (Kutz et al. 2017, "Spectral and
// Decomposition Tracking for Rendering Heterogeneous Volumes", spectral
// tracking), whose weights keep the throughput bounded. Null collisions
// come from the channels below the majorant and from fictitious particles
// (darts' "real fraction" below 1).
#ifndef WP_MEDIA_GLSL
#define WP_MEDIA_GLSL

#ifndef __cplusplus
#include "pnanovdb.glsl"  // C++: at namespace scope (shader_cpp.h)
#endif

// What a free flight met (medium_free_flight).
#define MEDIUM_EVENT_SURFACE 0u  // the end of the segment: its surface, or nothing
#define MEDIUM_EVENT_SCATTER 1u  // a real scattering collision inside the medium
#define MEDIUM_EVENT_ABSORB 2u   // absorbed: the path ends

Medium load_medium(uint i) {
  int at = int(i) * MEDIUM_TEXELS;
  Medium m;
  m.info = texelFetch(mediumTexels, at);
  m.sigmaA = texel_vec4(texelFetch(mediumTexels, at + 1));
  m.sigmaS = texel_vec4(texelFetch(mediumTexels, at + 2));
  m.sigmaN = texel_vec4(texelFetch(mediumTexels, at + 3));
  m.toIndex0 = texel_vec4(texelFetch(mediumTexels, at + 4));
  m.toIndex1 = texel_vec4(texelFetch(mediumTexels, at + 5));
  m.toIndex2 = texel_vec4(texelFetch(mediumTexels, at + 6));
  m.boundsLo = texel_vec4(texelFetch(mediumTexels, at + 7));
  m.boundsHi = texel_vec4(texelFetch(mediumTexels, at + 8));
  return m;
}

// A medium's coefficients in a path's colours: as its record gives them in
// RGB, at the path's wavelengths in the spectral mode (spectral.glsl).
struct MediumCoefficients {
  Spectrum sigmaA;  // (a grid's: per unit density)
  Spectrum sigmaS;
  Spectrum sigmaN;  // (homogeneous only)
};

// Medium m's coefficients at the wavelengths lambdas (unbounded spectra) in
// the spectral mode, and the majorant (Medium.sigmaS.w) raised where they
// exceed it; in RGB, as they are.
MediumCoefficients medium_coefficients(INOUT(Medium) m, vec4 lambdas) {
  MediumCoefficients c;
  vec3 sa = vec3(m.sigmaA.x, m.sigmaA.y, m.sigmaA.z);
  vec3 ss = vec3(m.sigmaS.x, m.sigmaS.y, m.sigmaS.z);
  vec3 sn = vec3(m.sigmaN.x, m.sigmaN.y, m.sigmaN.z);
  if (!spectral_mode() || m.info.x == MEDIUM_VACUUM) {
    c.sigmaA = spectrum_rgb(sa);
    c.sigmaS = spectrum_rgb(ss);
    c.sigmaN = spectrum_rgb(sn);
    return c;
  }
  c.sigmaA = unbounded_spectrum(sa, lambdas);
  c.sigmaS = unbounded_spectrum(ss, lambdas);
  c.sigmaN = unbounded_spectrum(sn, lambdas);
  // Homogeneous: at least sigma_a + sigma_s + sigma_n in each; a grid's:
  // at least sigma_a + sigma_s per unit density (media.glsl).
  Spectrum t = m.info.x == MEDIUM_HOMOGENEOUS ? c.sigmaA + c.sigmaS + c.sigmaN : c.sigmaA + c.sigmaS;
  m.sigmaS.w = max(m.sigmaS.w, spectrum_max(t));
  return c;
}

// Medium i as a path of wavelengths lambdas sees it, and its coefficients c.
Medium load_medium_at(uint i, vec4 lambdas, OUT(MediumCoefficients) c) {
  Medium m = load_medium(i);
  c = medium_coefficients(m, lambdas);
  return m;
}

// The media material `material` bounds: x inside, y outside (WP_INVALID:
// none, the surface is not a boundary).
uvec2 material_media(uint material) {
  uvec4 t = texelFetch(materialTexels, int(material) * MATERIAL_TEXELS + MATERIAL_MEDIA_TEXEL);
  return uvec2(t.x, t.y);
}

// The medium a ray in `current` is in after it leaves a surface of
// `material` and geometric normal ng in direction dir.
uint medium_beyond(uint current, uint material, vec3 ng, vec3 dir) {
  uvec2 m = material_media(material);
  if (m.x == WP_INVALID) return current;
  return dot(dir, ng) < 0.0f ? m.x : m.y;
}

bool is_interface(uint material) {
  return MATERIAL_COMPILED(MAT_INTERFACE) && load_material(material).info.x == MAT_INTERFACE;
}

// One tentative collision of a free flight against `majorant`, where the
// medium's coefficients are sa, ss and sn (the null coefficient: what the
// majorant leaves over). Picks the event with spectral tracking's
// probabilities and multiplies `throughput` by its weight: absorbed,
// scattered, or a null collision (MEDIUM_EVENT_SURFACE: the flight goes on).
uint medium_collision(Spectrum sa, Spectrum ss, Spectrum sn, float majorant, INOUT(uint) rng, INOUT(Spectrum) throughput) {
  float pa = spectrum_sum(sa * throughput);
  float ps = spectrum_sum(ss * throughput);
  float pn = spectrum_sum(sn * throughput);
  float c = pa + ps + pn;
  if (!(c > 0.0f)) return MEDIUM_EVENT_ABSORB;
  float u = rng_next(rng) * c;
  if (u < pa) return MEDIUM_EVENT_ABSORB;  // the medium emits nothing
  if (u < pa + ps) {
    throughput *= ss * (c / (majorant * ps));
    return MEDIUM_EVENT_SCATTER;
  }
  throughput *= sn * (c / (majorant * pn));
  return MEDIUM_EVENT_SURFACE;
}

// ---- Grid media (MEDIUM_NANOVDB) ---------------------------------------------
// The density at a point is NanoVDB's trilinear lookup (SampleFromVoxels of
// order 1, as darts' NanoVDBMedium::coeffs): voxel values sit at integer
// index coordinates, and a negative value counts as none. Flights and
// transmittance walk the majorant grid's cells along the ray in index space
// (a 3D DDA; the ray's parameter is the scene's distance in both spaces),
// sampling collisions against each cell's majorant.

// The value of voxel c, through accessor acc (which caches the path to the
// last leaf, so that the eight lookups of one point rarely start at the root).
float grid_voxel(INOUT(pnanovdb_readaccessor_t) acc, ivec3 c) {
  pnanovdb_coord_t ijk;
  ijk.x = c.x;
  ijk.y = c.y;
  ijk.z = c.z;
  pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, volume_buf(), PNANOVDB_REF(acc), PNANOVDB_REF(ijk));
  return pnanovdb_read_float(volume_buf(), a);
}

// The density at index-space point q. The eight corners are looked up in a
// loop, not unrolled: every lookup inlines the accessor's whole walk, and
// eight copies of it per call made the kernels slow to compile.
float grid_density(INOUT(pnanovdb_readaccessor_t) acc, vec3 q) {
  vec3 f = floor(q);
  ivec3 c = ivec3(f);
  vec3 w = q - f;
  float d = 0.0f;
  for (int k = 0; k < 8; ++k) {
    ivec3 o = ivec3(k & 1, (k >> 1) & 1, k >> 2);
    float weight = (o.x == 1 ? w.x : 1.0f - w.x) * (o.y == 1 ? w.y : 1.0f - w.y) * (o.z == 1 ? w.z : 1.0f - w.z);
    d += weight * grid_voxel(acc, c + o);
  }
  return max(d, 0.0f);
}

pnanovdb_readaccessor_t grid_accessor(Medium m) {
  pnanovdb_grid_handle_t grid;
  grid.address.byte_offset = m.info.y;
  pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(volume_buf(), grid);
  pnanovdb_root_handle_t root = pnanovdb_tree_get_root(volume_buf(), tree);
  pnanovdb_readaccessor_t acc;
  pnanovdb_readaccessor_init(PNANOVDB_REF(acc), root);
  return acc;
}

// A ray's walk through a grid medium's majorant cells, in index space.
struct MajorantWalk {
  vec3 o;       // the ray in index space: o + t d
  vec3 d;
  vec3 tNext;   // where the ray leaves the cell through each axis' next plane
  vec3 tDelta;  // the distance between two planes of an axis, along the ray
  ivec3 cell;
  ivec3 step;
  uvec3 cells;  // the majorant grid's cells along each axis
  float t;         // where the walk is
  float tEnd;      // where it leaves the grid's box, or the segment ends
  float majorant;  // of the cell it is in, per unit length
};

// Where the walk leaves its cell (or the box, or the segment).
float majorant_walk_cell_end(MajorantWalk w) {
  return min(min(min(w.tNext.x, w.tNext.y), w.tNext.z), w.tEnd);
}

// The majorant of the walk's cell, per unit length.
float majorant_walk_majorant(Medium m, MajorantWalk w) {
  uint cell = uint(w.cell.x) + w.cells.x * (uint(w.cell.y) + w.cells.y * uint(w.cell.z));
  return uintBitsToFloat(pnanovdb_buf_read_uint32(volume_buf(), (m.info.z + cell) * 4u)) * m.sigmaS.w;
}

// Starts the walk of the ray o + t dir, t in [0, tmax), through grid medium
// m; false where the ray misses the grid's box.
bool majorant_walk_begin(Medium m, vec3 o, vec3 dir, float tmax, OUT(MajorantWalk) w) {
  w.o = xform_point(m.toIndex0, m.toIndex1, m.toIndex2, o);
  w.d = xform_vector(m.toIndex0, m.toIndex1, m.toIndex2, dir);
  vec3 lo = vec3(m.boundsLo.x, m.boundsLo.y, m.boundsLo.z);
  vec3 hi = vec3(m.boundsHi.x, m.boundsHi.y, m.boundsHi.z);
  // The box's slabs; a zero direction component gives infinite distances,
  // and a NaN (an origin on a slab's plane) leaves that slab open.
  vec3 inv = vec3(1.0f) / w.d;
  vec3 t0 = (lo - w.o) * inv;
  vec3 t1 = (hi - w.o) * inv;
  vec3 tn = min(t0, t1);
  vec3 tf = max(t0, t1);
  float enter = max(max(max(tn.x, tn.y), tn.z), 0.0f);
  float leave = min(min(min(tf.x, tf.y), tf.z), tmax);
  if (!(enter < leave)) return false;
  w.t = enter;
  w.tEnd = leave;
  w.cells = uvec3(m.info.w & 1023u, (m.info.w >> 10u) & 1023u, (m.info.w >> 20u) & 1023u);
  vec3 size = (hi - lo) / vec3(w.cells);
  vec3 p = w.o + w.d * enter;
  w.cell = clamp(ivec3(floor((p - lo) / size)), ivec3(0), ivec3(w.cells) - ivec3(1));
  w.step = ivec3(w.d.x >= 0.0f ? 1 : -1, w.d.y >= 0.0f ? 1 : -1, w.d.z >= 0.0f ? 1 : -1);
  vec3 next = lo + (vec3(w.cell) + vec3(w.step.x > 0 ? 1.0f : 0.0f, w.step.y > 0 ? 1.0f : 0.0f, w.step.z > 0 ? 1.0f : 0.0f)) * size;
  w.tNext = vec3(w.d.x != 0.0f ? (next.x - w.o.x) * inv.x : WP_INF, w.d.y != 0.0f ? (next.y - w.o.y) * inv.y : WP_INF,
                 w.d.z != 0.0f ? (next.z - w.o.z) * inv.z : WP_INF);
  w.tDelta = vec3(w.d.x != 0.0f ? size.x * abs(inv.x) : WP_INF, w.d.y != 0.0f ? size.y * abs(inv.y) : WP_INF,
                  w.d.z != 0.0f ? size.z * abs(inv.z) : WP_INF);
  w.majorant = majorant_walk_majorant(m, w);
  return true;
}

// Moves the walk into the next cell; false where it has left the box.
bool majorant_walk_next(INOUT(MajorantWalk) w) {
  w.t = majorant_walk_cell_end(w);
  if (w.t >= w.tEnd) return false;
  if (w.tNext.x <= w.tNext.y && w.tNext.x <= w.tNext.z) {
    w.cell.x += w.step.x;
    w.tNext.x += w.tDelta.x;
  } else if (w.tNext.y <= w.tNext.z) {
    w.cell.y += w.step.y;
    w.tNext.y += w.tDelta.y;
  } else {
    w.cell.z += w.step.z;
    w.tNext.z += w.tDelta.z;
  }
  return w.cell.x >= 0 && w.cell.y >= 0 && w.cell.z >= 0 && uint(w.cell.x) < w.cells.x && uint(w.cell.y) < w.cells.y &&
         uint(w.cell.z) < w.cells.z;
}

// Moves the walk to its next tentative collision: an exponential step
// against the majorant of the cell it is in, restarted at the cell's end
// where it would leave the cell (which the exponential's lack of memory
// allows). False where the walk leaves the box first.
bool majorant_walk_collide(Medium m, INOUT(MajorantWalk) w, INOUT(uint) rng) {
  for (uint i = 0u; i < 3u * MAJORANT_GRID_CELLS_MAX; ++i) {
    float next = w.majorant > 0.0f ? w.t - log(1.0f - rng_next(rng)) / w.majorant : WP_INF;
    if (next < majorant_walk_cell_end(w)) {
      w.t = next;
      return true;
    }
    if (!majorant_walk_next(w)) return false;
    w.majorant = majorant_walk_majorant(m, w);
  }
  return false;
}

// A free flight through grid medium m (see medium_free_flight), each cell's
// stretch of the ray tracked against the cell's majorant.
uint grid_free_flight(Medium m, MediumCoefficients c, vec3 o, vec3 dir, float tmax, INOUT(uint) rng, INOUT(Spectrum) throughput, OUT(float) t) {
  t = tmax;
  MajorantWalk w;
  if (!majorant_walk_begin(m, o, dir, tmax, w)) return MEDIUM_EVENT_SURFACE;
  pnanovdb_readaccessor_t acc = grid_accessor(m);
  Spectrum sa = c.sigmaA;
  Spectrum ss = c.sigmaS;
  for (uint i = 0u; i < MEDIUM_COLLISIONS_MAX; ++i) {
    if (!majorant_walk_collide(m, w, rng)) return MEDIUM_EVENT_SURFACE;
    float density = grid_density(acc, w.o + w.d * w.t);
    Spectrum sn = max(Spectrum(w.majorant) - (sa + ss) * density, Spectrum(0.0f));
    uint event = medium_collision(sa * density, ss * density, sn, w.majorant, rng, throughput);
    if (event == MEDIUM_EVENT_SCATTER) t = w.t;
    if (event != MEDIUM_EVENT_SURFACE) return event;
  }
  return MEDIUM_EVENT_ABSORB;
}

// The transmittance of grid medium m along o + t dir, t in [0, tmax), by
// ratio tracking against the majorant cells.
Spectrum grid_transmittance(Medium m, MediumCoefficients c, vec3 o, vec3 dir, float tmax, INOUT(uint) rng) {
  MajorantWalk w;
  if (!majorant_walk_begin(m, o, dir, tmax, w)) return Spectrum(1.0f);
  pnanovdb_readaccessor_t acc = grid_accessor(m);
  Spectrum st = c.sigmaA + c.sigmaS;
  Spectrum tr = Spectrum(1.0f);
  for (uint i = 0u; i < MEDIUM_COLLISIONS_MAX; ++i) {
    if (!majorant_walk_collide(m, w, rng)) return tr;
    tr *= max(Spectrum(1.0f) - st * (grid_density(acc, w.o + w.d * w.t) / w.majorant), Spectrum(0.0f));
    if (!spectrum_positive(tr)) return tr;
  }
  return Spectrum(0.0f);
}

// ---- Any medium ---------------------------------------------------------------

// Samples the distance to the next real collision along the ray o + t dir
// (dir of unit length) in medium m, within [0, tmax) (tmax may be WP_INF),
// by delta tracking against the majorant with spectral tracking's event
// probabilities (c: m's coefficients, medium_coefficients). Multiplies `throughput` by the collision weights; returns
// the event and, for a scattering collision, its distance t. A flight longer
// than MEDIUM_COLLISIONS_MAX collisions ends absorbed (a bound on the loop,
// as lavapipe's budget requires; it takes over a hundred mean free paths of
// null collisions).
uint medium_free_flight(Medium m, MediumCoefficients c, vec3 o, vec3 dir, float tmax, INOUT(uint) rng, INOUT(Spectrum) throughput,
                        OUT(float) t) {
  t = tmax;
  if (FEATURE_COMPILED(FEATURE_MEDIA_GRID) && m.info.x == MEDIUM_NANOVDB) return grid_free_flight(m, c, o, dir, tmax, rng, throughput, t);
  float majorant = m.sigmaS.w;
  if (m.info.x == MEDIUM_VACUUM || !(majorant > 0.0f)) return MEDIUM_EVENT_SURFACE;
  // A homogeneous medium's coefficients are the same here as anywhere.
  Spectrum sa = c.sigmaA;
  Spectrum ss = c.sigmaS;
  Spectrum sn = max(Spectrum(majorant) - sa - ss, Spectrum(0.0f));
  float at = 0.0f;
  for (uint i = 0u; i < MEDIUM_COLLISIONS_MAX; ++i) {
    at -= log(1.0f - rng_next(rng)) / majorant;
    if (at >= tmax) return MEDIUM_EVENT_SURFACE;
    uint event = medium_collision(sa, ss, sn, majorant, rng, throughput);
    if (event == MEDIUM_EVENT_SCATTER) t = at;
    if (event != MEDIUM_EVENT_SURFACE) return event;
  }
  return MEDIUM_EVENT_ABSORB;
}

// The fraction of light that crosses the segment o + t dir, t in [0, tmax)
// (tmax may be WP_INF; dir of any length), of medium m. Homogeneous without
// null particles: Beer-Lambert's law in closed form; with them, and in grid
// media, ratio tracking against the majorant (unbiased; the estimator
// darts' null particles are there to exercise).
Spectrum medium_transmittance(Medium m, MediumCoefficients c, vec3 o, vec3 dir, float tmax, INOUT(uint) rng) {
  if (m.info.x == MEDIUM_VACUUM) return Spectrum(1.0f);
  float len = length(dir);
  if (FEATURE_COMPILED(FEATURE_MEDIA_GRID) && m.info.x == MEDIUM_NANOVDB) return grid_transmittance(m, c, o, dir / len, tmax * len, rng);
  float d = tmax * len;
  Spectrum sigmaT = c.sigmaA + c.sigmaS;
  if (!(d < WP_INF)) {
    vec4 s = spectrum_values(sigmaT);
    return spectrum_at(vec4(s.x > 0.0f ? 0.0f : 1.0f, s.y > 0.0f ? 0.0f : 1.0f, s.z > 0.0f ? 0.0f : 1.0f, s.w > 0.0f ? 0.0f : 1.0f));
  }
  if (!spectrum_positive(c.sigmaN)) return exp(-sigmaT * d);
  float majorant = m.sigmaS.w;
  Spectrum ratio = max(Spectrum(1.0f) - sigmaT / majorant, Spectrum(0.0f));
  Spectrum tr = Spectrum(1.0f);
  float at = 0.0f;
  for (uint i = 0u; i < MEDIUM_COLLISIONS_MAX; ++i) {
    at -= log(1.0f - rng_next(rng)) / majorant;
    if (at >= d) break;
    tr *= ratio;
  }
  return tr;
}

// The medium's phase function for light travelling along `dir` and
// scattered into wi, per steradian (Henyey-Greenstein; g = 0 isotropic).
float medium_phase(Medium m, vec3 dir, vec3 wi) {
  return henyey_greenstein_pdf(dot(dir, wi), m.sigmaA.w);
}

// A direction scattered from `dir` with the phase function's density.
vec3 medium_sample_phase(Medium m, vec3 dir, vec2 u) {
  vec3 t;
  vec3 bt;
  make_frame(dir, t, bt);
  return frame_to_world(square_to_henyey_greenstein(u, m.sigmaA.w), t, bt, dir);
}

#endif  // WP_MEDIA_GLSL
