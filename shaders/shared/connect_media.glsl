// connect_media.glsl — the shadow-ray stage with participating media
// (FEATURE_MEDIA), for connect.comp and connect_multi.comp: each shadow ray,
// one to an invocation, is traced for its closest hits through the
// interfaces on its segment (shadow_ray_transmittance, integrator.glsl), and
// its contribution reaches the path scaled by the transmittance. The
// including kernel defines trace_item_count() and add_to_path(path, light).
void connect_through_media() {
  uint count = trace_item_count();
  uint item = dispatch_item(count);
  if (item >= count) return;
  ShadowRay sr = read_shadow_ray(item);
  uint truncated = 0u;
  // (The path's wavelengths: its fifth texel, which shade wrote before.)
  Spectrum tr = shadow_ray_transmittance(sr, spectral_mode() ? read_path(sr.path).wavelengths : 0.0f, truncated);
  if (truncated > 0u) atomicAdd(counters[COUNTER_TRUNCATED], truncated);
  if (spectrum_positive(tr)) add_to_path(sr.path, sr.contribution * tr);
}
