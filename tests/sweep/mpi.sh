# Sourced by the sweep test scripts. Sets MPIRUN to the MPI launcher ($1,
# e.g. CMake's MPIEXEC_EXECUTABLE) with the options these tests need: Open
# MPI refuses more ranks than cores without --oversubscribe (the tests may
# share the machine with other tests) and runs as root only with
# --allow-run-as-root, which is added only when we are root.
mpi_launcher() {
  MPIRUN="$1"
  if "$1" --version 2>&1 | grep -q -i -e "Open MPI" -e "OpenRTE" -e "open-mpi.org"; then
    MPIRUN="$MPIRUN --oversubscribe"
    if [ "$(id -u)" -eq 0 ]; then MPIRUN="$MPIRUN --allow-run-as-root"; fi
  fi
}

# Runs "$@" and stores its exit status in RC (set -e safe).
run() {
  RC=0
  "$@" || RC=$?
}

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# Starts "$@" in a new session (setsid) in the background; SESSION = its id.
start_session() {
  rm -f session.id
  setsid sh -c 'echo $$ > session.id; exec "$@"' sh "$@" &
  while [ ! -s session.id ]; do sleep 0.01; done
  SESSION=$(cat session.id)
}

# The processes of session $1, from /proc (no procps needed): in
# /proc/<pid>/stat the session id is the 4th field after the ")" that ends
# the command name.
session_pids() {
  cat /proc/[0-9]*/stat 2>/dev/null | awk -v s="$1" '{ pid = $1; sub(/.*\) /, ""); if ($4 == s) print pid }'
}

# kill -9 every process of session $1 at once (mpirun and its ranks, which
# Open MPI puts in process groups of their own), as a node failure would;
# repeated until none is left.
kill_session() {
  for _ in 1 2 3 4 5 6 7 8 9 10; do
    pids=$(session_pids "$1")
    [ -z "$pids" ] && break
    # shellcheck disable=SC2086
    kill -9 $pids 2>/dev/null || true
    sleep 0.05
  done
  wait 2>/dev/null || true
}
