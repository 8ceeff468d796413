// partial.h — renders as partial accumulations that merge exactly: what
// identifies a render (its scene's content and the settings that change its
// image), sample ranges as text, and the merge of partial files with its
// refusals. docs/partial-renders.md describes the files and the guarantees.
#pragma once

#include <string>
#include <vector>

#include "image/image.h"
#include "render/compiled_scene.h"
#include "render/render_control.h"
#include "scene/scene.h"

namespace wp {

// "wavepath 0.1.0"
std::string wavepath_version();
// The integrator the kernels' parameters select, by its darts name.
std::string integrator_name(const shader::SceneParams& params);

// A 64-bit FNV-1a hash of the contents of every file the scene was read
// from (Scene::inputFiles, in order), as 16 hex digits: equal for the same
// files wherever they lie. Throws InputError if a file cannot be read.
std::string scene_content_hash(const Scene& scene);

// The settings that change a render's image, as "key=value; ..." in a fixed
// order: resolution, samples per pixel (the whole render's), integrator,
// bounces, Russian roulette, sampler, light samples, seed, lens, adaptive
// sampling and AOV layers. The renderer (GPU variant or CPU reference) is not
// among them: every one of them draws the same random numbers for a sample
// and is tested to estimate the same image, so parts rendered by different
// ones merge (render --devices does just that).
std::string render_settings(const CompiledScene& scene);

// The value of `key` in a settings string (render_settings), or "".
std::string render_setting(const std::string& settings, const std::string& key);

// "0:16,16:40" and back. parse_sample_ranges throws InputError naming
// `where` for anything else (ranges must be A:B with A < B).
std::string format_sample_ranges(const std::vector<SampleRange>& ranges);
std::vector<SampleRange> parse_sample_ranges(const std::string& text, const std::string& where);
// The samples per pixel of the whole render a settings string describes.
uint32_t samples_of_settings(const std::string& settings);

// A partial file as read back: its image (exact sums), record and ranges.
struct PartialFile {
  std::string path;
  ImageStats image;  // empty where only the header was read (read_partial_header)
  int width = 0, height = 0;
  std::vector<std::string> aovs;  // the AOV layers it holds
  RenderRecord record;
  std::vector<SampleRange> ranges;  // sorted, disjoint
};

// Reads a partial file, refusing (InputError, naming the file) one without
// a render record or exact sums.
PartialFile read_partial(const std::string& path);
// The same from the header of `exr` (the file at `path`) alone, the image
// left empty: a merge reads the pixels a block of rows at a time.
PartialFile read_partial_header(const std::string& path, const RenderExrReader& exr);

// Throws InputError, naming both files and what differs, unless `b` is a part
// of the same render as `a` (same scene content, same settings).
void require_same_render(const PartialFile& a, const PartialFile& b);

// The ranges of [0, total) that `ranges` (sorted, disjoint) leave out.
std::vector<SampleRange> missing_ranges(const std::vector<SampleRange>& ranges, uint32_t total);

// Adds the parts of one render up, one at a time, so that memory holds the
// sum and one part: `add` refuses a part of another render or one whose
// ranges overlap a part added before (naming both files); `finish` refuses,
// unless allowGaps, samples of the render that no part holds (naming the
// missing ranges). The result's record lists the merged ranges, "complete"
// when they are the whole render.
class PartialMerger {
 public:
  // Checks `part` against those added and adds its image (if it was read)
  // to theirs.
  void add(PartialFile part);
  PartialFile finish(bool allowGaps);

 private:
  PartialFile total_;
  bool empty_ = true;
  std::vector<std::pair<SampleRange, std::string>> ranges_;  // every range added, with its file
  std::string renderers_;
};

// The parts merged by a PartialMerger.
PartialFile merge_partials(const std::vector<PartialFile>& parts, bool allowGaps);

}  // namespace wp
