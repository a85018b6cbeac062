# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of ``oraclemesh batch`` studies and runners (issue 11 item 9, issue 12 item 6): a study's
scenes x parameter sweeps with a folder per case (mesh, report, pictures) and per-material columns;
resumption after an interrupted run; Dask distributed (a scheduler and two workers on 127.0.0.1,
one killed mid-study) giving the same summary as the local pool. Run by ctest with
/usr/bin/python3 and PYTHONPATH set to the build tree."""
import csv
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

from vtkmodules.util.numpy_support import vtk_to_numpy

# A ball (material 2) in a block (1), meshed in about a second; both volumes are exact.
BALL = {
    "domains": [
        {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 3, "material": 2},
        {"name": "block", "type": "box", "bounds": [-5, 5, -5, 5, -5, 5], "material": 1},
    ],
    "mesh": {"strategy": "None", "criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.5}, "seed": 1},
    "reference_volumes": {"2": 4 / 3 * math.pi * 27, "1": 1000 - 4 / 3 * math.pi * 27},
}
# The same without reference volumes and with a smaller ball: its rows have no volume errors.
SMALL_BALL = {"domains": [dict(BALL["domains"][0], radius=2), BALL["domains"][1]], "mesh": BALL["mesh"]}
try:
    import distributed  # noqa: F401

    HAVE_DASK = True
except ImportError:
    HAVE_DASK = False
VARIABLE = ("seconds",)  # the only column that differs between two runs of one study


def run(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "oraclemesh"] + [str(a) for a in args], capture_output=True,
                          encoding="utf-8", check=False, **kwargs)


def write_json(path, description):
    with open(path, "w") as f:
        json.dump(description, f)
    return path


def read_rows(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        return reader.fieldnames, list(reader)


def stable(rows):
    """Rows without the columns that legitimately differ between runs (wall time)."""
    return [{k: v for k, v in row.items() if k not in VARIABLE} for row in rows]


def read_vtu(path):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


class Study(unittest.TestCase):
    def test_a_study_meshes_every_scene_with_every_swept_value_into_a_folder_each(self):
        from oraclemesh.report import quality

        with tempfile.TemporaryDirectory() as tmp:
            write_json(os.path.join(tmp, "ball.json"), BALL)
            write_json(os.path.join(tmp, "small_ball.json"), SMALL_BALL)
            study = write_json(os.path.join(tmp, "study.json"), {
                "scenes": ["*ball.json"], "sweep": {"criteria.cell_size": [2, 4]}, "formats": ["vtu", "inp"]})
            out = os.path.join(tmp, "out")
            result = run("batch", "--study", study, "-o", out, "--jobs", "2")
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            columns, rows = read_rows(os.path.join(out, "summary.csv"))
            self.assertEqual([r["case"] for r in rows], ["ball__cell_size-2", "ball__cell_size-4",
                                                         "small_ball__cell_size-2", "small_ball__cell_size-4"])
            self.assertEqual([r["criteria.cell_size"] for r in rows], ["2", "4", "2", "4"])
            for name in ("tets_1", "volume_1", "volume_error_1", "min_dihedral_1", "tets_2", "volume_2",
                         "volume_error_2", "min_dihedral_2", "validity_defects", "flat_tetrahedra",
                         "inverted_tetrahedra"):
                self.assertIn(name, columns)
            for row in rows:
                folder = os.path.join(out, row["case"])
                self.assertEqual(row["status"], "ok", row)
                self.assertEqual(sorted(f for f in os.listdir(folder) if not f.startswith(".")),
                                 ["dihedral.png", "mesh.inp", "mesh.log", "mesh.vtu", "mesh_surfaces.vtu",
                                  "report.txt", "result.json", "section.png"])
                self.assertTrue(is_png(os.path.join(folder, "dihedral.png")))
                self.assertTrue(is_png(os.path.join(folder, "section.png")))
                with open(os.path.join(folder, "report.txt")) as f:
                    self.assertIn("validity: no defects", f.read())
                # the columns are the mesh's: per material tets, volume, min and max dihedral
                grid = read_vtu(os.path.join(folder, "mesh.vtu"))
                material = vtk_to_numpy(grid.GetCellData().GetArray("Material"))
                angles = vtk_to_numpy(grid.GetCellData().GetArray("MinDihedralAngle"))
                largest = vtk_to_numpy(grid.GetCellData().GetArray("MaxDihedralAngle"))
                self.assertEqual(int(row["tets"]), grid.GetNumberOfCells())
                self.assertEqual(int(row["validity_defects"]), 0)
                self.assertAlmostEqual(float(row["max_dihedral"]), largest.max(), places=2)
                for m in (1, 2):
                    self.assertEqual(int(row[f"tets_{m}"]), int((material == m).sum()))
                    self.assertAlmostEqual(float(row[f"min_dihedral_{m}"]), angles[material == m].min(), places=2)
                    self.assertAlmostEqual(float(row[f"max_dihedral_{m}"]), largest[material == m].max(), places=2)
                q = quality(grid)
                for m in (1, 2):
                    self.assertAlmostEqual(float(row[f"volume_{m}"]), q["materials"][m]["volume"], places=4)
            by_case = {r["case"]: r for r in rows}
            # volume errors where the scene gives reference volumes, (mesh - reference) / reference
            ball = by_case["ball__cell_size-2"]
            reference = BALL["reference_volumes"]["2"]
            self.assertAlmostEqual(float(ball["volume_error_2"]),
                                   (float(ball["volume_2"]) - reference) / reference, places=5)
            self.assertLess(abs(float(ball["volume_error_2"])), 0.3)
            self.assertEqual(by_case["small_ball__cell_size-2"]["volume_error_2"], "")
            # the swept value reached the mesher: coarser cells, fewer tetrahedra; the smaller ball has fewer
            self.assertLess(int(by_case["ball__cell_size-4"]["tets"]), int(ball["tets"]))
            self.assertLess(int(by_case["small_ball__cell_size-2"]["tets_2"]), int(ball["tets_2"]))

    def test_bad_studies_and_options_are_usage_errors(self):
        with tempfile.TemporaryDirectory() as tmp:
            write_json(os.path.join(tmp, "ball.json"), BALL)
            study = write_json(os.path.join(tmp, "study.json"), {
                "scenes": ["ball.json", "cases/*.json"], "sweep": {"criteria.cell_size": [], "mesh_size": [1]},
                "format": "vtu"})
            result = run("batch", "--study", study, "-o", tmp)
            self.assertEqual(result.returncode, 2, result.stderr)
            for text in ("$.format: unknown key", "$.scenes[1]: 'cases/*.json' matches no file",
                         "$.sweep.criteria.cell_size: must be a non-empty list",
                         "mesh key 'mesh_size': 'mesh_size' is not a key of the mesh block"):
                self.assertIn(text, result.stderr)
            result = run("batch", os.path.join(tmp, "ball.json"), "--workers", "2", "--scheduler", "tcp://127.0.0.1:1")
            self.assertEqual(result.returncode, 2)
            self.assertIn("--scheduler and --workers: give one", result.stderr)
            result = run("batch", os.path.join(tmp, "ball.json"), "--workers", "2", "--jobs", "2")
            self.assertEqual(result.returncode, 2)
            self.assertIn("--jobs: the local pool's size", result.stderr)
            result = run("batch", "-o", tmp)
            self.assertEqual(result.returncode, 2)
            self.assertIn("no scenes", result.stderr)
            result = run("mesh", os.path.join(tmp, "ball.json"), "-o", os.path.join(tmp, "x.vtu"),
                         "--set", "criteria.cell_sise=2")
            self.assertEqual(result.returncode, 2)
            self.assertIn("$.mesh.criteria.cell_sise: unknown criterion", result.stderr)


class Resume(unittest.TestCase):
    def test_an_interrupted_study_redoes_only_the_missing_cases(self):
        with tempfile.TemporaryDirectory() as tmp:
            write_json(os.path.join(tmp, "ball.json"), BALL)
            study = write_json(os.path.join(tmp, "study.json"),
                               {"scenes": "ball.json", "sweep": {"criteria.cell_size": [2, 3, 4]}})
            out = os.path.join(tmp, "out")
            first = os.path.join(out, "ball__cell_size-2", "result.json")
            batch = subprocess.Popen([sys.executable, "-m", "oraclemesh", "batch", "--study", study, "-o", out,
                                      "--jobs", "1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     encoding="utf-8")
            deadline = time.monotonic() + 40
            while not os.path.exists(first) and time.monotonic() < deadline and batch.poll() is None:
                time.sleep(0.02)
            batch.send_signal(signal.SIGINT)  # Ctrl-C: the case running is stopped
            stdout, stderr = batch.communicate(timeout=60)
            self.assertEqual(batch.returncode, 130, stdout + stderr)
            self.assertIn("interrupted", stderr)
            _, rows = read_rows(os.path.join(out, "summary.csv"))  # written for the cases done so far
            self.assertEqual(rows[0]["status"], "ok")
            self.assertTrue(all(r["status"] != "ok" for r in rows[1:]), rows)
            done = os.path.join(out, "ball__cell_size-2")
            stamps = {f: os.stat(os.path.join(done, f)).st_mtime_ns for f in os.listdir(done)}
            # restarted (on a local Dask cluster this time): only the missing cases are meshed
            result = run("batch", "--study", study, "-o", out, *(["--workers", "2"] if HAVE_DASK else ["--jobs", "2"]))
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertIn("3 case(s), 1 done earlier (skipped)", result.stdout)
            self.assertEqual(result.stdout.count(": ok, "), 2, result.stdout)
            self.assertEqual({f: os.stat(os.path.join(done, f)).st_mtime_ns for f in os.listdir(done)}, stamps)
            _, again = read_rows(os.path.join(out, "summary.csv"))
            self.assertEqual([r["status"] for r in again], ["ok"] * 3)
            self.assertEqual(again[0], rows[0])
            self.assertLess(int(again[2]["tets"]), int(again[0]["tets"]))
            # a third run finds everything done
            result = run("batch", "--study", study, "-o", out)
            self.assertIn("3 case(s), 3 done earlier (skipped)", result.stdout)
            self.assertEqual(read_rows(os.path.join(out, "summary.csv"))[1], again)

    def test_a_case_is_redone_when_its_inputs_change(self):
        from oraclemesh.batch import finished_row, make_cases

        with tempfile.TemporaryDirectory() as tmp:
            scene = write_json(os.path.join(tmp, "ball.json"), BALL)
            out = os.path.join(tmp, "out")
            case = make_cases([scene], [], out, ["vtu"])[0]
            os.makedirs(case["folder"])
            for name in ("mesh.vtu", "dihedral.png", "section.png"):
                open(os.path.join(case["folder"], name), "w").close()
            row = {"case": "ball", "status": "ok", "outputs": "ball/mesh.vtu;ball/dihedral.png;ball/section.png"}
            write_json(os.path.join(case["folder"], "result.json"), {"fingerprint": case["fingerprint"], "row": row})
            self.assertEqual(finished_row(case), row)
            self.assertIsNone(finished_row(make_cases([scene], [("seed", [2])], out, ["vtu"])[0]))
            self.assertIsNone(finished_row(make_cases([scene], [], out, ["vtu", "inp"])[0]))
            write_json(scene, dict(BALL, mesh=dict(BALL["mesh"], seed=2)))
            self.assertIsNone(finished_row(make_cases([scene], [], out, ["vtu"])[0]))
            write_json(scene, BALL)
            self.assertEqual(finished_row(make_cases([scene], [], out, ["vtu"])[0]), row)
            os.remove(os.path.join(case["folder"], "section.png"))
            self.assertIsNone(finished_row(case))


@unittest.skipUnless(HAVE_DASK, "python3-distributed is not installed")
class Dask(unittest.TestCase):
    """A scheduler and two workers (no nanny: a killed worker stays dead) on 127.0.0.1."""

    def setUp(self):
        import ctypes

        # Orphans become this process's children (PR_SET_CHILD_SUBREAPER), so the exit status of a
        # killed worker's mesh process can be read.
        self.subreaper = ctypes.CDLL(None, use_errno=True).prctl(36, 1) == 0
        self.processes = []
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.addCleanup(self.stop_all)

    def stop_all(self):
        for process in self.processes:
            if process.poll() is None:
                process.terminate()
        for process in self.processes:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()

    def start(self, *args):
        log = open(os.path.join(self.tmp.name, f"dask-{len(self.processes)}.log"), "w")
        self.addCleanup(log.close)
        process = subprocess.Popen([sys.executable, "-m"] + list(args), stdout=log, stderr=subprocess.STDOUT,
                                   cwd=self.tmp.name)
        self.processes.append(process)
        return process

    def test_a_killed_worker_case_is_rerun_and_the_summary_is_that_of_a_local_run(self):
        import psutil
        from distributed import Client

        tmp = self.tmp.name
        write_json(os.path.join(tmp, "ball.json"), BALL)
        write_json(os.path.join(tmp, "small_ball.json"), SMALL_BALL)
        study = write_json(os.path.join(tmp, "study.json"),
                           {"scenes": ["ball.json", "small_ball.json"], "sweep": {"criteria.cell_size": [2, 3]}})
        scheduler_file = os.path.join(tmp, "scheduler.json")
        self.start("distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                   "--scheduler-file", scheduler_file)
        workers = [self.start("distributed.cli.dask_worker", "--scheduler-file", scheduler_file, "--host",
                              "127.0.0.1", "--nthreads", "1", "--no-nanny", "--no-dashboard",
                              "--local-directory", tmp)
                   for _ in range(2)]
        local = run("batch", "--study", study, "-o", os.path.join(tmp, "local"), "--jobs", "2", "--no-pictures")
        self.assertEqual(local.returncode, 0, local.stdout + local.stderr)
        deadline = time.monotonic() + 30
        while not os.path.exists(scheduler_file) and time.monotonic() < deadline:
            time.sleep(0.1)
        with open(scheduler_file) as f:
            address = json.load(f)["address"]
        with Client(address, timeout="20s") as client:
            client.wait_for_workers(2, timeout=30)
        batch = subprocess.Popen([sys.executable, "-m", "oraclemesh", "batch", "--study", study, "-o",
                                  os.path.join(tmp, "dask"), "--scheduler", address, "--no-pictures"],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding="utf-8")
        killed, orphan = None, None
        deadline = time.monotonic() + 60
        while killed is None and batch.poll() is None and time.monotonic() < deadline:
            for worker in workers:
                meshes = []
                for child in psutil.Process(worker.pid).children():
                    try:
                        if "mesh" in child.cmdline():
                            meshes.append(child)
                    except psutil.NoSuchProcess:
                        pass
                if meshes:  # this worker is running a case: kill it (SIGKILL, no goodbye to the scheduler)
                    orphan = meshes[0]
                    worker.kill()
                    worker.wait()
                    killed = worker
                    break
            time.sleep(0.01)
        self.assertIsNotNone(killed, "no worker was seen running a case")
        stdout, stderr = batch.communicate(timeout=120)
        self.assertEqual(batch.returncode, 0, stdout + stderr)
        self.assertIn("on the Dask cluster at tcp://127.0.0.1:", stdout)
        # the killed worker's mesh process ended with it, not running on beside the rerun: killed by
        # the kernel (PR_SET_PDEATHSIG), or exit 137 when it was still starting (its parent already gone)
        if self.subreaper:
            pid, status = os.waitpid(orphan.pid, 0)
            self.assertTrue((os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL)
                            or (os.WIFEXITED(status) and os.WEXITSTATUS(status) == 137), status)
        # complete, and the same as the local run: every column but the wall time
        local_columns, local_rows = read_rows(os.path.join(tmp, "local", "summary.csv"))
        dask_columns, dask_rows = read_rows(os.path.join(tmp, "dask", "summary.csv"))
        self.assertEqual(dask_columns, local_columns)
        self.assertEqual([r["status"] for r in dask_rows], ["ok"] * 4)
        self.assertEqual([r["tets"] for r in dask_rows], [r["tets"] for r in local_rows])
        self.assertEqual(stable(dask_rows), stable(local_rows))
        for row in dask_rows:  # and the same meshes
            a = read_vtu(os.path.join(tmp, "local", row["case"], "mesh.vtu"))
            b = read_vtu(os.path.join(tmp, "dask", row["case"], "mesh.vtu"))
            np.testing.assert_array_equal(vtk_to_numpy(a.GetPoints().GetData()), vtk_to_numpy(b.GetPoints().GetData()))


if __name__ == "__main__":
    unittest.main()
