# SPDX-License-Identifier: GPL-3.0-or-later
"""VTK reports filter errors through vtkErrorMacro (an ErrorEvent and a line on stderr) and a
failed update; Python users want an exception. ``update`` gives them one."""
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING


class OracleMeshError(RuntimeError):
    """Bad input or a failed pipeline stage; the message names the input and what is wrong."""


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
    """'ERROR: In file, line N\\nvtkClass (0x...): message' -> 'message'."""
    text = str(text).strip()
    head, sep, tail = text.partition("): ")
    return tail.strip() if sep and "\n" in head else text


def update(algorithm, port=0):
    """Update ``algorithm`` and return its output data object on ``port``.

    Raises OracleMeshError with the first error message of the algorithm or of anything upstream
    (all messages are in the exception's ``messages`` attribute)."""
    messages, executive_messages = [], []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, calldata):
        messages.append(_clean(calldata))

    @calldata_type(VTK_STRING)
    def on_executive_error(obj, event, calldata):
        executive_messages.append(_clean(calldata))  # "returned failure for request": noise

    observed = []
    for alg in _pipeline(algorithm):
        observed.append((alg, alg.AddObserver("ErrorEvent", on_error)))
        executive = alg.GetExecutive()
        observed.append((executive, executive.AddObserver("ErrorEvent", on_executive_error)))
    try:
        ok = algorithm.Update(port) if port else algorithm.Update()
    finally:
        for alg, tag in observed:
            alg.RemoveObserver(tag)
    if messages:
        error = OracleMeshError(messages[0])
        error.messages = messages
        raise error
    if ok == 0:
        raise OracleMeshError(
            executive_messages[0] if executive_messages else f"{algorithm.GetClassName()} failed to update")
    return algorithm.GetOutputDataObject(port)
