#!/usr/bin/env bash
# One entry point for people and CI. On a fresh Debian 12 machine it installs what is missing,
# configures and builds, then:
#   scripts/dev.sh run [ARGS...]   builds Release and runs `ardcell run ARGS...` (default scene)
#   scripts/dev.sh test            builds with ASan+UBSan and runs the whole test suite (ctest),
#                                  then the libFuzzer targets for a bounded time
#   scripts/dev.sh bench [ARGS...] builds Release and runs `ardcell bench ARGS...`
#   scripts/dev.sh deps            installs the Debian packages only
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache
  libgtest-dev libgmock-dev libbenchmark-dev
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  libhidapi-dev libgpiod-dev libsdl2-dev libsdl2-ttf-dev fonts-dejavu-core
  libpng-dev libcli11-dev libtomlplusplus-dev
  nlohmann-json3-dev liblo-dev libsystemd-dev libplplot-dev libfftw3-dev
  clang libclang-rt-14-dev
  libosd-dev libcgal-demo
  libopenmpi-dev openmpi-bin
  xvfb xauth python3-numpy
)

install_packages() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "dev.sh: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

jobs=$(nproc)

configure_release() {
  cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DARDCELL_BUILD_TESTS=OFF \
    -DARDCELL_BUILD_BENCH=ON >/dev/null
}

cmd=${1:-run}
[ $# -gt 0 ] && shift
case "$cmd" in
  deps)
    install_packages
    ;;
  run)
    install_packages
    configure_release
    cmake --build build/release --target ardcell -j "$jobs"
    exec build/release/ardcell run "$@"
    ;;
  bench)
    install_packages
    configure_release
    cmake --build build/release -j "$jobs"
    exec build/release/ardcell bench "$@"
    ;;
  test)
    install_packages
    werror=OFF
    [ "${CI:-}" = "true" ] && werror=ON
    cmake -S . -B build/test -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARDCELL_SANITIZE=ON \
      -DARDCELL_WERROR=$werror -DARDCELL_BUILD_TESTS=ON -DARDCELL_BUILD_BENCH=ON >/dev/null
    cmake --build build/test -j "$jobs"
    # SDL tests need an X server: run the suite under a private Xvfb.
    # intercept_tls_get_addr=0: GCC 12's leak checker can take a dlopen'ed library's dynamic TLS
    # block for an older glibc's layout and crash scanning it at exit ("Tracer caught signal
    # 11", google/sanitizers#1322); leaks are still found everywhere else.
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0}
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
    (cd build/test && xvfb-run -a -s "-screen 0 1280x1024x24" \
      ctest --output-on-failure -j "$jobs" --timeout 600 "$@")
    scripts/fuzz.sh 30
    ;;
  *)
    echo "dev.sh: unknown command '$cmd' (expected run, test, bench or deps)" >&2
    exit 2
    ;;
esac
