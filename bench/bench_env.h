#pragma once
// Environment knobs shared by the benchmark programs.
#include <cstdlib>
#include <string>
#include <vector>

#include "drivers/bench_program.h"

namespace ardcell {

// Grid sizes from ARDCELL_BENCH_SIZES="512,1024", else `defaults`.
inline std::vector<int> bench_sizes_from_env(std::vector<int> defaults) {
  const char* s = std::getenv("ARDCELL_BENCH_SIZES");
  if (!s) return defaults;
  std::vector<int> sizes;
  for (const std::string& item : split_commas(s)) sizes.push_back(std::atoi(item.c_str()));
  return sizes;
}

}  // namespace ardcell
