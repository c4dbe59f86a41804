"""Studies: many independent calibrations, on a Dask cluster or in this process.

``reproduce(trials=200, client=client)`` is the paper's Monte Carlo, ``kincal reproduce``:
it returns what ``kincal reproduce --json -`` writes, with the same numbers whatever the
number of workers, since trial t of a case is a function of (options, case, t) alone. With a
``dask.distributed`` Client the trials are spread over its workers in tasks of consecutive
trials of every case (by default in shrinking batches, see ``_factored_chunks``); a task
whose worker dies is run again elsewhere (``retries``), and each trial's result is stored
under its (case, trial) index, so nothing is lost or counted twice. Without a client they
run on this machine's cores, the GIL released (``threads``).
"""

from __future__ import annotations

import json
import os
import sys
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

from . import _kincal
from ._errors import KincalError, KincalInterrupt, _on_main_thread

__all__ = ["reproduce", "accuracy", "design_study", "calibrate_fleet"]

NUM_CASES = 5  # the paper's Table 2


def _study_spec(solver: str, seed: int, validation: int, param_error: Union[str, float],
                config_range: Optional[Union[str, float]], max_iterations: int,
                solver_option: Optional[Dict[str, Any]]) -> Dict[str, Any]:
    """The study's settings as typed values, in a plain dict that pickles (it travels to
    Dask's workers as it is)."""
    return {
        "solver": solver,
        "seed": seed,
        "validation": validation,
        "param_error": param_error if isinstance(param_error, str) else repr(float(param_error)),
        "config_range": None if config_range is None
        else config_range if isinstance(config_range, str) else repr(float(config_range)),
        "max_iterations": max_iterations,
        "solver_option": {str(k): str(v) for k, v in (solver_option or {}).items()},
    }


def _run_chunk(spec: Dict[str, Any], tasks: Sequence[Tuple[int, int]]) -> List[Any]:
    """One Dask task: trials of (case index, trial), one thread (the worker's slot)."""
    return list(_kincal.reproduce_trials(spec, list(tasks), 1, False))


def _tasks(first: int, last: int) -> List[Tuple[int, int]]:
    """Trials first..last-1 of every case, as (case index, trial) pairs."""
    return [(c, t) for t in range(first, last) for c in range(NUM_CASES)]


def _chunks(trials: int, chunk: int) -> List[List[Tuple[int, int]]]:
    """Tasks of ``chunk`` consecutive trials (the last one shorter)."""
    return [_tasks(first, min(first + chunk, trials)) for first in range(0, trials, chunk)]


MAX_TRIALS_PER_TASK = 50  # progress steps and a lost worker's work stay small on long studies


def _factored_chunks(trials: int, slots: int) -> List[List[Tuple[int, int]]]:
    """Tasks for ``slots`` workers' threads, largest first: in batches of ``slots`` tasks, each
    task takes 1/(2 slots) of the trials still left (at most MAX_TRIALS_PER_TASK), so a batch
    covers half of what is left and the last tasks hold one trial each. Few tasks (each costs
    about 5 ms of a worker's time and 5 ms of the client's CPU), and the workers finish
    within about a trial of each other: equal chunks leave up to a whole chunk's time on one worker at the
    end, the more so when the machine's other load slows one of them (docs/benchmarks.md,
    "Studies on Dask"). client.map keeps this order (its tasks' priorities are their
    positions)."""
    out: List[List[Tuple[int, int]]] = []
    first = 0
    while first < trials:
        size = min(MAX_TRIALS_PER_TASK, max(1, -(-(trials - first) // (2 * slots))))  # ceil
        for _ in range(slots):
            if first >= trials:
                break
            last = min(first + size, trials)
            out.append(_tasks(first, last))
            first = last
    return out


def _client_slots(client: Any) -> int:
    """The client's worker threads (at least 1, e.g. while its workers are still starting)."""
    return max(1, sum(client.nthreads().values()))


def _progress(done: int, total: int) -> None:
    sys.stderr.write(f"\rkincal.studies.reproduce: {done}/{total} tasks")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _directory_step(step: Callable[..., None], *args: str) -> None:
    """Checks or writes reproduce's out directory as ``kincal reproduce --out`` does (only a
    directory holding just the three tables is replaced, in one step); its refusal is a
    KincalError with the program's message."""
    try:
        step(*args)
    except _kincal.OutputError as e:
        raise KincalError(str(e)) from None


def reproduce(
    trials: int = 100,
    client: Any = None,
    *,
    solver: str = "lm",
    seed: int = 1,
    validation: int = 200,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    chunk: Optional[int] = None,
    retries: int = 3,
    threads: int = 0,
    progress: Union[bool, Callable[[int, int], None]] = False,
    param_error: Union[str, float] = "5mm,0.01rad",
    config_range: Optional[Union[str, float]] = None,
    max_iterations: int = 200,
    solver_option: Optional[Dict[str, Any]] = None,
) -> Dict[str, Any]:
    """The paper's five cases as a Monte Carlo of ``trials`` seeds, as ``kincal reproduce
    --trials TRIALS``; returns its JSON document (a dict). The options are the command's, as
    typed keyword arguments (``param_error="5mm,0.01rad"``, ``config_range=``,
    ``solver_option={...}``, ``max_iterations=``). ``out``: also write summary.csv, trials.csv and trace.csv there
    (the document's "out" is then that directory, else None) as the program does: the
    directory is replaced whole, in one step, so it may hold only those three files
    (anything else is refused before any work, with KincalError). ``progress``: True reports
    tasks done on stderr (with a client, also see the Dask dashboard); a callable is called
    as progress(done, total) after each task (a notebook's progress bar). ``chunk``: trials
    of every case per task; by default, with a client, tasks that shrink as the study nears
    its end (one per worker thread covers the first half; at most 50 trials each), in this
    process 10 (a progress step). The results do not depend on it. Ctrl-C raises
    KincalInterrupt whose ``result`` is the partial document."""
    if trials < 1:
        raise ValueError("trials: expected at least 1")
    if chunk is not None and chunk < 1:
        raise ValueError("chunk: expected at least 1")
    spec = _study_spec(solver, seed, validation, param_error, config_range, max_iterations,
                       solver_option)
    # Bad options fail here, before any work: the same checks the trials make.
    try:
        _kincal.reproduce_report(spec, 1, [[None]] * NUM_CASES, "")
    except ValueError as e:
        raise KincalError(str(e)) from None
    out_dir = None if out is None else os.fspath(out)
    if out_dir is not None:
        # The program's rule for its out directory, checked before any work too.
        _directory_step(_kincal.check_reproduce_directory, out_dir)
    results: List[List[Any]] = [[None] * trials for _ in range(NUM_CASES)]
    report: Optional[Callable[[int, int], None]] = None
    if callable(progress):
        report = progress
    elif progress:
        report = _progress
    interrupted = False
    if chunk is not None:
        chunks = _chunks(trials, chunk)
    elif client is not None:
        chunks = _factored_chunks(trials, _client_slots(client))
    else:
        chunks = _chunks(trials, 10)
    if client is None:
        done = 0
        for tasks in chunks if report else [[task for c in chunks for task in c]]:
            values = _kincal.reproduce_trials(spec, tasks, threads, _on_main_thread())
            for (c, t), value in zip(tasks, values):
                results[c][t] = value
            if any(v is None for v in values):
                interrupted = True
                break
            done += 1
            if report:
                report(done, len(chunks))
    else:
        from distributed import as_completed

        # One graph for all chunks (client.map), and Ctrl-C honoured from the first moment:
        # an interrupt while the tasks are still being sent cancels what was sent.
        futures: List[Any] = []
        done = 0
        try:
            futures = client.map(_run_chunk, [spec] * len(chunks), chunks, pure=False, retries=retries)
            tasks_of = {future.key: tasks for future, tasks in zip(futures, chunks)}
            for future in as_completed(futures):
                for (c, t), value in zip(tasks_of[future.key], future.result()):
                    results[c][t] = value
                done += 1
                if report:
                    report(done, len(chunks))
        except KeyboardInterrupt:
            if futures:
                client.cancel(futures)
            interrupted = True
    text, _rows, summary, trials_csv, trace = _kincal.reproduce_report(spec, trials, results, out_dir or "")
    document: Dict[str, Any] = json.loads(text)
    if out_dir is None:
        document["out"] = None
    else:
        _directory_step(_kincal.write_reproduce_directory, out_dir, summary, trials_csv, trace)
    if interrupted:
        raise KincalInterrupt("kincal.studies.reproduce interrupted: partial results", document)
    return document


def accuracy(
    solvers: Sequence[str], trials: int = 100, client: Any = None, **options: Any
) -> Dict[str, Dict[str, Any]]:
    """The accuracy study over backends: ``reproduce`` once per solver (the same seeds, so
    the same scenarios for every solver), as ``kincal reproduce --solver S`` for each;
    returns solver -> document. Options as ``reproduce``'s."""
    return {s: reproduce(trials, client, solver=s, **options) for s in solvers}


def _portable(model: Any) -> Any:
    """A model as it travels to the workers: a file name, or a Model's model-file text."""
    return ("model-json", model.to_json()) if isinstance(model, _kincal.Model) else model


def _unpacked(model: Any) -> Any:
    if isinstance(model, tuple) and model[0] == "model-json":
        return _kincal.Model.from_json(model[1])
    return model


def _design_one(model: Any, count: int, criterion: str, options: Dict[str, Any]) -> Dict[str, Any]:
    from .workflows import design

    return design(_unpacked(model), count=count, criterion=criterion, **options).to_dict()


def _calibrate_one(model: Any, data: Any, options: Dict[str, Any]) -> Dict[str, Any]:
    from .workflows import calibrate

    return calibrate(_unpacked(model), data, **options).to_dict()


def design_study(
    model: Any,
    counts: Sequence[int],
    criteria: Sequence[str] = ("D",),
    client: Any = None,
    *,
    retries: int = 3,
    **options: Any,
) -> List[Dict[str, Any]]:
    """A design study: ``kincal design`` for every (count, criterion) pair, on the client's
    workers when one is given; returns their JSON reports in the order of the pairs
    (criteria varying fastest). ``model`` is a model file (readable on the workers) or a
    Model; options as the command's (``noise_std=``, ``seed=``, ``bound=True``...)."""
    pairs = [(n, c) for n in counts for c in criteria]
    if client is None:
        return [_design_one(model, n, c, options) for n, c in pairs]
    m = _portable(model)
    futures = [client.submit(_design_one, m, n, c, options, pure=False, retries=retries) for n, c in pairs]
    return list(client.gather(futures))


def calibrate_fleet(
    jobs: Sequence[Tuple[Any, Any]], client: Any = None, *, retries: int = 3, **options: Any
) -> List[Dict[str, Any]]:
    """Calibrates each (model, measurement file) pair, as ``kincal calibrate``, and returns
    their JSON reports in order; on the client's workers when one is given (files must then
    be readable there; a Model travels as its model file's text), else one after the other
    here."""
    if client is None:
        return [_calibrate_one(m, d, options) for m, d in jobs]
    futures = [
        client.submit(_calibrate_one, _portable(m), d, options, pure=False, retries=retries)
        for m, d in jobs
    ]
    return list(client.gather(futures))
