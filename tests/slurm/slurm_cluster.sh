# A real one-node Slurm cluster on localhost, for tests and measurements.
# shellcheck shell=bash
# Source this file (bash), then:
#
#   slurm_cluster_missing     prints why a cluster cannot start here (not root,
#                             slurm-wlm or munge not installed) and returns 0;
#                             returns 1 when it can start
#   start_slurm_cluster       starts munged, slurmctld and slurmd with a
#                             generated configuration in a fresh temporary
#                             directory, waits until the node is idle, exports
#                             SLURM_CONF (the client commands sbatch, squeue,
#                             sinfo, scontrol read it) and sets:
#                               SLURM_CLUSTER_DIR   the temporary directory
#                               SLURM_CLUSTER_PIDS  "munged-pid slurmctld-pid slurmd-pid"
#                               SLURM_PARTITION     the partition's name
#                             and installs traps (EXIT, INT, TERM) that stop the
#                             cluster; returns non-zero (and stops what it
#                             started) when a daemon does not come up, with the
#                             daemons' logs on stderr
#   stop_slurm_cluster        cancels the cluster's jobs, stops every daemon by
#                             its pid (TERM, then KILL after 10 s) and removes
#                             the temporary directory; safe to call twice
#
# Nothing outside the temporary directory is used: munged gets its own key,
# socket, pid, seed and log files; the ports of slurmctld and slurmd are chosen
# free when the cluster starts; the machine's /etc/munge, /etc/slurm and
# systemd units are left alone. The cluster runs as root (SlurmUser=root):
# slurmd must be root to start jobs as their user.
#
# The functions also work in shells with set -e.
#
# Debian 12: apt-get install slurm-wlm munge (scripts/install-deps.sh has them
# in the test set). Slurm 22.05.

slurm_cluster_missing() {
  if [ "$(id -u)" != 0 ]; then
    echo "a Slurm cluster needs root (slurmd starts jobs as their user); running as $(id -un)"
    return 0
  fi
  local cmd
  for cmd in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
    if ! command -v "$cmd" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$cmd" ]; then
      echo "$cmd not found: install Debian's slurm-wlm and munge (scripts/install-deps.sh)"
      return 0
    fi
  done
  return 1
}

# _slurm_free_port: a TCP port nobody listens on now (the kernel's choice).
_slurm_free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# _slurm_wait SECONDS CMD...: runs CMD every 0.2 s until it succeeds; 1 on timeout.
_slurm_wait() {
  local deadline=$((SECONDS + $1)); shift
  until "$@"; do
    [ $SECONDS -lt $deadline ] || return 1
    sleep 0.2
  done
}

_slurm_node_idle() {
  [ "$(sinfo -h -N -n localhost -o %t 2>/dev/null)" = idle ]
}

_slurm_logs() {
  local f
  for f in "$SLURM_CLUSTER_DIR"/log/*.log; do
    [ -f "$f" ] || continue
    echo "--- $f (last lines)" >&2
    tail -n 20 "$f" >&2
  done
}

start_slurm_cluster() {
  local -
  set +e
  local dir sbin=/usr/sbin
  dir=$(mktemp -d "${TMPDIR:-/tmp}/vox-slurm.XXXXXX") || return 4
  SLURM_CLUSTER_DIR=$dir
  SLURM_CLUSTER_PIDS=""
  SLURM_PARTITION=debug
  mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/run" "$dir/log"
  chmod 700 "$dir/munge"

  # Stop the cluster however the caller's shell ends; an EXIT trap the caller
  # had before (e.g. removing its own work directory) still runs after it.
  local prev; prev=$(trap -p EXIT)
  _slurm_prev_exit=""
  [ -z "$prev" ] || { eval "prev=($prev)"; _slurm_prev_exit=${prev[2]}; }  # trap -- 'CMD' EXIT
  trap 'stop_slurm_cluster; eval "$_slurm_prev_exit"' EXIT
  trap 'stop_slurm_cluster; trap - INT; kill -INT $$' INT
  trap 'stop_slurm_cluster; trap - TERM; kill -TERM $$' TERM

  # munge: a key of our own, a daemon on a socket of our own.
  head -c 1024 /dev/urandom >"$dir/munge/munge.key"
  chmod 400 "$dir/munge/munge.key"
  local sock=$dir/munge/munge.socket
  "$sbin/munged" --foreground --force --socket="$sock" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" \
    --log-file="$dir/log/munged.log" --num-threads=2 </dev/null >>"$dir/log/munged.log" 2>&1 &
  SLURM_CLUSTER_PIDS=$!
  if ! _slurm_wait 10 test -S "$sock"; then
    echo "slurm_cluster: munged did not create $sock" >&2
    _slurm_logs; stop_slurm_cluster; return 4
  fi

  # A watcher stops the daemons should this shell die without running its
  # traps (SIGKILL); stop_slurm_cluster ends it first.
  local owner=$BASHPID
  (
    while kill -0 "$owner" 2>/dev/null && [ -d "$dir" ]; do sleep 2; done
    [ -d "$dir" ] || exit 0
    pids=$(cat "$dir/run/daemons" 2>/dev/null)
    # shellcheck disable=SC2086
    kill -TERM $pids 2>/dev/null
    for _ in 1 2 3 4 5 6 7 8 9 10; do
      alive=0
      for p in $pids; do kill -0 "$p" 2>/dev/null && alive=1; done
      [ $alive = 1 ] || break
      sleep 1
    done
    # shellcheck disable=SC2086
    kill -KILL $pids 2>/dev/null; rm -rf "$dir"
  ) </dev/null >/dev/null 2>&1 &
  SLURM_CLUSTER_WATCHER=$!
  echo "$SLURM_CLUSTER_PIDS" >"$dir/run/daemons"

  # The node as slurmd sees it (CPUs, memory); the ports free right now.
  local cpus mem ctld_port slurmd_port
  cpus=$("$sbin/slurmd" -C | sed -n 's/.* CPUs=\([0-9]*\).*/\1/p')
  mem=$("$sbin/slurmd" -C | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')
  ctld_port=$(_slurm_free_port); slurmd_port=$(_slurm_free_port)
  while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(_slurm_free_port); done

  cat >"$dir/slurm.conf" <<EOF
# Generated by tests/slurm/slurm_cluster.sh: a one-node cluster in $dir.
ClusterName=voxtest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# cred_expire: how long a requeued job waits before it may start again
# (default 120 s); short, so the requeue test does not sit idle.
AuthInfo=socket=$sock,cred_expire=10
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=512
KillWait=5
MinJobAge=600
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=$SLURM_PARTITION Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF=$dir/slurm.conf

  "$sbin/slurmctld" -D -i -f "$SLURM_CONF" </dev/null >>"$dir/log/slurmctld.stdout.log" 2>&1 &
  SLURM_CLUSTER_PIDS="$SLURM_CLUSTER_PIDS $!"
  echo "$SLURM_CLUSTER_PIDS" >"$dir/run/daemons"
  if ! _slurm_wait 30 scontrol ping >/dev/null 2>&1; then
    echo "slurm_cluster: slurmctld did not answer on port $ctld_port" >&2
    _slurm_logs; stop_slurm_cluster; return 4
  fi
  "$sbin/slurmd" -D -N localhost -f "$SLURM_CONF" </dev/null >>"$dir/log/slurmd.stdout.log" 2>&1 &
  SLURM_CLUSTER_PIDS="$SLURM_CLUSTER_PIDS $!"
  echo "$SLURM_CLUSTER_PIDS" >"$dir/run/daemons"
  if ! _slurm_wait 60 _slurm_node_idle; then
    echo "slurm_cluster: node localhost not idle after 60 s: $(sinfo -N 2>&1)" >&2
    _slurm_logs; stop_slurm_cluster; return 4
  fi
  return 0
}

stop_slurm_cluster() {
  # Options local to this function: a caller's set -e must not end the
  # shell at the first daemon whose exit status is a signal's.
  local -
  set +e
  [ -n "${SLURM_CLUSTER_DIR:-}" ] || return 0
  local pid deadline jobs
  # Cancel what is still queued or running, so no job step outlives slurmd.
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$SLURM_CONF" ]; then
    jobs=$(squeue -h -o %A 2>/dev/null | tr '\n' ' ')
    if [ -n "${jobs// /}" ]; then
      # shellcheck disable=SC2086
      scancel $jobs 2>/dev/null || true
      _slurm_wait 20 test -z "$(squeue -h -o %A 2>/dev/null)" || true
    fi
  fi
  if [ -n "${SLURM_CLUSTER_WATCHER:-}" ]; then
    kill -TERM "$SLURM_CLUSTER_WATCHER" 2>/dev/null || true
    wait "$SLURM_CLUSTER_WATCHER" 2>/dev/null || true
    SLURM_CLUSTER_WATCHER=""
  fi
  # slurmd, then slurmctld, then munged (the reverse of their start).
  for pid in $(echo "$SLURM_CLUSTER_PIDS" | tr ' ' '\n' | tac); do
    kill -TERM "$pid" 2>/dev/null || continue
  done
  deadline=$((SECONDS + 10))
  for pid in $SLURM_CLUSTER_PIDS; do
    while kill -0 "$pid" 2>/dev/null && [ $SECONDS -lt $deadline ]; do sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then
      kill -KILL "$pid" 2>/dev/null || true
    fi
    wait "$pid" 2>/dev/null || true
  done
  rm -rf "$SLURM_CLUSTER_DIR"
  SLURM_CLUSTER_DIR=""
  unset SLURM_CONF
  trap - INT TERM
  return 0
}
