// The bundled scenes, from bench/CMakeLists.txt (SWEEPGEN_BENCH_SCENES: "stem=path|stem=path...").
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace sweepgen::bench {

inline std::vector<std::pair<std::string, std::string>> bundled_scenes() {
  std::vector<std::pair<std::string, std::string>> scenes;
  const std::string all = SWEEPGEN_BENCH_SCENES;
  std::size_t start = 0;
  while (start < all.size()) {
    std::size_t end = all.find('|', start);
    if (end == std::string::npos) end = all.size();
    const std::string entry = all.substr(start, end - start);
    const std::size_t eq = entry.find('=');
    scenes.emplace_back(entry.substr(0, eq), entry.substr(eq + 1));
    start = end + 1;
  }
  return scenes;
}

}  // namespace sweepgen::bench
