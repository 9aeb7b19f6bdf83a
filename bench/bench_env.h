#pragma once
// Environment knobs shared by the Table 1 benchmark programs.
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace ardcell {

// Grid sizes from ARDCELL_BENCH_SIZES="512,1024", else `defaults`.
inline std::vector<int> bench_sizes_from_env(std::vector<int> defaults) {
  const char* s = std::getenv("ARDCELL_BENCH_SIZES");
  if (!s) return defaults;
  std::vector<int> sizes;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) sizes.push_back(std::atoi(item.c_str()));
  return sizes;
}

}  // namespace ardcell
