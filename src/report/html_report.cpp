#include "report/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/error.h"

namespace wp {

namespace {

std::string base64(const std::vector<uint8_t>& data) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = uint32_t(data[i]) << 16;
    if (i + 1 < data.size()) v |= uint32_t(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? table[v & 63] : '=';
  }
  return out;
}

std::string data_uri(int w, int h, const std::vector<uint8_t>& rgb) {
  return "data:image/png;base64," + base64(encode_png(w, h, rgb));
}

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

// A perceptual ramp, black - purple - orange - pale yellow (after "inferno").
glm::vec3 heat(float t) {
  const glm::vec3 stops[] = {{0.0f, 0.0f, 0.02f}, {0.34f, 0.06f, 0.43f}, {0.73f, 0.21f, 0.33f}, {0.98f, 0.55f, 0.04f}, {0.99f, 1.0f, 0.64f}};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  int i = std::min(3, int(t));
  return glm::mix(stops[i], stops[i + 1], t - float(i));
}

uint8_t byte(float v) {
  return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

void write_html_report(const std::string& dir, const ImageStats& a, const ImageStats& b, const CompareResult& r,
                       const ReportLabels& labels) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the report directory: " + ec.message());
  const int w = a.width, h = a.height;
  const size_t n = a.pixels();

  // |A - B| (mean over channels), scaled so the 99th percentile is the top.
  std::vector<float> diff(n);
  for (size_t p = 0; p < n; ++p) {
    glm::dvec3 d = glm::abs(a.mean(p) - b.mean(p));
    diff[p] = float((d.x + d.y + d.z) / 3.0);
  }
  std::vector<float> sorted = diff;
  std::sort(sorted.begin(), sorted.end());
  float top = std::max(sorted.empty() ? 0.0f : sorted[size_t(0.99 * double(sorted.size() - 1))], 1e-12f);
  std::vector<uint8_t> diffRgb(n * 3), zRgb(n * 3);
  const float zMax = 5.0f;
  for (size_t p = 0; p < n; ++p) {
    glm::vec3 c = heat(diff[p] / top);
    float z = std::clamp(r.zMap[p] / zMax, -1.0f, 1.0f);
    // Diverging: blue below zero, white at zero, red above.
    glm::vec3 zc = z >= 0.0f ? glm::mix(glm::vec3(1.0f), glm::vec3(0.75f, 0.05f, 0.1f), z)
                             : glm::mix(glm::vec3(1.0f), glm::vec3(0.1f, 0.25f, 0.8f), -z);
    for (int k = 0; k < 3; ++k) {
      diffRgb[3 * p + size_t(k)] = byte(c[k]);
      zRgb[3 * p + size_t(k)] = byte(zc[k]);
    }
  }

  std::ostringstream tiles;
  for (const TileResult& t : r.tiles) {
    if (!t.failed) continue;
    tiles << "<rect x=\"" << t.x0 << "\" y=\"" << t.y0 << "\" width=\"" << (t.x1 - t.x0) << "\" height=\"" << (t.y1 - t.y0)
          << "\"><title>tile x " << t.x0 << "-" << t.x1 - 1 << ", y " << t.y0 << "-" << t.y1 - 1 << ": bias "
          << 100.0 * t.relativeBias << "%, z " << t.z << "</title></rect>";
  }
  const std::string overlay = "<svg class=\"tiles\" viewBox=\"0 0 " + std::to_string(w) + " " + std::to_string(h) +
                              "\" preserveAspectRatio=\"none\">" + tiles.str() + "</svg>";
  auto figure = [&](const std::string& caption, const std::string& uri, bool withTiles) {
    return "<figure><div class=\"frame\"><img alt=\"" + escape(caption) + "\" src=\"" + uri + "\">" + (withTiles ? overlay : "") +
           "</div><figcaption>" + escape(caption) + "</figcaption></figure>\n";
  };
  char line[512];
  std::ostringstream rows;
  auto row = [&](const char* name, const std::string& value, bool ok) {
    rows << "<tr><th>" << name << "</th><td>" << value << "</td><td class=\"" << (ok ? "pass\">pass" : "fail\">fail")
         << "</td></tr>\n";
  };
  std::snprintf(line, sizeof(line), "%zu of %zu pixel-channels differ (%.3f%% pass; at least 99.75%% must)",
                r.failingPixelChannels, r.pixelChannels, 100.0 * r.pixelPassFraction);
  row("per-pixel Welch tests (Sidak)", line, r.pixelTestPassed);
  std::snprintf(line, sizeof(line), "%.6g vs %.6g; worst channel z = %.2f, p = %.3g", r.meanA, r.meanB, r.meanZ, r.meanP);
  row("image mean per channel", line, r.meanTestPassed);
  std::snprintf(line, sizeof(line), "%zu of %zu tiles differ", r.failingTiles, r.tiles.size());
  row("tile means", line, r.tileTestPassed);
  std::snprintf(line, sizeof(line), "%+.3f%% &plusmn; %.3f%% (95%%)", 100.0 * r.relativeBias, 100.0 * r.relativeBiasCi95);
  rows << "<tr><th>relative bias of A</th><td>" << line << "</td><td></td></tr>\n";
  for (const TileResult& t : r.worst_tiles(5)) {
    if (!t.failed) break;
    std::snprintf(line, sizeof(line), "x %d-%d, y %d-%d: bias %+.2f%%, z = %.2f", t.x0, t.x1 - 1, t.y0, t.y1 - 1,
                  100.0 * t.relativeBias, t.z);
    rows << "<tr><th>failing tile</th><td>" << line << "</td><td class=\"fail\">fail</td></tr>\n";
  }

  std::ostringstream html;
  html << R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>wavepath compare: )"
       << escape(labels.title) << R"(</title>
<style>
body { font: 14px/1.4 system-ui, sans-serif; margin: 24px; color: #222; }
h1 { font-size: 20px; } .verdict { font-size: 18px; font-weight: bold; }
.AGREE { color: #1a7f37; } .DIFFER { color: #c62828; }
.grid { display: flex; flex-wrap: wrap; gap: 16px; }
figure { margin: 0; width: 322px; } figcaption { text-align: center; margin-top: 4px; overflow-wrap: anywhere; }
.frame { position: relative; width: 320px; }
.frame img { display: block; width: 100%; image-rendering: pixelated; border: 1px solid #ccc; }
.tiles { position: absolute; left: 0; top: 0; width: 100%; height: 100%; }
.tiles rect { fill: none; stroke: #00e5ff; stroke-width: 1; vector-effect: non-scaling-stroke; }
table { border-collapse: collapse; margin-top: 16px; } th, td { text-align: left; padding: 4px 10px; border-bottom: 1px solid #eee; }
.pass { color: #1a7f37; } .fail { color: #c62828; font-weight: bold; }
</style></head>
<body>
<h1>wavepath compare: )"
       << escape(labels.title) << "</h1>\n<p class=\"verdict " << (r.passed() ? "AGREE\">AGREE" : "DIFFER\">DIFFER")
       << "</p>\n<p>A = " << escape(labels.a) << "; B = " << escape(labels.b) << "; " << w << "x" << h
       << " pixels. Failing tiles are outlined.</p>\n<div class=\"grid\">\n"
       << figure("A: " + labels.a, data_uri(w, h, to_srgb8(a)), true)
       << figure("B: " + labels.b, data_uri(w, h, to_srgb8(b)), false)
       << figure("|A - B|, black 0 to yellow " + std::to_string(top), data_uri(w, h, diffRgb), false)
       << figure("z score, blue -5 to white 0 to red +5", data_uri(w, h, zRgb), true) << "</div>\n<table>\n"
       << rows.str() << R"(</table>
<script>
// Lets automated checks see that every embedded image decoded.
window.addEventListener("load", function () {
  var imgs = document.querySelectorAll("img"), ok = 0;
  imgs.forEach(function (i) { if (i.complete && i.naturalWidth > 0) ok++; });
  document.body.setAttribute("data-images-decoded", ok + "/" + imgs.length);
});
</script>
</body></html>
)";
  std::string path = (std::filesystem::path(dir) / "index.html").string();
  std::ofstream out(path, std::ios::binary);
  out << html.str();
  if (!out) throw InputError(path + ": cannot write the report");
}

}  // namespace wp
