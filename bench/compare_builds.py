#!/usr/bin/python3
"""Compares two builds of the package: their speed in interleaved rounds, or their outputs byte for
byte. How every before/after figure of docs/performance_history.md is measured.

  compare_builds.py snapshot DEVEL DIR
      Copies the devel space's lib/ (the core library, the tools, the benchmarks) to DIR/lib, to
      keep the build before a change as the "before" side.
  compare_builds.py time BEFORE AFTER [--rounds N] -- TOOL ARG...
      Runs BEFORE/lib/multimodal_nvs/TOOL and AFTER/lib/multimodal_nvs/TOOL in N rounds (default
      5), each with LD_LIBRARY_PATH at its own lib/ (the tools find the core library by RUNPATH,
      which LD_LIBRARY_PATH overrides). The order alternates (before-after, after-before, ...), so
      that the machine's speed drifting during a run favours neither side. TOOL is a tool that
      prints "median_ms" in its JSON line (complete_depth --repeat N) or a Google Benchmark binary
      (bench_*: each case's median over --benchmark_repetitions, else its time). Prints every
      round, then per case the median of the rounds on each side, their ratio and how many rounds
      the after build was faster.
  compare_builds.py same BEFORE AFTER [--ignore GLOB]... -- TOOL ARG...
      Runs TOOL once per build with `--output <temporary folder>/out` appended and compares every
      file it wrote byte for byte (except those matching --ignore, default *.json: timings).
      Exit 1 if any file differs or is missing on one side.

BEFORE and AFTER are devel spaces (e.g. devel/) or snapshots. Exit 2: bad arguments or a tool
that is not there; 3: a tool failed or printed no time (its output's end is shown).
Why interleaved rounds: on this project's 2-core VM the same binary's median drifts by 10-50 %
between minutes, so two builds timed one after the other differ by the machine as much as by the
change.
"""
import argparse
import filecmp
import fnmatch
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile


class Failure(Exception):
    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def tool_path(build, tool):
    path = os.path.join(build, "lib", "multimodal_nvs", tool)
    if not os.access(path, os.X_OK):
        raise Failure(2, "%s: no such executable (is %s a devel space or a snapshot?)" % (path, build))
    return path


def run(build, tool, args):
    env = dict(os.environ)
    lib = os.path.join(os.path.abspath(build), "lib")
    env["LD_LIBRARY_PATH"] = lib + (":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
    result = subprocess.run([tool_path(build, tool)] + args, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        tail = (result.stdout + result.stderr)[-2000:]
        raise Failure(3, "%s (%s) exited with %d:\n%s" % (tool, build, result.returncode, tail))
    return result.stdout


def is_benchmark(tool):
    return os.path.basename(tool).startswith("bench_")


def times_of(tool, stdout):
    """{case: milliseconds} from one run's output."""
    if is_benchmark(tool):
        report = json.loads(stdout)
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
        runs = report.get("benchmarks", [])
        medians = [b for b in runs if b.get("aggregate_name") == "median"]
        chosen = medians if medians else [b for b in runs if b.get("run_type", "iteration") == "iteration"]
        times = {}
        for b in chosen:
            if b.get("error_occurred"):
                raise Failure(3, "%s: %s: %s" % (tool, b.get("run_name", b["name"]), b.get("error_message", "error")))
            times[b.get("run_name", b["name"])] = b["real_time"] * scale[b.get("time_unit", "ns")]
        if not times:
            raise Failure(3, "%s ran no benchmark (check --benchmark_filter)" % tool)
        return times
    found = re.findall(r'"median_ms":\s*([0-9.eE+-]+)', stdout)
    if not found:
        raise Failure(3, "%s printed no \"median_ms\" (complete_depth prints it with --repeat N):\n%s"
                      % (tool, stdout[-2000:]))
    return {"median_ms": float(found[-1])}


def command_time(options):
    tool, args = options.command[0], options.command[1:]
    if is_benchmark(tool) and not any(a.startswith("--benchmark_format") for a in args):
        args = args + ["--benchmark_format=json"]
    for build in (options.before, options.after):
        tool_path(build, tool)
    rounds = {"before": [], "after": []}
    for r in range(options.rounds):
        order = ("before", "after") if r % 2 == 0 else ("after", "before")
        line = []
        for side in order:
            build = options.before if side == "before" else options.after
            times = times_of(tool, run(build, tool, args))
            rounds[side].append(times)
            line.append("%s %s" % (side, " ".join("%.3f" % t for t in times.values())))
        print("round %d: %s" % (r + 1, ", ".join(line)), flush=True)
    cases = list(rounds["before"][0].keys())
    print("%-50s %14s %14s %8s %14s" % ("case (ms, median of rounds)", "before", "after",
                                        "ratio", "after faster"))
    for case in cases:
        before = [t[case] for t in rounds["before"] if case in t]
        after = [t[case] for t in rounds["after"] if case in t]
        wins = sum(1 for b, a in zip(before, after) if a < b)
        mb, ma = statistics.median(before), statistics.median(after)
        print("%-50s %14.3f %14.3f %8.3f %9d of %d" % (case, mb, ma, ma / mb if mb > 0 else float("nan"),
                                                     wins, len(after)))
    return 0


def written_files(root):
    files = set()
    for folder, _, names in os.walk(root):
        for name in names:
            files.add(os.path.relpath(os.path.join(folder, name), root))
    return files


def command_same(options):
    tool, args = options.command[0], options.command[1:]
    ignore = options.ignore if options.ignore else ["*.json"]
    with tempfile.TemporaryDirectory(prefix="compare_builds_") as scratch:
        roots = {}
        for side, build in (("before", options.before), ("after", options.after)):
            roots[side] = os.path.join(scratch, side)
            os.makedirs(roots[side])
            run(build, tool, args + ["--output", os.path.join(roots[side], "out")])
        files = {side: {f for f in written_files(root)
                        if not any(fnmatch.fnmatch(os.path.basename(f), g) for g in ignore)}
                 for side, root in roots.items()}
        differing = []
        for f in sorted(files["before"] | files["after"]):
            if f not in files["before"] or f not in files["after"]:
                differing.append("%s: written by the %s build only" %
                                 (f, "before" if f in files["before"] else "after"))
            elif not filecmp.cmp(os.path.join(roots["before"], f), os.path.join(roots["after"], f),
                                 shallow=False):
                differing.append("%s: differs" % f)
        compared = len(files["before"] & files["after"])
        if differing:
            print("\n".join(differing))
            print("%d of %d files differ" % (len(differing), len(files["before"] | files["after"])))
            return 1
        if compared == 0:
            raise Failure(3, "%s wrote no file to compare (does it take --output?)" % tool)
        print("identical: %d files (%s)" % (compared, ", ".join(sorted(files["after"]))))
        return 0


def command_snapshot(options):
    source = os.path.join(options.devel, "lib")
    if not os.path.isdir(os.path.join(source, "multimodal_nvs")):
        raise Failure(2, "%s: not a devel space (no lib/multimodal_nvs)" % options.devel)
    target = os.path.join(options.dir, "lib")
    if os.path.exists(target):
        raise Failure(2, "%s exists: choose a new folder" % target)
    shutil.copytree(source, target, symlinks=True)
    print("snapshot of %s in %s" % (source, target))
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n", 1)[1])
    sub = parser.add_subparsers(dest="command_name", required=True)
    snap = sub.add_parser("snapshot", help="copy a devel space's lib/ as the build before a change")
    snap.add_argument("devel")
    snap.add_argument("dir")
    snap.set_defaults(handler=command_snapshot)
    for name, handler, helptext in (("time", command_time, "interleaved timing rounds"),
                                    ("same", command_same, "byte-for-byte comparison of outputs")):
        p = sub.add_parser(name, help=helptext)
        p.add_argument("before")
        p.add_argument("after")
        if name == "time":
            p.add_argument("--rounds", type=int, default=5)
        else:
            p.add_argument("--ignore", action="append", metavar="GLOB")
        p.set_defaults(handler=handler)
    # Everything after the first "--" is the tool's command line, untouched by argparse.
    argv = sys.argv[1:]
    command = argv[argv.index("--") + 1:] if "--" in argv else []
    options = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    options.command = command
    if options.command_name in ("time", "same") and not command:
        parser.error("no tool given (... -- TOOL ARG...)")
    if getattr(options, "rounds", 1) < 1:
        parser.error("--rounds must be at least 1")
    try:
        return options.handler(options)
    except Failure as failure:
        print("compare_builds: %s" % failure, file=sys.stderr)
        return failure.code
    except (json.JSONDecodeError, OSError) as error:
        print("compare_builds: %s" % error, file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())
