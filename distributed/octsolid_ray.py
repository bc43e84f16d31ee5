#!/usr/bin/env python3
"""Runs one sharded octsolid job as tasks of Ray, on this machine or a Ray cluster.

    python3 distributed/octsolid_ray.py [--address ADDR] [--workers N] [--tasks T]
        [--octsolid PATH] [--threads-per-task K] [--retries R]
        -- JOB... -o OUT.octs --shard-level L [-- JOB... ...]

JOB is an octsolid command line writing a sharded solid (`shape`, `build`,
`voxelize`, `csg` with `-o OUT.octs --shard-level L`); several jobs, each after its own
`--`, run one after the other on one Ray session (a job may read an earlier one's
output, as `csg` does). A job's 8^L cells (Morton order)
are cut into T contiguous ranges; each range is one Ray task running
`octsolid JOB... --cells FIRST..END`, which writes that range's shards and a part file
into OUT.octs.partial/job-ID/ (ID: the job's identity; see src/sharded/writer.rs).
A task whose process dies (a killed worker, a lost machine) or whose octsolid exits
non-zero is run again by Ray, up to R times; a task's output depends on its cells
only, so a retry writes the same bytes. Once every task is done, `octsolid join
OUT.octs` runs here, once: it checks that the parts cover every cell exactly once,
checks every shard and writes the index. Any T and any number of workers give the
same bytes as the job run in one process.

Without --address, a Ray instance of N worker processes is started on this machine,
listening on 127.0.0.1 only, without a dashboard, and stopped at the end. With --address (`HEAD:6379`, or
`auto` on a machine of the cluster) the tasks run on an existing cluster: every
machine needs the same octsolid binary at the same path (--octsolid) and the job's
files, inputs and output, in a folder shared at the same path (tasks run in this
script's working directory). docs/DISTRIBUTED.md has the steps.

For the tests only: OCTSOLID_RAY_KILL_ONCE=MARKER makes the first task to start
create the file MARKER and kill its own worker process (SIGKILL) before running
octsolid, so the engine's retry is exercised; later attempts see MARKER and run.
"""

import argparse
import os
import shutil
import signal
import subprocess
import sys
import time

# A local run sends nothing anywhere.
os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")


def parse_args(argv):
    parser = argparse.ArgumentParser(
        description="Run a sharded octsolid job (-o OUT.octs --shard-level L) as Ray tasks, then join it.",
        usage="%(prog)s [options] -- JOB... -o OUT.octs --shard-level L [-- JOB... ...]",
    )
    parser.add_argument("--address", help="an existing Ray cluster (HEAD:6379 or auto); default: start one here")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="worker processes of the local Ray instance (default: the cores); ignored with --address")
    parser.add_argument("--tasks", type=int, default=None,
                        help="ranges of cells a job, one task each (default: 4 for each task Ray runs at once)")
    parser.add_argument("--octsolid", default=None,
                        help="the octsolid binary, at this path on every machine (default: `octsolid` on PATH)")
    parser.add_argument("--threads-per-task", type=int, default=1,
                        help="CPUs a task reserves and threads its octsolid uses (default: 1)")
    parser.add_argument("--retries", type=int, default=3, help="times Ray runs a failed task again (default: 3)")
    if "--" not in argv:
        parser.parse_args(argv)  # --help, or an unknown option
        parser.error("the job comes after `--`: ... -- shape sphere --depth 9 -o ball.octs --shard-level 2")
    at = argv.index("--")
    args = parser.parse_args(argv[:at])
    args.jobs = [[]]
    for arg in argv[at + 1:]:
        if arg == "--":
            args.jobs.append([])
        else:
            args.jobs[-1].append(arg)
    for name in ("workers", "threads_per_task"):
        if getattr(args, name) < 1:
            parser.error(f"--{name.replace('_', '-')} must be at least 1")
    if args.tasks is not None and args.tasks < 1:
        parser.error("--tasks must be at least 1")
    if args.retries < 0:
        parser.error("--retries must be at least 0")
    return args


def flag_value(job, *names):
    """The value of the last of `names` in the job's arguments (`-o X`, `-oX`, `--output=X`)."""
    value = None
    for i, arg in enumerate(job):
        for name in names:
            if arg == name:
                if i + 1 >= len(job):
                    raise SystemExit(f"octsolid_ray: {name} in the job has no value")
                value = job[i + 1]
            elif name.startswith("--") and arg.startswith(name + "="):
                value = arg[len(name) + 1:]
            elif not name.startswith("--") and arg.startswith(name) and len(arg) > len(name):
                value = arg[len(name):]
    return value


def check_job(job):
    """The job's output folder and cell level; refuses a job that cannot be split."""
    if not job:
        raise SystemExit("octsolid_ray: no job after `--`")
    if flag_value(job, "--cells") is not None:
        raise SystemExit("octsolid_ray: the job must not have --cells: this script gives each task its cells")
    out = flag_value(job, "-o", "--output")
    if out is None or not out.lower().endswith(".octs"):
        raise SystemExit("octsolid_ray: the job needs a sharded output, -o OUT.octs")
    level = flag_value(job, "--shard-level")
    if level is None:
        raise SystemExit("octsolid_ray: the job needs --shard-level L (its 8^L cells are what tasks share)")
    try:
        level = int(level)
    except ValueError:
        raise SystemExit(f"octsolid_ray: --shard-level {level!r} is not a number") from None
    if not 0 <= level <= 21:
        raise SystemExit(f"octsolid_ray: --shard-level {level} is not 0..=21")
    return out, level


def split(count, tasks):
    """`tasks` contiguous ranges covering 0..count, sizes differing by at most one."""
    tasks = max(1, min(tasks, count))
    return [(count * i // tasks, count * (i + 1) // tasks) for i in range(tasks)]


def find_octsolid(path):
    found = shutil.which(path or "octsolid")
    if found is None:
        where = path or "`octsolid` on PATH"
        raise SystemExit(f"octsolid_ray: {where}: no such executable (build it: cargo build --release)")
    return os.path.abspath(found)


class TaskFailed(Exception):
    """An octsolid task exited non-zero (Ray runs it again, up to --retries)."""


def run_cells(octsolid, job, cells, cwd, threads, kill_marker):
    """One task: `octsolid JOB... --cells FIRST..END` in the driver's folder."""
    first, end = cells
    if kill_marker:
        try:
            os.close(os.open(kill_marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            pass
        else:
            os.kill(os.getpid(), signal.SIGKILL)
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    started = time.monotonic()
    done = subprocess.run(
        [octsolid, *job, "--cells", f"{first}..{end}"],
        cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
    )
    if done.returncode != 0:
        how = f"exit {done.returncode}" if done.returncode > 0 else f"signal {-done.returncode}"
        raise TaskFailed(f"cells {first}..{end} on {os.uname().nodename}: octsolid {how}: {done.stderr.strip()}")
    return first, end, time.monotonic() - started, os.uname().nodename


def run_job(ray, task, args, octsolid, job, tasks, kill_marker):
    """Runs one job's tasks on Ray, then its join here."""
    out, level = check_job(job)
    cwd = os.getcwd()
    count = 8 ** level
    ranges = split(count, tasks)
    # A job's folder left by an interrupted run may hold parts of another split, which
    # the join would refuse as overlapping (the run- folders of writers are left alone).
    staging = os.path.join(cwd, out + ".partial")
    if os.path.isdir(staging) and not os.path.islink(staging):
        for name in os.listdir(staging):
            if name.startswith("job-"):
                shutil.rmtree(os.path.join(staging, name))
    print(f"octsolid {' '.join(job)}: {len(ranges)} tasks over {count} cells", flush=True)
    submitted = time.monotonic()
    pending = [task.remote(octsolid, job, r, cwd, args.threads_per_task, kill_marker) for r in ranges]
    done = 0
    try:
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            first, end, seconds, node = ray.get(ready[0])
            done += 1
            print(f"tasks done {done}/{len(ranges)}: cells {first}..{end} in {seconds:.2f} s on {node} "
                  f"({time.monotonic() - submitted:.1f} s)", flush=True)
    except ray.exceptions.RayError as e:
        cause = e.cause if isinstance(getattr(e, "cause", None), TaskFailed) else e
        raise SystemExit(f"octsolid_ray: a task failed after {args.retries} retries: {cause}") from None
    tasks_seconds = time.monotonic() - submitted
    joined = subprocess.run([octsolid, "join", out], cwd=cwd)
    if joined.returncode != 0:
        raise SystemExit(f"octsolid_ray: octsolid join {out} failed (exit {joined.returncode})")
    print(f"{out}: tasks {tasks_seconds:.2f} s, with the join {time.monotonic() - submitted:.2f} s", flush=True)


def main(argv):
    args = parse_args(argv)
    for job in args.jobs:
        check_job(job)
    octsolid = find_octsolid(args.octsolid)
    kill_marker = os.environ.get("OCTSOLID_RAY_KILL_ONCE")
    if kill_marker:
        kill_marker = os.path.abspath(kill_marker)
    if not args.address:
        # A local Ray only on the loopback: Ray's own switch for single-machine use
        # (its default on macOS and Windows) makes every server of it listen on and
        # announce 127.0.0.1 rather than this machine's network address.
        os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
    try:
        import ray
    except ImportError:
        raise SystemExit("octsolid_ray: Ray is not installed for this python (distributed/install_ray.sh)") from None

    started = time.monotonic()
    if args.address:
        ray.init(address=args.address, log_to_driver=False)
        where = f"the Ray cluster at {args.address} ({int(ray.cluster_resources().get('CPU', 0))} CPUs)"
    else:
        ray.init(num_cpus=args.workers, include_dashboard=False, _node_ip_address="127.0.0.1",
                 log_to_driver=False)
        address = ray.nodes()[0]["NodeManagerAddress"]
        where = f"{args.workers} local worker{'s' if args.workers > 1 else ''} on {address}"
    print(f"Ray up in {time.monotonic() - started:.1f} s: {where}", flush=True)
    workers = max(1, int(ray.cluster_resources().get("CPU", 1)) // args.threads_per_task)
    tasks = args.tasks or 4 * workers
    task = ray.remote(run_cells).options(
        num_cpus=args.threads_per_task, max_retries=args.retries, retry_exceptions=[TaskFailed])
    try:
        for job in args.jobs:
            run_job(ray, task, args, octsolid, job, tasks, kill_marker)
    finally:
        ray.shutdown()
    print(f"total {time.monotonic() - started:.2f} s", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
