// The fuzzers' findings, replayed, beside the cases that pin down what the
// loaders accept: each file under tests/fuzz/findings/KIND/ is an input of
// that kind as the fuzz targets take it (fuzz_loaders.h), either one that
// scripts/fuzz.sh found crashing or misleading a loader, or one written by
// hand (a GIF named .png, a valid TGA). Its name says what the loader must do
// with it: "refused-*" files must be refused with an InputError naming the
// file, "loads-*" files must load. The fuzzers also start from these files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz/fuzz_loaders.h"
#include "test_support.h"

namespace wp {
namespace {

TEST(Loaders, FuzzFindingsAreHandledAsRecorded) {
  const std::filesystem::path root = test::source_path("tests/fuzz/findings");
  int replayed = 0;
  for (const char* kind : {"scene", "obj", "image", "partial", "gltf", "collada", "nvdb"}) {
    const std::filesystem::path folder = root / kind;
    if (!std::filesystem::is_directory(folder)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      const std::string name = entry.path().filename().string();
      const bool shouldLoad = name.rfind("loads-", 0) == 0;
      ASSERT_TRUE(shouldLoad || name.rfind("refused-", 0) == 0) << entry.path() << ": name it loads-* or refused-*";
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      SCOPED_TRACE(entry.path().string());
      bool loaded = false;
      EXPECT_NO_THROW(loaded = load_fuzzed(fuzzed_input_named(kind), reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
      EXPECT_EQ(loaded, shouldLoad);
      ++replayed;
    }
  }
  EXPECT_GT(replayed, 0) << "no findings under " << root;
}

}  // namespace
}  // namespace wp
