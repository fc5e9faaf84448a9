#!/usr/bin/env bash
# run_then_linger.sh SECONDS COMMAND [ARGS...]: runs COMMAND, then waits SECONDS before exiting
# with COMMAND's status. launch/demo.launch prefixes `rosbag play` with it so that, when the player
# is a required node (exit_at_end:=true), roslaunch shuts the pipeline down only after the last
# frames have gone through it. A SIGINT/SIGTERM (roslaunch signals the whole process group) ends
# the wait at once.
set -u
linger=${1:?usage: run_then_linger.sh SECONDS COMMAND [ARGS...]}
shift
interrupted=0
trap 'interrupted=1' INT TERM
"$@"
status=$?
if ((!interrupted)) && [[ "$linger" != 0 && "$linger" != 0.0 ]]; then
  sleep "$linger" &
  wait $! || true
  kill $! 2>/dev/null || true
fi
exit "$status"
