# SPDX-License-Identifier: GPL-3.0-or-later
"""Command line: ``oraclemesh <command> ...`` or ``python3 -m oraclemesh <command> ...`` (see ``--help``).

  sample SCENE   sample a scene's oracle to a label image and report material volumes
  mesh SCENE     tetrahedralize a scene to .vtu / .inp / .msh / .mesh (with boundary and interface sets)
                 and print a quality report
  report MESH    quality report of a mesh written by 'mesh' (any of its formats): table, validity check,
                 dihedral-angle histogram
  batch SCENES   mesh many cases (scenes, a study's sweeps), each in its own process, locally or on
                 Dask distributed, with a folder per case and a summary CSV; resumable

Exit codes: 0 done, 2 bad input (the message names it), 3 meshing failed (its time limit too; or --strict found
defects or warnings about the inputs), 130 interrupted (SIGINT or SIGTERM), 1 an internal error (a bug; ORACLEMESH_TRACEBACK=1
shows where).
"""
import argparse
import json
import os
import resource
import signal
import sys
import time

from .atomic import write_text
from .defaults import mesh_defaults
from .errors import MeshingError, OracleMeshError, scene_spelling, update
from . import fieldkeys
from .meshing import mesh
from .progress import ProgressPrinter
from .scene import FEATURE_SOURCES, STRATEGIES, load_scene
from .writers import MESH_FORMATS, write_vtk_xml


class Interrupted(Exception):
    """SIGINT or SIGTERM arrived outside a filter's update."""


class _Signals:
    """SIGINT and SIGTERM end the command with one line and exit code 130. Inside a filter's update
    (Python's handlers run in the progress callbacks) they abort the filter, which stops at its next
    progress report; elsewhere they raise Interrupted."""

    def __init__(self):
        self.received = None
        self.running = []

    def install(self):
        for number in (signal.SIGINT, signal.SIGTERM):
            try:
                signal.signal(number, self.handle)
            except (ValueError, OSError):  # not the main thread
                pass

    def handle(self, number, frame):
        self.received = signal.Signals(number).name
        if self.running:
            for algorithm in self.running:
                algorithm.SetAbortExecute(1)
            return
        raise Interrupted(self.received)

    def update(self, algorithm, warnings=None):
        """om.update(algorithm, warnings=...), abortable by the signals: the filter reports progress
        to Python."""
        tag = algorithm.AddObserver("ProgressEvent", lambda *unused: None)
        self.running.append(algorithm)
        try:
            output = update(algorithm, warnings=warnings)
        finally:
            self.running.remove(algorithm)
            algorithm.RemoveObserver(tag)
        if self.received:  # arrived after the filter's last progress report
            raise Interrupted(self.received)
        return output


SIGNALS = _Signals()


def check_output_path(path, what="output"):
    """Refuses, before any heavy work, an output whose folder cannot be made (a file in the way) or
    that is itself a folder."""
    full = os.path.abspath(path)
    if os.path.isdir(full):
        raise OracleMeshError(f"{path}: cannot write the {what}: it is a folder")
    folder = os.path.dirname(full)
    while not os.path.exists(folder):
        folder = os.path.dirname(folder)
    if not os.path.isdir(folder):
        raise OracleMeshError(f"{path}: cannot write the {what}: {folder} is a file, not a folder")
    if not os.access(folder, os.W_OK):
        raise OracleMeshError(f"{path}: cannot write the {what}: no permission to write in {folder}")


def _publish(lines, report_path):
    """Prints a report and, when asked, saves it (property names as the scene files spell them)."""
    report = scene_spelling("\n".join(lines))
    print(report)
    if report_path:
        write_text(report_path, report + "\n")


def _sample(args):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    from .report import volume_text

    from . import vtkOracleSampler

    started = time.perf_counter()
    for path, what in ((args.output, "image"), (args.report, "report")):
        if path:
            check_output_path(path, what)
    if any(d < 1 or d > 2**31 - 1 for d in args.dims):
        raise OracleMeshError(f"--dims {' '.join(map(str, args.dims))}: each must be an integer from 1 to {2**31 - 1}")
    scene = load_scene(args.scene)
    sampler = vtkOracleSampler()
    sampler.SetInputConnection(scene.oracle.GetOutputPort())
    sampler.SetDimensions(*args.dims)
    image = SIGNALS.update(sampler)
    if args.output:
        write_vtk_xml(image, args.output, vtkXMLImageDataWriter)
    names = scene.material_names()
    fd = image.GetFieldData()
    ids, volumes = fd.GetArray(fieldkeys.MATERIAL_IDS), fd.GetArray(fieldkeys.MATERIAL_VOLUME)
    total = sum(volumes.GetValue(i) for i in range(volumes.GetNumberOfTuples()))
    lines = [f"Oracle of {args.scene} sampled on {' x '.join(map(str, args.dims))} points "
             f"({time.perf_counter() - started:.2f} s)",
             f"{'material':>8}  {'name':<18} {'volume [mm^3]':>14} {'share':>7}"]
    for i in range(ids.GetNumberOfTuples()):
        m, v = ids.GetValue(i), volumes.GetValue(i)
        lines.append(f"{m:>8}  {names.get(m, '?'):<18} {volume_text(v):>14} {100 * v / total:>6.1f}%")
    lines.append(f"{'all':>8}  {'':<18} {volume_text(total):>14}")
    if args.output:
        lines.append(f"wrote {args.output} (point array '{fieldkeys.MATERIAL}', -1 outside): open it in ParaView")
    _publish(lines, args.report)
    return 0


def _settings(items):
    """--set KEY=VALUE items as {dotted key: value}: the value read as JSON, else taken as a string."""
    settings = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        if not sep or not key:
            raise OracleMeshError(f"--set {item}: use KEY=VALUE with a key of the scene's mesh block, "
                                  "e.g. criteria.cell_size=2 or strategy=None")
        try:
            settings[key] = json.loads(text)
        except ValueError:
            settings[key] = text
    return settings


class _VtkMessages:
    """VTK's warnings and errors during a run, printed once it ends: without those the report
    prints anyway (the mesher's warnings, which VTK would print a second time, in its own format)."""

    def __init__(self):
        self.known = ()

    def __enter__(self):
        from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow

        # VTK logs each message to stderr besides handing it to the output window: only the window
        self.cutoff = vtkLogger.GetCurrentVerbosityCutoff()
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        self.previous = vtkOutputWindow.GetInstance()
        self.previous.Register(None)  # keep VTK's window alive while it is not the instance
        self.window = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.window)
        return self

    def __exit__(self, *exc):
        from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow

        vtkLogger.SetStderrVerbosity(self.cutoff)
        vtkOutputWindow.SetInstance(self.previous)
        self.previous.UnRegister(None)
        known = set(self.known)
        for block in self.window.GetOutput().split("\n\n"):
            lines = [line for line in block.strip().splitlines() if line]
            if lines and lines[0].startswith(("Warning: In ", "ERROR: In ", "Generic Warning: In ")):
                lines = lines[1:]  # the C++ source file and line: of no use here
            text = "\n".join(lines)
            if not text or text.partition("): ")[2] in known:
                continue
            print(text, file=sys.stderr)
        return False


def _mesh(args):
    from .report import VALIDITY_ITEMS, save_histogram, save_section, statistics

    settings = _settings(args.set)
    if args.time_limit is not None:
        settings["time_limit"] = args.time_limit
    scene = load_scene(args.scene, settings)
    outputs = args.output or scene.outputs.get("mesh")
    if not outputs:
        raise OracleMeshError(f"{args.scene}: no output: give -o OUT (or \"outputs\": {{\"mesh\": ...}} in the scene)")
    for out in outputs:
        ext = os.path.splitext(out)[1].lower()
        if ext not in MESH_FORMATS:
            raise OracleMeshError(f"{out}: unknown mesh format '{ext}' (use one of {', '.join(MESH_FORMATS)})")
        check_output_path(out, "mesh")
    for path, what in ((args.report or scene.outputs.get("report"), "report"),
                       (args.histogram or scene.outputs.get("histogram"), "histogram"),
                       (args.section, "section"),
                       (args.summary, "summary")):
        if path:
            check_output_path(path, what)
    progress = ProgressPrinter(sys.stderr, machine=args.progress_lines) if args.progress or args.progress_lines else None
    with _VtkMessages() as messages:
        try:
            result = mesh(scene, args.strategy, progress, updater=SIGNALS.update, element_order=args.order,
                          features=args.features, threads=args.threads)
        except OracleMeshError as e:  # the scene's name in front: a batch log names the case
            if args.scene not in str(e):
                e.args = (f"{args.scene}: {e}",)
            raise
        messages.known = result.warnings
    started = time.perf_counter()
    written = result.save(*outputs)
    lines = result.report.split("\n")
    sets = result.surface_sets
    lines.append("boundary and interface sets (triangles): "
                 + ", ".join(f"{name} ({int(sets.select(i).sum())})" for i, name in enumerate(sets.names)))
    lines.append(f"wrote {', '.join(written)} ({time.perf_counter() - started:.1f} s)"
                 + (" (.vtu: cell data Material, MinDihedralAngle, MaxDihedralAngle, RadiusEdgeRatio; open it in ParaView)"
                    if any(o.lower().endswith(".vtu") for o in outputs) else ""))
    q = result.quality
    histogram = args.histogram or scene.outputs.get("histogram")
    if histogram:
        save_histogram(q, histogram, result.material_names, f"Dihedral angles: {os.path.basename(args.scene)}")
        lines.append(f"wrote {histogram}")
    if args.section:
        save_section(result.grid, args.section, result.material_names)
        lines.append(f"wrote {args.section}")
    _publish(lines, args.report or scene.outputs.get("report"))
    status = _strict_status(args, q, outputs, result.input_warnings)
    if args.summary:
        stats = statistics(result.grid)
        summary = {"tets": q["tets"], "vertices": q["vertices"], "min_dihedral": q["min_dihedral"],
                   "max_dihedral": q["max_dihedral"],
                   fieldkeys.FEATURE_COVERAGE: stats.get(fieldkeys.FEATURE_COVERAGE) if scene.mesh.get("features") else None,
                   "seconds": result.seconds, "outputs": outputs,
                   "validity_defects": q["validity"][fieldkeys.VALIDITY_DEFECTS],
                   "validity": {key: int(q["validity"][key]) for key, _ in VALIDITY_ITEMS if key in q["validity"]},
                   "materials": {str(m): {"tets": row["tets"], "volume": row["volume"],
                                          "min_dihedral": row["min_dihedral"],
                                          "max_dihedral": row["worst_max_dihedral"]}
                                 for m, row in q["materials"].items()},
                   "material_names": {str(m): n for m, n in result.material_names.items()},
                   "reference_volumes": {str(m): v for m, v in scene.reference_volumes.items()},
                   "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}
        write_text(args.summary, json.dumps(summary))
    return status


def dihedral_window(text):
    """--strict's optional MIN,MAX [degrees] as a (min, max) pair; argparse's type."""
    try:
        low, high = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give the dihedral window as MIN,MAX in degrees, e.g. 15,155") \
            from None
    if not 0 <= low < high <= 180:
        raise argparse.ArgumentTypeError(f"{text!r}: need 0 <= MIN < MAX <= 180 degrees")
    return low, high


def _strict_status(args, q, what, input_warnings=()):
    """3 when --strict and the mesh has validity defects or warnings about its inputs (frames or
    units that do not match, materials or labels without a tetrahedron; the report lists them), or,
    with --strict MIN,MAX, a dihedral angle outside that window; else 0."""
    defects = int(q["validity"][fieldkeys.VALIDITY_DEFECTS])
    where = ', '.join(what) if isinstance(what, list) else what
    status = 0
    if isinstance(args.strict, tuple):
        low, high = args.strict
        shape = q["shape"]
        outside = (shape["min_dihedral"] < low) | (shape["max_dihedral"] > high)
        if outside.any():
            print(f"oraclemesh: error: {where}: {int(outside.sum())} of {q['tets']} tetrahedra have a dihedral angle "
                  f"outside [{low:g}, {high:g}]° (smallest {shape['min_dihedral'].min():.2f}°, largest "
                  f"{shape['max_dihedral'].max():.2f}°; the report's worst tetrahedra say where) (--strict)",
                  file=sys.stderr)
            status = 3
    if args.strict and defects:
        print(f"oraclemesh: error: {where}: {defects} validity defects (--strict)", file=sys.stderr)
        status = 3
    if args.strict and input_warnings:
        print(f"oraclemesh: error: {where}: {len(input_warnings)} warning(s) about the inputs (--strict): "
              + scene_spelling("; ".join(input_warnings)), file=sys.stderr)
        status = 3
    return status


def _report(args):
    from .report import read_mesh, report_lines, save_histogram

    for path, what in ((args.png, "histogram"), (args.report, "report")):
        if path:
            check_output_path(path, what)
    grid = read_mesh(args.mesh)
    lines, q = report_lines(grid, f"Mesh {args.mesh}", source=args.mesh)
    stem, ext = os.path.splitext(args.mesh)  # out.vtu -> out_vtu_dihedral.png: one picture per format
    png = None if args.no_png else (args.png or f"{stem}_{ext[1:].lower()}_dihedral.png")
    if png:
        from .report import material_names

        save_histogram(q, png, material_names(grid), f"Dihedral angles: {os.path.basename(args.mesh)}")
        lines.append(f"wrote {png}")
    _publish(lines, args.report)
    from .fielddata import strings

    return _strict_status(args, q, args.mesh, strings(grid.GetFieldData(), fieldkeys.INPUT_WARNINGS))


def _batch(args):
    from .batch import run_batch

    return run_batch(args)


def _die_with_parent():
    """For batch's children (ORACLEMESH_PARENT_PID set): the kernel kills this process when the one
    that started it dies (Linux PR_SET_PDEATHSIG), so a Dask worker killed mid-case leaves no mesh
    running beside the case's rerun."""
    parent = os.environ.pop("ORACLEMESH_PARENT_PID", None)
    if not parent:
        return
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1: PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if str(os.getppid()) != parent:  # the parent died before the call
        os._exit(137)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="oraclemesh", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("sample", help="sample a scene's oracle to a label image and report material volumes")
    p.add_argument("scene", help="scene file (JSON)")
    p.add_argument("-o", "--output", help="output image (.vti)")
    p.add_argument("--dims", type=int, nargs=3, default=(128, 128, 128), metavar=("NX", "NY", "NZ"),
                   help="grid points per axis (default 128 128 128)")
    p.add_argument("--report", help="also write the report to this text file")
    p.set_defaults(run=_sample)
    p = sub.add_parser("mesh", help="tetrahedralize a scene (its \"mesh\" block sets the criteria)")
    p.add_argument("scene", help="scene file (JSON)")
    p.add_argument("-o", "--output", action="append",
                   help=f"output mesh, format by extension ({' '.join(MESH_FORMATS)}); repeat for several "
                        "(default: the scene's outputs.mesh)")
    p.add_argument("--strategy", choices=STRATEGIES,
                   help=f"feature strategy (default: the scene's, else {mesh_defaults()['strategy']})")
    p.add_argument("--threads", type=int, metavar="N",
                   help="threads of the refinement (default: the scene's \"threads\", else "
                        f"{mesh_defaults()['threads']}): 1 = sequential, the same seed gives the same mesh; "
                        "N > 1 = parallel (0 = every core): same criteria and checks, but the mesh differs "
                        "from run to run (the threads refine at circumcentres, then one thread refines the slivers "
                        "they left at picked points)")
    p.add_argument("--order", type=int, choices=(1, 2),
                   help="element order: 1 = 4-node, 2 = 10-node tetrahedra with the mid-edge nodes of interface "
                        f"edges on the true surfaces (default: the scene's \"element_order\", else "
                        f"{mesh_defaults()['element_order']})")
    p.add_argument("--features", choices=FEATURE_SOURCES,
                   help="which feature lines are kept: given (the scene's), found where the inputs meet (cut "
                        "rims, entry curves, triple lines), or both (default: the scene's mesh.features.use, "
                        f"else {mesh_defaults()['features']['use']})")
    p.add_argument("--report", help="also write the quality report to this text file")
    p.add_argument("--histogram", help="save the dihedral-angle histogram to this PNG")
    p.add_argument("--section", help="save a cross-section of the mesh to this PNG (the plane through its "
                                     "centre normal to its thinnest axis, tetrahedra coloured by material)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="set a key of the scene's mesh block (dotted, the value as JSON or a string), e.g. "
                        "criteria.cell_size=2, strategy=None, materials.3.cell_size=1; repeat for several")
    p.add_argument("--time-limit", type=float, metavar="SECONDS",
                   help="wall-clock seconds for the meshing, every phase (the scene's mesh.time_limit); reaching "
                        "it is a failure (exit 3) naming the phase, with the figures so far and no mesh written. "
                        "0 = automatic (the default: 10 minutes), -1 = none; criteria that cannot be met within it are "
                        "refused before meshing")
    p.add_argument("--progress", action="store_true", help="show the mesher's progress on stderr")
    p.add_argument("--progress-lines", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--summary", help=argparse.SUPPRESS)  # JSON of the figures batch puts in its CSV
    p.add_argument("--strict", nargs="?", const=True, default=False, type=dihedral_window, metavar="MIN,MAX",
                   help="exit with status 3 when the mesh has validity defects or warnings about the inputs "
                        "(frames or units that do not match, materials or labels without a tetrahedron), and "
                        "with MIN,MAX (e.g. --strict 15,155) when a dihedral angle lies outside that window "
                        "[degrees]; the files are still written")
    p.set_defaults(run=_mesh)
    p = sub.add_parser("report", help="quality report of a mesh written by 'mesh' (.vtu .inp .msh .mesh): table and histogram")
    p.add_argument("mesh", help="tetrahedral mesh written by 'mesh' (.vtu, .inp, .msh or .mesh)")
    p.add_argument("--png", help="histogram picture (default: MESH's name with its format, out.inp -> "
                                 "out_inp_dihedral.png)")
    p.add_argument("--no-png", action="store_true", help="do not save the histogram picture")
    p.add_argument("--report", help="also write the report to this text file")
    p.add_argument("--strict", nargs="?", const=True, default=False, type=dihedral_window, metavar="MIN,MAX",
                   help="exit with status 3 when the mesh has validity defects or warnings about its inputs, and "
                        "with MIN,MAX (e.g. --strict 15,155) when a dihedral angle lies outside that window")
    p.set_defaults(run=_report)
    p = sub.add_parser("batch", help="mesh many cases (scenes, or a study's scenes x parameter sweeps), each in "
                                     "its own process, locally or on Dask, with a summary CSV; resumable")
    p.add_argument("scenes", nargs="*", help="scene files (JSON)")
    p.add_argument("--study", help="study file (JSON): scenes or glob patterns, and a sweep of mesh keys, e.g. "
                                   '{"scenes": ["*.json"], "sweep": {"criteria.cell_size": [2, 1]}}')
    p.add_argument("-j", "--jobs", type=int, help="cases meshed at once on this machine (default 1; not with Dask)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="run the cases on a local Dask cluster of N worker processes (one case each at a time)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="run the cases on an existing Dask cluster (its workers need this package and the "
                        "same paths to the scenes and OUTPUT_DIR)")
    p.add_argument("--retries", type=int, default=1,
                   help="with Dask: times a case's task is run again after an error of its own (default 1); "
                        "a case whose worker dies is run again anyway")
    p.add_argument("-o", "--output-dir", default="batch-output",
                   help="folder for a folder per case (meshes, report, pictures, log) and summary.csv "
                        "(default ./batch-output)")
    p.add_argument("-f", "--format", action="append", choices=[f[1:] for f in MESH_FORMATS],
                   help="mesh format(s) to write (default the study's, else vtu; repeat for several)")
    p.add_argument("--csv", help="summary CSV (default OUTPUT_DIR/summary.csv)")
    p.add_argument("--strategy", choices=STRATEGIES, help="feature strategy for every case")
    p.add_argument("--timeout", type=float, help="seconds after which a case's process is stopped")
    p.add_argument("--no-pictures", action="store_true",
                   help="no dihedral-angle histogram and cross-section PNG per case")
    p.add_argument("--force", action="store_true",
                   help="mesh every case again (default: cases done earlier with the same inputs are skipped)")
    p.set_defaults(run=_batch)
    args = parser.parse_args(argv)
    _die_with_parent()
    SIGNALS.install()
    try:
        return args.run(args)
    except (Interrupted, KeyboardInterrupt):
        return _interrupted()
    except MeshingError as e:
        if e.aborted and SIGNALS.received:
            return _interrupted()
        if e.statistics:
            print("partial statistics: " + ", ".join(f"{k} {v:g}" for k, v in sorted(e.statistics.items())),
                  file=sys.stderr)
        print(f"oraclemesh: error: {scene_spelling(str(e))}", file=sys.stderr)
        return 3
    except OracleMeshError as e:
        if SIGNALS.received:
            return _interrupted()
        print(f"oraclemesh: error: {scene_spelling(str(e))}", file=sys.stderr)
        return 2
    except MemoryError:
        print("oraclemesh: error: out of memory", file=sys.stderr)
        return 3
    except OSError as e:  # a file that cannot be read or written, named by the system
        where = e.filename or "oraclemesh"
        print(f"oraclemesh: error: {where}: {e.strerror or e}", file=sys.stderr)
        return 2
    except Exception as e:  # a bug: one line unless asked for the traceback
        if os.environ.get("ORACLEMESH_TRACEBACK"):
            raise
        print(f"oraclemesh: internal error: {type(e).__name__}: {e} (ORACLEMESH_TRACEBACK=1 shows where; "
              "please report it)", file=sys.stderr)
        return 1


def _interrupted():
    print(f"oraclemesh: interrupted ({SIGNALS.received or 'SIGINT'})", file=sys.stderr)
    return 130


if __name__ == "__main__":
    sys.exit(main())
