# SPDX-License-Identifier: GPL-3.0-or-later
"""VTK reports filter errors through vtkErrorMacro (an ErrorEvent and a line on stderr) and a
failed update; Python users want an exception. ``update`` gives them one."""
import re
import sys

from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING

from . import fieldkeys


class OracleMeshError(RuntimeError):
    """Bad input or a failed pipeline stage; the message names the input and what is wrong."""


class MeshingError(OracleMeshError):
    """The input was accepted but meshing did not finish: a failure inside CGAL, memory, or an abort
    (``aborted`` is then True). The command line exits with 3 (130 when a signal aborted it)."""

    aborted = False
    statistics = {}  # the mesher's figures so far, when it left some (its time limit reached)


def _pipeline(algorithm):
    """The algorithm and every algorithm upstream of it, each once."""
    seen, stack, order = set(), [algorithm], []
    while stack:
        alg = stack.pop()
        if alg is None or id(alg) in seen:
            continue
        seen.add(id(alg))
        order.append(alg)
        for port in range(alg.GetNumberOfInputPorts()):
            for conn in range(alg.GetNumberOfInputConnections(port)):
                stack.append(alg.GetInputAlgorithm(port, conn))
    return order


def _clean(text):
    """'ERROR: In file, line N\\nvtkClass (0x...): message' -> 'message'; drops object addresses."""
    text = str(text).strip()
    head, sep, tail = text.partition("): ")
    text = tail.strip() if sep and "\n" in head else text
    return re.sub(r" ?\(0x[0-9a-fA-F]+\)", "", text)


def scene_spelling(text):
    """A message of the VTK classes with their property names ("InsideTest WindingNumber",
    "CellSize", "MaximumNumberOfVertices") in the scene files' spelling ("inside_test":
    "winding_number", cell_size, maximum_number_of_vertices): what a scene's author types."""
    from .defaults import CRITERIA_KEYS, MESH_PROPERTIES

    for phrase, key in _PHRASES:
        text = text.replace(phrase, key)
    names = {prop: key for key, prop in list(CRITERIA_KEYS.items()) + list(MESH_PROPERTIES.items())}
    names.update(_DOMAIN_PROPERTIES)
    return re.sub(r"\b(" + "|".join(sorted(names, key=len, reverse=True)) + r")\b",
                  lambda m: names[m.group(1)], text)


# VTK spellings with a value, and domain properties, as the scene spells them
_PHRASES = (("InsideTest WindingNumber", '"inside_test": "winding_number"'),
            ("InsideTest Closed", '"inside_test": "closed"'),
            ("InsideTest Automatic", '"inside_test": "automatic"'))
_DOMAIN_PROPERTIES = {"InsideTest": "inside_test", "AllowSelfIntersections": "allow_self_intersections",
                      "MergeTolerance": "merge_tolerance", "CreaseAngle": "features.feature_angle",
                      "ResampleFeatureLines": "features.resample", "BackgroundLabel": "background"}


def _named(obj, message):
    """A reader's message with its file name in front, when the reader did not name it."""
    get = getattr(obj, "GetFileName", None)
    name = get() if callable(get) else None
    if name and name not in message:
        return f"{name}: {message}"
    return message


def _error_for(message):
    """The exception class for a filter's message: MeshingError for the mesher's own failures."""
    if message.startswith("meshing failed") or message.startswith("meshing aborted"):
        error = MeshingError(message)
        error.aborted = message.startswith("meshing aborted")
        return error
    return OracleMeshError(message)


def _statistics(output):
    """The mesher's statistics {name: value} in `output`'s field data (empty without)."""
    from .fielddata import labelled

    return dict(labelled(output.GetFieldData(), fieldkeys.STATISTIC_VALUES)) if output is not None else {}


def update_information(algorithm, port=0, warnings=None):
    """As update(), for the pipeline's information pass only (a reader's header: extent, origin,
    spacing), without reading the data; returns nothing."""
    _run(algorithm, port, warnings, information=True)


def update(algorithm, port=0, warnings=None):
    """Update ``algorithm`` and return its output data object on ``port``.

    Raises OracleMeshError with the first error message of the algorithm or of anything upstream
    (all messages are in the exception's ``messages`` attribute); MeshingError when the input was
    accepted but meshing failed or was aborted. A failed update without a message (a wrong data type
    on a port, a port left unconnected) raises too: never an empty output as success.

    The pipeline's warnings go to the list `warnings` when given, else to stderr as
    "oraclemesh: warning: ...": either way without VTK's source line and object address."""
    return _run(algorithm, port, warnings, information=False)


def _run(algorithm, port, warnings, information):
    messages, executive_messages, warned = [], [], []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, calldata):
        messages.append(_named(obj, _clean(calldata)))

    @calldata_type(VTK_STRING)
    def on_warning(obj, event, calldata):
        warned.append(_clean(calldata))

    @calldata_type(VTK_STRING)
    def on_executive_error(obj, event, calldata):
        executive_messages.append(_clean(calldata))  # "returned failure for request": noise

    observed = []
    for alg in _pipeline(algorithm):
        observed.append((alg, alg.AddObserver("ErrorEvent", on_error)))
        observed.append((alg, alg.AddObserver("WarningEvent", on_warning)))
        executive = alg.GetExecutive()
        observed.append((executive, executive.AddObserver("ErrorEvent", on_executive_error)))
    try:
        executive = algorithm.GetExecutive()  # vtkAlgorithm.Update() returns nothing
        ok = executive.UpdateInformation() if information else executive.Update(port)
    finally:
        for alg, tag in observed:
            alg.RemoveObserver(tag)
        if warnings is not None:
            warnings.extend(warned)
        else:
            for text in warned:
                print(f"oraclemesh: warning: {text}", file=sys.stderr)
    if messages:
        error = _error_for(messages[0])
        error.messages = messages
        if isinstance(error, MeshingError):  # a time limit leaves the figures so far in the empty output
            error.statistics = _statistics(algorithm.GetOutputDataObject(port))
        raise error
    if not ok:
        error = OracleMeshError(
            executive_messages[0] if executive_messages else f"{algorithm.GetClassName()} failed to update")
        error.messages = executive_messages
        raise error
    return None if information else algorithm.GetOutputDataObject(port)
