#pragma once
// OpenCL C sources of kernels/cl/*.cl, embedded at build time (cmake/embed_cl.cmake).
#include <span>
#include <string_view>

namespace ardcell {

struct ClSource {
  const char* name;  // file name, e.g. "advect.cl"
  const char* text;  // the whole file
};

// Every embedded .cl file, sorted by name.
std::span<const ClSource> cl_sources();

// The text of one file, or an empty view when there is no such file.
inline std::string_view cl_source(std::string_view name) {
  for (const ClSource& s : cl_sources())
    if (name == s.name) return s.text;
  return {};
}

}  // namespace ardcell
