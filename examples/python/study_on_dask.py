"""The paper's study on a Dask cluster (docs/python.md). Usage: study_on_dask.py [TRIALS]
[SCHEDULER]: without SCHEDULER (e.g. tcp://host:8786, started with dask-scheduler and
dask-worker on the machines), a LocalCluster of 2 worker processes here."""

import sys

from distributed import Client, LocalCluster

import kincal.studies

if __name__ == "__main__":  # worker processes import this file again
    trials = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    if len(sys.argv) > 2:
        client = Client(sys.argv[2])
    else:
        client = Client(LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None))
    with client:
        doc = kincal.studies.reproduce(trials=trials, client=client, progress=True)
    for case in doc["cases"]:
        print(f"case {case['case']}: {case['trials']} trials, position after calibration "
              f"{case['position_after_median_mm']:.4f} mm (median)")
