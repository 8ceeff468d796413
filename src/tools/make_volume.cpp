// wavepath-volume — writes the procedural density grids of wavepath's scenes
// as .nvdb files (NanoVDB, uncompressed). scripts/make-plume.sh runs it for
// scenes/plume.nvdb.
//
//   wavepath-volume plume OUT.nvdb [HEIGHT [SEED]]
//   wavepath-volume ramp OUT.nvdb N A B
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "tools/volume_shapes.h"

int main(int argc, char** argv) {
  const std::string usage = "usage: wavepath-volume plume OUT.nvdb [HEIGHT [SEED]] | ramp OUT.nvdb N A B\n";
  try {
    const std::string kind = argc > 2 ? argv[1] : "";
    if (kind == "plume" && argc <= 5) {
      const int height = argc > 3 ? std::atoi(argv[3]) : 96;
      const unsigned seed = argc > 4 ? unsigned(std::strtoul(argv[4], nullptr, 10)) : 7u;
      if (height < 8 || height > 1024) throw std::runtime_error("HEIGHT must lie in [8, 1024]");
      nanovdb::io::writeGrid(argv[2], wp::volumes::plume(height, seed));
    } else if (kind == "ramp" && argc == 6) {
      const int n = std::atoi(argv[3]);
      if (n < 1 || n > 1024) throw std::runtime_error("N must lie in [1, 1024]");
      nanovdb::io::writeGrid(argv[2], wp::volumes::ramp(n, std::strtof(argv[4], nullptr), std::strtof(argv[5], nullptr)));
    } else {
      std::fputs(usage.c_str(), stderr);
      return 2;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wavepath-volume: %s\n", e.what());
    return 1;
  }
  return 0;
}
