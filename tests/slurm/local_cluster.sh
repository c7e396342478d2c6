#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests and the
# benchmark: munged, slurmctld and slurmd from Debian's packages
# (munge, slurm-wlm), all of their state in a scratch directory.
#
#   tests/slurm/local_cluster.sh start STATE_DIR   # prints nothing on success
#   tests/slurm/local_cluster.sh stop STATE_DIR
#
# start writes STATE_DIR/env (SLURM_CONF=..., for sbatch and the others)
# and stops again whatever it started if any step fails, saying why.
# stop cancels the cluster's jobs, stops the daemons (SIGKILL after 10 s)
# and removes the scratch directory; it fails if a daemon survives.
#
# The cluster: its own munge key and socket (nothing under /etc/munge or
# /run/munge is used), slurmctld and slurmd on 127.0.0.1 at two free
# ports, the node sized to this machine's CPUs, proctrack/linuxproc and
# task/none (no cgroups), no accounting database. Needs root: munged runs
# as the munge user, slurmd as root.
set -uo pipefail
export PATH="$PATH:/usr/sbin:/sbin"

log() { echo "slurm cluster: $*" >&2; }

# The lowest free TCP port from $1 on (not listening on IPv4 or IPv6).
free_port() {
  local port="$1" used
  local hex
  used=$(awk 'NR > 1 && $4 == "0A" { split($2, a, ":"); print a[2] }' \
    /proc/net/tcp /proc/net/tcp6 2>/dev/null | while read -r hex; do echo $((16#$hex)); done)
  while grep -qx "$port" <<<"$used" || [ "$port" = "${2:-}" ]; do port=$((port + 1)); done
  echo "$port"
}

# Waits up to $1 seconds for command "${@:2}" to succeed.
wait_for() {
  local timeout="$1" start=$SECONDS
  shift
  until "$@" >/dev/null 2>&1; do
    [ $((SECONDS - start)) -ge "$timeout" ] && return 1
    sleep 0.2
  done
}

alive() { [ -n "$1" ] && kill -0 "$1" 2>/dev/null; }

pid_of() { [ -s "$1" ] && cat "$1"; }

stop_cluster() {
  local state="$1" scratch="" failed=0
  [ -f "$state/env" ] || return 0
  scratch=$(sed -n 's/^IPMC_SLURM_SCRATCH=//p' "$state/env")
  export SLURM_CONF="$scratch/slurm.conf"
  if [ -n "$scratch" ] && [ -d "$scratch" ]; then
    timeout 10 scancel --full --quiet --user=root >/dev/null 2>&1
    no_jobs() { [ -z "$(squeue -h 2>/dev/null)" ]; }
    wait_for 10 no_jobs
    local daemon pid
    for daemon in slurmd slurmctld; do
      pid=$(pid_of "$scratch/$daemon.pid")
      alive "$pid" && kill -TERM "$pid" 2>/dev/null
    done
    for daemon in slurmd slurmctld; do
      pid=$(pid_of "$scratch/$daemon.pid")
      if alive "$pid" && ! wait_for 10 bash -c "! kill -0 $pid"; then
        log "$daemon (pid $pid) did not stop on SIGTERM; killing it"
        kill -KILL "$pid" 2>/dev/null
        wait_for 5 bash -c "! kill -0 $pid" || { log "$daemon (pid $pid) survives SIGKILL"; failed=1; }
      fi
    done
    kill_leftover_jobs "$scratch"
    pid=$(pid_of "$scratch/munge/munged.pid")
    if alive "$pid"; then
      kill -TERM "$pid" 2>/dev/null
      wait_for 10 bash -c "! kill -0 $pid" || { kill -KILL "$pid" 2>/dev/null; }
      alive "$pid" && { log "munged (pid $pid) survives"; failed=1; }
    fi
    [ "$failed" -eq 0 ] && rm -rf "$scratch"
  fi
  [ "$failed" -eq 0 ] && rm -f "$state/env"
  return "$failed"
}

# Processes of this cluster's jobs that outlived its daemons: job steps
# (slurmstepd) and their children carry SLURM_CONF=<scratch>/slurm.conf in
# their environment; each is ended by its own process id.
kill_leftover_jobs() {
  local scratch="$1" dir pid environment
  for dir in /proc/[0-9]*; do
    pid=${dir#/proc/}
    [ "$pid" = "$$" ] && continue
    environment=$(tr '\0' '\n' 2>/dev/null <"$dir/environ") || continue
    grep -qx "SLURM_CONF=$scratch/slurm.conf" <<<"$environment" || continue
    if [ "$(cat "$dir/comm" 2>/dev/null)" = slurmstepd ] || grep -q "^SLURM_JOB_ID=" <<<"$environment"; then
      kill -KILL "$pid" 2>/dev/null
    fi
  done
}

# Says why the cluster did not start, with the end of each log, stops
# what started, and exits 1.
fail_start() {
  local state="$1" scratch="$2"
  shift 2
  log "cannot start: $*"
  local file
  for file in "$scratch"/log/*.log "$scratch"/munge/munged.log; do
    [ -s "$file" ] && { log "--- last lines of $file"; tail -n 15 "$file" >&2; }
  done
  stop_cluster "$state"
  exit 1
}

start_cluster() {
  local state="$1"
  mkdir -p "$state"
  stop_cluster "$state" || { log "a cluster of an earlier run in $state does not stop"; exit 1; }
  if [ "$(id -u)" -ne 0 ]; then
    log "cannot start: needs root (munged runs as the munge user, slurmd as root); running as $(id -un)"
    exit 1
  fi
  local missing="" tool
  for tool in munged mungekey slurmctld slurmd sbatch scontrol sinfo scancel runuser; do
    command -v "$tool" >/dev/null 2>&1 || missing="$missing $tool"
  done
  if [ -n "$missing" ]; then
    log "cannot start: not installed:$missing (scripts/setup.sh installs slurm-wlm and munge)"
    exit 1
  fi
  id munge >/dev/null 2>&1 || { log "cannot start: no user munge (Debian's munge package makes it)"; exit 1; }

  local scratch node cpus ctld_port slurmd_port
  scratch=$(mktemp -d "${TMPDIR:-/tmp}/ipmc-slurm.XXXXXX") || { log "cannot make a scratch directory"; exit 1; }
  # munged refuses sockets and keys in directories others cannot enter
  # or may write.
  chmod 755 "$scratch"
  printf 'IPMC_SLURM_SCRATCH=%s\nSLURM_CONF=%s/slurm.conf\n' "$scratch" "$scratch" >"$state/env"
  mkdir -p "$scratch/munge" "$scratch/state" "$scratch/spool" "$scratch/log"
  chown munge:munge "$scratch/munge"
  chmod 755 "$scratch/munge"

  mungekey --create --keyfile="$scratch/munge/munge.key" >/dev/null 2>&1 ||
    fail_start "$state" "$scratch" "mungekey could not create a key"
  chown munge:munge "$scratch/munge/munge.key"
  chmod 600 "$scratch/munge/munge.key"
  runuser -u munge -- munged --socket="$scratch/munge/munge.socket" \
    --key-file="$scratch/munge/munge.key" --pid-file="$scratch/munge/munged.pid" \
    --log-file="$scratch/munge/munged.log" --seed-file="$scratch/munge/munged.seed" \
    </dev/null >"$scratch/log/munged.out" 2>&1 ||
    fail_start "$state" "$scratch" "munged exited: $(cat "$scratch/log/munged.out")"
  wait_for 10 test -S "$scratch/munge/munge.socket" ||
    fail_start "$state" "$scratch" "munged made no socket in 10 s"

  node=$(hostname -s)
  cpus=$(nproc --all)
  ctld_port=$(free_port 16817)
  slurmd_port=$(free_port $((ctld_port + 1)) "$ctld_port")
  cat >"$scratch/slurm.conf" <<EOF
# Generated by tests/slurm/local_cluster.sh: one node, this machine.
ClusterName=ipmc-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$scratch/munge/munge.socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$scratch/state
SlurmdSpoolDir=$scratch/spool
SlurmctldPidFile=$scratch/slurmctld.pid
SlurmdPidFile=$scratch/slurmd.pid
SlurmctldLogFile=$scratch/log/slurmctld.log
SlurmdLogFile=$scratch/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
SchedulerType=sched/backfill
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=600
KillWait=5
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$scratch/slurm.conf"
  slurmctld -f "$SLURM_CONF" -i </dev/null >"$scratch/log/slurmctld.out" 2>&1 ||
    fail_start "$state" "$scratch" "slurmctld exited: $(cat "$scratch/log/slurmctld.out")"
  slurmd -f "$SLURM_CONF" -N "$node" </dev/null >"$scratch/log/slurmd.out" 2>&1 ||
    fail_start "$state" "$scratch" "slurmd exited: $(cat "$scratch/log/slurmd.out")"
  node_idle() { [ "$(sinfo -h -n "$node" -o %t 2>/dev/null)" = "idle" ]; }
  wait_for 30 node_idle ||
    fail_start "$state" "$scratch" "node $node not idle after 30 s (sinfo: $(sinfo -h -o '%t %E' 2>&1))"
}

case "${1:-}" in
  start) [ -n "${2:-}" ] || { echo "usage: $0 start|stop STATE_DIR" >&2; exit 2; }; start_cluster "$2" ;;
  stop) [ -n "${2:-}" ] || { echo "usage: $0 start|stop STATE_DIR" >&2; exit 2; }; stop_cluster "$2" ;;
  *) echo "usage: $0 start|stop STATE_DIR" >&2; exit 2 ;;
esac
