# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the Python and pvpython tests: per-material sample counts, and comparing them with
the C++ pipeline's counts."""
import json
import os

SAMPLES = 64  # per axis, as in the C++ reference (DemoScene.Cxx)


def counts_of(material_array):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    import numpy as np

    values, counts = np.unique(vtk_to_numpy(material_array), return_counts=True)
    return {int(v): int(c) for v, c in zip(values, counts)}


def reference_counts():
    path = os.environ.get("ORACLEMESH_CXX_COUNTS")
    if not path or not os.path.isfile(path):
        raise RuntimeError("ORACLEMESH_CXX_COUNTS must name the C++ counts file (run the DemoScene.Cxx test first)")
    with open(path) as f:
        return {int(k): v for k, v in json.load(f).items()}
