#!/usr/bin/env bash
# Runs the README's cluster recipes, as the README writes them, on a real Slurm
# (a one-node cluster on this machine: scripts/slurm-local.sh) and checks with
# `ggk diff` that each writes the file a single process writes. CI runs it after
# the reduced sweeps; locally, as root, after scripts/install-deps.sh and a build:
#   bash scripts/slurm-recipes.sh [BUILD_DIR]            (default: build)
# REFERENCE=file.h5 skips computing the single-process file of jobs/ci-khepera.toml
# (.ci/run passes the one its reduced sweep wrote).
#
# The recipes are the fenced blocks after `<!-- slurm-recipe: NAME -->` in
# README.md (one-allocation, array, merge), taken byte for byte. Each runs in a
# scratch folder shaped like the repository (build/, jobs/, results/) whose
# jobs/khepera-paper.toml is the reduced jobs/ci-khepera.toml (3 runs), and with
# sbatch options for this machine's 2 CPUs, which take precedence over the
# recipes' #SBATCH lines: one-allocation on 1 node x 2 ranks x 1 CPU (srun
# --mpi=pmix: two MPI ranks), array as --array=0-1 x 1 CPU (two shards), then the
# merge block. About a minute on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
ggk=$build/ggk
readme=$root/README.md
start=$SECONDS

die() {
  echo "slurm-recipes: $*" >&2
  exit 1
}
[ -x "$ggk" ] || die "$ggk not found: build first (bash scripts/build.sh)"

# The fenced block right after the marker line `<!-- slurm-recipe: NAME -->`.
recipe() {
  local name=$1 text
  text=$(awk -v marker="<!-- slurm-recipe: $name -->" '
    $0 == marker { found = 1; next }
    found == 1 && /^```/ { found = 2; next }
    found == 1 { exit 1 }                      # the block must follow the marker
    found == 2 && /^```/ { exit 0 }
    found == 2 { print }
  ' "$readme") || die "README.md: the line after '<!-- slurm-recipe: $name -->' is not a fenced block"
  [ -n "$text" ] || die "README.md has no recipe '$name' (<!-- slurm-recipe: $name --> before a fenced block)"
  printf '%s\n' "$text"
}

scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-slurm-recipes-XXXXXX")
started_slurm=0
cleanup() {
  [ "$started_slurm" -eq 1 ] && bash "$root/scripts/slurm-local.sh" stop || true
  rm -rf "$scratch"
}
trap cleanup EXIT

# A folder like the repository for a recipe: build/ -> the build, jobs/ -> the
# repository's jobs (arenas, maps) but khepera-paper.toml = ci-khepera.toml.
workspace() {
  local dir=$scratch/$1 entry
  mkdir -p "$dir/jobs" "$dir/results"
  ln -s "$build" "$dir/build"
  for entry in "$root"/jobs/*; do ln -s "$entry" "$dir/jobs/"; done
  rm "$dir/jobs/khepera-paper.toml"
  cp "$root/jobs/ci-khepera.toml" "$dir/jobs/khepera-paper.toml"
  echo "$dir"
}

# Shows a recipe's job output when it failed.
show_outputs() {
  local file
  for file in "$1"/slurm-*.out; do
    [ -r "$file" ] || continue
    echo "--- $file" >&2
    cat "$file" >&2
  done
}

one_allocation=$(recipe one-allocation)
array=$(recipe array)
merge=$(recipe merge)

if [ -z "${SLURM_CONF:-}" ] || ! sinfo >/dev/null 2>&1; then
  eval "$(bash "$root/scripts/slurm-local.sh" start)"
  started_slurm=1
fi
sinfo

reference=${REFERENCE:-}
if [ -z "$reference" ]; then
  reference=$scratch/reference.h5
  echo "slurm-recipes: the single-process file (jobs/ci-khepera.toml -j 2)"
  "$ggk" run "$root/jobs/ci-khepera.toml" -j 2 -q -o "$reference"
fi

echo "slurm-recipes: one allocation, srun (2 ranks x 1 CPU on one node):"
printf '%s\n' "$one_allocation" | sed 's/^/    /'
dir=$(workspace one-allocation)
printf '%s\n' "$one_allocation" >"$dir/recipe.sh"
t=$SECONDS
(cd "$dir" && sbatch --wait --quiet --nodes=1 --ntasks-per-node=2 --cpus-per-task=1 \
  --output=slurm-%j.out recipe.sh) || { show_outputs "$dir"; die "the one-allocation recipe failed"; }
# (Had srun started two single processes instead of one job on two ranks, the
# second would have found the output locked and failed the job.)
cat "$dir"/slurm-*.out
! grep -q "ggk: warning" "$dir"/slurm-*.out || die "ggk warned under the one-allocation recipe"
"$ggk" diff "$reference" "$dir/results/ci-khepera.h5"
echo "slurm-recipes: one allocation equals the single-process file ($((SECONDS - t)) s)"

echo "slurm-recipes: job array (2 tasks x 1 CPU), then merge:"
printf '%s\n' "$array" "$merge" | sed 's/^/    /'
dir=$(workspace array)
printf '%s\n' "$array" >"$dir/recipe.sh"
t=$SECONDS
(cd "$dir" && sbatch --wait --quiet --array=0-1 --cpus-per-task=1 \
  --output=slurm-%A_%a.out recipe.sh) || { show_outputs "$dir"; die "the array recipe failed"; }
ls "$dir/results"
(cd "$dir" && bash -euo pipefail -c "$merge") || die "the merge recipe failed"
"$ggk" diff "$reference" "$dir/results/ci-khepera.h5"
echo "slurm-recipes: array + merge equals the single-process file ($((SECONDS - t)) s)"

echo "slurm-recipes: every README recipe ran on Slurm and matched ($((SECONDS - start)) s)"
