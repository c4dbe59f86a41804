#!/usr/bin/env python3
"""Whole commands on real data: kincal's `model -> calibrate -> validate` against an
independent numpy/scipy calibration of the same data (tracker_fit.py, socket_fit.py), both
timed as whole processes, back to back, with their agreement printed next to the times.

    run.py [DATASETS_DIR] --kincal PATH [--sizes 1e3,1e4,1e5,1e6] [--only NAME,...]
           [--repeat N] [--repeat-large N] [--work DIR] [--out results.md] [--out results.json]

DATASETS_DIR (default: the environment's KINCAL_DATASETS) is the public datasets folder: ur5-laser-tracker/ (the UR5 example's two CSV
files, examples/ur5-laser-tracker/README.md says where they come from) and robot-sockets/
(platonics-delft/kinematics_calibration, examples/robot_sockets/README.md). The simulated sets
(the UR5 URDF with a point and a pose tracker, --sizes rows each) are made by `kincal
simulate` and kept in --work between runs. Preparing the files is not timed. Then, per
dataset and repeat: kincal's chain (each command a process; `validate` without `--report`,
which it refuses above 16 MiB, i.e. from about 10^5 rows; what the runner does between
them, such as adding the sockets to the model file, is not timed), then the script's process
(its imports included). Wall time, CPU (user + system of the processes themselves) and peak
resident memory, from GNU time where it is installed (/usr/bin/time; otherwise os.wait4, whose
peak then counts this runner's own); the table shows the best of --repeat runs of each
(--repeat-large of the sets of --large-rows rows or more); a command over --timeout is
stopped and shown as such.

Agreement: the residual RMS at each one's minimum (sqrt(2 cost / residuals), whitened where
the model states reading_std), relative difference; the held-out residuals (predicted -
measured, from `kincal validate` and from the script), largest difference in mm (and rad for
the pose tracker); how many parameters both estimate (the same number, or the check fails)
and how many of the script's are named differently from kincal's: where one of two exact
duplicates (base.rz and tracker.frame.rz) is a tie, each may keep the other; the same minimum
says the sets are equivalent. Exit 1 when an agreement check fails, 77 when DATASETS_DIR is
absent (a skipped test), 0 otherwise.
"""

import argparse
import importlib.util
import json
import os
import platform
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
UR5_URDF = os.path.join(SOURCE, "examples", "ur5-laser-tracker", "ur5.urdf")
POINT_NOISE, POSE_NOISE = (0.01,), (0.05, 1e-4)  # mm; mm, rad (std)
PART_ROWS = 100000
MAX_RMS_RELATIVE, MAX_HELD_MM, MAX_HELD_RAD = 1e-6, 1e-4, 1e-7


def load_example(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.stderr.write(p.stdout[-2000:] + p.stderr[-2000:])
        raise SystemExit("run.py: '%s' failed with exit code %d" % (" ".join(cmd), p.returncode))
    return p


class TimedOut(Exception):
    pass


class Failed(Exception):
    """A timed command that exited non-zero: its last line says why."""


# A child's peak memory counts the memory of the process it was started from (Linux records
# the old image's high-water mark at exec), and this runner grows when it reads a report of
# 10^6 rows: GNU time, a small process, starts each command and reports its rusage instead.
GNU_TIME = "/usr/bin/time" if os.access("/usr/bin/time", os.X_OK) else None


def timed(cmd, timeout=None):
    """Wall, CPU (user + system, s) and peak RSS (MiB) of one process (its rusage from GNU
    time, or from os.wait4 without it); raises Failed on failure, TimedOut (the process
    killed) after `timeout` seconds."""
    with tempfile.TemporaryFile() as out, tempfile.NamedTemporaryFile("r") as usage_file:
        run_cmd = ([GNU_TIME, "-f", "%U %S %M", "-o", usage_file.name] + cmd if GNU_TIME
                   else cmd)
        start = time.perf_counter()
        p = subprocess.Popen(run_cmd, stdout=out, stderr=subprocess.STDOUT,
                             start_new_session=True)
        killer = threading.Timer(timeout, os.killpg, (p.pid, 9)) if timeout else None
        if killer:
            killer.start()
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - start
        if killer:
            killer.cancel()
        p.returncode = code = os.waitstatus_to_exitcode(status)
        if timeout and wall >= timeout and code in (-9, 137):
            raise TimedOut(" ".join(os.path.basename(c) for c in cmd[:2]))
        # validate exits 1 for its verdict "the held-out residuals are larger than predicted"
        if code != 0 and not (code == 1 and cmd[1:2] == ["validate"]):
            out.seek(0)
            text = out.read().decode(errors="replace")
            last = text.strip().splitlines()[-1] if text.strip() else ""
            raise Failed("%s exited %d: %s" % (" ".join(os.path.basename(c) for c in cmd[:2]),
                                               code, last))
        if GNU_TIME:
            user, system, kib = usage_file.read().strip().splitlines()[-1].split()
            return wall, float(user) + float(system), float(kib) / 1024.0
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


class Dataset:
    """One row of the table: `steps` is kincal's chain (a command list is timed, a callable
    is the runner's own work between commands), `script` the independent calibration."""

    def __init__(self, name, rows, folder, steps, script, report, validation, readings,
                 extra_residuals=0):
        self.name, self.rows, self.folder = name, rows, folder
        self.steps, self.script = steps, script
        self.report, self.validation, self.readings = report, validation, readings
        self.extra_residuals = extra_residuals


# ---- preparing the inputs (not timed) -------------------------------------------------------

def tracker_steps(k, d, sensor, data, test, reading_std=None):
    model = os.path.join(d, "model.json")
    steps = [[k, "model", "--urdf", UR5_URDF, "--tip", "flange", "--sensor", sensor + "-tracker",
              "--out", model]]
    if reading_std:
        steps.append(lambda: add_reading_std(model, reading_std))
    steps += [[k, "calibrate", "--model", model, "--data", data, "--out",
               os.path.join(d, "calibrated.json"), "--json", os.path.join(d, "report.json")],
              [k, "validate", "--model", os.path.join(d, "calibrated.json"), "--data", test,
               "--json", os.path.join(d, "validation.json")]]
    return steps


def add_reading_std(model, std):
    with open(model) as f:
        m = json.load(f)
    m["reading_std"] = {"tracker." + a: std[0] for a in "xyz"}
    m["reading_std"]["tracker.rotvec_*"] = std[1]
    with open(model, "w") as f:
        json.dump(m, f, indent=1)


def tracker_script(python, d, sensor, data, test, reading_std=None, urdf=UR5_URDF, tip="flange"):
    cmd = [python, os.path.join(HERE, "tracker_fit.py"), "--urdf", urdf, "--tip", tip,
           "--sensor", sensor, "--data", data, "--test", test,
           "--out", os.path.join(d, "script.json")]
    if reading_std:
        cmd += ["--reading-std", ",".join("%g" % v for v in reading_std)]
    return cmd


def prepare_ur5(args, python):
    source = os.path.join(args.datasets, "ur5-laser-tracker")
    ex = load_example(os.path.join(SOURCE, "examples", "ur5-laser-tracker", "run.py"), "ur5ex")
    if not all(os.path.isfile(os.path.join(source, f)) for f in (ex.GRID, ex.TEST)):
        return None, "the UR5 files are not in %s" % source
    d = os.path.join(args.work, "ur5")
    os.makedirs(d, exist_ok=True)
    grid, test = (os.path.join(d, f) for f in ("grid.csv", "test.csv"))
    rows = ex.read_dataset(os.path.join(source, ex.GRID))
    ex.write_measurements(rows, grid)
    ex.write_measurements(ex.read_dataset(os.path.join(source, ex.TEST)), test)
    return Dataset("UR5, laser tracker", len(rows), d, tracker_steps(args.kincal, d, "point", grid,
                                                                      test),
                   tracker_script(python, d, "point", grid, test),
                   os.path.join(d, "report.json"), os.path.join(d, "validation.json"),
                   ["tracker." + a for a in "xyz"]), None


def prepare_simulated(args, python, sensor, rows):
    d = os.path.join(args.work, "sim-%s-%d" % (sensor, rows))
    os.makedirs(d, exist_ok=True)
    noise = POINT_NOISE if sensor == "point" else POSE_NOISE
    units = ["mm", "rad"]
    noise_arg = ",".join("%g%s" % (v, u) for v, u in zip(noise, units))
    data, test = os.path.join(d, "data.csv"), os.path.join(d, "test.csv")
    stamp = os.path.join(d, "made-by.json")
    # kept while these match, whichever kincal made them: before and after see the same data
    made = {"rows": rows, "noise": noise_arg, "seeds": [1, 2], "held_out": 200}
    # kincal simulate holds about 38.5 KB per pose-tracker configuration of this arm (and
    # stops above the memory available: 10^6 would need 38.5 GB), so larger pose sets are
    # simulated in parts of 10^5 rows from the first part's true model, then joined
    part = rows if sensor == "point" else min(rows, PART_ROWS)
    if part < rows:
        made["part_rows"] = part
    try:
        with open(stamp) as f:
            fresh = json.load(f) == made
    except (OSError, ValueError):
        fresh = False
    if not fresh:  # the simulation of 10^6 rows takes minutes: kept between runs
        model = os.path.join(d, "sim-model.json")
        truth = os.path.join(d, "data.truth.json")
        run([args.simulate_with, "model", "--urdf", UR5_URDF, "--tip", "flange", "--sensor",
             sensor + "-tracker", "--out", model])
        common = ["--model", model, "--noise-std", noise_arg, "--allow-rank-deficient",
                  "--validation", "10"]
        run([args.simulate_with, "simulate", "--poses", str(part), "--seed", "1",
             "--write-data", data] + common)
        for i in range(1, (rows + part - 1) // part):
            piece = os.path.join(d, "part.csv")
            run([args.simulate_with, "simulate", "--poses", str(min(part, rows - i * part)),
                 "--seed", str(100 + i), "--truth", truth, "--write-data", piece] + common)
            with open(piece) as f, open(data, "a") as out:
                lines = (line for line in f if not line.startswith("#"))
                next(lines)  # the header
                out.writelines(lines)
            os.remove(piece)
            os.remove(os.path.join(d, "part.truth.json"))
        run([args.simulate_with, "simulate", "--poses", "200", "--seed", "2", "--truth",
             truth, "--write-data", test] + common)
        with open(stamp, "w") as f:
            json.dump(made, f)
    std = noise if sensor == "pose" else None
    readings = ["tracker." + a for a in "xyz"]
    if sensor == "pose":
        readings += ["tracker.rotvec_" + a for a in "xyz"]
    return Dataset("UR5 URDF, simulated %s tracker" % sensor, rows, d,
                   tracker_steps(args.kincal, d, sensor, data, test, std),
                   tracker_script(python, d, sensor, data, test, std),
                   os.path.join(d, "report.json"), os.path.join(d, "validation.json"),
                   readings), None


def prepare_sockets(args, python, robot_key):
    ex = load_example(os.path.join(SOURCE, "examples", "robot_sockets", "run.py"), "socketex")
    robot = ex.ROBOTS[robot_key]
    source = os.path.join(args.datasets, "robot-sockets")
    root = os.path.join(source, "data", robot.folder)
    urdf = os.path.join(source, "urdf", robot.urdf)
    if not (os.path.isdir(root) and os.path.isfile(urdf)):
        return None, "the %s socket data are not in %s" % (robot.name, source)
    d = os.path.join(args.work, "sockets-" + robot_key)
    os.makedirs(d, exist_ok=True)
    k = args.kincal
    # The example's split: every 4th configuration of each socket held out, its outliers left
    # out; its free set (what joint angles determine on this arm) and its sockets' weights.
    train, held = {}, {}
    for s in sorted(os.listdir(root)):
        for hole in (0, 1):
            rows = ex.read_joints(os.path.join(root, s, "hole_%d.csv" % hole))
            rows = [q for i, q in enumerate(rows) if i not in robot.outliers.get((s, hole), ())]
            train[(s, hole)] = [q for i, q in enumerate(rows) if i % 4]
            held[(s, hole)] = [q for i, q in enumerate(rows) if not i % 4]
    names = [ex.sensor_name(s, h) for s, h in sorted(train)]
    columns = [n + "." + a for n in names for a in "xyz"]

    def write(rows_by_socket, path):
        with open(path, "w") as f:
            f.write(",".join(robot.joints + columns) + "\n")
            for (s, hole), rows in sorted(rows_by_socket.items()):
                name = ex.sensor_name(s, hole)
                cells = ["0" if c.startswith(name + ".") else "" for c in columns]
                for q in rows:
                    f.write(",".join(["%.17g" % v for v in q] + cells) + "\n")

    train_csv, held_csv = os.path.join(d, "train.csv"), os.path.join(d, "held.csv")
    write(train, train_csv)
    write(held, held_csv)
    nominal, model = os.path.join(d, "nominal.json"), os.path.join(d, "sockets.json")
    # The sockets start where the nominal model puts the ball (kincal fk, as the example).
    configs = os.path.join(d, "configs.csv")
    ex.write_configs(robot.joints, [q for key in sorted(train) for q in train[key]], configs)
    run([k, "model", "--urdf", urdf, "--tip", "ball_link", "--sensor", "point-tracker",
         "--out", nominal])
    run([k, "fk", "--model", nominal, "--data", configs, "--json", configs + ".json"])
    with open(configs + ".json") as f:
        balls = [[r["pose"][a + "_mm"] for a in "xyz"] for r in json.load(f)["rows"]]
    starts, at = {}, 0
    for key in sorted(train):
        n = len(train[key])
        starts[ex.sensor_name(*key)] = ex.mean_point(balls[at:at + n])
        at += n
    sessions = sorted({s for s, _ in train})

    def make_socket_model():
        with open(model) as f:
            m = json.load(f)
        m["sensors"] = [{"type": "socket", "name": n, "point": starts[n]} for n in names]
        m["constraints"] = [{"type": "fixture-distance", "between": [ex.sensor_name(s, 0),
                                                                     ex.sensor_name(s, 1)],
                             "distance": ex.DISTANCE_MM, "std": 0.05} for s in sessions]
        m["reading_std"] = {"s_*": 0.1}
        m["free"] = robot.free
        with open(model, "w") as f:
            json.dump(m, f, indent=1)

    free_txt = os.path.join(d, "free.txt")
    with open(free_txt, "w") as f:
        f.write("\n".join(robot.free) + "\n")
    steps = [[k, "model", "--urdf", urdf, "--tip", "ball_link", "--sensor", "point-tracker",
              "--out", model],
             make_socket_model,
             [k, "calibrate", "--model", model, "--data", train_csv, "--free", "s_*",
              "--out", os.path.join(d, "calibrated.json"), "--json",
              os.path.join(d, "report.json")],
             [k, "validate", "--model", os.path.join(d, "calibrated.json"), "--data", held_csv,
              "--json", os.path.join(d, "validation.json")]]
    script = [python, os.path.join(HERE, "socket_fit.py"), "--urdf", urdf, "--tip", "ball_link",
              "--data", train_csv, "--test", held_csv, "--free", free_txt, "--reading-std",
              "0.1", "--distance", "%g" % ex.DISTANCE_MM, "--distance-std", "0.05",
              "--out", os.path.join(d, "script.json")]
    rows = sum(len(v) for v in train.values())
    return Dataset("%s, sockets (%d sessions)" % (robot.name, len(sessions)), rows, d, steps,
                   script, os.path.join(d, "report.json"), os.path.join(d, "validation.json"),
                   columns, extra_residuals=len(sessions)), None


# ---- agreement ------------------------------------------------------------------------------

def agreement(ds):
    with open(ds.report) as f:
        report = json.load(f)
    with open(ds.validation) as f:
        validation = json.load(f)
    with open(os.path.join(ds.folder, "script.json")) as f:
        script = json.load(f)
    residuals = report["readings"] + ds.extra_residuals
    kincal_rms = (2.0 * report["final_cost"] / residuals) ** 0.5
    rms_rel = abs(script["residual_rms"] - kincal_rms) / kincal_rms
    held_mm, held_rad = 0.0, 0.0
    rows = validation["residuals"]
    mine = script["held_out_residuals"]
    if len(rows) != len(mine):
        return dict(ok=False, why="held-out rows: kincal %d, script %d" % (len(rows), len(mine)))
    if ds.name.startswith(("Panda", "KUKA")):  # one socket a row: its three readings
        kincal_rows = [[r[c] for c in ds.readings if r.get(c) is not None] for r in rows]
    else:
        kincal_rows = [[r[c] for c in ds.readings] for r in rows]
    for a, b in zip(kincal_rows, mine):
        for i, (u, v) in enumerate(zip(a, b)):
            if i < 3:
                held_mm = max(held_mm, abs(u - v))
            else:
                held_rad = max(held_rad, abs(u - v))
    kincal_free = {p["name"] for p in report["parameters"]}
    differ = len(kincal_free ^ set(script["free"])) // 2
    same_count = len(kincal_free) == len(script["free"])
    ok = (residuals == script["residuals"] and rms_rel <= MAX_RMS_RELATIVE
          and held_mm <= MAX_HELD_MM and held_rad <= MAX_HELD_RAD and same_count)
    return dict(ok=ok, rms_kincal=kincal_rms, rms_script=script["residual_rms"],
                rms_relative=rms_rel, held_mm=held_mm, held_rad=held_rad,
                free=len(kincal_free), free_differ=differ, free_same_count=same_count,
                residuals=residuals, script_residuals=script["residuals"],
                kincal_iterations=report["iterations"], script_iterations=script["iterations"])


# ---- the runs and the table -----------------------------------------------------------------

def measure(ds, timeout, work):
    """(wall, CPU, peak MiB) of kincal's chain and of the script, None for one that ran out
    of time or failed, and what happened to it then."""
    wall = cpu = peak = 0.0
    notes, failed = [], False
    try:
        for step in ds.steps:
            if callable(step):
                step()
                continue
            w, c, m = timed(step, timeout)
            wall, cpu, peak = wall + w, cpu + c, max(peak, m)
        kincal = (wall, cpu, peak)
    except (TimedOut, Failed) as e:
        failed = failed or isinstance(e, Failed)
        notes.append("kincal: %s" % (e if isinstance(e, Failed) else
                                     "over %g s (%s stopped)" % (timeout, e)))
        print("  " + notes[-1], flush=True)
        kincal = None
    try:
        script = timed(ds.script, timeout)
    except (TimedOut, Failed) as e:
        failed = failed or isinstance(e, Failed)
        notes.append("script: %s" % (e if isinstance(e, Failed) else "over %g s" % timeout))
        print("  " + notes[-1], flush=True)
        script = None
    return kincal, script, "; ".join(notes).replace(work + os.sep, ""), failed


def table(results, timeout):
    lines = ["| dataset | rows | kincal wall s | kincal CPU s | kincal MiB | script wall s | "
             "script CPU s | script MiB | script / kincal (wall) | RMS rel. diff | "
             "held-out max diff | free |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in results:
        a = r["agreement"]
        k, s = r["kincal"], r["script"]
        cells = lambda t: ("%.2f | %.2f | %.0f" % t) if t else "– | | "
        if "why" in a:
            lines.append("| %s | %d | %s | %s | %s | %s | | |" % (
                r["dataset"], r["rows"], cells(k), cells(s),
                "%.1f×" % (s[0] / k[0]) if k and s else "", a["why"].replace("|", "/")))
            continue
        held = "%.1e mm" % a["held_mm"] + (", %.1e rad" % a["held_rad"] if a["held_rad"] else "")
        free = "%d, same" % a["free"] if not a["free_differ"] else \
            "%d, %d named differently" % (a["free"], a["free_differ"])
        lines.append("| %s | %d | %s | %s | %.1f× | %.1e | %s | %s%s |"
                     % (r["dataset"], r["rows"], cells(k), cells(s), s[0] / k[0],
                        a["rms_relative"], held, free, "" if a["ok"] else " **disagree**"))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("datasets", nargs="?", default=os.environ.get("KINCAL_DATASETS"),
                    help="the public datasets folder (default: $KINCAL_DATASETS)")
    ap.add_argument("--kincal", required=True, help="the kincal program")
    ap.add_argument("--sizes", default="1e3,1e4,1e5,1e6",
                    help="rows of the simulated sets, comma-separated (default 1e3,1e4,1e5,1e6)")
    ap.add_argument("--only", help="comma-separated subset of: ur5, panda, iiwa14, point, pose")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each, best shown (default 3)")
    ap.add_argument("--repeat-large", type=int, default=1,
                    help="runs of the sets of --large-rows rows or more (default 1)")
    ap.add_argument("--large-rows", type=float, default=1e6,
                    help="the sets run --repeat-large times (default 1e6 rows or more)")
    ap.add_argument("--timeout", type=float, default=1800,
                    help="a command running longer is stopped and shown as '> T s' (default 1800)")
    ap.add_argument("--simulate-with", metavar="PATH",
                    help="the kincal that simulates the sets (default --kincal); the sets are "
                         "kept in --work and reused whichever kincal made them")
    ap.add_argument("--work", default="real-data-work", help="folder for the files (created)")
    ap.add_argument("--out", action="append", default=[],
                    help="write the results: .json as JSON, otherwise the Markdown table")
    ap.add_argument("--python", default=sys.executable,
                    help="the interpreter of the scripts (default: this one)")
    args = ap.parse_args()
    if not args.datasets or not os.path.isdir(args.datasets):
        print("skipped: no datasets folder %s" % args.datasets)
        return 77
    check = subprocess.run([args.python, "-c", "import numpy, scipy"], capture_output=True)
    if check.returncode != 0:
        print("skipped: %s cannot import numpy and scipy (Debian: python3-numpy, python3-scipy)"
              % args.python)
        return 77
    if args.repeat < 1 or args.repeat_large < 1:
        ap.error("--repeat and --repeat-large must be at least 1")
    sizes = [int(float(s)) for s in args.sizes.split(",") if s]
    only = set(args.only.split(",")) if args.only else {"ur5", "panda", "iiwa14", "point", "pose"}
    args.kincal = os.path.abspath(args.kincal)
    args.simulate_with = os.path.abspath(args.simulate_with or args.kincal)
    args.work = os.path.abspath(args.work)
    os.makedirs(args.work, exist_ok=True)

    prepared, skipped = [], []
    for key, make in (("ur5", lambda: prepare_ur5(args, args.python)),
                      ("panda", lambda: prepare_sockets(args, args.python, "panda")),
                      ("iiwa14", lambda: prepare_sockets(args, args.python, "iiwa14"))):
        if key in only:
            ds, why = make()
            (prepared.append(ds) if ds else skipped.append(why))
    for sensor in ("point", "pose"):
        if sensor in only:
            for n in sizes:
                prepared.append(prepare_simulated(args, args.python, sensor, n)[0])

    load_before = os.getloadavg()
    results = []
    for ds in prepared:
        runs = [measure(ds, args.timeout, args.work) for _ in range(
            args.repeat_large if ds.rows >= args.large_rows else args.repeat)]

        def best(i):
            done = [r[i] for r in runs if r[i] is not None]
            return tuple(min(d[j] for d in done) for j in range(3)) if done else None
        kincal, script = best(0), best(1)
        # the outputs of the last run, when both sides finished it
        a = (agreement(ds) if runs[-1][0] and runs[-1][1] else
              # a failure counts as a failed check, running out of time does not
             dict(ok=False if runs[-1][3] else None,
                  why="not checked: " + runs[-1][2]))
        results.append(dict(dataset=ds.name, rows=ds.rows, kincal=kincal, script=script,
                            runs=[dict(kincal=r[0], script=r[1], note=r[2]) for r in runs],
                            agreement=a))
        seconds = lambda t: "%.2f s" % t[0] if t else "–"
        print("%s (%d rows): kincal %s, script %s, %s" % (
            ds.name, ds.rows, seconds(kincal), seconds(script),
            a.get("why") or "RMS rel. diff %.1e, held-out %.1e mm%s" % (
                a["rms_relative"], a["held_mm"], "" if a["ok"] else "  DISAGREE")), flush=True)
    load_after = os.getloadavg()

    text = table(results, args.timeout)
    where = ("%s, %d cores, load average %.2f/%.2f/%.2f before and %.2f/%.2f/%.2f after; "
             "best of %d runs (%d of the sets of %g rows or more); kincal %s; scripts on %s" % (
                 platform.processor() or platform.machine(), os.cpu_count(), *load_before,
                 *load_after, args.repeat, args.repeat_large, args.large_rows, args.kincal, args.python))
    print()
    print(text)
    print()
    print(where)
    for why in skipped:
        print("skipped: " + why)
    for path in args.out:
        with open(path, "w") as f:
            if path.endswith(".json"):
                json.dump(dict(results=results, machine=where, skipped=skipped), f, indent=1)
            else:
                f.write(text + "\n\n" + where + "\n")
    failed = [r for r in results if r["agreement"]["ok"] is False]
    for r in failed:
        print("FAILED: %s, %d rows: kincal's and the script's calibrations disagree or one "
              "failed: %s" % (r["dataset"], r["rows"], json.dumps(r["agreement"])))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
