#!/usr/bin/env bash
# Installs every Debian 12 package ggk needs to build, test, benchmark and analyse.
# Idempotent: prints nothing and changes nothing when all packages are present.
# libopenblas0-pthread: Eigen's dense products, CHOLMOD and UMFPACK run on the BLAS
# (libblas.so.3), called from many threads at once. OpenBLAS is ~8x faster than the
# reference BLAS; its pthread build is safe to call concurrently (Debian's serial
# build is not) and ggk sets it to one thread per call (kernels/blas_runtime.hpp).
# libblas-dev gives the libblas.so that ggk links; libblas.so.3 at run time is the
# highest-priority alternative, the pthread OpenBLAS.
# slurm-wlm, munge: a one-node Slurm for running the README's cluster recipes
# (scripts/slurm-local.sh, scripts/slurm-recipes.sh); srun --mpi=pmix needs nothing
# more: Slurm's mpi_pmix plugin comes with slurm-wlm (slurm-wlm-basic-plugins) and
# OpenMPI's PMIx (libpmix2) with libopenmpi3.
# python3-dev, pybind11-dev: the CPython that the python_env task embeds
# (engine/tasks/python_env/).
# python3-xarray, python3-setuptools, -pip and -venv: the package python/ggk_results,
# its labelled views and its install into a venv without a package index
# (python/README.md, tests/python/test_install.py); python3-pytest runs tests/python.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git clang-format
  clang libclang-rt-14-dev
  libeigen3-dev libspectra-dev libsuitesparse-dev libblas-dev liblapack-dev libopenblas0-pthread libhdf5-dev hdf5-tools libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtomlplusplus-dev libcli11-dev librandom123-dev
  libopenmpi-dev openmpi-bin
  slurm-wlm munge
  libboost-dev
  python3-dev pybind11-dev
  python3-h5py python3-matplotlib python3-numpy python3-scipy python3-pandas
  python3-xarray python3-setuptools python3-pip python3-venv python3-pytest
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
