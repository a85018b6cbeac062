# SPDX-License-Identifier: GPL-3.0-or-later
"""Text in a mesh's field data, in a form every .vtu reader accepts.

The mesher labels numbers with string arrays (StatisticNames for StatisticValues, MaterialNames for
MaterialIds) and lists Warnings as strings. meshio cannot read a .vtu holding any string array, so
the files carry the text as **component names** of numeric arrays instead: StatisticValues and
MaterialIds become one tuple whose components are named after the statistics / materials, Warnings
an integer array (1..k) whose components are the warnings. ParaView shows component names as the
columns of the spreadsheet view (Attribute: Field Data) and in the Information panel.

``labelled`` and ``strings`` read both forms (the mesher's grid and a file written before or since).
"""
from . import fieldkeys

# string array -> the numeric array it labels
LABELLED = {fieldkeys.STATISTIC_NAMES: fieldkeys.STATISTIC_VALUES, fieldkeys.MATERIAL_NAMES: fieldkeys.MATERIAL_IDS,
            fieldkeys.VALIDITY_NAMES: fieldkeys.VALIDITY_VALUES}
# field data the oracle's first domain passes down the pipeline: it describes that domain, not the mesh
DOMAIN_PREFIX = "OracleMesh_"


def _escape(text):
    """VTK's XML writer puts component names into attributes unescaped (VTK 9.2); expat decodes these."""
    text = str(text)
    for raw, entity in (("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"), ("\n", "&#10;"),
                        ("\r", "&#13;"), ("\t", "&#9;")):
        text = text.replace(raw, entity)
    return text


def _string_values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def _is_string(array):
    return array is not None and array.IsA("vtkStringArray")


def without_strings(data):
    """A shallow copy of `data` whose field data holds no string arrays: each labelling string array
    becomes its numeric array's component names (one tuple), other string arrays an integer array
    whose components are named after the strings; the leaked domain description is left out."""
    from vtkmodules.vtkCommonCore import vtkIntArray
    from vtkmodules.vtkCommonDataModel import vtkFieldData

    copy = data.NewInstance()
    copy.ShallowCopy(data)
    source, target = data.GetFieldData(), vtkFieldData()
    copy.SetFieldData(target)  # a new one: the shallow copy may share the original's
    arrays = [source.GetAbstractArray(i) for i in range(source.GetNumberOfArrays())]
    labels = {}  # numeric array name -> its labels, where they match it one to one
    for array in arrays:
        target_name = LABELLED.get(array.GetName()) if _is_string(array) else None
        values = source.GetArray(target_name) if target_name else None
        if values is not None and values.GetNumberOfComponents() == 1 \
                and values.GetNumberOfTuples() == array.GetNumberOfValues() > 0:
            labels[target_name] = _string_values(array)
    for array in arrays:
        name = array.GetName() or ""
        # the writers' own data (the surface sets' faces), not the files'
        if name.startswith(DOMAIN_PREFIX) or name == fieldkeys.SEPARATING_FACES or \
                (_is_string(array) and LABELLED.get(name) in labels):
            continue
        if name in labels:
            row = array.NewInstance()
            row.SetName(name)
            row.SetNumberOfComponents(len(labels[name]))
            row.SetNumberOfTuples(1)
            for i, label in enumerate(labels[name]):
                row.SetComponent(0, i, array.GetComponent(i, 0))
                row.SetComponentName(i, _escape(label))
            target.AddArray(row)
        elif _is_string(array):
            values = _string_values(array)
            if not values:
                continue
            row = vtkIntArray()
            row.SetName(name)
            row.SetNumberOfComponents(len(values))
            row.SetNumberOfTuples(1)
            for i, value in enumerate(values):
                row.SetComponent(0, i, i + 1)
                row.SetComponentName(i, _escape(value))
            target.AddArray(row)
        else:
            target.AddArray(array)
    return copy


def labelled(field_data, values_name):
    """[(label, value)] of a labelled numeric array in either form; [] when absent."""
    names_name = next((n for n, v in LABELLED.items() if v == values_name), None)
    values = field_data.GetArray(values_name)
    if values is None:
        return []
    names = field_data.GetAbstractArray(names_name) if names_name else None
    if _is_string(names):
        n = min(names.GetNumberOfValues(), values.GetNumberOfTuples())
        return [(names.GetValue(i), values.GetComponent(i, 0)) for i in range(n)]
    if values.GetNumberOfTuples() == 1 and values.GetComponentName(0) is not None:
        return [(values.GetComponentName(i), values.GetComponent(0, i)) for i in range(values.GetNumberOfComponents())]
    return []


def strings(field_data, name):
    """The strings of a field array in either form (a string array, or component names); [] when absent."""
    array = field_data.GetAbstractArray(name)
    if array is None:
        return []
    if _is_string(array):
        return _string_values(array)
    return [array.GetComponentName(i) for i in range(array.GetNumberOfComponents())
            if array.GetComponentName(i) is not None]


def add_material_names(field_data, names):
    """Stores {material id: name} as the arrays MaterialIds and MaterialNames (what the report and
    the writers read)."""
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkStringArray

    ids, strings = vtkIntArray(), vtkStringArray()
    ids.SetName(fieldkeys.MATERIAL_IDS)
    strings.SetName(fieldkeys.MATERIAL_NAMES)
    for m, name in sorted(names.items()):
        ids.InsertNextValue(m)
        strings.InsertNextValue(name)
    field_data.AddArray(ids)
    field_data.AddArray(strings)
