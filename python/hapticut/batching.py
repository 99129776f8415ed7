"""Batch experiments: every combination of a spec's sweep, for each trajectory or recorded session it
names, run headless in simulated time on a Dask cluster (an embedded LocalCluster on this machine unless
a running scheduler's address is given).

    hapticut batch sweep.toml --workers 2 --out results
    hapticut.batch("sweep.toml", workers=2, out="results")

OUT/results.csv has one row a run: its parameters, then the numbers of its report. OUT/runs/ID/ holds
each run's report.json, force_log.csv and params.json, or error.json when it failed. A run's ID is a
hash of what it runs, so running the spec again skips the runs that are done (and tries those that
failed again). A run is written to a folder of its own and renamed into place when complete, so a
worker that dies mid-run leaves nothing half-written, and Dask runs its task again on another worker.
"""

import argparse
import contextlib
import csv
import hashlib
import importlib.machinery
import io
import itertools
import json
import logging
import multiprocessing.process
import os
import pathlib
import shutil
import sys
import time
import tomllib

from . import _hapticut
from .errors import HapticutError

__all__ = ["BatchResult", "batch", "plan"]

RESULTS = "results.csv"
_FIRST_COLUMNS = ["run", "id", "status", "session"]


def _value(toml_text):
    """A swept value's TOML text as Python (4400000.0, 'rk4', [0.5, 0.25])."""
    return tomllib.loads(f"v = {toml_text}")["v"]


def plan(spec):
    """The runs a spec asks for, in order: a list of dicts with the run's index, ID, swept values
    (params), the TOML laid over the scene (overlay), the trajectory it replays (session) and the base
    settings (base). Raises HapticutError, with the spec's file and line, for a spec that cannot run."""
    s = json.loads(_hapticut._batch_spec(str(spec)))
    base = {k: s[k] for k in ("scene", "model", "triangles", "tool", "steps", "integrator", "rate_hz")}
    axes = s["sweep"]
    sessions = [str(pathlib.Path(p).resolve()) for p in s["sessions"]] or [None]
    runs = []
    for session, combination in itertools.product(sessions, itertools.product(*(a["values"] for a in axes))):
        overlay = "".join(f"{a['key']} = {v}\n" for a, v in zip(axes, combination))
        what = json.dumps({"base": base, "overlay": overlay, "session": session}, sort_keys=True)
        runs.append({
            "index": len(runs),
            "id": hashlib.sha256(what.encode()).hexdigest()[:12],
            "params": {a["key"]: _value(v) for a, v in zip(axes, combination)},
            "overlay": overlay,
            "session": session,
            "base": base,
        })
    return runs


def _execute(run, out):
    """One run in a worker: writes OUT/runs/ID/ whole, or not at all, and returns its row."""
    runs = pathlib.Path(out) / "runs"
    final = runs / run["id"]
    work = runs / f".{run['id']}.{os.getpid()}.partial"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    b = run["base"]
    (work / "params.json").write_text(json.dumps(
        {"index": run["index"], "id": run["id"], "params": run["params"], "session": run["session"], "base": b},
        indent=1) + "\n")
    # The workers take a core each, so a run's implicit solve takes one thread rather than the pool a lone
    # run takes (every core but two), unless the sweep sets it; the results are the same either way.
    overlay = run["overlay"]
    if "simulation.solver_threads" not in overlay:
        overlay = "simulation.solver_threads = 1\n" + overlay
    try:
        report, log = _hapticut._run(b["scene"] or "", overlay, b["model"], b["triangles"], run["session"],
                                     b["tool"], b["steps"], b["integrator"], b["rate_hz"])
        (work / "report.json").write_text(report + "\n")
        (work / "force_log.csv").write_text(log)
    except (HapticutError, ValueError) as e:
        _write_error(work, e)
    _move_into_place(work, final)
    return _row(run, final)


def _write_error(folder, error):
    (folder / "error.json").write_text(json.dumps({
        "message": str(error), "type": type(error).__name__,
        "file": getattr(error, "file", None), "line": getattr(error, "line", None)}) + "\n")


def _move_into_place(work, final):
    if final.exists() and not (final / "report.json").exists():
        shutil.rmtree(final, ignore_errors=True)  # a failed attempt of an earlier batch
    try:
        os.rename(work, final)
    except OSError:  # the same run finished elsewhere first (a worker thought lost was not)
        shutil.rmtree(work, ignore_errors=True)


def _done(out, run):
    return (pathlib.Path(out) / "runs" / run["id"] / "report.json").is_file()


def _row(run, folder):
    row = {"run": run["index"], "id": run["id"], "status": "ok",
           "session": pathlib.Path(run["session"]).name if run["session"] else ""}
    row.update(run["params"])
    report = folder / "report.json"
    if report.is_file():
        for key, value in json.loads(report.read_text()).items():
            if key != "provenance" and not isinstance(value, (dict, list)):
                row[key] = value
    else:
        error = folder / "error.json"
        row["status"] = "failed"
        row["error"] = json.loads(error.read_text())["message"] if error.is_file() else "no result"
    return row


def _csv_value(value):
    if isinstance(value, (list, tuple)):
        return " ".join(str(v) for v in value)
    return "" if value is None else value


def _write_results(out, runs, rows):
    columns = list(_FIRST_COLUMNS)
    for row in rows:
        for key in row:
            if key not in columns and key != "error":
                columns.append(key)
    columns.append("error")
    text = io.StringIO()
    writer = csv.DictWriter(text, columns, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _csv_value(row.get(k)) for k in columns})
    partial = pathlib.Path(out) / f".{RESULTS}.partial"
    partial.write_text(text.getvalue())
    os.replace(partial, pathlib.Path(out) / RESULTS)


class _Progress:
    """A line on stderr that counts runs: redrawn in place on a terminal, every tenth otherwise."""

    def __init__(self, total, skipped, where, show):
        self.total, self.done, self.failed, self.where = total, skipped, 0, where
        self.show, self.tty = show, sys.stderr.isatty()
        self.started = time.monotonic()
        self.step = max(1, (total - skipped) // 10)
        if show:
            print(f"hapticut batch: {total} runs ({skipped} done before) on {where}", file=sys.stderr, flush=True)

    def update(self, row):
        self.done += 1
        if row["status"] != "ok":
            self.failed += 1
            if self.show:
                params = ", ".join(f"{k}={v}" for k, v in row.items() if k not in _FIRST_COLUMNS and k != "error")
                print(f"{chr(13) if self.tty else ''}hapticut batch: run {row['run']} ({params}) failed: "
                      f"{row.get('error')}", file=sys.stderr, flush=True)
        if not self.show:
            return
        bar = "#" * (30 * self.done // max(1, self.total))
        line = (f"hapticut batch: [{bar:<30}] {self.done}/{self.total} runs, {self.failed} failed, "
                f"{time.monotonic() - self.started:.1f} s")
        if self.tty:
            print("\r" + line, end="", file=sys.stderr, flush=True)
        elif self.done % self.step == 0 or self.done == self.total:
            print(line, file=sys.stderr, flush=True)

    def finish(self):
        if self.show and self.tty:
            print(file=sys.stderr, flush=True)


class BatchResult:
    """What a batch did: `rows` (one dict a run, as in results.csv), how many `ran` now, were `skipped`
    (done before) or `failed`, the wall time it took, the cluster it ran on (`where`) and where its
    files are (`out`, `results`)."""

    def __init__(self, out, rows, ran, skipped, elapsed_s, where):
        self.out, self.rows, self.ran, self.skipped = pathlib.Path(out), rows, ran, skipped
        self.failed = sum(1 for r in rows if r["status"] != "ok")
        self.elapsed_s, self.where = elapsed_s, where
        self.results = self.out / RESULTS

    def __repr__(self):
        return (f"<hapticut.BatchResult {len(self.rows)} runs: {self.ran} ran, {self.skipped} done before, "
                f"{self.failed} failed; {self.elapsed_s:.1f} s; {self.results}>")


@contextlib.contextmanager
def _workers_skip_main():
    """While it lasts, new worker processes do not import the script that started the batch. Python's
    spawn imports a script run by path in every child (as __mp_main__), so a script that calls batch()
    at its top level, as scripts do, would start a cluster in each worker without end. A __main__ with a
    spec named __main__ is one a child skips; the workers need nothing from it, only hapticut.batching."""
    main = sys.modules.get("__main__")
    hide = main is not None and getattr(main, "__spec__", None) is None and getattr(main, "__file__", None)
    if hide:
        main.__spec__ = importlib.machinery.ModuleSpec("__main__", None)
    try:
        yield
    finally:
        if hide:
            main.__spec__ = None


def _local_cluster(workers):
    from dask.distributed import LocalCluster

    # The workers are new processes: they must find this package however this one found it.
    here = str(pathlib.Path(__file__).resolve().parent.parent)
    paths = os.environ.get("PYTHONPATH", "").split(os.pathsep)
    if here not in paths:
        os.environ["PYTHONPATH"] = os.pathsep.join([here] + [p for p in paths if p])
    # Dask's statistical profiler samples each worker's Python stack a hundred times a second: a run is
    # C++, so it would learn nothing, and on a small machine it takes time from the runs.
    os.environ.setdefault("DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED", "False")
    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                        silence_logs=logging.ERROR)


def batch(spec, workers=None, scheduler=None, out=None, progress=True, client=None):
    """Runs every combination of `spec`'s sweep (a batch spec file: docs/batch.md) and returns a
    BatchResult. workers: the local cluster's worker processes (default: one a core); scheduler: a
    running Dask scheduler's address ("tcp://host:8786") instead; client: a dask.distributed Client
    of the caller's instead of either. out: the results' folder (default SPEC-STEM-batch in the current
    folder). A run that fails is recorded and the others go on; runs already done are skipped."""
    if getattr(multiprocessing.process.current_process(), "_inheriting", False):
        # A process of the script's own multiprocessing importing it: a batch there would start a
        # cluster in each such process.
        raise RuntimeError("hapticut.batch was called while a new process was importing the script: "
                           "put the script's call under `if __name__ == \"__main__\":`")
    if workers is not None and (int(workers) < 1 or scheduler or client):
        raise ValueError("workers: a number of local worker processes, at least 1, and only for the local cluster")
    spec = pathlib.Path(spec)
    runs = plan(spec)
    out = pathlib.Path(out) if out is not None else pathlib.Path(f"{spec.stem}-batch")
    (out / "runs").mkdir(parents=True, exist_ok=True)
    todo = [r for r in runs if not _done(out, r)]
    with _workers_skip_main():
        return _batch(runs, todo, out, workers, scheduler, client, progress)


def _batch(runs, todo, out, workers, scheduler, client, progress):
    started = time.monotonic()
    cluster = None
    if todo and client is None:
        from dask.distributed import Client

        if scheduler:
            client = Client(scheduler, timeout="30s")
        else:
            cluster = _local_cluster(int(workers or os.cpu_count() or 1))
            client = Client(cluster)
        own_client = True
    else:
        own_client = False
    where = "no cluster (nothing to run)"
    if client is not None:
        where = f"{len(client.scheduler_info()['workers'])} workers at {client.scheduler.address}"
    bar = _Progress(len(runs), len(runs) - len(todo), where, progress)
    try:
        if todo:
            _run_all(client, todo, out, bar)
    finally:
        bar.finish()
        if own_client:
            client.close()
        if cluster is not None:
            cluster.close()
    rows = [_row(r, out / "runs" / r["id"]) for r in runs]
    _write_results(out, runs, rows)
    result = BatchResult(out, rows, len(todo), len(runs) - len(todo), time.monotonic() - started, where)
    if progress:
        print(f"hapticut batch: {len(runs)} runs: {result.ran} ran, {result.skipped} done before, {result.failed} "
              f"failed; {result.elapsed_s:.1f} s; {result.results}", file=sys.stderr, flush=True)
    return result


def _run_all(client, todo, out, bar):
    from dask.distributed import as_completed

    # One map, not a submit a run: Dask reads the caller's source for each call it is given (some 8 ms of
    # the coordinator's time each, which on a 2-core machine the workers would feel).
    submitted = client.map(_execute, todo, [str(out)] * len(todo), key=[f"hapticut-run-{r['id']}" for r in todo],
                           pure=False)
    futures = dict(zip(submitted, todo))
    for future in as_completed(futures):
        run = futures[future]
        try:
            row = future.result()
        except Exception as e:  # the task itself died: its worker was lost too often (KilledWorker), or no hapticut
            folder = pathlib.Path(out) / "runs" / run["id"]
            work = folder.parent / f".{run['id']}.coordinator.partial"
            shutil.rmtree(work, ignore_errors=True)
            work.mkdir(parents=True)
            _write_error(work, RuntimeError(f"{type(e).__name__}: {e}"))
            _move_into_place(work, folder)
            row = _row(run, folder)
        bar.update(row)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="hapticut batch",
        description="Run every combination of a spec's sweep headless on a Dask cluster; write OUT/results.csv "
                    "(a row a run) and OUT/runs/ (each run's report and force log). Runs already done are skipped.")
    parser.add_argument("spec", help="the batch spec (TOML: [batch] and [sweep]; docs/batch.md)")
    parser.add_argument("--workers", type=int, help="worker processes of the local cluster (default: one a core)")
    parser.add_argument("--scheduler", help="a running Dask scheduler's address (tcp://HOST:8786) instead")
    parser.add_argument("--out", help="the results' folder (default: SPEC-STEM-batch here)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    a = parser.parse_args(argv)
    if a.workers is not None and a.scheduler:
        parser.error("--workers sets the local cluster's size; a scheduler's cluster has its own workers")
    try:
        result = batch(a.spec, workers=a.workers, scheduler=a.scheduler, out=a.out, progress=not a.quiet)
    except (HapticutError, ValueError) as e:
        print(f"hapticut batch: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"hapticut batch: {e}", file=sys.stderr)
        return 1
    return 1 if result.failed else 0

