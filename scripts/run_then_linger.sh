#!/usr/bin/env bash
# run_then_linger.sh BEFORE AFTER COMMAND [ARGS...]: waits BEFORE seconds, runs COMMAND, then waits
# AFTER seconds before exiting with COMMAND's status. launch/demo.launch prefixes `rosbag play`
# with it: BEFORE lets the nodelets load and every subscriber (recorder, rviz) connect before the
# first message (rosbag play's own --delay comes before its --wait-for-subscribers, and that only
# sees the depth nodelet's inputs, not the renderer or the recorder); AFTER, when the player is a
# required node (exit_at_end:=true), lets the last frames through the pipeline before roslaunch
# shuts it down. A SIGINT/SIGTERM (roslaunch signals the whole process group) ends a wait at once.
set -u
if (($# < 3)); then
  echo "usage: run_then_linger.sh BEFORE AFTER COMMAND [ARGS...]" >&2
  exit 2
fi
before=$1 after=$2
shift 2
interrupted=0
trap 'interrupted=1' INT TERM
pause() {  # interruptible sleep
  if ((!interrupted)) && [[ "$1" != 0 && "$1" != 0.0 ]]; then
    sleep "$1" &
    wait $! || true
    kill $! 2>/dev/null || true
  fi
}
pause "$before"
((interrupted)) && exit 130
"$@"
status=$?
pause "$after"
exit "$status"
