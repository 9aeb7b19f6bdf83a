// ardcell: the command-line entry point. Everything lives in the libraries (drivers/cli.h).
#include "drivers/cli.h"

int main(int argc, char** argv) { return ardcell::run_cli(argc, argv); }
