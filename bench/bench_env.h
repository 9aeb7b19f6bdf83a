#pragma once
// Environment knobs shared by the benchmark programs.
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace ardcell {

// The non-empty items of a comma-separated list.
inline std::vector<std::string> split_list(const char* s) {
  std::vector<std::string> items;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

// Grid sizes from ARDCELL_BENCH_SIZES="512,1024", else `defaults`.
inline std::vector<int> bench_sizes_from_env(std::vector<int> defaults) {
  const char* s = std::getenv("ARDCELL_BENCH_SIZES");
  if (!s) return defaults;
  std::vector<int> sizes;
  for (const std::string& item : split_list(s)) sizes.push_back(std::atoi(item.c_str()));
  return sizes;
}

}  // namespace ardcell
