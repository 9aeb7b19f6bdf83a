#pragma once
// Invariant checks. ARDCELL_CHECK is always on: it guards bad input and broken invariants whose
// cost is negligible. ARDCELL_DCHECK is on in debug and sanitizer builds (ARDCELL_CHECKS=1) and
// guards per-element or per-tile conditions.
#include <cstdio>
#include <cstdlib>

namespace ardcell::detail {
[[noreturn]] inline void check_failed(const char* expr, const char* file, int line,
                                      const char* why) {
  std::fprintf(stderr, "ardcell: internal check failed: %s (%s) at %s:%d\n", why, expr, file, line);
  std::abort();
}
}  // namespace ardcell::detail

#define ARDCELL_CHECK(cond, why) \
  ((cond) ? (void)0 : ::ardcell::detail::check_failed(#cond, __FILE__, __LINE__, why))

#if defined(ARDCELL_CHECKS) && ARDCELL_CHECKS
#define ARDCELL_DCHECK(cond, why) ARDCELL_CHECK(cond, why)
#else
#define ARDCELL_DCHECK(cond, why) ((void)0)
#endif
