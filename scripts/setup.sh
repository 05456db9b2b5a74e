#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: install the packages, build ggk, run
# the default job (jobs/quick.toml) and say where its results are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p results
build/ggk run jobs/quick.toml --overwrite
build/ggk info results/quick.h5
