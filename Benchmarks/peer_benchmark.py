#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""OracleMesh side by side with stock CGAL 5.5 Mesh_3 (issue 12, item 1).

Prepares three inputs in --work (the demo's tibia label map; an organic closed surface of 100k
triangles; the demo's implant with its sharp edges at 60 degrees as given feature segments), then
for each case and mesh size runs, each in its own process:
  PeerCgal --opt default          stock CGAL: make_mesh_3's defaults (perturb and exude each limited
                                  to the refinement's time)
  PeerOracleMesh --opt default    OracleMesh's defaults (Conforming, its optimisation policy, no time limit)
  PeerOracleMesh --opt limit:T    CGAL's optimisation policy: perturb and exude each limited to T =
                                  CGAL's refinement time of that case, nothing else
and prints a Markdown table (raw figures in <work>/results.jsonl). With --refine-only: refinement alone,
like for like (issue 12, item 2: refinement time per tetrahedron against CGAL's): --opt none, our
circumcentres (--sliver-angle 0), each repetition runs CGAL, the --reference build (if given) and
--oraclemesh in turn, each pinned to one core with taskset; prints each run's per-tet ratio of
refinement CPU seconds, their median and the best of --repeat in microseconds per tetrahedron. With --threads 1 2: OracleMesh
alone per refinement thread count (circumcentres on each: --sliver-angle 0), the best of --repeat runs, and the refinement's speed-up. Same criteria for both tools
(facet angle 25, radius-edge 3, cell size = facet size = h, facet distance h/4, edge size h/2 for
the CAD part), same seed. Min dihedral angle, validity and coverage are computed from each output
by the same code (Filters/Core/Quality/MeshQuality, MeshValidity).

    cmake --build build --target peer_benchmark        # or peer_benchmark_quick
    python3 Benchmarks/peer_benchmark.py --cgal build/bin/PeerCgal --oraclemesh build/bin/PeerOracleMesh \
        --data Data/demo --work build/peer_benchmark [--cases labels surface cad] [--sizes 4 2] [--repeat 3]
        [--threads 1 2 [--opt none]]
    python3 Benchmarks/peer_benchmark.py --cgal build/bin/PeerCgal --oraclemesh build/bin/PeerOracleMesh \
        --data Data/demo --work build/peer_benchmark --refine-only --sizes 4 2 1 --repeat 7 [--reference OTHER/PeerOracleMesh]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

# Mesh sizes h per case (cell size = facet size = h): about 10k to 2M tetrahedra.
SIZES = {
    "labels": [4.0, 2.0, 1.0, 0.65],
    "surface": [3.5, 2.0, 1.0, 0.62],
    "cad": [2.0, 1.0, 0.5, 0.34],
}
QUICK_SIZES = {"labels": [4.0], "surface": [3.5], "cad": [2.0]}
TIME_KEYS = ("setup", "refine", "perturb", "exude", "optimise", "call", "call_cpu", "refine_cpu", "optimise_cpu",
             "refine_critical_cpu", "peak_rss")


def prepare(data, work):
    """Writes labels.oml, surface.off, cad.off and cad_features.txt into work (once)."""
    os.makedirs(work, exist_ok=True)
    paths = {"labels": os.path.join(work, "labels.oml"), "surface": os.path.join(work, "surface.off"),
             "cad": os.path.join(work, "cad.off"), "cad_features": os.path.join(work, "cad_features.txt")}
    if all(os.path.exists(p) for p in paths.values()):
        return paths
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkFiltersCore import vtkFeatureEdges, vtkTriangleFilter
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataReader

    r = vtkXMLImageDataReader()
    r.SetFileName(os.path.join(data, "tibia_labels.vti"))
    r.Update()
    im = r.GetOutput()
    labels = vtk_to_numpy(im.GetPointData().GetArray("labels")).astype(np.uint8)
    with open(paths["labels"], "wb") as f:
        f.write(("OMLABELS %d %d %d %r %r %r %r %r %r\n" % (*im.GetDimensions(), *im.GetSpacing(),
                                                         *im.GetOrigin())).encode())
        f.write(labels.tobytes())

    def write_off(poly, path):
        pts = vtk_to_numpy(poly.GetPoints().GetData())
        tris = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        with open(path, "w") as f:
            f.write("OFF\n%d %d 0\n" % (len(pts), len(tris)))
            f.writelines("%.17g %.17g %.17g\n" % tuple(p) for p in pts)
            f.writelines("3 %d %d %d\n" % tuple(t) for t in tris)

    # An organic closed surface: a sphere of radius 30 mm (100,352 triangles) with smooth bumps.
    s = vtkSphereSource()
    s.SetRadius(1.0)
    s.SetThetaResolution(224)
    s.SetPhiResolution(226)
    s.Update()
    poly = s.GetOutput()
    u = vtk_to_numpy(poly.GetPoints().GetData())
    u = u / np.linalg.norm(u, axis=1)[:, None]
    radius = 30.0 * (1.0 + 0.18 * np.sin(3 * u[:, 0] + 1) * np.cos(2 * u[:, 1]) + 0.12 * np.sin(4 * u[:, 2]))
    poly.GetPoints().SetData(numpy_to_vtk(u * radius[:, None], deep=1))
    write_off(poly, paths["surface"])

    p = vtkXMLPolyDataReader()
    p.SetFileName(os.path.join(data, "implant.vtp"))
    t = vtkTriangleFilter()
    t.SetInputConnection(p.GetOutputPort())
    t.Update()
    write_off(t.GetOutput(), paths["cad"])
    e = vtkFeatureEdges()
    e.SetInputConnection(t.GetOutputPort())
    e.BoundaryEdgesOff()
    e.NonManifoldEdgesOff()
    e.ManifoldEdgesOff()
    e.FeatureEdgesOn()
    e.SetFeatureAngle(60)
    e.Update()
    edges = e.GetOutput()
    pts = vtk_to_numpy(edges.GetPoints().GetData())
    lines = vtk_to_numpy(edges.GetLines().GetConnectivityArray()).reshape(-1, 2)
    with open(paths["cad_features"], "w") as f:
        for a, b in lines:
            f.write("2 %.17g %.17g %.17g %.17g %.17g %.17g\n" % (*pts[a], *pts[b]))
    return paths


def criteria(case, h):
    c = ["--facet-angle", "25", "--radius-edge", "3", "--cell-size", repr(h), "--facet-size", repr(h),
         "--facet-distance", repr(h / 4)]
    if case == "cad":
        c += ["--edge-size", repr(h / 2)]
    return c


def tool_args(exe, case, paths, h, opt, threads=1, extra=()):
    """The command line of one peer program's run."""
    return [exe, case, paths[case]] + ([paths["cad_features"]] if case == "cad" else []) + criteria(case, h) + \
        ["--opt", opt, "--seed", "1"] + (["--threads", str(threads)] if threads != 1 else []) + list(extra)


def run_once(args):
    """Runs a peer program; its figures (the JSON of its last output line). Exits on failure."""
    p = subprocess.run(args, capture_output=True, text=True, timeout=3600)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(args), p.stderr[-2000:]))
    return json.loads(p.stdout.strip().splitlines()[-1])


def run(exe, case, paths, h, opt, repeat, log, threads=1, best=False, extra=()):
    """Runs one configuration `repeat` times; the timings are the medians (the minima with `best`)."""
    args = tool_args(exe, case, paths, h, opt, threads, extra)
    runs = [run_once(args) for _ in range(repeat)]
    r = dict(runs[0])
    for k in TIME_KEYS:  # medians (or minima) of the timings and peak memory
        r[k] = (min if best else statistics.median)(x.get(k, float("nan")) for x in runs)
    r.update(case=case, h=h, repeat=repeat, loadavg=os.getloadavg()[0], threads=threads,
             refine_runs=[x["refine"] for x in runs])
    log.write(json.dumps(r) + "\n")
    log.flush()
    print("  %-10s %-9s h=%-5g %9d tets  refine %7.2f s  optimise %7.2f s  %6.0f MiB  min %.1f deg  defects %d"
          % (r["tool"], opt, h, r["tets"], r["refine"], r["optimise"], r["peak_rss"] / 2**20, r["min_dihedral"],
             r["defects"]), file=sys.stderr, flush=True)
    return r


def table(rows):
    def per_tet(r, key):
        return r[key] / max(r["tets"], 1)

    out = ["| case | h | optimisation | tets OM / CGAL | refine s OM / CGAL (per-tet ratio) | optimise s OM / CGAL "
           "| total per-tet ratio | CPU s OM / CGAL (per-tet ratio) | optimise CPU s OM / CGAL | peak RSS MiB OM / CGAL "
           "| bytes/tet OM / CGAL (ratio) | min dihedral OM / CGAL (before optimisation) | ° gained per optimise CPU s OM / CGAL "
           "| defects OM / CGAL | coverage OM / CGAL |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for case, h, label, om, cg in rows:
        rr = per_tet(om, "refine") / per_tet(cg, "refine")
        tot = lambda r: (r["refine"] + r["optimise"]) / max(r["tets"], 1)  # noqa: E731
        bpt = lambda r: r["peak_rss"] / max(r["tets"], 1)  # noqa: E731
        cpu = lambda r: r.get("call_cpu", float("nan"))  # noqa: E731
        cpus = "%.2f / %.2f (%.2fx)" % (cpu(om), cpu(cg), (cpu(om) / max(om["tets"], 1)) / (cpu(cg) / max(cg["tets"], 1)))
        ocpu = lambda r: r.get("optimise_cpu", float("nan"))  # noqa: E731
        gain = lambda r: (r["min_dihedral"] - r.get("min_refined", float("nan"))) / max(ocpu(r), 1e-9)  # noqa: E731
        opt = "%.2f / %.2f" % (ocpu(om), ocpu(cg))
        angles = "%.1f° / %.1f° (%.1f° / %.1f°)" % (om["min_dihedral"], cg["min_dihedral"], om.get("min_refined", float("nan")),
                                                    cg.get("min_refined", float("nan")))
        gains = "%.1f / %.1f" % (gain(om), gain(cg))
        cov = "–" if om["coverage"] < 0 else "%.0f %% / %.0f %%" % (100 * om["coverage"], 100 * cg["coverage"])
        out.append("| %s | %g | %s | %s / %s | %.2f / %.2f (%.2fx) | %.2f / %.2f | %.2fx | %s | %s | %.0f / %.0f | %.0f / %.0f "
                   "(%.2fx) | %s | %s | %d / %d | %s |" % (
                       case, h, label, f"{om['tets']:,}", f"{cg['tets']:,}", om["refine"], cg["refine"], rr,
                       om["optimise"], cg["optimise"], tot(om) / tot(cg), cpus, opt, om["peak_rss"] / 2**20,
                       cg["peak_rss"] / 2**20, bpt(om), bpt(cg), bpt(om) / bpt(cg), angles, gains,
                       om["defects"], cg["defects"], cov))
    return "\n".join(out)


def threads_table(rows):
    """OracleMesh alone, per thread count: refinement time (initialisation included; best of the
    repeats, every run in brackets) and its speed-up over one thread; CPU seconds of the refinement
    (every thread) and along its critical path (the calling thread's plus the busiest refinement
    thread's: its time on idle cores, which a shared machine's load hides from the wall time) and
    the speed-up that gives; what the mesh is like (tets, min dihedral, validity)."""
    out = ["| case | h | threads | tets | refine s, best (all runs) | wall speed-up | refine CPU s, all threads "
           "| critical-path CPU s | critical-path speed-up | optimise s | min dihedral (before optimisation) "
           "| defects | coverage |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    one = {(r["case"], r["h"]): r for r in rows if r["threads"] == 1}
    for r in rows:
        base = one.get((r["case"], r["h"]))
        speedup = "%.2fx" % (base["refine"] / r["refine"]) if base else "–"
        critical = r.get("refine_critical_cpu", float("nan"))
        cpu_speedup = "%.2fx" % (base["refine_critical_cpu"] / critical) if base and critical > 0 else "–"
        cov = "–" if r["coverage"] < 0 else "%.0f %%" % (100 * r["coverage"])
        out.append("| %s | %g | %d | %s | %.2f (%s) | %s | %.2f | %.2f | %s | %.2f | %.1f° (%.1f°) | %d | %s |" % (
            r["case"], r["h"], r["threads"], f"{r['tets']:,}", r["refine"],
            ", ".join("%.2f" % x for x in r["refine_runs"]), speedup, r.get("refine_cpu", float("nan")), critical,
            cpu_speedup, r["optimise"], r["min_dihedral"], r.get("min_refined", float("nan")), r["defects"], cov))
    return "\n".join(out)


def refine_only(a, paths):
    """Refinement alone, CGAL and OracleMesh (and a reference build) alternately, --repeat times per size."""
    tools = [("CGAL", a.cgal)] + ([("reference", a.reference)] if a.reference else []) + [("OracleMesh", a.oraclemesh)]
    pin = ["taskset", "-c", str(a.cpu)] if shutil.which("taskset") else []
    started, loads = time.time(), [os.getloadavg()[0]]
    out = []
    for case in a.cases:
        for h in a.sizes or (QUICK_SIZES if a.quick else SIZES)[case]:
            runs = {name: [] for name, _ in tools}
            for rep in range(a.repeat):
                for name, exe in tools:
                    # refinement only: no optimisation; ours places circumcentres as CGAL does (no
                    # picked points, whose sliver rule CGAL does not have)
                    r = run_once(pin + tool_args(exe, case, paths, h, "none",
                                                 extra=["--sliver-angle", "0"] if name != "CGAL" else []))
                    runs[name].append(r)
                    loads.append(os.getloadavg()[0])
                    print("  %s h=%g run %d: %d tets, refine CPU %.3f s (%.2f us/tet), load %.1f" % (
                        name, h, rep + 1, r["tets"], r["refine_cpu"], 1e6 * r["refine_cpu"] / r["tets"], loads[-1]),
                        file=sys.stderr, flush=True)
            per_tet = {n: [1e6 * r["refine_cpu"] / r["tets"] for r in rs] for n, rs in runs.items()}
            for name, _ in tools[1:]:
                ratios = [x / c for x, c in zip(per_tet[name], per_tet["CGAL"])]
                out.append("| %s | %g | %s | %s / %s | %.2f / %.2f (%.2fx) | %s | %.2fx |" % (
                    case, h, name, f"{runs[name][0]['tets']:,}", f"{runs['CGAL'][0]['tets']:,}",
                    min(per_tet[name]), min(per_tet["CGAL"]), min(per_tet[name]) / min(per_tet["CGAL"]),
                    " ".join("%.2f" % x for x in ratios), statistics.median(ratios)))
    print("| case | h | build | tets / CGAL | best of %d: us per tet / CGAL (ratio) | per-run ratios | median ratio |"
          % a.repeat)
    print("|---|---|---|---|---|---|---|")
    print("\n".join(out))
    print("\nRefinement CPU seconds per tetrahedron (ours without the initialisation, CGAL's refine_mesh_3 with it), "
          "%s; %.0f s; load average %.1f-%.1f (median %.1f)." % (
              "pinned to CPU %d" % a.cpu if pin else "not pinned (no taskset)", time.time() - started, min(loads),
              max(loads), statistics.median(loads)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cgal", help="PeerCgal (not needed with --threads)")
    ap.add_argument("--oraclemesh", required=True)
    ap.add_argument("--data", required=True, help="Data/demo")
    ap.add_argument("--work", required=True)
    ap.add_argument("--cases", nargs="+", default=["labels", "surface", "cad"], choices=sorted(SIZES))
    ap.add_argument("--sizes", nargs="+", type=float, help="mesh sizes h (default: per case, 4 sizes)")
    ap.add_argument("--repeat", type=int, default=1, help="runs per configuration; medians are printed")
    ap.add_argument("--quick", action="store_true", help="one small size per case")
    ap.add_argument("--no-same-budget", action="store_true", help="skip the same-budget OracleMesh runs")
    ap.add_argument("--threads", nargs="+", type=int, metavar="N",
                    help="instead of the side-by-side table: OracleMesh alone with each of these refinement thread "
                         "counts (MesherOptions::threads; e.g. 1 2), the best of --repeat runs, and the speed-up")
    ap.add_argument("--opt", default="default", help="with --threads: the optimisation (default, none, ...)")
    ap.add_argument("--refine-only", action="store_true",
                    help="refinement alone, like for like: CGAL, --reference and --oraclemesh in turn per repetition, "
                         "each pinned with taskset; per-run ratios, their median and the best of --repeat")
    ap.add_argument("--reference", help="with --refine-only: another PeerOracleMesh (e.g. a build of the previous main)")
    ap.add_argument("--cpu", type=int, default=1, help="with --refine-only: the core taskset pins each run to")
    a = ap.parse_args()
    paths = prepare(a.data, a.work)
    if a.refine_only:
        if not a.cgal:
            ap.error("--refine-only needs --cgal")
        refine_only(a, paths)
        return
    started = time.time()
    load0 = os.getloadavg()[0]
    if not a.threads and not a.cgal:
        ap.error("--cgal is needed (but with --threads)")
    if a.threads:
        rows = []
        with open(os.path.join(a.work, "results.jsonl"), "a") as log:
            for case in a.cases:
                for h in a.sizes or (QUICK_SIZES if a.quick else SIZES)[case]:
                    for n in a.threads:
                        # circumcentres on every thread count: one thread would pick its points
                        # (PickingSliverAngle), parallel refinement does not
                        rows.append(run(a.oraclemesh, case, paths, h, a.opt, a.repeat, log, threads=n, best=True,
                                        extra=["--sliver-angle", "0"]))
        print(threads_table(rows))
        print("\n%.0f s; best of %d run(s) per configuration; load average %.1f at start, %.1f at end (the machine's "
              "2 cores are shared: times vary)." % (time.time() - started, a.repeat, load0, os.getloadavg()[0]))
        return
    rows = []
    with open(os.path.join(a.work, "results.jsonl"), "a") as log:
        # smallest sizes of every case first: an interrupted run still has the small end of the table
        plan = [(i, case, h) for case in a.cases
                for i, h in enumerate(a.sizes or (QUICK_SIZES if a.quick else SIZES)[case])]
        for _, case, h in sorted(plan, key=lambda x: x[0]):
            cg = run(a.cgal, case, paths, h, "default", a.repeat, log)
            om = run(a.oraclemesh, case, paths, h, "default", a.repeat, log)
            rows.append((case, h, "defaults", om, cg))
            if not a.no_same_budget:
                limit = max(cg["refine"], 0.01)
                same = run(a.oraclemesh, case, paths, h, "limit:%.3f" % limit, a.repeat, log)
                rows.append((case, h, "same budget (%.2f s each)" % limit, same, cg))
    order = {c: k for k, c in enumerate(a.cases)}
    rows.sort(key=lambda r: (order[r[0]], -r[1]))  # stable: defaults before same budget
    print(table(rows))
    print("\n%d cases, %.0f s; %d run(s) per configuration (medians); load average %.1f at start, %.1f at end "
          "(the machine's 2 cores are shared: times vary)." % (len(rows), time.time() - started, a.repeat, load0,
                                                              os.getloadavg()[0]))


if __name__ == "__main__":
    main()
