#include "render/partial.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "util/error.h"

namespace wp {

namespace {

// A settings string's "key=value" items, in order.
std::vector<std::pair<std::string, std::string>> settings_items(const std::string& settings) {
  std::vector<std::pair<std::string, std::string>> items;
  std::istringstream in(settings);
  for (std::string item; std::getline(in, item, ';');) {
    size_t start = item.find_first_not_of(' '), eq = item.find('=');
    if (start == std::string::npos || eq == std::string::npos || eq < start) continue;
    items.emplace_back(item.substr(start, eq - start), item.substr(eq + 1));
  }
  return items;
}

// The first setting whose value differs, as "key A vs B".
std::string first_difference(const std::string& a, const std::string& b) {
  for (const auto& [key, value] : settings_items(a))
    if (render_setting(b, key) != value) return key + " " + value + " vs " + render_setting(b, key);
  return "\"" + a + "\" vs \"" + b + "\"";
}

}  // namespace

std::string integrator_name(const shader::SceneParams& p) {
  const uint32_t flags = p.counts.w;
  switch (p.mode.x) {
    case INTEGRATOR_NORMALS: return "normals";
    case INTEGRATOR_AO: return "ao";
    case INTEGRATOR_MIXTURE: return "path tracer mixture";
    case INTEGRATOR_PHOTONS: return "photon mapper";
    default: break;
  }
  if (flags & SCENE_FLAG_HEMISPHERE) return "path tracer hemisphere";
  if (flags & SCENE_FLAG_NO_NEE) return "path tracer mats";
  if (flags & SCENE_FLAG_NO_BSDF_MIS) return "path tracer nee";
  return "path tracer mis";
}

std::string render_setting(const std::string& settings, const std::string& key) {
  for (const auto& [k, v] : settings_items(settings))
    if (k == key) return v;
  return "";
}

std::string wavepath_version() {
  return "wavepath " WAVEPATH_VERSION;
}

std::string scene_content_hash(const Scene& scene) {
  uint64_t h = 14695981039346656037ull;  // FNV-1a, 64-bit
  auto mix = [&h](const char* data, size_t n) {
    for (size_t i = 0; i < n; ++i) {
      h ^= uint8_t(data[i]);
      h *= 1099511628211ull;
    }
  };
  std::vector<char> buffer(1 << 16);
  for (const std::string& path : scene.inputFiles) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot read it again to identify the render");
    uint64_t size = 0;
    while (in) {
      in.read(buffer.data(), std::streamsize(buffer.size()));
      mix(buffer.data(), size_t(in.gcount()));
      size += uint64_t(in.gcount());
    }
    mix(reinterpret_cast<const char*>(&size), sizeof size);  // file boundaries count
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016" PRIx64, h);
  return hex;
}

std::string render_settings(const CompiledScene& cs) {
  const shader::SceneParams& p = cs.params;
  char lens[64];
  std::snprintf(lens, sizeof lens, "%.9g/%.9g", double(p.camLens.z), double(p.camLens.w));
  std::string adaptive = "off";
  if (cs.adaptive.enabled()) {
    char a[64];
    std::snprintf(a, sizeof a, "%d/%.9g", cs.adaptive.batch, double(cs.adaptive.tolerance));
    adaptive = a;
  }
  std::string aovs;
  for (const std::string& a : cs.aovs) aovs += (aovs.empty() ? "" : ",") + a;
  std::ostringstream s;
  s << "resolution=" << cs.width << "x" << cs.height << "; spp=" << cs.spp << "; integrator=" << integrator_name(p)
    << "; max_bounces=" << p.image.z << "; rr_depth=" << p.image.w << "; sampler=" << (p.mode.y == SAMPLER_CMJ ? "cmj" : "independent")
    << "; mis_power=" << p.mis.x << "; light_samples=" << p.mode.w << "; seed=" << p.counts.y << "; lens=" << lens << "; adaptive=" << adaptive
    << "; aovs=" << (aovs.empty() ? "none" : aovs);
  if (!cs.cameraName.empty()) s << "; camera=" << cs.cameraName;
  // The view itself: a camera settings file (-c) or a cell of the frame (-p)
  // changes it without changing the scene's files.
  std::string view;
  for (const glm::vec4& r : {p.camToWorld0, p.camToWorld1, p.camToWorld2, glm::vec4(p.camLens.x, p.camLens.y, 0, 0), p.camWindow})
    for (int c = 0; c < 4; ++c) {
      char v[32];
      std::snprintf(v, sizeof v, "%.9g", double(r[c]));
      view += (view.empty() ? "" : ",") + std::string(v);
    }
  s << "; view=" << view;
  if (p.counts.w & SCENE_FLAG_CS184) s << "; estimator=cs184";
  if (p.counts.w & SCENE_FLAG_CS184_LATLONG) s << "; latlong=cs184";
  if (p.counts.w & SCENE_FLAG_SPECTRAL) s << "; colour=spectral";
  if (cs.eightBitCurve != EightBitCurve::Srgb) s << "; png=" << eight_bit_curve_name(cs.eightBitCurve);
  if (cs.cs184Skeleton == 32) s << "; skeleton=cs184-3-2";  // the scene as that skeleton builds it
  return s.str();
}

std::string format_sample_ranges(const std::vector<SampleRange>& ranges) {
  std::string out;
  for (const SampleRange& r : ranges) out += (out.empty() ? "" : ",") + std::to_string(r.begin) + ":" + std::to_string(r.end);
  return out;
}

std::vector<SampleRange> parse_sample_ranges(const std::string& text, const std::string& where) {
  std::vector<SampleRange> ranges;
  std::vector<std::string> items(1);
  for (char c : text) {
    if (c == ',') items.emplace_back();
    else items.back() += c;
  }
  for (const std::string& item : items) {
    unsigned long a = 0, b = 0;
    char colon = 0;
    std::istringstream is(item);
    if (!(is >> a >> colon >> b) || colon != ':' || !(is >> std::ws).eof() || a >= b || b > MAX_SAMPLES_PER_PIXEL)
      throw InputError(where + ": \"" + item + "\" is not a sample range A:B with 0 <= A < B <= " + std::to_string(MAX_SAMPLES_PER_PIXEL));
    ranges.push_back({uint32_t(a), uint32_t(b)});
  }
  return ranges;
}

uint32_t samples_of_settings(const std::string& settings) {
  return uint32_t(std::strtoul(render_setting(settings, "spp").c_str(), nullptr, 10));
}

PartialFile read_partial_header(const std::string& path, const RenderExrReader& exr) {
  PartialFile f;
  f.path = path;
  f.width = exr.width();
  f.height = exr.height();
  for (size_t l = 1; l < exr.layers().size(); ++l) f.aovs.push_back(exr.layers()[l].name);
  f.record = exr.record();
  if (f.record.sceneHash.empty() || f.record.settings.empty() || f.record.samples.empty())
    throw InputError(path + ": not a partial render (its header lacks wavepath's render record)");
  if (!f.record.exactSums) throw InputError(path + ": not a partial render (it lacks the exact sums a merge adds up)");
  f.ranges = parse_sample_ranges(f.record.samples, path + ": wavepath:samples");
  std::sort(f.ranges.begin(), f.ranges.end(), [](SampleRange a, SampleRange b) { return a.begin < b.begin; });
  for (size_t i = 1; i < f.ranges.size(); ++i)
    if (f.ranges[i].begin < f.ranges[i - 1].end) throw InputError(path + ": wavepath:samples: its ranges overlap");
  return f;
}

PartialFile read_partial(const std::string& path) {
  RenderExrReader exr(path);
  PartialFile f = read_partial_header(path, exr);
  f.image = exr.all();
  return f;
}

void require_same_render(const PartialFile& a, const PartialFile& b) {
  if (a.record.sceneHash != b.record.sceneHash)
    throw InputError(b.path + " is a render of another scene than " + a.path + " (scene content " + b.record.sceneHash + " vs " +
                     a.record.sceneHash + ")");
  if (a.record.settings != b.record.settings)
    throw InputError(b.path + " is a render with other settings than " + a.path + " (" + first_difference(b.record.settings, a.record.settings) + ")");
  if (a.width != b.width || a.height != b.height || a.aovs != b.aovs)
    throw InputError(b.path + " has another size or other layers than " + a.path);
}

std::vector<SampleRange> missing_ranges(const std::vector<SampleRange>& ranges, uint32_t total) {
  std::vector<SampleRange> missing;
  uint32_t at = 0;
  for (const SampleRange& r : ranges) {
    if (r.begin > at) missing.push_back({at, r.begin});
    at = std::max(at, r.end);
  }
  if (at < total) missing.push_back({at, total});
  return missing;
}

void PartialMerger::add(PartialFile part) {
  if (!empty_) require_same_render(total_, part);
  for (SampleRange r : part.ranges) {
    for (const auto& [had, from] : ranges_) {
      if (r.begin < had.end && had.begin < r.end)
        throw InputError(part.path + " (samples " + format_sample_ranges({r}) + ") overlaps " + from + " (samples " +
                         format_sample_ranges({had}) + ")");
    }
  }
  for (SampleRange r : part.ranges) ranges_.push_back({r, part.path});
  if (renderers_.find(part.record.renderer) == std::string::npos)
    renderers_ += (renderers_.empty() ? "" : "; ") + part.record.renderer;
  if (empty_) {
    total_ = std::move(part);
    empty_ = false;
  } else if (!part.image.sum.empty()) {
    total_.image.add(part.image);
  }
}

PartialFile PartialMerger::finish(bool allowGaps) {
  if (empty_) throw InputError("nothing to merge");
  std::vector<SampleRange> all;
  for (const auto& [r, from] : ranges_) all.push_back(r);
  std::sort(all.begin(), all.end(), [](SampleRange x, SampleRange y) { return x.begin < y.begin; });
  PartialFile out = std::move(total_);
  out.path.clear();
  out.ranges.clear();
  for (SampleRange r : all) {  // adjacent ranges join
    if (!out.ranges.empty() && out.ranges.back().end == r.begin) out.ranges.back().end = r.end;
    else out.ranges.push_back(r);
  }
  const uint32_t total = samples_of_settings(out.record.settings);
  std::vector<SampleRange> missing = missing_ranges(out.ranges, total);
  if (!missing.empty() && !allowGaps)
    throw InputError("the parts leave out samples " + format_sample_ranges(missing) + " of the render's 0:" + std::to_string(total) +
                     " (render them, or merge with --allow-gaps for an image of fewer samples)");
  out.record.samples = format_sample_ranges(out.ranges);
  out.record.status = missing.empty() ? "complete" : "partial: samples " + format_sample_ranges(missing) + " missing";
  out.record.renderer = renderers_;
  out.record.version = wavepath_version();
  empty_ = true;
  ranges_.clear();
  renderers_.clear();
  return out;
}

PartialFile merge_partials(const std::vector<PartialFile>& parts, bool allowGaps) {
  PartialMerger merger;
  for (const PartialFile& p : parts) merger.add(p);
  return merger.finish(allowGaps);
}

}  // namespace wp
