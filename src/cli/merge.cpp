// `wavepath merge`: partial renders (EXRs of sample ranges of one render)
// added up into the image of all their samples, and a combined partial.
#include <algorithm>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render/partial.h"
#include "util/error.h"

namespace wp::cli {

namespace {

struct MergeArgs {
  std::vector<std::string> parts;
  std::string output;
  std::string exr;
  bool allowGaps = false;
  bool quiet = false;
};

int run_merge(const MergeArgs& m) {
  if (std::filesystem::path(m.output).extension() != ".png") throw InputError(m.output + ": the output image must be a .png file");
  std::string exr = m.exr.empty() ? std::filesystem::path(m.output).replace_extension(".exr").string() : m.exr;
  if (std::filesystem::path(exr).extension() != ".exr") throw InputError(exr + ": the combined partial must be an .exr file");
  for (const std::string& path : {m.output, exr}) require_output_directory(path);
  // The parts' headers first: parts of other renders, overlaps and gaps are
  // refused before a pixel is read.
  std::vector<std::unique_ptr<RenderExrReader>> parts;
  PartialMerger merger;
  for (const std::string& p : m.parts) {
    parts.push_back(std::make_unique<RenderExrReader>(p));
    merger.add(read_partial_header(p, *parts.back()));
  }
  const PartialFile merged = merger.finish(m.allowGaps);
  // Then a block of rows at a time, every part's rows added up and written
  // on: what the merge holds is a block per part and the PNG's bytes.
  const int width = merged.width, height = merged.height;
  const std::vector<ImageLayer> layers = image_layers(merged.aovs);
  const int blockRows = exr_block_rows(width, layers);
  // The parts merge into the image their render writes, in its scene format's 8-bit curve.
  const EightBitCurve curve = eight_bit_curve_named(render_setting(merged.record.settings, "png"));
  std::vector<uint8_t> rgb8(size_t(width) * size_t(height) * 3);
  write_atomically(exr, "EXR", [&](const std::string& tmp, std::string& error) {
    try {
      RenderExrWriter out(tmp, width, height, layers, merged.record, true);
      for (int y0 = 0; y0 < height; y0 += blockRows) {
        const int y1 = std::min(height, y0 + blockRows);
        ImageStats block(width, y1 - y0, layers);
        for (auto& part : parts) block.add(part->rows(y0, y1));
        out.write(block);
        const std::vector<uint8_t> bytes = encode_8bit_pixels(mean_rgb(block), curve);
        std::copy(bytes.begin(), bytes.end(), rgb8.begin() + ptrdiff_t(size_t(y0) * size_t(width) * 3));
      }
      return true;
    } catch (const std::exception& e) {
      error = e.what();
      return false;
    }
  });
  try {
    write_bytes_atomically(m.output, "PNG", encode_png(width, height, rgb8));
  } catch (...) {
    std::remove(exr.c_str());  // both or neither
    throw;
  }
  if (!m.quiet) {
    std::printf("merged %zu parts (samples %s, %s) into %s and %s\n", m.parts.size(), merged.record.samples.c_str(),
                merged.record.status.c_str(), m.output.c_str(), exr.c_str());
  }
  return 0;
}

}  // namespace

Command add_merge(CLI::App& app) {
  auto m = std::make_shared<MergeArgs>();
  CLI::App* merge = app.add_subcommand("merge", "add up partial renders (EXRs of sample ranges of one render) into one image");
  merge->add_option("parts", m->parts, "partial EXRs written by `wavepath render` (--samples, --checkpoint, --time)")->required();
  merge->add_option("-o,--output", m->output, "PNG to write")->required();
  merge->add_option("--exr", m->exr, "the combined partial EXR (default: next to the PNG)");
  merge->add_flag("--allow-gaps", m->allowGaps, "merge even where samples of the render are in no part (an image of fewer samples)");
  merge->add_flag("-q,--quiet", m->quiet, "no summary");
  return {merge, [m] { return run_merge(*m); }};
}

}  // namespace wp::cli
