# What the cluster tests share (sourced): failing with a message, the
# cluster's environment from local_cluster.sh's STATE_DIR/env, and waiting
# for a job to end.

fail() { echo "FAIL: $*" >&2; exit 1; }

# Exports the cluster's SLURM_CONF and the rest from $1/env.
load_cluster_env() {
  [ -f "$1/env" ] || fail "no cluster: $1/env is missing (the slurm_cluster_start test did not start one)"
  set -a
  # shellcheck disable=SC1091
  source "$1/env"
  set +a
}

# The states of job $1's tasks, once each ("COMPLETED " for a whole array done).
job_state() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort -u | tr '\n' ' '; }

job_ended() {
  case "$(job_state "$1")" in
    "COMPLETED " | "FAILED " | "CANCELLED " | "TIMEOUT " | "NODE_FAIL " | "OUT_OF_MEMORY ") return 0 ;;
    *) return 1 ;;
  esac
}

# Waits for job $1 to end, at most $2 seconds.
wait_ended() {
  local start=$SECONDS
  until job_ended "$1"; do
    [ $((SECONDS - start)) -lt "$2" ] || fail "job $1 not done after $2 s (state: $(job_state "$1"))"
    sleep 0.5
  done
  echo "job $1 done in $((SECONDS - start)) s"
}
