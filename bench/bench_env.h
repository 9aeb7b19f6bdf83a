#pragma once
// Environment knobs shared by the benchmark programs.
#include <cstdlib>
#include <string>
#include <vector>

#include "drivers/bench_program.h"

namespace ardcell {

// The environment variable `name` when set and not empty, else `fallback`.
inline std::string bench_env_text(const char* name, const char* fallback) {
  const char* s = std::getenv(name);
  return s && *s ? s : fallback;
}
inline int bench_env_int(const char* name, int fallback) {
  const char* s = std::getenv(name);
  return s && *s ? std::atoi(s) : fallback;
}

// Grid sizes from ARDCELL_BENCH_SIZES="512,1024", else `defaults`.
inline std::vector<int> bench_sizes_from_env(std::vector<int> defaults) {
  const char* s = std::getenv("ARDCELL_BENCH_SIZES");
  if (!s) return defaults;
  std::vector<int> sizes;
  for (const std::string& item : split_commas(s)) sizes.push_back(std::atoi(item.c_str()));
  return sizes;
}

}  // namespace ardcell
