"""kincal.studies.reproduce: the same document as `kincal reproduce`, in-process and on a
2-worker LocalCluster, also when a worker dies mid-study."""

import os
import signal

import pytest

import kincal
from conftest import without_timing

import kincal.studies

TRIALS = 12  # the CI's budget; docs/python.md reports the 200-trial run


def without_paths(doc):
    """A report without timing and the names of the temporary files a Model is passed in."""
    return {k: v for k, v in without_timing(doc).items() if k not in ("model", "template")}


def without_out(doc):
    return {k: v for k, v in doc.items() if k != "out"}


@pytest.fixture(scope="module")
def expected(cli_json, tmp_path_factory):
    out = tmp_path_factory.mktemp("reproduce")
    return cli_json(["reproduce", "--trials", str(TRIALS), "--out", str(out / "tables")])


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as c:
        with distributed.Client(c) as client:
            yield client


def test_in_process_matches_the_program(expected):
    doc = kincal.studies.reproduce(trials=TRIALS)
    assert without_out(doc) == without_out(expected)
    assert doc["out"] is None


def test_two_workers_match_the_program_bit_for_bit(expected, cluster):
    doc = kincal.studies.reproduce(trials=TRIALS, client=cluster, chunk=3)
    assert without_out(doc) == without_out(expected)


def test_the_default_tasks_on_workers_give_the_programs_numbers(expected, cluster):
    # The default shrinking tasks (3, 3, 2, 2, 1, 1 trials on two worker threads) and one
    # trial per task: the same document as the program's.
    assert [len(t) // 5 for t in kincal.studies._factored_chunks(TRIALS, 2)] == [3, 3, 2, 2, 1, 1]
    assert without_out(kincal.studies.reproduce(trials=TRIALS, client=cluster)) == without_out(expected)
    assert without_out(kincal.studies.reproduce(trials=TRIALS, client=cluster, chunk=1)) == without_out(expected)


def test_in_process_steps_give_the_programs_numbers(expected):
    steps = []
    doc = kincal.studies.reproduce(trials=TRIALS, chunk=5, progress=lambda done, total: steps.append(done))
    assert steps == [1, 2, 3]
    assert without_out(doc) == without_out(expected)


@pytest.mark.parametrize("trials", [1, 2, 3, 12, 49, 50, 200, 1001])
@pytest.mark.parametrize("slots", [1, 2, 3, 16])
def test_factored_tasks_hold_every_trial_once_largest_first(trials, slots):
    chunks = kincal.studies._factored_chunks(trials, slots)
    pairs = [pair for chunk in chunks for pair in chunk]
    assert sorted(pairs) == [(c, t) for c in range(5) for t in range(trials)]
    assert len(set(pairs)) == len(pairs)
    sizes = [len(chunk) // 5 for chunk in chunks]
    assert all(5 * size == len(chunk) for size, chunk in zip(sizes, chunks))
    # Each task holds consecutive trials of every case, in order of the trials.
    firsts = [chunk[0][1] for chunk in chunks]
    assert firsts == sorted(firsts) and firsts[0] == 0
    assert sizes == sorted(sizes, reverse=True) and sizes[-1] == 1
    assert max(sizes) <= min(kincal.studies.MAX_TRIALS_PER_TASK, -(-trials // (2 * slots)))
    # Two tasks per worker thread, or more, and far fewer tasks than trials on long studies.
    assert len(chunks) >= min(trials, 2 * slots)
    if trials >= 200 and slots <= 3:
        assert len(chunks) <= trials // 5


def test_tables_are_written_like_the_programs(cluster, tmp_path, program):
    import subprocess

    kincal.studies.reproduce(trials=3, client=cluster, out=str(tmp_path / "py"))
    subprocess.run([program, "reproduce", "--trials", "3", "--out", str(tmp_path / "cli")], check=True,
                   capture_output=True)
    for name in ("summary.csv", "trace.csv"):
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()


def test_a_worker_killed_mid_study_loses_and_duplicates_nothing(expected, cluster):
    pids = cluster.run(os.getpid)
    victim = sorted(pids.values())[0]
    seen = []

    def kill_after_the_first_task(done, total):
        # As a crash would: SIGKILL, mid-study, while tasks are queued and running on it.
        seen.append((done, total))
        if done == 1:
            os.kill(victim, signal.SIGKILL)

    doc = kincal.studies.reproduce(trials=TRIALS, client=cluster, chunk=1, retries=3,
                                   progress=kill_after_the_first_task)
    assert seen[0] == (1, TRIALS) and seen[-1] == (TRIALS, TRIALS)
    assert without_out(doc) == without_out(expected)
    assert sum(c["trials"] for c in doc["cases"]) == 5 * TRIALS


def test_bad_options_fail_before_any_work():
    with pytest.raises(ValueError, match="param_error"):
        kincal.studies.reproduce(trials=2, param_error="5parsecs")


def test_accuracy_over_backends_is_reproduce_per_solver(cli_json, tmp_path):
    docs = kincal.studies.accuracy(["lm", "gn"], trials=2)
    for solver in ("lm", "gn"):
        expected = cli_json(["reproduce", "--trials", "2", "--solver", solver, "--out", str(tmp_path / solver)])
        assert without_out(docs[solver]) == without_out(expected)


def test_design_study_on_workers_matches_the_command(cluster, program, tmp_path):
    model = kincal.Model.preset("cube-hexapod")
    reports = kincal.studies.design_study(model, counts=[30, 40], criteria=["D", "A"], client=cluster,
                                          noise_std="0.0007mm", seed=1)
    assert len(reports) == 4
    local = kincal.design(model, count=40, criterion="A", noise_std="0.0007mm", seed=1).to_dict()
    assert (reports[3]["count"], reports[3]["criterion"]) == (40, "A")
    assert without_paths(reports[3]) == without_paths(local)


def test_fleet_calibration_on_workers(cluster, tmp_path):
    jobs = []
    for seed in (1, 2):
        data = tmp_path / f"robot{seed}.csv"
        kincal.simulate(case=3, seed=seed, write_data=str(data))
        jobs.append((kincal.Model.preset("cube-hexapod"), str(data)))
    reports = kincal.studies.calibrate_fleet(jobs, client=cluster)
    local = [kincal.calibrate(m, d).to_dict() for m, d in jobs]
    assert [without_paths(r) for r in reports] == [without_paths(r) for r in local]
    assert reports[0]["parameters"] != reports[1]["parameters"]  # two robots, two geometries
