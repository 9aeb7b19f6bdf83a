// ardcell: the command-line entry point. Everything lives in the libraries (drivers/cli.h).
#include "drivers/cli.h"

// Sanitizer builds: SDL keeps D-Bus/X11 helper allocations, Open MPI its runtime's, and PoCL/LLVM
// their compiler state, for the life of the process (runtime/opencl/opencl_context.cpp suppresses
// those). The report of the suppressions used would otherwise land on stderr whenever PoCL compiles
// a program (a cold kernel cache), breaking the CLI's "stderr only for errors" contract.
extern "C" const char* __lsan_default_options() {
  return "suppressions=" ARDCELL_SOURCE_DIR "/scripts/lsan.supp:print_suppressions=0";
}

int main(int argc, char** argv) { return ardcell::run_cli(argc, argv); }
