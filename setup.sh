#!/usr/bin/env bash
# Set-up, build and run VolumetricIllumination on Debian 12.
#
#   ./setup.sh demo    install, build, render the shipped CT head lit by two coloured lights
#                      beside the same view with local shading only (volillum-demo.png)
#   ./setup.sh test    install, build, run every test, a benchmark smoke run and the
#                      sanitizer (ASan + UBSan) build's tests and fuzz corpus
#   ./setup.sh build   install and build only
#   ./setup.sh test-paraview-5.13
#                      the same tests against Debian 13's ParaView 5.13 (Qt 6), in a Debian 13
#                      root of its own made with debootstrap (VOLILLUM_DEBIAN13_ROOT, default
#                      ../volillum-debian13 beside the clone) and the build folder
#                      build-paraview-5.13/
#
# Installs Debian packages with apt-get (never libvtk9-dev or python3-vtk9: they would
# remove ParaView's pvpython), configures into build/ and builds with every core.
set -euo pipefail
cd "$(dirname "$0")"

# The -dev packages ParaView's CMake files look for, and what the tests and benchmarks run;
# each ParaView line adds its Qt (packages: Debian 12's ParaView 5.11 and Qt 5).
common_packages=(
  cmake g++ make pkg-config
  paraview-dev python3-paraview python3-dev
  libhdf5-openmpi-dev libnetcdf-dev libgdal-dev libutfcpp-dev libdouble-conversion-dev zlib1g-dev
  libtiff-dev libtheora-dev libpng-dev libopenmpi-dev liblzma-dev liblz4-dev libjpeg-dev
  libglew-dev libgl2ps-dev libfreetype-dev libavformat-dev libavcodec-dev libavutil-dev
  libswscale-dev libeigen3-dev libexpat1-dev libboost-dev libxml2-dev libx11-dev libxt-dev
  libgl-dev xvfb xauth mesa-utils libgl1-mesa-dri mpi-default-bin
  libtet1.5-dev libcgal-dev libgtest-dev libbenchmark-dev python3-matplotlib
)
packages=(
  "${common_packages[@]}"
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5x11extras5-dev qtxmlpatterns5-dev-tools
  libqt5opengl5-dev
)

# Installs the packages given that are missing (also run inside the Debian 13 root).
install_packages() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "setup.sh: installing ${missing[*]}"
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

build() {
  install_packages "${packages[@]}"
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j"$(nproc)"
  echo "setup.sh: installed and built in ${SECONDS} s"
}

# AddressSanitizer + UndefinedBehaviorSanitizer: a second build folder with the C++ tests
# and the CLI, run on the tests and on the fuzz corpus. Any report in the project's code
# fails; leaks inside the GL stack are suppressed by Testing/Sanitizers/lsan.supp.
sanitize() {
  local flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
  # -g1: line tables only, enough for the reports' stacks (and 15 % less compile time than -g).
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DCMAKE_MODULE_LINKER_FLAGS="-fsanitize=address,undefined"
  cmake --build build-asan -j"$(nproc)" --target VolIllumKernelTests VolIllumFilterTests volillum-render
  echo "setup.sh: sanitizer build done after ${SECONDS} s"
  for tests in VolIllumKernelTests VolIllumFilterTests; do
    ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$PWD/Testing/Sanitizers/lsan.supp" \
      UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 "build-asan/bin/$tests"
  done
  echo "setup.sh: sanitized tests passed after ${SECONDS} s"
  VOLILLUM_SANITIZED_CLI="$PWD/build-asan/bin/volillum-render" python3 Testing/Fuzz/run_fuzz.py \
    --cli Testing/Sanitizers/sanitized-cli.sh --pvpython pvpython --no-filters --memory-limit 0 \
    --plugin build/lib/paraview-5.11/plugins/VolumetricIllumination/VolumetricIllumination.so \
    --corpus build-asan/fuzz-corpus --generate --jobs 2
}

# Debian 13 (trixie) and its ParaView 5.13: Qt 6 and the libraries 5.13's CMake files look for
# besides.
packages_debian13=(
  "${common_packages[@]}"
  qt6-base-dev qt6-tools-dev qt6-svg-dev qt6-5compat-dev qt6-declarative-dev libqt6opengl6-dev
  qt6-base-private-dev libcli11-dev libfmt-dev nlohmann-json3-dev libpugixml-dev libprotobuf-dev
  protobuf-compiler libcgns-dev
)

# The Debian mirror this machine's apt uses (the root comes from the same one).
debian_mirror() {
  local uri
  uri=$(grep -hoE '^(URIs:|deb) +https?://[^ ]+/debian/?( |$)' /etc/apt/sources.list.d/*.sources \
    /etc/apt/sources.list 2>/dev/null | grep -oE 'https?://[^ ]+' | head -n 1 || true)
  echo "${uri:-http://deb.debian.org/debian}"
}

# Build and run the whole ctest suite against ParaView 5.13 inside a Debian 13 root: made once
# with debootstrap (and reused), /proc, /dev, /sys, the clone (/src) and ../shared (/shared)
# bound while it runs and unbound after, also on failure.
test_paraview_513() {
  # Globals: the EXIT trap unbinds after this function has returned.
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  local root
  root=$(realpath -m "${VOLILLUM_DEBIAN13_ROOT:-$PWD/../volillum-debian13}")
  install_packages debootstrap
  if [ ! -x "$root/usr/bin/apt-get" ] || [ ! -e "$root/.volillum-debootstrap-done" ]; then
    $sudo debootstrap --variant=minbase trixie "$root" "$(debian_mirror)"
    $sudo touch "$root/.volillum-debootstrap-done"
  fi
  mounts=()
  unbind() {
    local i
    for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do $sudo umount -l "${mounts[i]}" || true; done
  }
  trap unbind EXIT
  bind() {
    $sudo mkdir -p "$2"
    mountpoint -q "$2" || { $sudo mount --bind "$1" "$2" && mounts+=("$2"); }
  }
  bind /proc "$root/proc"
  bind /dev "$root/dev"
  bind /sys "$root/sys"
  bind "$PWD" "$root/src"
  [ -d ../shared ] && bind "$(realpath ../shared)" "$root/shared"
  $sudo cp /etc/resolv.conf "$root/etc/resolv.conf"
  $sudo chroot "$root" /bin/bash -c \
    "set -euo pipefail; $(declare -f install_packages); install_packages ${packages_debian13[*]}"
  $sudo chroot "$root" /bin/bash -s <<'EOS'
set -euo pipefail
# Debian 13's ParaView CMake files name its Python modules X.so; Debian installs them as
# X.cpython-313-x86_64-linux-gnu.so, and find_package(ParaView) stops at the first name that
# is missing. Inside this root only: a link of each missing name to the installed module.
grep -rhoE '"\$\{_IMPORT_PREFIX\}/lib/python3/dist-packages/[^"]*\.so"' \
  /usr/lib/x86_64-linux-gnu/cmake/paraview-5.13 | tr -d '"' | sed 's|^${_IMPORT_PREFIX}|/usr|' |
  sort -u | while read -r module; do
    installed="${module%.so}.cpython-313-x86_64-linux-gnu.so"
    if [ ! -e "$module" ] && [ -e "$installed" ]; then
      ln -s "$(basename "$installed")" "$module"
    fi
  done
EOS
  $sudo chroot "$root" /usr/bin/env VTK_SMP_BACKEND_IN_USE=STDThread /bin/bash -s <<'EOS'
set -euo pipefail
cd /src
# -Wno-dev: 5.13's CMake files warn about policies newer than they set, at every configure.
cmake -S . -B build-paraview-5.13 -DCMAKE_BUILD_TYPE=Release -DVOLILLUM_SHARED_DATA=/shared/data \
  -Wno-dev
cmake --build build-paraview-5.13 -j"$(nproc)"
cd build-paraview-5.13
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j"$(nproc)"
EOS
}

export VTK_SMP_BACKEND_IN_USE=STDThread

case "${1:-}" in
  demo)
    build
    xvfb-run -a build/bin/volillum-render Data/headsq.vti --config Data/demo.json \
      --output "$PWD/volillum-demo.png"
    ;;
  test)
    build
    # One X server for the tests (each xvfb-run start is a chance for a display race);
    # -noreset keeps it from resetting whenever its last client leaves, which a program
    # connecting at that moment sees as a bad connection. The benchmarks' smoke runs are
    # the README's commands, run by the test README.CommandsRunAsWritten. Tests run as many at
    # a time as there are cores (those that must run alone say so: RUN_SERIAL).
    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" bash -c 'set -e
      (cd build && ctest --output-on-failure -j"$(nproc)")
      echo "setup.sh: tests passed after ${SECONDS} s"
      ./setup.sh sanitize
      echo "setup.sh: sanitizer stage passed after ${SECONDS} s"'
    ;;
  build)
    build
    ;;
  sanitize)
    # The sanitizer stage of "test" (run by it under its X server; needs a display).
    sanitize
    ;;
  test-paraview-5.13)
    test_paraview_513
    echo "setup.sh: ParaView 5.13's tests passed in ${SECONDS} s"
    ;;
  *)
    echo "usage: ./setup.sh demo | test | build | sanitize | test-paraview-5.13" >&2
    exit 2
    ;;
esac
