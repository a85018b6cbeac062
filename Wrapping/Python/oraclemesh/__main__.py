# SPDX-License-Identifier: GPL-3.0-or-later
"""Command line: ``python3 -m oraclemesh <command> ...`` (see ``--help``)."""
import argparse
import os
import sys
import time

from .errors import OracleMeshError, update
from .scene import load_scene


def _sample(args):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    from . import vtkOracleSampler

    started = time.perf_counter()
    scene = load_scene(args.scene)
    sampler = vtkOracleSampler()
    sampler.SetInputConnection(scene.oracle.GetOutputPort())
    sampler.SetDimensions(*args.dims)
    image = update(sampler)
    if args.output:
        os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
        writer = vtkXMLImageDataWriter()
        writer.SetFileName(args.output)
        writer.SetInputData(image)
        writer.SetCompressorTypeToZLib()
        writer.Write()
    names = scene.material_names()
    fd = image.GetFieldData()
    ids, volumes = fd.GetArray("MaterialIds"), fd.GetArray("MaterialVolume")
    total = sum(volumes.GetValue(i) for i in range(volumes.GetNumberOfTuples()))
    lines = [f"Oracle of {args.scene} sampled on {' x '.join(map(str, args.dims))} points "
             f"({time.perf_counter() - started:.2f} s)",
             f"{'material':>8}  {'name':<18} {'volume [mm^3]':>14} {'share':>7}"]
    for i in range(ids.GetNumberOfTuples()):
        m, v = ids.GetValue(i), volumes.GetValue(i)
        lines.append(f"{m:>8}  {names.get(m, '?'):<18} {v:>14.1f} {100 * v / total:>6.1f}%")
    lines.append(f"{'all':>8}  {'':<18} {total:>14.1f}")
    if args.output:
        lines.append(f"wrote {args.output} (point array 'Material', -1 outside): open it in ParaView")
    report = "\n".join(lines)
    print(report)
    if args.report:
        with open(args.report, "w") as f:
            f.write(report + "\n")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="oraclemesh", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("sample", help="sample a scene's oracle to a label image and report material volumes")
    p.add_argument("scene", help="scene file (JSON)")
    p.add_argument("-o", "--output", help="output image (.vti)")
    p.add_argument("--dims", type=int, nargs=3, default=(128, 128, 128), metavar=("NX", "NY", "NZ"),
                   help="grid points per axis (default 128 128 128)")
    p.add_argument("--report", help="also write the report to this text file")
    p.set_defaults(run=_sample)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except OracleMeshError as e:
        print(f"oraclemesh: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
