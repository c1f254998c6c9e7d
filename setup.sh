#!/usr/bin/env bash
# Set-up, build and run VolumetricIllumination on Debian 12.
#
#   ./setup.sh demo    install, build, render the demo phantom lit by three coloured lights
#   ./setup.sh test    install, build, run every test and a benchmark smoke run
#   ./setup.sh build   install and build only
#
# Installs Debian packages with apt-get (never libvtk9-dev or python3-vtk9: they would
# remove ParaView's pvpython), configures into build/ and builds with every core.
set -euo pipefail
cd "$(dirname "$0")"

packages=(
  cmake g++ make pkg-config
  paraview-dev python3-paraview python3-dev
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5x11extras5-dev qtxmlpatterns5-dev-tools
  libqt5opengl5-dev libhdf5-openmpi-dev libnetcdf-dev libgdal-dev libutfcpp-dev
  libdouble-conversion-dev zlib1g-dev libtiff-dev libtheora-dev libpng-dev libopenmpi-dev
  liblzma-dev liblz4-dev libjpeg-dev libglew-dev libgl2ps-dev libfreetype-dev
  libavformat-dev libavcodec-dev libavutil-dev libswscale-dev libeigen3-dev libexpat1-dev
  libboost-dev libxml2-dev libx11-dev libxt-dev libgl-dev
  xvfb xauth mesa-utils libgl1-mesa-dri mpi-default-bin
  libtet1.5-dev libcgal-dev libgtest-dev libbenchmark-dev
)

install_packages() {
  local missing=()
  for p in "${packages[@]}"; do
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
  install_packages
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j"$(nproc)"
}

export VTK_SMP_BACKEND_IN_USE=STDThread

case "${1:-}" in
  demo)
    build
    xvfb-run -a build/bin/volillum-render --output "$PWD/volillum-demo.png"
    ;;
  test)
    build
    # One X server for the tests and the benchmark smoke runs (each xvfb-run start is a
    # chance for a display race).
    xvfb-run -a bash -c 'set -e
      (cd build && ctest --output-on-failure)
      build/bin/volillum-benchmark --smoke --json build/benchmark-smoke.json
      build/bin/volillum-unstructured-benchmark --smoke
      pvpython Testing/Benchmarks/IlluminatedVolumeBenchmark.py \
        build/lib/paraview-5.11/plugins/VolumetricIllumination/VolumetricIllumination.so \
        ../shared/data --smoke --json build/representation-benchmark-smoke.json'
    ;;
  build)
    build
    ;;
  *)
    echo "usage: ./setup.sh demo | test | build" >&2
    exit 2
    ;;
esac
