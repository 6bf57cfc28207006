#!/usr/bin/env bash
# PoreSPH set-up on Debian bookworm: installs what is missing (apt-get),
# configures and builds, then runs the default scene (`run`) or every test
# through CTest (`test`).
#
#   scripts/setup.sh run  [extra poresph arguments]
#   scripts/setup.sh test [extra ctest arguments]
#   scripts/setup.sh build
#   scripts/setup.sh tools   # also the reference tools (FreeFem++ for perf/stokes_reference.py, SciPy for
#                            # perf/periodic_stokes_spheres.py); `test` installs them too
#   scripts/setup.sh openfoam  # the tools, and OpenFOAM v1912 (Debian's `openfoam`) for
#                              # perf/openfoam_side_by_side.py; not part of `test` (large, and no CTest needs it)
#
# Environment: BUILD_DIR (default build), CMAKE_ARGS (extra configure flags).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${BUILD_DIR:-$here/build}"
mode="${1:-run}"
[ $# -gt 0 ] && shift

# Debian's Trilinos 13.2: Zoltan2's headers and CMake targets also need the
# Tpetra/Xpetra/Epetra/KokkosKernels/Zoltan headers and PT-Scotch (see docs/building.md).
packages=(
  g++ cmake ccache ninja-build pkg-config
  libtrilinos-kokkos-dev libtrilinos-teuchos-dev libtrilinos-zoltan2-dev
  libtrilinos-zoltan-dev libtrilinos-tpetra-dev libtrilinos-xpetra-dev
  libtrilinos-thyra-dev libtrilinos-epetra-dev libtrilinos-epetraext-dev
  libtrilinos-triutils-dev libtrilinos-rtop-dev libtrilinos-kokkos-kernels-dev
  libptscotch-dev libopenmpi-dev openmpi-bin libhdf5-openmpi-dev libgtest-dev nlohmann-json3-dev
  libpng-dev libtiff-dev
  python3 python3-numpy python3-matplotlib python3-h5py python3-pil
)

# Not needed to build; their tests run where they are installed (`test`, `tools`).
tool_packages=(freefem++ python3-scipy)
# The OpenFOAM yardstick (docs/openfoam.md): simpleFoam, blockMesh, subsetMesh, decomposePar on /usr/bin;
# they need WM_PROJECT_DIR=/usr/share/openfoam (or `. /usr/share/openfoam/etc/bashrc`).
openfoam_packages=(openfoam time)

install_missing() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "setup: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

configure_and_build() {
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    cmake -S "$here" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      "${launcher[@]}" ${CMAKE_ARGS:-}
  fi
  cmake --build "$build_dir" -j "${JOBS:-2}"
}

if [ "$mode" = tools ] || [ "$mode" = test ]; then packages+=("${tool_packages[@]}"); fi
if [ "$mode" = openfoam ]; then packages+=("${tool_packages[@]}" "${openfoam_packages[@]}"); fi
install_missing
configure_and_build

# Open MPI refuses root and more ranks than cores unless told.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1

case "$mode" in
  run)   exec "$build_dir/poresph" "$here/input/poiseuille.xml" --output "$build_dir/run-poiseuille" "$@" ;;
  test)  cd "$build_dir" && exec ctest --output-on-failure -j "${JOBS:-2}" "$@" ;;
  build|tools|openfoam) ;;
  *) echo "usage: $0 run|test|build|tools|openfoam" >&2; exit 2 ;;
esac
