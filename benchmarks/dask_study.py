"""The paper's Monte Carlo on a 2-worker Dask LocalCluster against `kincal reproduce` on two
threads (docs/benchmarks.md, "Studies on Dask"), back to back, REPS times:

- the program: `kincal reproduce --trials N --threads 2 --json -`, a whole process;
- a whole Dask script (once per --chunk value), a process of its own: import distributed and kincal, start a
  LocalCluster(n_workers=2, threads_per_worker=1, processes=True), run
  kincal.studies.reproduce(N, client), close the cluster; the phases are timed inside;
- the study in this process without a client, on two threads;
- the study on a running cluster (started once, before the first repetition, and warmed by
  a 2-trial study): kincal.studies.reproduce(N, client), once per --chunk value given (the
  default tasks when none).

Wall seconds, and CPU seconds (the program's; the workers' and this process's during the
study on the running cluster). Each document is compared with the program's (every field
but "out"): "same" or "DIFFERENT". Usage (with the module on PYTHONPATH, Debian's
python3-distributed):

    PYTHONPATH=build/python /usr/bin/python3 benchmarks/dask_study.py build/cli/kincal \\
        [--trials 200] [--reps 3] [--chunk 10 --chunk 0] [--no-profiler]   # chunk 0: the default
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from typing import Any, Dict, List, Optional, Tuple


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _without_out(doc: Dict[str, Any]) -> Dict[str, Any]:
    return {k: v for k, v in doc.items() if k != "out"}


def _program(program: str, trials: int) -> Tuple[float, float, Dict[str, Any]]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    run = subprocess.run([program, "reproduce", "--trials", str(trials), "--threads", "2", "--json", "-"],
                         check=True, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return wall, cpu, json.loads(run.stdout)


def _whole_script(trials: int, chunk: Optional[int]) -> None:
    """The whole Dask script (run as a process of its own): prints its phases and document."""
    start = time.perf_counter()
    from distributed import Client, LocalCluster

    import kincal.studies

    imported = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    started = time.perf_counter()
    doc = kincal.studies.reproduce(trials, client, chunk=chunk)
    studied = time.perf_counter()
    client.close()
    cluster.close()
    closed = time.perf_counter()
    print(json.dumps({"import": imported - start, "start": started - imported, "study": studied - started,
                      "close": closed - studied, "document": doc}))


def _whole(trials: int, chunk: Optional[int], no_profiler: bool) -> Tuple[float, Dict[str, Any]]:
    start = time.perf_counter()
    command = [sys.executable, __file__, "--whole-script", "--trials", str(trials), "--chunk", str(chunk or 0)]
    run = subprocess.run(command + (["--no-profiler"] if no_profiler else []), check=True, capture_output=True,
                         text=True)
    wall = time.perf_counter() - start
    phases = json.loads(run.stdout.strip().splitlines()[-1])
    phases["process"] = wall
    return wall, phases


def _others_busy() -> str:
    """Processes of other users above 20 % of a core just before a repetition (a shared machine)."""
    try:
        lines = subprocess.run(["top", "-b", "-n1"], capture_output=True, text=True).stdout.splitlines()[7:]
    except OSError:
        return "?"
    busy = [line.split()[11] for line in lines if len(line.split()) > 11 and float(line.split()[8]) > 20]
    return " ".join(busy) or "none"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("program", nargs="?")
    parser.add_argument("--trials", type=int, default=200)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--chunk", type=int, action="append", help="0: the default tasks")
    parser.add_argument("--no-profiler", action="store_true",
                        help="distributed.worker.profile.enabled: False (Dask samples each worker's threads every 10 ms)")
    parser.add_argument("--whole-script", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.no_profiler:
        import dask

        dask.config.set({"distributed.worker.profile.enabled": False})  # the workers inherit it
    if args.whole_script:
        _whole_script(args.trials, (args.chunk or [0])[0] or None)
        return
    if not args.program:
        parser.error("the program's path is required")
    from distributed import Client, LocalCluster

    import kincal.studies

    chunks: List[Optional[int]] = [c or None for c in (args.chunk or [0])]
    rows: Dict[str, List[float]] = {}

    def note(name: str, value: float) -> None:
        rows.setdefault(name, []).append(value)

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        kincal.studies.reproduce(2, client)
        for rep in range(args.reps):
            print(f"repetition {rep + 1} (others' processes busy: {_others_busy()})", flush=True)
            wall, cpu, expected = _program(args.program, args.trials)
            note("program wall", wall)
            note("program cpu", cpu)
            print(f"  program                 wall {wall:5.2f} s  cpu {cpu:5.2f} s", flush=True)
            for chunk in chunks:
                tasks = f"chunk={chunk}" if chunk else "default tasks"
                wall, phases = _whole(args.trials, chunk, args.no_profiler)
                same = _without_out(phases["document"]) == _without_out(expected)
                for phase in ("import", "start", "study", "close", "process"):
                    note(f"whole script, {tasks}: {phase}", phases[phase])
                print(f"  whole Dask script, {tasks:13s} wall {wall:5.2f} s  (import {phases['import']:.2f}, "
                      f"cluster start {phases['start']:.2f}, study {phases['study']:.2f}, close "
                      f"{phases['close']:.2f})  {'same' if same else 'DIFFERENT'}", flush=True)
            start, cpu0 = time.perf_counter(), _cpu()
            doc = kincal.studies.reproduce(args.trials, threads=2)
            wall, cpu = time.perf_counter() - start, _cpu() - cpu0
            same = _without_out(doc) == _without_out(expected)
            note("no client, threads=2 wall", wall)
            print(f"  no client, threads=2           wall {wall:5.2f} s  cpu {cpu:5.2f} s  {'same' if same else 'DIFFERENT'}",
                  flush=True)
            for chunk in chunks:
                name = f"running cluster, chunk={chunk}" if chunk else "running cluster, default tasks"
                workers0, client0 = sum(client.run(_cpu).values()), _cpu()
                start = time.perf_counter()
                doc = kincal.studies.reproduce(args.trials, client, chunk=chunk)
                wall = time.perf_counter() - start
                workers1, client1 = sum(client.run(_cpu).values()), _cpu()
                same = _without_out(doc) == _without_out(expected)
                note(f"{name} wall", wall)
                print(f"  {name:30s} wall {wall:5.2f} s  cpu workers {workers1 - workers0:5.2f} s, this process "
                      f"{client1 - client0:4.2f} s  {'same' if same else 'DIFFERENT'}", flush=True)
    print("best of", args.reps, "(median):")
    for name, values in rows.items():
        print(f"  {name:45s} {min(values):5.2f} s ({sorted(values)[len(values) // 2]:.2f})")


if __name__ == "__main__":
    os.environ.setdefault("PYTHONWARNINGS", "ignore::DeprecationWarning")
    main()
