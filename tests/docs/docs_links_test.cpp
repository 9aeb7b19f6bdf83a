// The documentation stays true: scripts/check_links.sh finds every relative link, anchor and
// cited repository path of README.md, docs/*.md and bench/*.md; scripts/make_figures.sh --small
// runs every command that made the docs' images (64x64, 4 frames) with the real binary.
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace ardcell {
namespace {

int run(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Docs, EveryLinkAndCitedPathExists) {
  EXPECT_EQ(run("'" ARDCELL_SOURCE_DIR "/scripts/check_links.sh'"), 0)
      << "broken references above (scripts/check_links.sh)";
}

TEST(Docs, FigureCommandsRunAtASmallSize) {
  EXPECT_EQ(
      run("ARDCELL='" ARDCELL_BINARY "' '" ARDCELL_SOURCE_DIR "/scripts/make_figures.sh' --small"),
      0)
      << "scripts/make_figures.sh --small failed (its lines above)";
}

}  // namespace
}  // namespace ardcell
