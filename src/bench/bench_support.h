// bench_support.h — what the three benchmarks (bench.cpp, raycast_bench.cpp,
// build_bench.cpp) share: medians and ranges, scenes at the asked
// resolution, number and CSV formatting, JSON output.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench.h"
#include "scene/scene.h"
#include "util/error.h"

namespace wp::bench {

struct Spread {
  double median = 0.0, min = 0.0, max = 0.0;
};

inline Spread spread(std::vector<double> v) {
  Spread s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.min = v.front();
  s.max = v.back();
  return s;
}

inline Scene with_resolution(Scene scene, const BenchOptions& o) {
  if (!o.resolution.empty()) {
    scene.camera.width = o.resolution[0];
    scene.camera.height = o.resolution[1];
  }
  return scene;
}

inline std::string format_number(double x, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, x);
  return buf;
}

inline nlohmann::json to_json(const Spread& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}};
}

// A CSV field (RFC 4180): quoted, its quotes doubled, where it holds a
// comma, a quote or a line break (a scene's path may).
inline std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// Writes the results as JSON to `path`.
inline void write_json(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path + ": cannot write the results");
}

// A variant's times include work redone one ray per invocation: say so
// under its row.
inline void print_one_ray_note(const std::string& variant, uint64_t reruns) {
  std::printf("  (%s: %llu dispatch(es) redone one ray per invocation, a ray having outrun its share of the loop budget;\n"
              "   its times are partly those of one ray per invocation)\n",
              variant.c_str(), (unsigned long long)reruns);
}

}  // namespace wp::bench
