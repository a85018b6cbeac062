#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Noisy organic surfaces with automatic sharp edges (issue 9 items 7 and 8): a sphere whose points
move radially at random (fixed seeds), its sharp edges found by vtkFeatureEdges as the scene files
find them (mesh.features.from_surface), meshed with the Conforming strategy at sizes of 1/40 of the
bounding-box diagonal. Such edges come as thousands of short noisy segments meeting at small angles.

Per case and resampling on/off it prints the feature segments given and after resampling, wall time,
tetrahedra, validity defects, feature-line pieces missing from the mesh edges and how many of those
the segment level could not split (shorter than its floor), feature coverage, cell points dropped
where T3.2 cycled, and the refinement's wall and CPU seconds (the mesher's own statistics, from the
written mesh's field data).

    /usr/bin/python3 Benchmarks/noisy_features.py [--cases small medium large] [--resample on off]
        [--timeout 600] [--work DIR] [--check]

Needs PYTHONPATH=<build>/lib/python3.11/site-packages and the `oraclemesh` command (ORACLEMESH_COMMAND,
else `python3 -m oraclemesh`). --check (the ctest version) exits 1 unless every mesh is valid and
keeps 100% of its feature lines (--min-coverage: at least that fraction of their length, pieces
missing from the mesh edges then allowed).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

# name: sphere resolution (theta = phi), radial noise (fraction of the radius), seed, feature angle
CASES = {
    "tiny": (30, 0.05, 3, 45.0),
    "small": (80, 0.02, 1, 60.0),
    "medium": (80, 0.05, 2, 45.0),
    "large": (120, 0.05, 3, 45.0),
}


def command():
    cmd = os.environ.get("ORACLEMESH_COMMAND")
    return [cmd] if cmd else [sys.executable, "-m", "oraclemesh"]


def noisy_sphere(path, resolution, noise, seed):
    """Writes a unit sphere of resolution x resolution whose points move radially by up to `noise`."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    source = vtkSphereSource()
    source.SetRadius(1.0)
    source.SetThetaResolution(resolution)
    source.SetPhiResolution(resolution)
    source.Update()
    surface = source.GetOutput()
    points = vtk_to_numpy(surface.GetPoints().GetData()).astype(np.float64)
    points *= (1.0 + noise * np.random.default_rng(seed).uniform(-1.0, 1.0, len(points)))[:, None]
    surface.GetPoints().SetData(numpy_to_vtk(points, deep=True))
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(surface)
    writer.Write()


def make_case(folder, name, resample):
    resolution, noise, seed, angle = CASES[name]
    os.makedirs(folder, exist_ok=True)
    surface = os.path.join(folder, "surface.vtp")
    if not os.path.exists(surface):
        noisy_sphere(surface, resolution, noise, seed)
    h = 2.0 * (1.0 + noise) * 3 ** 0.5 / 40.0  # 1/40 of the bounding box's diagonal
    scene = {
        "domains": [{"name": "organ", "type": "surface", "file": "surface.vtp", "material": 1}],
        "mesh": {
            "strategy": "Conforming",
            "criteria": {"facet_angle": 25, "facet_size": h, "facet_distance": h / 5, "cell_size": h,
                         "cell_radius_edge_ratio": 2.0, "edge_size": h},
            "features": {"from_surface": "organ", "feature_angle": angle, "resample": resample},
            "seed": 1,
        },
    }
    path = os.path.join(folder, f"scene_{'resampled' if resample else 'raw'}.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def run_case(work, name, resample, timeout):
    from oraclemesh.report import statistics, validity
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    folder = os.path.join(work, name)
    scene = make_case(folder, name, resample)
    out = os.path.join(folder, f"mesh_{'resampled' if resample else 'raw'}.vtu")
    if os.path.exists(out):
        os.remove(out)
    started = time.perf_counter()
    try:
        proc = subprocess.run(command() + ["mesh", scene, "-o", out], stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, encoding="utf-8", timeout=timeout)
        rc, tail = proc.returncode, (proc.stderr or "").strip().splitlines()[-1:] or [""]
    except subprocess.TimeoutExpired:
        rc, tail = -9, [f"timeout after {timeout:.0f} s"]
    seconds = time.perf_counter() - started
    row = {"case": name, "resample": resample, "seconds": seconds, "error": ""}
    if rc != 0 or not os.path.exists(out):
        row["error"] = tail[0] or f"exit {rc}"
        return row
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(out)
    reader.Update()
    grid = reader.GetOutput()
    stats = statistics(grid)
    counts = validity(grid)
    meshed = int(stats.get("feature_segments", 0))
    row.update(given=int(stats.get("feature_segments_before_resampling", meshed)), meshed=meshed,
               tets=grid.GetNumberOfCells(), defects=int(counts["validity.defects"]),
               missing=int(counts.get("validity.missing_segment_pieces", 0)),
               too_short=int(stats.get("segment_pieces_missing_too_short", 0)),
               coverage=stats.get("feature_coverage", 0.0), refine_s=stats.get("time.refinement", 0.0),
               cpu_refine_s=stats.get("cpu.refinement", 0.0), min_dihedral=stats.get("min_dihedral_angle", 0.0),
               cycles=int(stats.get("cell_points_dropped_in_facet_cycles", 0)),
               splits=int(stats.get("segment_splits_encroached", 0) + stats.get("segment_splits_missing_from_mesh", 0)
                          + stats.get("segment_splits_for_refused_points_T2.1_T3.1", 0)))
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=["small", "medium", "large"], choices=sorted(CASES))
    parser.add_argument("--resample", nargs="+", default=["on", "off"], choices=["on", "off"])
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--work", default=None)
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--min-coverage", type=float, default=1.0,
                        help="--check: the smallest feature coverage accepted (a fraction of the length)")
    args = parser.parse_args(argv)
    work = args.work or tempfile.mkdtemp(prefix="noisy_features_")
    print(f"{'case':<8} {'resample':<8} {'given':>6} {'meshed':>6} {'tets':>8} {'defects':>7} {'missing':>7} "
          f"{'short':>6} {'cover%':>7} {'min°':>6} {'splits':>7} {'cycles':>6} {'time s':>7} {'refine':>7} {'cpu ref':>7}",
          flush=True)
    rows = []
    for name in args.cases:
        for resample in args.resample:
            r = run_case(work, name, resample == "on", args.timeout)
            rows.append(r)
            if r["error"]:
                print(f"{name:<8} {resample:<8} failed after {r['seconds']:.1f} s: {r['error'][:100]}", flush=True)
                continue
            print(f"{name:<8} {resample:<8} {r['given']:>6} {r['meshed']:>6} {r['tets']:>8} {r['defects']:>7} "
                  f"{r['missing']:>7} {r['too_short']:>6} {100 * r['coverage']:>7.2f} {r['min_dihedral']:>6.2f} "
                  f"{r['splits']:>7} {r['cycles']:>6} {r['seconds']:>7.1f} {r['refine_s']:>7.1f} {r['cpu_refine_s']:>7.1f}",
                  flush=True)
    print(f"work folder: {work}")
    if args.check:
        bad = [r for r in rows if r["error"] or r["defects"] > r["missing"] or r["coverage"] < args.min_coverage - 1e-9
               or (args.min_coverage >= 1.0 and r["missing"])]
        for r in bad:
            why = r["error"] or f"{r['defects']} defects, coverage {100 * r['coverage']:.2f}%"
            print(f"FAILED: {r['case']} resample={r['resample']}: {why}")
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
