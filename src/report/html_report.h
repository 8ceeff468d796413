// html_report.h — the comparison as a page a person can read: both images, the
// absolute difference as a heat map, the z-score map with the failing tiles
// outlined, and the numbers. One self-contained HTML file (images embedded as
// PNG data URIs), so it can be mailed or archived as it is.
#pragma once

#include <string>

#include "image/image.h"
#include "stats/compare.h"

namespace wp {

struct ReportLabels {
  std::string title;  // what was compared, e.g. the scene file
  std::string a;      // e.g. "gpu (llvmpipe), seed 1"
  std::string b;
};

// Writes DIR/index.html (creating DIR). Throws InputError if it cannot.
void write_html_report(const std::string& dir, const ImageStats& a, const ImageStats& b, const CompareResult& result,
                       const ReportLabels& labels);

}  // namespace wp
