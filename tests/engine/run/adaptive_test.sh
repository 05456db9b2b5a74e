#!/usr/bin/env bash
# Adaptive studies (engine/run/adaptive_runner.hpp) through the real ggk binary.
# One case per call (tests/CMakeLists.txt):
#   looks      jobs/ci-adaptive.toml runs its looks until no cell asks for more:
#              `info --adaptive` shows each cell decided with the runs it took,
#              the file holds exactly the runs the rule asked for, and -j 1
#              equals -j 2 (ggk diff)
#   resume     Ctrl-C mid-study, then the printed command, equals the study run
#              at once; so does a study capped at 10 runs grown by --resume to
#              the job's 60 (each look is a growth by runs)
#   shards     --shard I/N splits the study by run configurations: the shards
#              merged (--shards-of) equal the study run whole, for a comparison
#              over a fit axis (each configuration a shard) and over a study
#              axis (the compared configurations in one shard, more shards
#              refused); a shard interrupted and resumed with the printed
#              command equals; info names a shard's scope and the study's
#              cells; a merge missing a shard, or with a gap in a shard's runs,
#              is refused naming what lacks runs, and with --allow-partial its
#              printed command finishes it equal
#   cells      each cell stops on its own: with kernels 2 and 8 compared, the
#              runs after a cell is decided hold only the open cells' fits;
#              -j 1, interrupted and resumed, shards merged, and a study grown
#              by kernels 2 or 8 (its runs extended, or only renumbered) equal
#              the study run at once
#   refusals   a rule the study cannot follow is refused before anything runs,
#              exit 2, naming the key: an axis not swept, a value not on it, a
#              batch above runs, a metric with no known range, a metric the
#              task lacks (at the first look); --runs
# Environment: GGK (the binary), GGK_SOURCE_DIR.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-adaptive-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
status_of() { local s=0; "$@" >"$scratch/out" 2>"$scratch/err" || s=$?; echo $s; }
# ggk ARGS... in the background, SIGINT once FILE exists: prints its status,
# its stderr in $scratch/err.
interrupted_run() {
  local file=$1 pid s=0 deadline=$((SECONDS + 240)); shift
  set -m  # job control: SIGINT not ignored (as a background job of a script starts)
  "$GGK" "$@" 2>"$scratch/err" >/dev/null & pid=$!
  set +m
  until [ -e "$file" ] || [ "$SECONDS" -ge "$deadline" ]; do sleep 0.05; done
  [ -e "$file" ] || fail "no run written in 240 s"
  kill -INT $pid
  wait $pid || s=$?
  echo $s
}
# ggk run $job -j 1 -o OUT interrupted once OUT exists, then resumed with the
# command it printed: equal to REF.
interrupted_and_resumed() {
  local out=$1 ref=$2 s command
  s=$(interrupted_run "$out" run "$job" -j 1 -o "$out")
  [ "$s" = 130 ] || fail "SIGINT: status $s: $(cat "$scratch/err")"
  command=$(grep -o 'with `[^`]*`' "$scratch/err" | head -n 1 | sed 's/^with `//; s/`$//')
  bash -c "$command" 2>"$scratch/resume-err" || fail "the printed command failed: $(cat "$scratch/resume-err")"
  "$GGK" diff "$ref" "$out" >/dev/null || fail "the resumed study differs"
}

mkdir -p "$scratch/maps"
cp "$GGK_SOURCE_DIR/jobs/maps/four-rooms.txt" "$scratch/maps/"
job="$scratch/ci-adaptive.toml"
cp "$GGK_SOURCE_DIR/jobs/ci-adaptive.toml" "$job"

case $case_name in
looks)
  "$GGK" run "$job" -q -j 2 -o "$scratch/a.h5"
  "$GGK" info --adaptive "$scratch/a.h5" >"$scratch/cells"
  grep -q "done: 2 of 2 cells decided (+ 2, - 0), 0 open, 0 capped" "$scratch/cells" ||
    fail "cells: $(cat "$scratch/cells")"
  # The runs the rule asked for, and no more.
  wanted=$(sed -n 's/.*runs per configuration \([0-9, ]*\) (\([0-9]*\) of.*/\2/p' "$scratch/cells")
  [ -n "$wanted" ] && [ "$wanted" -lt 120 ] || fail "runs per configuration: $(cat "$scratch/cells")"
  "$GGK" info "$scratch/a.h5" | grep "^runs:     $wanted of 120 complete" >/dev/null ||
    fail "the file holds other runs than $wanted: $("$GGK" info "$scratch/a.h5" | grep runs:)"
  "$GGK" run "$job" -q -j 1 -o "$scratch/b.h5"
  "$GGK" diff "$scratch/a.h5" "$scratch/b.h5" >/dev/null || fail "-j 1 differs from -j 2"
  ;;
resume)
  "$GGK" run "$job" -q -j 2 -o "$scratch/ref.h5"
  interrupted_and_resumed "$scratch/cut.h5" "$scratch/ref.h5"
  # Capped at 10 runs: every cell capped or decided within 10; then grown.
  "$GGK" run "$job" -q --set runs=10 -o "$scratch/grown.h5"
  "$GGK" info --adaptive "$scratch/grown.h5" | grep "capped" >/dev/null || fail "runs = 10 capped nothing"
  "$GGK" run "$job" -q --resume -o "$scratch/grown.h5"
  "$GGK" diff "$scratch/ref.h5" "$scratch/grown.h5" >/dev/null || fail "the grown study differs"
  ;;
shards)
  "$GGK" run "$job" -q -j 2 -o "$scratch/whole.h5"
  for i in 0 1; do "$GGK" run "$job" -q -j 2 --shard $i/2 -o "$scratch/s.h5"; done
  "$GGK" info --adaptive "$scratch/s.shard-1-of-2.h5" >"$scratch/cells"
  grep -q "a shard of 1 of the 2 configurations.*over the study's 2 cells" "$scratch/cells" ||
    fail "info of a shard: $(cat "$scratch/cells")"
  "$GGK" merge "$scratch/s.h5" --shards-of "$job" 2>/dev/null
  "$GGK" diff "$scratch/whole.h5" "$scratch/s.h5" >/dev/null || fail "shards by basis differ"
  # Over the study axis: slip 0 and 0.1 in one shard, slip 0.2 (in no cell) the other.
  sed -e 's/^compare = .*/compare = "maze.slip=0.0,0.1"/' -e 's/^runs = 60 /runs = 20 /' \
    -e 's/^"maze.slip" = .*/"maze.slip" = [0.0, 0.1, 0.2]/' "$job" >"$scratch/slip.toml"
  grep -q 'compare = "maze.slip' "$scratch/slip.toml" && grep -q '^runs = 20 ' "$scratch/slip.toml" ||
    fail "slip.toml: $(cat "$scratch/slip.toml")"
  "$GGK" validate "$scratch/slip.toml" -o "$scratch/slip.h5" | grep -q "2 cells over 3 run configurations, in 2 groups.*N up to 2" ||
    fail "validate names no shard limit: $("$GGK" validate "$scratch/slip.toml" -o "$scratch/slip.h5")"
  "$GGK" run "$scratch/slip.toml" -q -j 2 -o "$scratch/slip.h5"
  s=$(status_of "$GGK" run "$scratch/slip.toml" -q --shard 0/3 -o "$scratch/t.h5")
  [ "$s" = 2 ] && grep -q "form 2 groups.*use at most 2 shards" "$scratch/err" ||
    fail "--shard 0/3 of 2 groups: status $s: $(cat "$scratch/err")"
  out="$scratch/t.shard-0-of-2.h5"
  s=$(interrupted_run "$out" run "$scratch/slip.toml" -j 1 --shard 0/2 -o "$scratch/t.h5")
  if [ "$s" = 130 ]; then  # else it finished first
    command=$(grep -o 'with `[^`]*`' "$scratch/err" | head -n 1 | sed 's/^with `//; s/`$//')
    [[ $command == *"--shard 0/2"* ]] || fail "the printed command lacks the shard: $command"
    bash -c "$command" 2>"$scratch/resume-err" || fail "the printed command failed: $(cat "$scratch/resume-err")"
  fi
  # One shard alone: refused, naming the configuration that lacks runs.
  s=$(status_of "$GGK" merge "$scratch/part.h5" "$out")
  [ "$s" = 2 ] && grep -q "asks for runs of maze/config_002" "$scratch/err" ||
    fail "a merge missing a shard: status $s: $(cat "$scratch/err")"
  [ ! -e "$scratch/part.h5" ] || fail "a refused merge left its output"
  "$GGK" merge "$scratch/part.h5" "$out" --allow-partial 2>"$scratch/err"
  command=$(grep -o 'finish it with `[^`]*`' "$scratch/err" | sed 's/^finish it with `//; s/`$//')
  bash -c "$command -q" || fail "the finishing command failed: $command"
  "$GGK" diff "$scratch/slip.h5" "$scratch/part.h5" >/dev/null || fail "the finished study differs"
  "$GGK" run "$scratch/slip.toml" -q -j 2 --shard 1/2 -o "$scratch/t.h5"
  "$GGK" merge "$scratch/t.h5" --shards-of "$scratch/slip.toml" 2>/dev/null
  "$GGK" diff "$scratch/slip.h5" "$scratch/t.h5" >/dev/null || fail "shards by slip differ"
  # A shard with a gap (run 3 of its first configuration gone, as a shard stopped
  # mid-look may hold run 7 without run 6): the merge names that configuration.
  for i in 0 1; do cp "$scratch/t.shard-$i-of-2.h5" "$scratch/gap.shard-$i-of-2.h5"; done
  /usr/bin/python3 -c 'import sys, h5py; del h5py.File(sys.argv[1], "r+")["maze/config_000/run_003"]' \
    "$scratch/gap.shard-0-of-2.h5"
  s=$(status_of "$GGK" merge "$scratch/gap.h5" "$scratch/gap.shard-0-of-2.h5" "$scratch/gap.shard-1-of-2.h5")
  [ "$s" = 2 ] && grep -q "asks for runs of maze/config_000 that" "$scratch/err" ||
    fail "a merge with a gap: status $s: $(cat "$scratch/err")"
  ;;
cells)
  sed -i 's/^kernels = .*/kernels = [2, 8]/' "$job"
  "$GGK" run "$job" -q -j 2 -o "$scratch/ref.h5"
  "$GGK" info --adaptive "$scratch/ref.h5" >"$scratch/cells"
  grep -q "done: 4 of 4 cells decided" "$scratch/cells" || fail "cells: $(cat "$scratch/cells")"
  read -r held whole < <(sed -n 's/.*holding \([0-9]*\) of their \([0-9]*\) fits.*/\1 \2/p' "$scratch/cells")
  [ -n "$held" ] && [ "$held" -lt "$whole" ] || fail "no fit left out: $(cat "$scratch/cells")"
  # Run 0 holds every point; the last run of config_000 only the open cell's two.
  /usr/bin/python3 - "$scratch/ref.h5" "$held" <<'PY' || fail "the runs' fits are not the open cells'"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    counts = {c: [len(f[f"maze/{c}/{r}/fit_metrics"]) for r in sorted(f[f"maze/{c}"]) if r.startswith("run_")]
              for c in f["maze"] if c.startswith("config_")}
assert counts["config_000"][0] == 4 and counts["config_000"][-1] == 2, counts
assert sum(map(sum, counts.values())) == int(sys.argv[2]), counts
PY
  "$GGK" run "$job" -q -j 1 -o "$scratch/j1.h5"
  "$GGK" diff "$scratch/ref.h5" "$scratch/j1.h5" >/dev/null || fail "-j 1 differs from -j 2"
  interrupted_and_resumed "$scratch/cut.h5" "$scratch/ref.h5"
  for i in 0 1; do "$GGK" run "$job" -q -j 2 --shard $i/2 -o "$scratch/s.h5"; done
  "$GGK" merge "$scratch/s.h5" --shards-of "$job" 2>/dev/null
  "$GGK" diff "$scratch/ref.h5" "$scratch/s.h5" >/dev/null || fail "the merged shards differ"
  # Grown by a kernel count: from [8], runs after kernels 2's cell decided hold
  # 8's fits under other indices (only renumbered); from [2], new runs.
  for k in 8 2; do
    "$GGK" run "$job" -q -j 2 --set "sweep.kernels=[$k]" -o "$scratch/grown-$k.h5"
    "$GGK" run "$job" -q -j 2 --resume -o "$scratch/grown-$k.h5"
    "$GGK" diff "$scratch/ref.h5" "$scratch/grown-$k.h5" >/dev/null ||
      fail "grown from kernels [$k]: $("$GGK" diff "$scratch/ref.h5" "$scratch/grown-$k.h5" | tail -n 3)"
  done
  ;;
refusals)
  expect_refusal() {  # what-to-find, ggk arguments...
    local find=$1; shift
    local s; s=$(status_of "$GGK" "$@")
    [ "$s" = 2 ] && grep -q -- "$find" "$scratch/err" ||
      fail "$*: status $s, expected 2 naming '$find': $(cat "$scratch/err")"
  }
  expect_refusal "no axis 'kernel'" validate "$job" -o "$scratch/v.h5" --set 'adaptive.compare="kernel=4,8"'
  expect_refusal "has no value 'pvf'" validate "$job" -o "$scratch/v.h5" --set 'adaptive.compare="basis=ggk,pvf"'
  expect_refusal "adaptive.batch" validate "$job" -o "$scratch/v.h5" --set adaptive.batch=61
  expect_refusal "\[adaptive.range\] mean_steps_to_goal" validate "$job" -o "$scratch/v.h5" \
    --set 'adaptive.metrics=["mean_steps_to_goal"]'
  expect_refusal "no metric 'succes_rate'" run "$job" -q -o "$scratch/m.h5" \
    --set 'adaptive.metrics=["succes_rate"]' --set 'adaptive.range.succes_rate=[0.0, 1.0]'
  expect_refusal "without --runs" run "$job" -q -o "$scratch/s.h5" --runs 0:5
  sed '/^\[adaptive\]/,/^correction/d' "$job" >"$scratch/fixed.toml"
  "$GGK" run "$scratch/fixed.toml" -q --set runs=2 -o "$scratch/fixed.h5"
  expect_refusal "is no adaptive study" info --adaptive "$scratch/fixed.h5"
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
