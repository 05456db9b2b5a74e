#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for CI and for trying the README's
# cluster recipes (scripts/slurm-recipes.sh). Usage, as root:
#   eval "$(bash scripts/slurm-local.sh start)"   # prints: export SLURM_CONF=...
#   sinfo; sbatch --wait ...
#   bash scripts/slurm-local.sh status
#   bash scripts/slurm-local.sh stop               # cancels jobs, stops every daemon
# Needs Debian 12's slurm-wlm and munge (scripts/install-deps.sh). Everything --
# munge key and socket, slurm.conf, state, spool, logs, pid files -- lives in
# $GGK_SLURM_DIR (default ${TMPDIR:-/tmp}/ggk-slurm), which `stop` removes; nothing
# is written to /etc or /var. The node is this machine (slurmd -C: its CPUs, sockets,
# cores and memory), in one partition `ggk`; SlurmUser=root,
# ProctrackType=proctrack/linuxproc (no cgroups needed), SelectType=select/cons_tres
# with CR_Core, TaskPlugin=task/affinity (steps are bound to their CPUs, as on most
# clusters). `start` waits (at most 60 s) until sinfo shows the node idle.
set -euo pipefail

dir=${GGK_SLURM_DIR:-${TMPDIR:-/tmp}/ggk-slurm}
conf=$dir/slurm.conf
wait_seconds=60

die() {
  echo "slurm-local: $*" >&2
  exit 1
}

# The pid in a pid file, when that process is alive.
live_pid() {
  local file=$1 pid
  [ -r "$file" ] || return 1
  pid=$(cat "$file")
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null && echo "$pid"
}

daemons=(slurmd slurmctld munged)

status() {
  local name any=0
  for name in "${daemons[@]}"; do
    if pid=$(live_pid "$dir/$name.pid"); then
      echo "$name: running (pid $pid)"
      any=1
    else
      echo "$name: not running"
    fi
  done
  if [ "$any" -eq 1 ] && [ -r "$conf" ]; then
    echo "export SLURM_CONF=$conf"
    SLURM_CONF=$conf sinfo || true
    SLURM_CONF=$conf squeue || true
  fi
  [ "$any" -eq 1 ]
}

show_logs() {
  local log
  for log in "$dir"/*.log; do
    [ -r "$log" ] || continue
    echo "--- $log (last lines)" >&2
    tail -n 15 "$log" >&2
  done
}

start() {
  [ "$(id -u)" -eq 0 ] || die "start needs root (SlurmUser=root, munged's key)"
  for tool in munged mungekey slurmctld slurmd sinfo; do
    command -v "$tool" >/dev/null || die "$tool not found: install slurm-wlm and munge (bash scripts/install-deps.sh)"
  done
  for name in "${daemons[@]}"; do
    if pid=$(live_pid "$dir/$name.pid"); then
      die "$name already runs from $dir (pid $pid): bash scripts/slurm-local.sh stop first"
    fi
  done
  rm -rf "$dir"
  mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
  chmod 0700 "$dir/munge"

  mungekey --create --keyfile="$dir/munge/munge.key" >/dev/null 2>&1 ||
    die "mungekey could not create $dir/munge/munge.key"
  chmod 0400 "$dir/munge/munge.key"
  munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/socket" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" \
    --seed-file="$dir/munge/seed" --force ||
    { show_logs; die "munged did not start"; }

  # slurmd -C: this machine as Slurm sees it (CPUs, boards, sockets, cores,
  # threads, RealMemory); its NodeName is the short host name, which slurmd
  # looks itself up by.
  local node host
  node=$(slurmd -C | head -n 1)
  host=$(hostname -s)
  [[ $node == NodeName=* ]] || die "slurmd -C printed no node line: $node"
  cat >"$conf" <<CONF
# Written by scripts/slurm-local.sh: a one-node cluster for CI.
ClusterName=ggk-local
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=60
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=ggk Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
CONF
  # UpTime= and such (slurmd -C's second line) are not slurm.conf keys: only the first line is used.

  export SLURM_CONF=$conf
  slurmctld -i || { show_logs; die "slurmctld did not start"; }
  slurmd || { show_logs; die "slurmd did not start"; }

  local waited=0 state=""
  while [ "$waited" -lt "$wait_seconds" ]; do
    state=$(sinfo --noheader --nodes="$host" --format=%T 2>/dev/null || true)
    [ "$state" = "idle" ] && break
    sleep 1
    waited=$((waited + 1))
  done
  if [ "$state" != "idle" ]; then
    show_logs
    stop >/dev/null 2>&1 || true
    die "node $host not idle after ${wait_seconds} s (sinfo: '${state:-no answer}'); daemons stopped"
  fi
  echo "slurm-local: node $host idle after ${waited} s; config in $conf" >&2
  echo "export SLURM_CONF=$conf"
}

# Sends TERM to a daemon from its pid file and waits (at most 15 s) for it to go;
# KILL after that.
stop_daemon() {
  local name=$1 pid tries=0
  pid=$(live_pid "$dir/$name.pid") || return 0
  kill -TERM "$pid" 2>/dev/null || true
  while kill -0 "$pid" 2>/dev/null && [ "$tries" -lt 150 ]; do
    sleep 0.1
    tries=$((tries + 1))
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "slurm-local: $name (pid $pid) ignored TERM for 15 s; killing it" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
}

stop() {
  if [ -r "$conf" ] && live_pid "$dir/slurmctld.pid" >/dev/null; then
    # Jobs first, while slurmd can still end their steps (slurmstepd).
    export SLURM_CONF=$conf
    scancel --full $(squeue --noheader --format=%i 2>/dev/null) 2>/dev/null || true
    local tries=0
    while [ -n "$(squeue --noheader 2>/dev/null)" ] && [ "$tries" -lt 30 ]; do
      sleep 1
      tries=$((tries + 1))
    done
  fi
  local name
  for name in "${daemons[@]}"; do stop_daemon "$name"; done
  local left=""
  for name in "${daemons[@]}"; do
    if pid=$(live_pid "$dir/$name.pid"); then left+=" $name($pid)"; fi
  done
  [ -z "$left" ] || die "still running:$left"
  rm -rf "$dir"
  echo "slurm-local: stopped" >&2
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *)
    echo "usage: $0 start|stop|status  (GGK_SLURM_DIR: where it lives, default ${TMPDIR:-/tmp}/ggk-slurm)" >&2
    exit 2
    ;;
esac
