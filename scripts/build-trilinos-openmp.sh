#!/usr/bin/env bash
# Builds the Trilinos subset PoreSPH needs with Kokkos' Serial AND OpenMP
# backends (Debian's Trilinos has Serial only), from Debian's own source
# package, into a prefix outside the source tree. Once: an existing install
# is reused. Then configure PoreSPH with `cmake --preset openmp`.
#
#   scripts/build-trilinos-openmp.sh
#
# Environment: TRILINOS_OPENMP_PREFIX (default /opt/poresph-trilinos-openmp),
# TRILINOS_WORK (sources and build tree, default /var/tmp/poresph-trilinos),
# JOBS (default 2).
set -euo pipefail

prefix="${TRILINOS_OPENMP_PREFIX:-/opt/poresph-trilinos-openmp}"
work="${TRILINOS_WORK:-/var/tmp/poresph-trilinos}"
jobs="${JOBS:-2}"
if [ -f "$prefix/lib/cmake/Trilinos/TrilinosConfig.cmake" ]; then
  echo "build-trilinos-openmp: $prefix already holds Trilinos; reusing it"
  exit 0
fi
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
start=$(date +%s)

# Build tools and the libraries Trilinos links (BLAS/LAPACK for Teuchos).
$sudo apt-get install -y -qq --no-install-recommends g++ cmake ninja-build ccache dpkg-dev \
  libopenmpi-dev openmpi-bin libblas-dev liblapack-dev

# The source package (scripts/debian-source.sh).
source "$(dirname "${BASH_SOURCE[0]}")/debian-source.sh"
fetch_debian_source trilinos "$work"

# Only what PoreSPH uses: Kokkos (Serial + OpenMP), Teuchos, Zoltan2 and
# what Zoltan2 requires; no tests, examples, Fortran, Epetra, Sphynx, and no
# explicit template instantiation (PoreSPH instantiates what it uses).
cmake -S "$source_dir" -B "$work/build" -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" -DBUILD_SHARED_LIBS=ON \
  -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
  -DTPL_ENABLE_MPI=ON -DTrilinos_ENABLE_OpenMP=ON \
  -DTrilinos_ENABLE_ALL_PACKAGES=OFF -DTrilinos_ENABLE_ALL_OPTIONAL_PACKAGES=OFF \
  -DTrilinos_ENABLE_Kokkos=ON -DTrilinos_ENABLE_Teuchos=ON -DTrilinos_ENABLE_Zoltan2=ON \
  -DTrilinos_ENABLE_Zoltan2Sphynx=OFF -DTrilinos_ENABLE_Epetra=OFF \
  -DKokkos_ENABLE_SERIAL=ON -DKokkos_ENABLE_OPENMP=ON \
  -DTrilinos_ENABLE_TESTS=OFF -DTrilinos_ENABLE_EXAMPLES=OFF -DTrilinos_ENABLE_Fortran=OFF \
  -DTrilinos_ENABLE_EXPLICIT_INSTANTIATION=OFF \
  -DTpetra_INST_INT_LONG_LONG=ON -DTpetra_INST_INT_INT=OFF -DTpetra_INST_DOUBLE=ON \
  -DTpetra_INST_COMPLEX_DOUBLE=OFF -DTpetra_INST_FLOAT=OFF
cmake --build "$work/build" -j "$jobs"
$sudo cmake --install "$work/build"

elapsed=$(( $(date +%s) - start ))
echo "build-trilinos-openmp: installed into $prefix in $((elapsed / 60)) min $((elapsed % 60)) s" | $sudo tee "$prefix/BUILD-TIME.txt"
