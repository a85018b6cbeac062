# SPDX-License-Identifier: GPL-3.0-or-later
"""``oraclemesh batch``: meshes many cases, each by ``oraclemesh mesh`` in its own process (a crash
or a bad scene stops only that case). The cases are scenes, or a study file's scenes times its
parameter sweeps (see load_study). They run on a local pool, ``--jobs`` at once (the default), or
on Dask distributed: a local cluster of ``--workers`` processes, or an existing cluster given by
``--scheduler tcp://HOST:PORT``; each case is one Dask task.

Per case a folder OUTDIR/<case>/ gets mesh.<format>, report.txt, dihedral.png (the dihedral-angle
histogram), section.png (a cross-section of the mesh), mesh.log (the process's messages) and, last
and atomically, result.json (the case's inputs' fingerprint and its summary row). A case whose
result.json says "ok" for the same inputs, with its files present, is not meshed again: a study
stopped midway (Ctrl-C, a killed client, a lost machine) redoes only what is missing when it is run
again. The summary CSV has a row per case, in the cases' order, whoever ran them. Exit code 1 when
any case failed."""
import csv
import glob
import hashlib
import itertools
import json
import os
import re
import subprocess
import sys
import threading
import time
import uuid
from concurrent.futures import ThreadPoolExecutor

from .progress import PROGRESS_PREFIX
from .errors import OracleMeshError
from . import fieldkeys

RESULT_VERSION = 2  # of result.json; a change redoes every case (2: the unused_vertices column)
STUDY_KEYS = {"scenes", "sweep", "formats", "description", "comment"}
# The validity check's counts (report.VALIDITY_ITEMS), one column each, without "validity.".
VALIDITY_COLUMNS = ("duplicate_vertices", "micro_tetrahedra", "flat_tetrahedra", "inverted_tetrahedra",
                    "non_manifold_faces", "bad_vertex_indices", "material_mismatches", "missing_segment_pieces",
                    "unused_vertices")
HEAD_COLUMNS = ("case", "scene")
MESH_COLUMNS = ("status", "tets", "vertices", "min_dihedral", "max_dihedral", fieldkeys.FEATURE_COVERAGE,
                "validity_defects") \
    + VALIDITY_COLUMNS
TAIL_COLUMNS = ("seconds", "outputs", "error")
MATERIAL_COLUMNS = ("tets", "volume", "volume_error", "min_dihedral", "max_dihedral")  # per material: tets_<id>, ...


def _stems(scenes):
    """Names per scene: the file name without .json (a study's scene.json files in folders of
    their own: the folder's name), made unique with -2, -3..."""
    used, stems = {}, []
    for scene in scenes:
        stem = os.path.splitext(os.path.basename(scene))[0] or "scene"
        if stem == "scene" and os.path.basename(os.path.dirname(os.path.abspath(scene))):
            stem = os.path.basename(os.path.dirname(os.path.abspath(scene)))
        stem = _safe(stem)
        used[stem] = used.get(stem, 0) + 1
        stems.append(stem if used[stem] == 1 else f"{stem}-{used[stem]}")
    return stems


def _safe(text):
    return re.sub(r"[^A-Za-z0-9.+_-]", "_", text) or "_"


def _cell(value):
    """A parameter value as a CSV cell and a folder-name part: strings as they are, else JSON."""
    return value if isinstance(value, str) else json.dumps(value, separators=(",", ":"))


def load_study(path):
    """Reads a study file (JSON):

        {"scenes": ["bone.json", "cases/*/scene.json"],
         "sweep": {"criteria.cell_radius_edge_ratio": [1.3, 2], "strategy": ["Conforming", "None"]},
         "formats": ["vtu", "inp"]}

    ``scenes`` (required): scene files or glob patterns, relative to the study file; ``sweep``
    (optional): keys of the scenes' mesh block (dotted, as ``mesh --set``) with the list of values
    each takes: every scene is meshed with every combination; ``formats`` (optional, default vtu).
    Returns (scene paths, [(key, values)], formats or None); OracleMeshError lists every problem."""
    from .scene import set_mesh_keys
    from .writers import MESH_FORMATS

    try:
        with open(path, encoding="utf-8") as f:
            study = json.load(f)
    except FileNotFoundError:
        raise OracleMeshError(f"{path}: study file not found") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise OracleMeshError(f"{path}: not valid JSON: {e}") from None
    except OSError as e:
        raise OracleMeshError(f"{path}: the study file cannot be read ({e.strerror or e})") from None
    if not isinstance(study, dict):
        raise OracleMeshError(f"{path}: a study is an object with 'scenes' and optionally 'sweep', 'formats'")
    base = os.path.dirname(os.path.abspath(path))
    problems = [f"$.{key}: unknown key (use {', '.join(sorted(STUDY_KEYS))})"
                for key in study if key not in STUDY_KEYS and not str(key).startswith("_")]
    patterns = study.get("scenes")
    patterns = [patterns] if isinstance(patterns, str) else patterns
    scenes = []
    if not isinstance(patterns, list) or not patterns or not all(isinstance(p, str) and p for p in patterns):
        problems.append("$.scenes: missing or not a scene file, glob pattern or a non-empty list of them")
        patterns = []
    for k, pattern in enumerate(patterns):
        full = pattern if os.path.isabs(pattern) else os.path.join(base, pattern)
        if glob.has_magic(pattern):
            matches = [m for m in sorted(glob.glob(full, recursive=True))
                       if os.path.abspath(m) != os.path.abspath(path)]  # not the study itself
            if not matches:
                problems.append(f"$.scenes[{k}]: {pattern!r} matches no file")
            scenes += matches
        else:
            scenes.append(os.path.normpath(full))
    sweep = study.get("sweep", {})
    if not isinstance(sweep, dict):
        problems.append("$.sweep: must be an object {mesh key: [values]}")
        sweep = {}
    for key, values in sweep.items():
        if not isinstance(values, list) or not values:
            problems.append(f"$.sweep.{key}: must be a non-empty list of values")
        try:
            set_mesh_keys({}, {key: None}, "$.sweep")
        except OracleMeshError as e:
            problems.append(str(e))
    formats = study.get("formats")
    if formats is not None:
        formats = [formats] if isinstance(formats, str) else formats
        known = [f[1:] for f in MESH_FORMATS]
        if not isinstance(formats, list) or not formats or any(f not in known for f in formats):
            problems.append(f"$.formats: must be a list of {', '.join(known)}, got {study['formats']!r}")
    if problems:
        raise OracleMeshError(f"{path}: " + "; ".join(problems))
    return scenes, [(key, values) for key, values in sweep.items()], formats


def make_cases(scenes, sweep, outdir, formats, strategy=None, timeout=None, pictures=True):
    """The cases: every scene with every combination of the sweep's values (scenes outer, the
    sweep's keys in order), each a plain dict (what a Dask task gets)."""
    keys = [key for key, _ in sweep]
    last = [key.split(".")[-1] for key in keys]
    short = [s if last.count(s) == 1 else key.replace(".", "_") for s, key in zip(last, keys)]
    cases, used = [], {}
    for scene, stem in zip(scenes, _stems(scenes)):
        for combination in itertools.product(*[values for _, values in sweep]):
            name = stem + "".join(f"__{s}-{_safe(_cell(v))}" for s, v in zip(short, combination))
            used[name] = used.get(name, 0) + 1
            name = name if used[name] == 1 else f"{name}-{used[name]}"
            case = {"id": name, "scene": scene, "params": dict(zip(keys, combination)),
                    "folder": os.path.join(outdir, name), "outdir": outdir, "formats": list(formats),
                    "strategy": strategy, "timeout": timeout, "pictures": pictures}
            case["fingerprint"] = _fingerprint(case)
            cases.append(case)
    return cases


def _inputs(scene):
    """The files a scene reads (domains' and feature files), with their size and modification time."""
    try:
        with open(scene, encoding="utf-8") as f:
            description = json.load(f)
    except (OSError, ValueError):
        return []
    if not isinstance(description, dict):
        return []
    files = [d.get("file") for d in description.get("domains", []) if isinstance(d, dict)]
    features = (description.get("mesh") or {}).get("features") if isinstance(description.get("mesh"), dict) else None
    if isinstance(features, dict):
        more = features.get("files", [])
        more = [more] if isinstance(more, (str, dict)) else more if isinstance(more, list) else []
        files += [m.get("file") if isinstance(m, dict) else m for m in more]  # {"file": ..., "edge_size": ...} entries
    out = []
    for file in files:
        if isinstance(file, str) and file:
            full = file if os.path.isabs(file) else os.path.join(os.path.dirname(os.path.abspath(scene)), file)
            try:
                st = os.stat(full)
                out.append([full, st.st_size, st.st_mtime_ns])
            except OSError:
                out.append([full, None, None])
    return out


def _fingerprint(case):
    """What a case's result depends on: the scene file's bytes, the size and time of the files it
    reads, the parameters, formats, strategy and pictures."""
    digest = hashlib.sha256()
    try:
        with open(case["scene"], "rb") as f:
            digest.update(f.read())
    except OSError as e:
        digest.update(f"unreadable: {e}".encode())
    digest.update(json.dumps({"version": RESULT_VERSION, "inputs": _inputs(case["scene"]),
                              "params": case["params"], "formats": case["formats"],
                              "strategy": case["strategy"], "pictures": case["pictures"]},
                             sort_keys=True).encode())
    return digest.hexdigest()


def _child_environment():
    """The environment for `python -m oraclemesh` in a child: this package importable first; the
    child ends when this process does (see __main__._die_with_parent)."""
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = package_parent + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["ORACLEMESH_PARENT_PID"] = str(os.getpid())
    return env


def _files(case):
    folder = case["folder"]
    return {"outputs": [os.path.join(folder, f"mesh.{f}") for f in case["formats"]],
            "report": os.path.join(folder, "report.txt"), "log": os.path.join(folder, "mesh.log"),
            "summary": os.path.join(folder, ".summary.json"), "result": os.path.join(folder, "result.json"),
            "histogram": os.path.join(folder, "dihedral.png"), "section": os.path.join(folder, "section.png")}


def _row_head(case):
    return {"case": case["id"], "scene": case["scene"], **{k: _cell(v) for k, v in case["params"].items()}}


def _angle(value):
    """An angle for the CSV; empty when the summary has none (a case meshed before the column)."""
    return "" if value is None else f"{value:.3f}"


def _summary_row(case, summary, files):
    """The CSV row of a case meshed: totals, validity counts, per material tets, volume, volume error
    (when the scene gives a reference volume: (mesh - reference) / reference), min and max dihedral."""
    coverage = summary.get(fieldkeys.FEATURE_COVERAGE)
    validity = summary.get("validity", {})
    row = dict(status="ok", tets=summary["tets"], vertices=summary["vertices"],
               min_dihedral=f"{summary['min_dihedral']:.3f}",
               max_dihedral=_angle(summary.get("max_dihedral")),
               feature_coverage="" if coverage is None else f"{coverage:.4f}",
               validity_defects=int(summary.get("validity_defects", 0)))
    for name in VALIDITY_COLUMNS:
        if "validity." + name in validity:
            row[name] = int(validity["validity." + name])
    references = summary.get("reference_volumes", {})
    for m, values in sorted(summary.get("materials", {}).items(), key=lambda item: int(item[0])):
        row[f"tets_{m}"] = values["tets"]
        row[f"volume_{m}"] = f"{values['volume']:.10g}"
        if m in references:
            row[f"volume_error_{m}"] = f"{(values['volume'] - references[m]) / references[m]:.6f}"
        row[f"min_dihedral_{m}"] = f"{values['min_dihedral']:.3f}"
        row[f"max_dihedral_{m}"] = _angle(values.get("max_dihedral"))
    picture = [files[k] for k in ("histogram", "section") if case["pictures"]]
    row["outputs"] = ";".join(os.path.relpath(p, case["outdir"]) for p in files["outputs"] + picture)
    row["error"] = ""
    return row


def run_case(case, on_progress=None, on_process=None):
    """Meshes one case with `python -m oraclemesh mesh` in a child process; writes its files and,
    last, result.json; returns the CSV row. Meshing failures are rows with status "failed", not
    exceptions. `on_progress(fraction)` gets the mesher's progress; `on_process(process)` the child
    (returning False stops it: the batch is being interrupted). This is the Dask task."""
    from .atomic import write_text

    files = _files(case)
    os.makedirs(case["folder"], exist_ok=True)
    for stale in (files["result"], files["summary"]):
        if os.path.exists(stale):
            os.remove(stale)
    command = [sys.executable, "-m", "oraclemesh", "mesh", case["scene"], "--report", files["report"],
               "--summary", files["summary"], "--progress-lines"]
    for out in files["outputs"]:
        command += ["-o", out]
    if case["pictures"]:
        command += ["--histogram", files["histogram"], "--section", files["section"]]
    if case["strategy"]:
        command += ["--strategy", case["strategy"]]
    for key, value in case["params"].items():
        command += ["--set", f"{key}={json.dumps(value)}"]
    started = time.perf_counter()
    messages = []
    timeout = case.get("timeout")
    with open(files["log"], "w", encoding="utf-8") as log:
        log.write("$ " + " ".join(command) + "\n")
        log.flush()
        process = subprocess.Popen(command, stdout=log, stderr=subprocess.PIPE, encoding="utf-8",
                                   errors="replace", env=_child_environment())
        if on_process is not None and on_process(process) is False:
            process.terminate()
        timer, timed_out = None, []
        if timeout:
            def stop():
                timed_out.append(True)
                process.kill()
            timer = threading.Timer(timeout, stop)
            timer.start()
        for line in process.stderr:
            if line.startswith(PROGRESS_PREFIX):
                if on_progress is not None:
                    try:
                        on_progress(float(line[len(PROGRESS_PREFIX):]))
                    except ValueError:
                        pass
                continue
            log.write(line)
            messages.append(line.rstrip("\n"))
        rc = process.wait()
        if timer:
            timer.cancel()
    seconds = time.perf_counter() - started
    row = _row_head(case)
    if rc == 0 and os.path.exists(files["summary"]):
        with open(files["summary"]) as f:
            summary = json.load(f)
        os.remove(files["summary"])
        row.update(_summary_row(case, summary, files))
    else:
        errors = [m[len("oraclemesh: error: "):] for m in messages if m.startswith("oraclemesh: error: ")]
        log_name = os.path.relpath(files["log"], case["outdir"])
        if timed_out:
            error = f"stopped after the {timeout:g} s timeout"
        elif errors:
            error = errors[-1]
        elif rc == 130:
            error = "interrupted"
        elif rc < 0:
            error = f"the mesh process died (signal {-rc}); see {log_name}"
        else:
            error = (messages[-1] if messages else f"exit code {rc}") + f" (see {log_name})"
        row.update(status="failed", error=error)
    row["seconds"] = f"{seconds:.2f}"
    write_text(files["result"], json.dumps({"version": RESULT_VERSION, "fingerprint": case["fingerprint"],
                                            "case": case["id"], "row": row}, indent=1) + "\n")
    return row


def finished_row(case):
    """The row of a case already meshed with the same inputs (result.json "ok", same fingerprint,
    its files present), else None."""
    try:
        with open(_files(case)["result"], encoding="utf-8") as f:
            result = json.load(f)
    except (OSError, ValueError):
        return None
    row = result.get("row") if isinstance(result, dict) else None
    if (not isinstance(row, dict) or result.get("fingerprint") != case["fingerprint"]
            or row.get("status") != "ok"):
        return None
    outputs = [p for p in str(row.get("outputs", "")).split(";") if p]
    if not outputs or not all(os.path.isfile(os.path.join(case["outdir"], p)) for p in outputs):
        return None
    return row


def write_summary(path, cases, rows):
    """The summary CSV, a row per case in the cases' order (atomically)."""
    from .atomic import write_text

    params = list(dict.fromkeys(k for case in cases for k in case["params"]))
    materials = sorted({int(k[5:]) for row in rows if row for k in row if re.fullmatch(r"tets_\d+", k)})
    columns = list(HEAD_COLUMNS) + params + list(MESH_COLUMNS)
    for m in materials:
        for name in MATERIAL_COLUMNS:
            if name != "volume_error" or any(row and f"volume_error_{m}" in row for row in rows):
                columns.append(f"{name}_{m}")
    columns += TAIL_COLUMNS
    import io

    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for case, row in zip(cases, rows):
        row = row or dict(_row_head(case), status="not run")
        writer.writerow({k: row.get(k, "") for k in columns})
    write_text(path, text.getvalue())


class _Board:
    """Prints a line per finished case (and, on a terminal, the running cases' progress)."""

    def __init__(self, total):
        self.total, self.done, self.failed = total, 0, 0
        self.tty = sys.stdout.isatty()

    def finished(self, case, row):
        self.done += 1
        if self.tty:
            sys.stdout.write("\r\033[K")
        if row["status"] == "ok":
            print(f"[{self.done}/{self.total}] {case['id']}: ok, {row['tets']} tetrahedra, min dihedral "
                  f"{row['min_dihedral']}°, {row['seconds']} s", flush=True)
        else:
            self.failed += 1
            print(f"[{self.done}/{self.total}] {case['id']}: FAILED", flush=True)
            error, scene = row["error"], case["scene"]
            print(f"oraclemesh batch: {case['id']}: "
                  + (error if error.startswith(scene + ':') else f"{scene}: {error}"),
                  file=sys.stderr, flush=True)

    def running(self, progress):
        if not self.tty or not progress:
            return
        width = 24
        filled = int(width * self.done / self.total)
        parts = [f"[{'#' * filled}{'-' * (width - filled)}] {self.done}/{self.total} cases"
                 + (f", {self.failed} failed" if self.failed else ""),
                 "meshing " + ", ".join(f"{name} {100 * p:.0f}%" for name, p in progress.items())]
        sys.stdout.write("\r\033[K" + " | ".join(parts)[:200])
        sys.stdout.flush()


def _run_local(todo, jobs, board, rows):
    """The local pool: `jobs` threads, each waiting on one case's process."""
    progress, processes, lock = {}, set(), threading.Lock()
    stopping = threading.Event()

    def start(case):
        def on_progress(fraction):
            progress[case["id"]] = fraction

        def on_process(process):
            with lock:
                processes.add(process)
            return not stopping.is_set()

        progress[case["id"]] = 0.0
        try:
            return run_case(case, on_progress, on_process)
        finally:
            progress.pop(case["id"], None)

    pool = ThreadPoolExecutor(max_workers=jobs)
    try:
        futures = {pool.submit(start, case): (index, case) for index, case in todo}
        pending = set(futures)
        while pending:
            finished = {f for f in pending if f.done()}
            for future in sorted(finished, key=lambda f: futures[f][0]):
                index, case = futures[future]
                try:
                    rows[index] = future.result()
                except Exception as e:  # a bug in the runner itself: still report the case
                    rows[index] = dict(_row_head(case), status="failed", error=f"batch runner: {e}")
                board.finished(case, rows[index])
            pending -= finished
            if pending:
                board.running(dict(progress))
                time.sleep(0.2)
    except BaseException:
        stopping.set()
        pool.shutdown(wait=False, cancel_futures=True)
        with lock:
            for process in processes:
                if process.poll() is None:
                    process.terminate()
        raise
    finally:
        pool.shutdown(wait=True)


def _dask_client(scheduler, workers):
    """A Dask client: of the cluster at `scheduler`, or of a new local cluster of `workers` processes
    with one thread each (one case at a time per process). Returns (client, cluster or None)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise OracleMeshError(f"{'--scheduler' if scheduler else '--workers'}: needs Dask distributed "
                              "(Debian: apt install python3-distributed)") from None
    if scheduler:
        try:
            return Client(scheduler, timeout="20s"), None
        except (OSError, TimeoutError, ValueError) as e:
            raise OracleMeshError(f"--scheduler {scheduler}: cannot connect: {e}") from None
    import logging

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def _run_dask(todo, client, retries, board, rows):
    """One Dask task per case (run_case on a worker). A task whose worker dies is run again on
    another worker by the scheduler (up to distributed.scheduler.allowed-failures deaths, default 3;
    then KilledWorker); a task that raises is retried `retries` times."""
    from distributed import as_completed

    token = uuid.uuid4().hex[:8]
    futures = {client.submit(run_case, case, key=f"oraclemesh-{case['id']}-{token}", pure=False,
                             retries=retries): (index, case) for index, case in todo}
    try:
        for future in as_completed(futures):
            index, case = futures[future]
            try:
                rows[index] = future.result()
            except Exception as e:
                name = type(e).__name__
                if name == "KilledWorker":
                    error = ("its Dask workers died each time they ran it (distributed.scheduler.allowed-failures); "
                             f"see {os.path.relpath(_files(case)['log'], case['outdir'])}")
                else:
                    error = f"Dask task failed: {name}: {e}"
                rows[index] = dict(_row_head(case), status="failed", error=error)
            board.finished(case, rows[index])
    except BaseException:
        client.cancel(list(futures))
        raise


def run_batch(args):
    scheduler, workers = getattr(args, "scheduler", None), getattr(args, "workers", None)
    if scheduler and workers is not None:
        raise OracleMeshError("--scheduler and --workers: give one (an existing Dask cluster, or a local one)")
    if args.jobs is not None and (scheduler or workers is not None):
        raise OracleMeshError("--jobs: the local pool's size; with Dask the workers' threads set how many cases run")
    jobs = 1 if args.jobs is None else args.jobs
    if jobs < 1:
        raise OracleMeshError(f"--jobs: must be at least 1, got {jobs}")
    if workers is not None and workers < 1:
        raise OracleMeshError(f"--workers: must be at least 1, got {workers}")
    if args.retries < 0:
        raise OracleMeshError(f"--retries: must be at least 0, got {args.retries}")
    scenes, sweep, study_formats = list(args.scenes), [], None
    if args.study:
        study_scenes, sweep, study_formats = load_study(args.study)
        scenes += study_scenes
    if not scenes:
        raise OracleMeshError("no scenes: give scene files and/or --study STUDY.json")
    formats = list(dict.fromkeys(args.format or study_formats or ["vtu"]))
    outdir = os.path.abspath(args.output_dir)
    os.makedirs(outdir, exist_ok=True)
    csv_path = args.csv or os.path.join(outdir, "summary.csv")
    cases = make_cases(scenes, sweep, outdir, formats, args.strategy, args.timeout, not args.no_pictures)
    rows = [None] * len(cases)
    todo = []
    for index, case in enumerate(cases):
        row = None if args.force else finished_row(case)
        if row is None:
            todo.append((index, case))
        else:
            rows[index] = row
    skipped = len(cases) - len(todo)
    where = (f"on the Dask cluster at {scheduler}" if scheduler else
             f"on a local Dask cluster of {workers} worker(s)" if workers is not None else f"{jobs} at a time")
    print(f"batch: {len(cases)} case(s)" + (f", {skipped} done earlier (skipped)" if skipped else "")
          + f", {where}, into {outdir}", flush=True)
    board = _Board(len(todo))
    try:
        if todo and (scheduler or workers is not None):
            client, cluster = _dask_client(scheduler, workers)
            try:
                _run_dask(todo, client, args.retries, board, rows)
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
        elif todo:
            _run_local(todo, jobs, board, rows)
    finally:  # also when interrupted: the cases done so far (their result.json) are in the summary
        for index, case in todo:
            if rows[index] is None:
                rows[index] = finished_row(case)
        write_summary(csv_path, cases, rows)
    failed = sum(1 for row in rows if row["status"] != "ok")
    print(f"batch: {len(cases) - failed} ok, {failed} failed; summary {csv_path}", flush=True)
    return 1 if failed else 0
