#!/usr/bin/env python3
"""Observer of the soak test (scripts/soak.sh): subscribes the pipeline's outputs (so that the lazy
nodelets run), counts input and output frames, changes dynamic_reconfigure parameters of both
nodelets at random, samples the resident memory of the pipeline's processes from /proc, and at the
end prints one summary line and writes it as JSON. Exit status 0 when every check passed.

Checks:
  - no crash: every watched node answers with the same pid at the end as at the start;
  - RSS growth < --max-rss-growth-mb between the end of the warm-up and the end;
  - drop policy: every output (depth/stats) is matched to the input cloud it came from by header
    stamp, in arrival order: an output that matches no input, or repeats the previous output's
    stamp, was published twice or from nothing. Only inputs that arrived inside the measured window
    count, and only outputs matched to them (a set in flight when the window opens belongs to no
    side). The frames lost (in - out) are at most --max-drop-percent of the frames in, every one of
    them accounted for by the documented policy: a set is dropped when the nodelet is busy (its
    1-deep subscriber queues keep the newest message), by the synchronizer (a cloud without an
    image within max_interval), at each loop restart (the synchronizer is recreated), or rejected
    with a counted reason.
"""
import argparse
import json
import os
import random
import statistics
import struct
import sys
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray

# Parameter changes drawn at random: values that keep the pipeline valid and its memory comparable
# (no output size changes), so that RSS growth means a leak and not a bigger frame.
DEPTH_CHANGES = {
    "retain_percent": [60.0, 70.0, 80.0, 90.0, 100.0],
    "radius_deg": [1.5, 2.0, 2.5, 3.0],
    "cloud_stride": [1, 2, 4],
    "threads": [1, 2],
    "var_threshold": [0.0, 50.0, 200.0],
    "model": ["ground_gp", "local_gp_mle", "kernel", "nearest"],
}
RENDERER_CHANGES = {
    "splat": ["gen3c", "zbuffer"],
    "edge_threshold": [0.02, 0.05, 0.1],
    "max_depth": [50.0, 100.0],
    "keyframe_interval": [0.0, 0.5, 2.0],
    "threads": [1, 2],
}


def rss_mb(pid):
    try:
        with open(f"/proc/{pid}/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def node_pid(master, name):
    try:
        uri = master.lookupNode(name)
        code, _, pid = xmlrpc.client.ServerProxy(uri).getPid("/soak_monitor")
        return pid if code == 1 else None
    except Exception:  # the node is gone or not up yet
        return None


class StampLog:
    """Header stamps of a topic's messages in arrival order, read from the serialized message
    (std_msgs/Header is the first field of PointCloud2, DepthCompletionStats and Image: uint32
    seq, uint32 secs, uint32 nsecs), so that no message type has to be deserialized."""

    def __init__(self, topic):
        self.stamps = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, rospy.AnyMsg, self.callback, queue_size=100)

    def callback(self, msg):
        _, secs, nsecs = struct.unpack_from("<III", msg._buff, 0)
        with self.lock:
            self.stamps.append((secs, nsecs))

    def snapshot(self):
        with self.lock:
            return list(self.stamps)

    def count(self):
        with self.lock:
            return len(self.stamps)


def match_outputs(inputs, outputs, in_begin, in_end, out_begin, lookback=10, horizon=200):
    """Matches each output from index out_begin on to the input it came from: the first input with
    the same stamp at or after the previous match (the nodelet keeps the order of its input and
    only drops), searching from `lookback` inputs before in_begin for sets in flight when the
    window opened, at most `horizon` inputs ahead. Returns (outputs matched to inputs in
    [in_begin, in_end), outputs that match no input, outputs repeating the previous output's input)."""
    position = max(0, in_begin - lookback)
    matched = unmatched = repeated = 0
    previous = None
    for stamp in outputs[out_begin:]:
        # The previous output's stamp again is the same input published twice, unless the very
        # next input carries that stamp too (a bag of one frame looped).
        if stamp == previous and not (position < len(inputs) and inputs[position] == stamp):
            repeated += 1
            continue
        found = next((i for i in range(position, min(len(inputs), position + horizon))
                      if inputs[i] == stamp), None)
        if found is None:
            unmatched += 1
            continue
        previous = stamp
        position = found + 1
        if in_begin <= found < in_end:
            matched += 1
    return matched, unmatched, repeated


def self_test():
    """The matching rules on hand-made sequences (soak.sh runs this before the soak)."""
    loop = [(i, 0) for i in range(5)] * 4  # a five-frame bag played four times
    cases = [
        ((loop, [(1, 0), (2, 0), (4, 0), (0, 0), (2, 0), (3, 0)], 0, 20, 0), (6, 0, 0)),
        # the first output came from an input before the window: neither side counts it
        ((loop, [(4, 0), (0, 0), (1, 0)], 5, 20, 0), (2, 0, 0)),
        ((loop, [(1, 0), (1, 0), (9, 9)], 0, 20, 0), (1, 1, 1)),
        (([(0, 0)] * 5, [(0, 0)] * 3, 0, 5, 0), (3, 0, 0)),  # a one-frame bag looped
    ]
    for arguments, expected in cases:
        got = match_outputs(*arguments)
        if got != expected:
            print(f"soak_monitor self-test: {arguments[1]} gave {got}, expected {expected}",
                  file=sys.stderr)
            return 1
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--duration", type=float, required=True, help="seconds of soak")
    parser.add_argument("--warmup", type=float, default=20.0, help="seconds before RSS baseline")
    parser.add_argument("--points", default="/radar/points", help="input cloud topic")
    parser.add_argument("--depth", default="/depth_completion", help="depth nodelet name")
    parser.add_argument("--renderer", default="/conditioning_renderer", help="renderer name")
    parser.add_argument("--processes", nargs="+", required=True,
                        help="nodes whose process must stay up (the first one's RSS is checked)")
    parser.add_argument("--reconfigure-period", type=float, default=3.0,
                        help="mean seconds between random parameter changes")
    parser.add_argument("--max-rss-growth-mb", type=float, default=20.0)
    parser.add_argument("--max-drop-percent", type=float, default=15.0)
    parser.add_argument("--json", help="write the summary here")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(rospy.myargv()[1:])

    rospy.init_node("soak_monitor")
    master = rosgraph.Master("/soak_monitor")
    rng = random.Random(args.seed)

    diagnostics = {}
    diag_lock = threading.Lock()

    def on_diagnostics(msg):
        with diag_lock:
            for status in msg.status:
                if "depth completion" in status.name:
                    diagnostics.update({kv.key: kv.value for kv in status.values})

    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics, queue_size=20)
    frames_in = StampLog(args.points)
    frames_out = StampLog("/depth/stats")
    renders = StampLog("/conditioning/image")

    # Wait for the pipeline to answer (nodelets loaded, subscriptions made, the bag playing).
    deadline = time.time() + 120.0
    while not rospy.is_shutdown() and not frames_out.count() and time.time() < deadline:
        time.sleep(0.2)
    if not frames_out.count():
        print("soak: the pipeline published no depth/stats within 120 s", file=sys.stderr)
        return 1
    pids = {name: node_pid(master, name) for name in args.processes}
    missing = [name for name, pid in pids.items() if pid is None]
    if missing:
        print(f"soak: no pid for {missing}", file=sys.stderr)
        return 1

    import dynamic_reconfigure.client  # after init_node: it creates subscribers

    clients = {}
    for name, changes in ((args.depth, DEPTH_CHANGES), (args.renderer, RENDERER_CHANGES)):
        try:
            clients[name] = (dynamic_reconfigure.client.Client(name, timeout=10.0), changes)
        except Exception as error:  # a missing server is a failure of the pipeline
            print(f"soak: no dynamic_reconfigure server {name}: {error}", file=sys.stderr)
            return 1

    main_pid = pids[args.processes[0]]
    start = time.time()
    # Output first: every output counted from here on came from an input at or after in_begin - a
    # few, which match_outputs searches.
    out_begin = frames_out.count()
    in_begin = frames_in.count()
    base_renders = renders.count()
    samples = []  # (seconds since start, RSS MB of the main process)
    changes_made = 0
    next_change = start + rng.expovariate(1.0 / args.reconfigure_period)
    while not rospy.is_shutdown():
        now = time.time()
        if now - start >= args.duration:
            break
        rss = rss_mb(main_pid)
        if rss is None:
            break  # the process is gone: reported below
        samples.append((now - start, rss))
        if now >= next_change:
            name = rng.choice(sorted(clients))
            client, changes = clients[name]
            key = rng.choice(sorted(changes))
            try:
                client.update_configuration({key: rng.choice(changes[key])})
                changes_made += 1
            except Exception as error:
                print(f"soak: reconfigure {name} {key} failed: {error}", file=sys.stderr)
            next_change = now + rng.expovariate(1.0 / args.reconfigure_period)
        time.sleep(1.0)
    elapsed = time.time() - start
    in_end = frames_in.count()
    time.sleep(2.0)  # frames in flight at the end
    inputs = frames_in.snapshot()
    n_in = in_end - in_begin
    n_out, unmatched, repeated = match_outputs(inputs, frames_out.snapshot(), in_begin, in_end,
                                               out_begin)
    n_renders = renders.count() - base_renders

    crashed = [name for name, pid in pids.items() if node_pid(master, name) != pid]
    warm = [rss for t, rss in samples if t >= min(args.warmup, args.duration / 2)]
    rss_start = warm[0] if warm else float("nan")
    rss_end = statistics.mean(rss for _, rss in samples[-3:]) if samples else float("nan")
    rss_peak = max((rss for _, rss in samples), default=float("nan"))
    growth = rss_end - rss_start
    drop_percent = 100.0 * (n_in - n_out) / n_in if n_in else 100.0
    with diag_lock:
        diag = dict(diagnostics)
    rejected = {k[len("rejected "):]: int(v) for k, v in diag.items()
                if k.startswith("rejected ") and k != "rejected total" and v != "0"}

    failures = []
    if crashed:
        failures.append(f"crashed or restarted: {crashed}")
    if not growth < args.max_rss_growth_mb:
        failures.append(f"RSS grew {growth:.1f} MB (limit {args.max_rss_growth_mb})")
    if unmatched:
        failures.append(f"{unmatched} outputs match no input stamp")
    if repeated:
        failures.append(f"{repeated} outputs repeat the previous output's stamp (published twice)")
    if drop_percent > args.max_drop_percent:
        failures.append(f"dropped {drop_percent:.1f} % (limit {args.max_drop_percent} %)")
    if changes_made == 0:
        failures.append("no parameter change was made")

    summary = {
        "duration_s": round(elapsed, 1),
        "frames_in": n_in,
        "frames_out": n_out,
        "outputs_unmatched": unmatched,
        "outputs_repeated": repeated,
        "renders": n_renders,
        "drop_percent": round(drop_percent, 2),
        "rss_start_mb": round(rss_start, 1),
        "rss_end_mb": round(rss_end, 1),
        "rss_growth_mb": round(growth, 1),
        "rss_peak_mb": round(rss_peak, 1),
        "reconfigures": changes_made,
        "time_jumps_back": int(diag.get("time jumps back", "0")),
        "rejected": rejected,
        "crashes": len(crashed),
        "result": "FAIL: " + "; ".join(failures) if failures else "PASS",
    }
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"summary": summary, "rss_samples": samples}, out, indent=1)
    print(
        f"soak: {summary['result']} | {elapsed:.0f} s, frames in {n_in} out {n_out} "
        f"(drop {drop_percent:.1f} %), renders {n_renders}, RSS {rss_start:.1f} -> {rss_end:.1f} MB "
        f"(growth {growth:+.1f} MB, peak {rss_peak:.1f}), reconfigures {changes_made}, "
        f"time jumps back {summary['time_jumps_back']}, rejected {rejected or 0}, "
        f"crashes {len(crashed)}",
        flush=True)
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(self_test() if sys.argv[1:] == ["--self-test"] else main())
