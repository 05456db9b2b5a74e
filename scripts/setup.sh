#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: install the packages, build ggk, and
# run a reduced reproduction of the paper (the arm and Khepera paper jobs with 10
# and 4 runs, under 2 minutes on 2 cores: scripts/reproduce.sh --quick), ending with the paper's
# figures on disk and where they are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
bash scripts/reproduce.sh --quick
