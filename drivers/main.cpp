// ardcell: the command-line entry point. Everything lives in the libraries; this file only
// hands the arguments over (see host/cli.h once the CLI lands).
#include <cstdio>

int main(int argc, char** argv) {
  (void)argc;
  (void)argv;
  std::printf("ardcell %s\n", ARDCELL_VERSION);
  return 0;
}
