"""Ctrl-C during a long solve: KeyboardInterrupt carrying the best point so far."""

import os
import signal
import subprocess
import sys
import textwrap
import time


def interrupted(script, first_line, wait, timeout=120, **popen):
    """Runs `script` in a new Python, sends it SIGINT `wait` seconds after its first line (which
    must be `first_line`), and returns what it printed after that line and the seconds from
    the signal to its exit, which must be 0."""
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                         env=os.environ, **popen)
    assert p.stdout is not None
    assert p.stdout.readline().strip() == first_line
    time.sleep(wait)
    start = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=timeout)
    assert p.returncode == 0, out
    return out, time.monotonic() - start

LONG_SOLVE = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    import kincal

    # r(x) = exp(-x): each Gauss-Newton step moves x by +1 and no tolerance of 0 is met
    # before exp(-x) underflows near x = 745, some 745 slow evaluations away.
    def residuals(x):
        time.sleep(0.005)
        return np.exp(-x)

    def jacobian(x):
        return np.diag(-np.exp(-x))

    problem = kincal.LeastSquaresProblem(residuals, jacobian, 1, 1)
    print("solving", flush=True)
    try:
        kincal.solve(problem, np.zeros(1), "gn", max_iterations=100000, function_tolerance=0,
                     parameter_tolerance=0, gradient_tolerance=0)
    except KeyboardInterrupt as e:
        r = e.result
        print("interrupted", r.termination, r.x[0], r.iterations, flush=True)
        sys.exit(0)
    print("finished", flush=True)
    """
)


def test_sigint_during_a_long_solve_raises_keyboard_interrupt_with_the_best_point():
    out, seconds = interrupted(LONG_SOLVE, "solving", 1.0, timeout=60)
    words = out.split()
    assert words[0] == "interrupted", out
    assert words[1] == "user_stopped"
    x, iterations = float(words[2]), int(words[3])
    assert 0 < iterations < 700 and abs(x - iterations) < 1e-6  # x moved by 1 per step
    assert seconds < 30  # stopped, did not run to the end


LONG_COMMAND = textwrap.dedent(
    """
    import kincal

    print("solving", flush=True)
    try:
        # A derivative-free method on 24 parameters and 600 configurations: about ten
        # seconds of evaluations, well past the signal at two (case 5's 60 configurations
        # ended in under two seconds once forward kinematics got faster).
        kincal.simulate(preset="cube-hexapod", poses=600, noise_half_width=0.0125, seed=2,
                        solver="nlopt:LN_NELDERMEAD", max_iterations=10**9)
    except KeyboardInterrupt as e:
        r = e.result
        print("interrupted", r.termination, r.iterations, r.final_cost < r.initial_cost, flush=True)
        raise SystemExit(0)
    print("finished", flush=True)
    """
)


def test_sigint_during_a_command_stops_its_solve_with_the_report_of_the_best_point():
    out, _ = interrupted(LONG_COMMAND, "solving", 2.0, timeout=60)
    assert out.split() == ["interrupted", "user_stopped", out.split()[2], "True"], out


LONG_STARTS = textwrap.dedent(
    """
    import time
    import kincal

    print("solving", flush=True)
    start = time.monotonic()
    try:
        # Four starts of the run above: tens of seconds on two cores.
        kincal.simulate(preset="cube-hexapod", poses=600, noise_half_width=0.0125, seed=2,
                        solver="nlopt:LN_NELDERMEAD", max_iterations=10**9, starts=4)
    except KeyboardInterrupt as e:
        r = e.result
        print("interrupted", r.termination, r.final_cost < r.initial_cost,
              time.monotonic() - start < 30, flush=True)
        raise SystemExit(0)
    print("finished", flush=True)
    """
)


def test_sigint_during_several_starts_stops_them_all():
    out, _ = interrupted(LONG_STARTS, "solving", 2.0)
    assert out.split() == ["interrupted", "user_stopped", "True", "True"], out


LONG_STUDY = textwrap.dedent(
    """
    import kincal.studies

    print("running", flush=True)
    try:
        kincal.studies.reproduce(trials=5000)
    except KeyboardInterrupt as e:
        doc = e.result
        print("interrupted", doc["partial"], min(c["trials"] for c in doc["cases"]), flush=True)
        raise SystemExit(0)
    print("finished", flush=True)
    """
)


def test_sigint_during_an_in_process_study_gives_the_partial_document():
    out, _ = interrupted(LONG_STUDY, "running", 1.5)
    words = out.split()
    assert words[:2] == ["interrupted", "True"], out
    assert 0 < int(words[2]) < 5000


GIL_RELEASED = textwrap.dedent(
    """
    import os, threading, time
    import kincal.studies

    started = threading.Event()

    def study():
        started.set()
        kincal.studies.reproduce(trials=500, threads=1)  # some 20 s of C++ on one core

    t = threading.Thread(target=study, daemon=True)
    t.start()
    started.wait()
    time.sleep(0.5)
    # Python runs here only if the study released the GIL: with it held, this thread would
    # wait for the whole study and find it finished.
    ticks, start = 0, time.monotonic()
    while time.monotonic() - start < 0.2:
        ticks += 1
    print("alive" if t.is_alive() else "finished", ticks, flush=True)
    os._exit(0)
    """
)


def test_the_gil_is_released_while_kincal_computes():
    p = subprocess.run([sys.executable, "-c", GIL_RELEASED], capture_output=True, text=True, env=os.environ,
                       timeout=120)
    words = p.stdout.split()
    assert words and words[0] == "alive", p.stdout + p.stderr
    assert int(words[1]) > 1000


LONG_DESIGN = textwrap.dedent(
    """
    import kincal

    model = kincal.Model.preset("cube-hexapod")
    print("designing", flush=True)
    try:
        kincal.design(model, count=200, noise_std="0.0007mm", candidates=2000000)
    except KeyboardInterrupt as e:
        print("interrupted", e.result["partial"], flush=True)
        raise SystemExit(0)
    print("finished", flush=True)
    """
)


def test_sigint_during_a_design_gives_the_best_design_so_far_marked_partial():
    out, _ = interrupted(LONG_DESIGN, "designing", 2.0)
    assert out.split() == ["interrupted", "True"], out


DASK_STUDY = textwrap.dedent(
    """
    import os
    from distributed import Client, LocalCluster
    import kincal.studies

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    client = Client(cluster)
    started = []

    def first_task_done(done, total):
        if not started:
            started.append(done)
            print("running", flush=True)

    try:
        kincal.studies.reproduce(trials=5000, client=client, chunk=5, progress=first_task_done)
    except KeyboardInterrupt as e:
        doc = e.result
        print("interrupted", doc["partial"], min(c["trials"] for c in doc["cases"]),
              max(c["trials"] for c in doc["cases"]), flush=True)
        os._exit(0)  # the cluster's teardown is not what is tested
    print("finished", flush=True)
    os._exit(0)
    """
)


def test_sigint_during_a_study_on_dask_cancels_it_and_gives_the_partial_document():
    # "running" comes once the first task has finished on a worker: the interrupt lands
    # mid-study however slow the machine is to start the cluster and send the tasks.
    out, _ = interrupted(DASK_STUDY, "running", 1.0, start_new_session=True)
    words = out.split()
    assert words[:2] == ["interrupted", "True"], out
    # Trials that finished on the workers are in the document; the study did not finish.
    assert 0 < int(words[2]) <= int(words[3]) < 5000, out


LONG_CALIBRATE = textwrap.dedent(
    """
    import kincal

    path = "d.csv"  # in the test's own directory
    kincal.simulate(preset="cube-hexapod", poses=600, noise_half_width=0.0125, seed=2,
                    write_data=path)
    model = kincal.Model.preset("cube-hexapod")
    data = kincal.Measurements.read(path, model)
    print("solving", flush=True)
    try:
        # The calibrate workflow, called directly: about ten seconds of evaluations.
        kincal.calibrate(model, data, solver="nlopt:LN_NELDERMEAD", max_iterations=10**9)
    except KeyboardInterrupt as e:
        r = e.result
        print("interrupted", r.termination, r.final_cost < r.initial_cost, flush=True)
        raise SystemExit(0)
    print("finished", flush=True)
    """
)


def test_sigint_during_the_calibrate_workflow_gives_the_report_of_the_best_point(tmp_path):
    out, _ = interrupted(LONG_CALIBRATE, "solving", 2.0, timeout=60, cwd=tmp_path)
    assert out.split() == ["interrupted", "user_stopped", "True"], out
