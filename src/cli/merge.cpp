// `wavepath merge`: partial renders (EXRs of sample ranges of one render)
// added up into the image of all their samples, and a combined partial.
#include <filesystem>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "image/image.h"
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
  PartialMerger merger;  // one part in memory at a time besides the sum
  for (const std::string& p : m.parts) merger.add(read_partial(p));
  PartialFile merged = merger.finish(m.allowGaps);
  write_exr(exr, merged.image, merged.record, true);
  try {
    // The parts merge into the image their render writes, in its scene format's 8-bit curve.
    write_image(m.output, mean_rgb(merged.image), eight_bit_curve_named(render_setting(merged.record.settings, "png")));
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
