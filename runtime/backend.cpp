#include "runtime/backend.h"

#include "runtime/check.h"

namespace ardcell {

void SerialBackend::dispatch(const Pass& pass, std::span<const Tile> /*tiles*/) {
  ARDCELL_CHECK(pass.run_whole != nullptr, "serial back end needs a whole-grid pass");
  pass.run_whole(pass.program);
}

}  // namespace ardcell
