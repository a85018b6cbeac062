# SPDX-License-Identifier: GPL-3.0-or-later
"""``oraclemesh batch``: meshes many scenes, each by ``oraclemesh mesh`` in its own process (a crash or
a bad scene stops only that one), at most ``--jobs`` at once. Shows a progress line over the scenes
with the running meshes' own progress, writes per scene OUTDIR/<stem>.<format>, <stem>_report.txt and
<stem>.log (the process's messages), and a summary CSV. Exit code 1 when any scene failed."""
import csv
import os
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

from .errors import OracleMeshError

CSV_COLUMNS = ("scene", "status", "tets", "vertices", "min_dihedral", "feature_coverage", "validity_defects",
               "seconds", "outputs", "error")


def _stems(scenes):
    """Output names per scene: the file name without .json, made unique with -2, -3..."""
    used, stems = {}, []
    for scene in scenes:
        stem = os.path.splitext(os.path.basename(scene))[0] or "scene"
        used[stem] = used.get(stem, 0) + 1
        stems.append(stem if used[stem] == 1 else f"{stem}-{used[stem]}")
    return stems


def _child_environment():
    """The environment for `python -m oraclemesh` in a child: this package importable first."""
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = package_parent + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


class _Job:
    def __init__(self, scene, stem, outdir, formats):
        self.scene, self.stem = scene, stem
        self.outputs = [os.path.join(outdir, f"{stem}.{f}") for f in formats]
        self.report = os.path.join(outdir, f"{stem}_report.txt")
        self.summary = os.path.join(outdir, f".{stem}_summary.json")
        self.log = os.path.join(outdir, f"{stem}.log")
        self.progress = None  # None: waiting; a fraction while meshing
        self.row = None


def _run_one(job, args, env):
    """Runs one scene's `mesh` process; returns the CSV row."""
    import json

    from .__main__ import PROGRESS_PREFIX

    command = [sys.executable, "-m", "oraclemesh", "mesh", job.scene, "--report", job.report,
               "--summary", job.summary, "--progress-lines"]
    for out in job.outputs:
        command += ["-o", out]
    if args.strategy:
        command += ["--strategy", args.strategy]
    started = time.perf_counter()
    job.progress = 0.0
    messages = []
    if os.path.exists(job.summary):
        os.remove(job.summary)
    with open(job.log, "w", encoding="utf-8") as log:
        process = subprocess.Popen(command, stdout=log, stderr=subprocess.PIPE, encoding="utf-8",
                                   errors="replace", env=env)
        timer, timed_out = None, []
        if args.timeout:
            def stop():
                timed_out.append(True)
                process.kill()
            timer = threading.Timer(args.timeout, stop)
            timer.start()
        for line in process.stderr:
            if line.startswith(PROGRESS_PREFIX):
                try:
                    job.progress = float(line[len(PROGRESS_PREFIX):])
                except ValueError:
                    pass
                continue
            log.write(line)
            messages.append(line.rstrip("\n"))
        rc = process.wait()
        if timer:
            timer.cancel()
    seconds = time.perf_counter() - started
    row = {"scene": job.scene, "seconds": f"{seconds:.2f}"}
    if rc == 0 and os.path.exists(job.summary):
        with open(job.summary) as f:
            summary = json.load(f)
        os.remove(job.summary)
        coverage = summary.get("feature_coverage")
        row.update(status="ok", tets=summary["tets"], vertices=summary["vertices"],
                   min_dihedral=f"{summary['min_dihedral']:.3f}",
                   feature_coverage="" if coverage is None else f"{coverage:.4f}",
                   validity_defects=int(summary.get("validity_defects", 0)),
                   outputs=";".join(job.outputs), error="")
    else:
        errors = [m[len("oraclemesh: error: "):] for m in messages if m.startswith("oraclemesh: error: ")]
        if timed_out:
            error = f"stopped after the {args.timeout:g} s timeout"
        elif errors:
            error = errors[-1]
        elif rc < 0:
            error = f"the mesh process died (signal {-rc}); see {job.log}"
        else:
            error = (messages[-1] if messages else f"exit code {rc}") + f" (see {job.log})"
        row.update(status="failed", error=error)
    job.progress = None
    job.row = row
    return row


def _status_line(done, failed, total, running):
    width = 24
    filled = int(width * done / total)
    parts = [f"[{'#' * filled}{'-' * (width - filled)}] {done}/{total} scenes"
             + (f", {failed} failed" if failed else "")]
    if running:
        parts.append("meshing " + ", ".join(f"{j.stem} {100 * j.progress:.0f}%" for j in running))
    return " | ".join(parts)


def run_batch(args):
    if args.jobs < 1:
        raise OracleMeshError(f"--jobs: must be at least 1, got {args.jobs}")
    formats = args.format or ["vtu"]
    formats = list(dict.fromkeys(formats))
    outdir = os.path.abspath(args.output_dir)
    os.makedirs(outdir, exist_ok=True)
    csv_path = args.csv or os.path.join(outdir, "summary.csv")
    jobs = [_Job(scene, stem, outdir, formats) for scene, stem in zip(args.scenes, _stems(args.scenes))]
    env = _child_environment()
    tty = sys.stdout.isatty()
    total, done, failed = len(jobs), 0, 0
    print(f"batch: {total} scene(s), {args.jobs} at a time, into {outdir}", flush=True)
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(_run_one, job, args, env): job for job in jobs}
        pending = set(futures)
        while pending:
            finished = {f for f in pending if f.done()}
            for future in sorted(finished, key=lambda f: jobs.index(futures[f])):
                job = futures[future]
                try:
                    row = future.result()
                except Exception as e:  # a bug in the runner itself: still report the scene
                    row = job.row = {"scene": job.scene, "status": "failed", "error": f"batch runner: {e}"}
                done += 1
                if tty:
                    sys.stdout.write("\r\033[K")
                if row["status"] == "ok":
                    print(f"[{done}/{total}] {job.scene}: ok, {row['tets']} tetrahedra, min dihedral "
                          f"{row['min_dihedral']}°, {row['seconds']} s", flush=True)
                else:
                    failed += 1
                    print(f"[{done}/{total}] {job.scene}: FAILED", flush=True)
                    error = row["error"]
                    print(f"oraclemesh batch: {error if error.startswith(job.scene + ':') else job.scene + ': ' + error}",
                          file=sys.stderr, flush=True)
            pending -= finished
            if tty and pending:
                running = [j for j in jobs if j.progress is not None]
                sys.stdout.write("\r\033[K" + _status_line(done, failed, total, running)[:200])
                sys.stdout.flush()
            if pending:
                time.sleep(0.2)
    with open(csv_path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        for job in jobs:
            writer.writerow({k: job.row.get(k, "") for k in CSV_COLUMNS})
    print(f"batch: {total - failed} ok, {failed} failed; summary {csv_path}", flush=True)
    return 1 if failed else 0
