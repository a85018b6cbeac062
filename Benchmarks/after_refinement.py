#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""What the whole call costs after refinement, phase by phase, beside stock CGAL's refinement.

The demo's tibia label map (trilinear, as CGAL's labelled-image domain) meshed through the Python
door (`oraclemesh.mesh`, i.e. vtkFeaturePreservingTetrahedralizer and the MeshResult a user gets)
and by stock CGAL 5.5 (`PeerCgal`, peer_benchmark.py's program) with the same criteria (facet angle
25, radius-edge 3, cell size = facet size = h, facet distance h/4) and seed, each run in its own
process. Prints, per size, the seconds of refinement and of every phase after it:

  output       the complex converted to the output mesh (TetMesh), the triangulation released
  location     the feature segments located as mesh edges
  validity     the independent validity check (duplicates, micro/flat/inverted tetrahedra,
               non-manifold faces, materials against the oracle), whose passes also measure every
               tetrahedron (the statistics, the cell arrays) and list the separating faces
  checks       the pipeline's checks on the mesh (vanished materials, repaired surfaces)
  vtk          the conversion to the filter's VTK outputs (cells, quality arrays, field data)
  python       the Python door's own work after the filter (the MeshResult: report, quality table;
               the package's modules imported before, once per process)
  sets         the boundary and interface sets (MeshResult.surface_sets) every written file gets

and their sum as a share of OracleMesh's refinement (the issue's aim: at most 10 %) and of CGAL's.
The optimisers and the quality step are improvement phases, listed apart.

    cmake --build build --target PeerCgal
    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/after_refinement.py \\
        --cgal build/bin/PeerCgal --data Data/demo --work build/after_refinement [--sizes 1.3 0.85] [--repeat 3]
"""
import argparse
import io
import json
import os
import resource
import statistics
import subprocess
import sys
import time

import peer_benchmark

AFTER = (("output", "time.output"), ("location", "time.feature_location"), ("validity", "time.validity"),
         ("checks", "time.input_checks_on_mesh"), ("vtk", "time.vtk_output"))


def child(data, h):
    """Runs in its own process: one om.mesh call; prints its figures as JSON."""
    import oraclemesh as om
    # the package's modules imported first: once per process (a batch pays them once), not the call's cost
    import oraclemesh.quadratic  # noqa: F401
    import oraclemesh.report  # noqa: F401
    import oraclemesh.surfaces  # noqa: F401
    import oraclemesh.writers  # noqa: F401

    scene = {"domains": [{"name": "tibia", "type": "labelmap", "file": os.path.join(data, "tibia_labels.vti"),
                          "array": "labels", "background": 0, "interpolation": "trilinear"}],
             "mesh": {"strategy": "Conforming",
                      "criteria": {"facet_angle": 25, "cell_radius_edge_ratio": 3, "cell_size": h, "facet_size": h,
                                   "facet_distance": h / 4},
                      "seed": 1, "maximum_number_of_vertices": 50000000, "time_limit": -1}}
    updated = []

    def updater(mesher, warnings=None):
        grid = om.update(mesher, warnings=warnings)
        updated.append(time.perf_counter())
        return grid

    started = time.perf_counter()
    result = om.mesh(scene, updater=updater)
    ended = time.perf_counter()
    result.surface_sets  # the boundary and interface sets every written file gets
    sets = time.perf_counter() - ended
    st = result.statistics
    figures = {"tets": int(st["tetrahedra"]), "call": ended - started,
               "refine": st["time.initialisation"] + st["time.refinement"],
               "optimise": st["time.optimisation"], "improve": st.get("time.improvement", 0.0),
               "python": ended - updated[0], "sets": sets, "peak_rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}
    for name, key in AFTER:
        figures[name] = st.get(key, 0.0)
    print(json.dumps(figures))


def run_child(data, h):
    p = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", repr(h), "--data", data],
                       capture_output=True, text=True, timeout=7200)
    if p.returncode != 0:
        sys.exit("OracleMesh failed at h=%g:\n%s" % (h, p.stderr[-2000:]))
    return json.loads(p.stdout.strip().splitlines()[-1])


def after_of(run):
    """The seconds of every phase after refinement in one run (or in the medians of the runs)."""
    return sum(run[name] for name, _ in AFTER) + run["python"] + run["sets"]


def median_of(runs):
    return {k: statistics.median(r[k] for r in runs) for k in runs[0]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cgal", help="PeerCgal (stock CGAL's refinement beside ours)")
    ap.add_argument("--data", required=True, help="Data/demo")
    ap.add_argument("--work", default="build/after_refinement")
    ap.add_argument("--sizes", nargs="+", type=float, default=[1.3, 0.85], help="h: about 300k and 1M tetrahedra")
    ap.add_argument("--repeat", type=int, default=1, help="runs per size; medians are printed")
    ap.add_argument("--child", type=float, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child is not None:
        return child(a.data, a.child)
    paths = peer_benchmark.prepare(a.data, a.work)
    rows = []
    for h in a.sizes:
        runs = [run_child(a.data, h) for _ in range(a.repeat)]
        om = median_of(runs)
        shares = [100 * after_of(r) / r["refine"] for r in runs]  # each run's own share, for its spread
        cg = None
        if a.cgal:
            cg = peer_benchmark.run(a.cgal, "labels", paths, h, "default", a.repeat, io.StringIO())
        om["after"] = after_of(om)
        om["share_range"] = "%.1f-%.1f" % (min(shares), max(shares))
        rows.append((h, om, cg))
        print("h=%g: %d tets, refine %.2f s, after %.2f s (%.0f %%)" %
              (h, om["tets"], om["refine"], om["after"], 100 * om["after"] / om["refine"]), file=sys.stderr)
    cols = [name for name, _ in AFTER] + ["python", "sets"]
    print("| h | tets OM / CGAL | refine s OM / CGAL | " + " | ".join(cols) +
          " | after refinement s | share of OM's refinement (runs) | share of CGAL's | optimise + quality step s | call s |"
          " peak MiB OM / CGAL | peak bytes per tet OM / CGAL (ratio) |")
    print("|" + "---|" * (len(cols) + 10))
    for h, om, cg in rows:
        cgal_tets = "%s" % format(int(cg["tets"]), ",") if cg else "–"
        cgal_refine = "%.2f" % cg["refine"] if cg else "–"
        share_cgal = "%.1f %%" % (100 * om["after"] / cg["refine"] * cg["tets"] / om["tets"]) if cg else "–"
        om_bytes = om["peak_rss"] / om["tets"]
        peak = "%.0f / %s" % (om["peak_rss"] / 2**20, "%.0f" % (cg["peak_rss"] / 2**20) if cg else "–")
        per_tet = "%.0f / %s" % (om_bytes, "%.0f (%.2fx)" % (cg["peak_rss"] / cg["tets"], om_bytes / (cg["peak_rss"] / cg["tets"]))
                                 if cg else "–")
        print("| %g | %s / %s | %.2f / %s | " % (h, format(om["tets"], ","), cgal_tets, om["refine"], cgal_refine) +
              " | ".join("%.3f" % om[c] for c in cols) +
              " | %.2f | %.1f %% (%s) | %s | %.2f + %.2f | %.2f | %s | %s |" % (
                  om["after"], 100 * om["after"] / om["refine"], om["share_range"], share_cgal, om["optimise"],
                  om["improve"], om["call"], peak, per_tet))
    # the peak's growth per tetrahedron between two sizes: what the mesh costs, without the
    # process's fixed part (the interpreter, numpy, VTK and the package: about 83 MiB before meshing)
    for (h0, om0, cg0), (h1, om1, cg1) in zip(rows, rows[1:]):
        if cg0 and cg1 and om1["tets"] != om0["tets"] and cg1["tets"] != cg0["tets"]:
            slope_om = (om1["peak_rss"] - om0["peak_rss"]) / (om1["tets"] - om0["tets"])
            slope_cg = (cg1["peak_rss"] - cg0["peak_rss"]) / (cg1["tets"] - cg0["tets"])
            print("\npeak growth from h %g to h %g: %.0f bytes per added tetrahedron, CGAL %.0f (%.2fx)" %
                  (h0, h1, slope_om, slope_cg, slope_om / slope_cg))
    print("\nshare of CGAL's: the after-refinement seconds per tetrahedron over CGAL's refinement seconds per "
          "tetrahedron; %d run(s) per configuration (medians); load average %.1f" % (a.repeat, os.getloadavg()[0]))


if __name__ == "__main__":
    main()
