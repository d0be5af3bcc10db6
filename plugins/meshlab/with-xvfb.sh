#!/usr/bin/env bash
# Runs a command under a private Xvfb server and exits with the command's own status.
# Usage: plugins/meshlab/with-xvfb.sh [-s "SERVER ARGS"] COMMAND [ARGS...]
# The server picks a free display itself (-displayfd), so two servers started at the same moment do
# not collide, as they can with `xvfb-run -a`; and nothing but the server is cleaned up afterwards:
# xvfb-run's clean-up of its temporary directory can fail, and it then replaces the command's exit
# status by 5.
set -euo pipefail
server_args=()
if [ "${1:-}" = -s ]; then read -ra server_args <<< "${2:?-s needs the server arguments}"; shift 2; fi
[ $# -gt 0 ] || { echo "usage: with-xvfb.sh [-s SERVER_ARGS] COMMAND [ARGS...]" >&2; exit 2; }
command -v Xvfb >/dev/null || { echo "with-xvfb.sh: Xvfb is missing (Debian package xvfb)" >&2; exit 1; }

state=$(mktemp -d "${TMPDIR:-/tmp}/with-xvfb.XXXXXX")
server=""
stop() {
  if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; fi
  rm -rf "$state"
}
trap stop EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

Xvfb -displayfd 3 -nolisten tcp "${server_args[@]}" 3> "$state/display" 2> "$state/server.log" &
server=$!
# The server writes its display number once it accepts clients.
for _ in $(seq 200); do
  [ -s "$state/display" ] && break
  kill -0 "$server" 2>/dev/null || break
  sleep 0.05
done
display=$(tr -dc 0-9 < "$state/display")
if [ -z "$display" ]; then
  echo "with-xvfb.sh: Xvfb did not start; its output:" >&2
  cat "$state/server.log" >&2
  exit 1
fi

rc=0
DISPLAY=:$display "$@" || rc=$?
exit "$rc"
