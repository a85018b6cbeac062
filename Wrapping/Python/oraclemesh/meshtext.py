# SPDX-License-Identifier: GPL-3.0-or-later
"""The text mesh formats (.inp, .msh, .mesh; ``writers.py`` says what each file holds) written in
blocks of rows.

Each block of rows (about ``BLOCK_VALUES`` numbers, or the caller's number of rows) becomes Python
numbers, is formatted with one printf-style pattern repeated once per row and is written before the
next block is made: a file costs one block's numbers and text beside the mesh, never a converted
copy of its nodes, elements or materials, nor the whole file's text. The block size changes nothing
in the file.

The text is what meshio 5.0's Abaqus and Gmsh 2.2 (ASCII) writers and numpy's ``savetxt`` make of
the same arrays: the same number formats, separators, element numbering and set lists, so the files
read as before in meshio, gmsh and CalculiX; the Abaqus heading names OracleMesh as the writer.
"""
import itertools

import numpy as np

from .surfaces import material_set_names

# Numbers formatted at a time, as whole rows (100,000 rows of a 4-node element): some 30 MB of Python
# numbers and text whatever the row's width, ~0.1 s.
BLOCK_VALUES = 500_000
# 13 significant digits: 19 characters at most; CalculiX's reader takes 20 per number and stops at
# longer ones ("*ERROR reading *NODE").
ABAQUS_FLOAT = "%.12e"
ABAQUS_PER_LINE = 8  # ids per line of an *ELSET or *NSET list (meshio's)
GMSH_FLOAT = "%.16e"
# Gmsh's 10-node tetrahedron lists the mid-edge nodes of edges 13 and 23 the other way round from VTK.
GMSH_TETRA10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
MEDIT_FLOAT = "%.17g"  # round-trips every double


def _columns(block):
    """The columns of a 2-D array block as lists of Python numbers."""
    return block.T.tolist()


def _block(block_rows, width):
    """Rows of `width` numbers formatted at a time: the caller's, else about BLOCK_VALUES numbers."""
    return block_rows or max(1, BLOCK_VALUES // width)


def write_rows(f, pattern, count, columns, block_rows=None):
    """Writes `count` rows to the text file `f`, each formatted with the printf-style `pattern` (a
    row with its newline); columns(start, stop) gives the columns of rows [start, stop) as sequences
    of Python numbers (ranges, lists)."""
    block_rows = _block(block_rows, pattern.count("%"))
    for start in range(0, count, block_rows):
        stop = min(start + block_rows, count)
        values = tuple(itertools.chain.from_iterable(zip(*columns(start, stop))))
        f.write((pattern * (stop - start)) % values)


def _numbered(rows, first=1):
    """columns() for write_rows: the row number (from `first`), then the columns of rows[start:stop] + 1
    (0-based node ids written 1-based)."""
    return lambda start, stop: [range(first + start, first + stop)] + _columns(rows[start:stop] + 1)


def write_id_lines(f, chunks, per_line=ABAQUS_PER_LINE):
    """Writes the integers of `chunks` (1-D integer arrays, in order) as an Abaqus data list:
    `per_line` to a line, separated by commas, every line but the last ending with a comma too."""
    pending = np.zeros(0, dtype=np.int64)
    line = ",".join(["%d"] * per_line) + ",\n"
    for chunk in chunks:
        pending = np.concatenate([pending, chunk])
        lines = (len(pending) - 1) // per_line  # the last id waits: the list's end has no comma
        if lines > 0:
            f.write((line * lines) % tuple(pending[:lines * per_line].tolist()))
            pending = pending[lines * per_line:]
    if len(pending):
        f.write(",".join(str(i) for i in pending.tolist()) + "\n")


def _matching(values, wanted, block_rows):
    """The 1-based positions of `wanted` in `values`, a block of `values` at a time."""
    block_rows = _block(block_rows, 1)
    for start in range(0, len(values), block_rows):
        yield np.flatnonzero(values[start:start + block_rows] == wanted) + (start + 1)


def _slices(array, block_rows):
    block_rows = _block(block_rows, 1)
    return (array[start:start + block_rows] for start in range(0, len(array), block_rows))


def write_inp(f, arrays, block_rows=None):
    """Abaqus: *NODE, *ELEMENT (C3D4 or C3D10), an *ELSET per material, an *NSET per surface, then
    the material comments and a *SURFACE per surface. `arrays`: a writers.MeshArrays."""
    f.write("*HEADING\nAbaqus DataFile Version 6.14\nwritten by OracleMesh\n*NODE\n")
    points, nodes = arrays.points, arrays.nodes
    write_rows(f, "%d, " + ", ".join([ABAQUS_FLOAT] * 3) + "\n", len(points),
               lambda start, stop: [range(start + 1, stop + 1)] + _columns(points[start:stop]), block_rows)
    f.write(f"*ELEMENT, TYPE={'C3D10' if arrays.quadratic else 'C3D4'}\n")
    write_rows(f, "%d," + ",".join(["%d"] * nodes.shape[1]) + "\n", len(nodes), _numbered(nodes), block_rows)
    set_names = material_set_names(arrays.ids, arrays.names)
    for m in arrays.ids:
        f.write(f"*ELSET, ELSET={set_names[m]}\n")
        write_id_lines(f, _matching(arrays.material, m, block_rows))
    sets = arrays.sets
    for i, name in enumerate(sets.names):
        f.write(f"*NSET, NSET={name}\n")
        write_id_lines(f, _slices(np.unique(arrays.face_nodes[sets.select(i)]) + 1, block_rows))
    f.write("** OracleMesh: element sets per material (id, set, name); per surface *SURFACE (faces of "
            "the first-named material's elements) and *NSET of the same name\n")
    for m in arrays.ids:
        f.write(f"** OracleMesh material {m} {set_names[m]} {arrays.names.get(m, '')}".rstrip().replace("\n", " ")
                + "\n")
    for i, name in enumerate(sets.names):
        rows = sets.select(i)
        owner, side = sets.owner[rows], sets.side[rows]
        f.write(f"*SURFACE, NAME={name}, TYPE=ELEMENT\n")
        write_rows(f, "%d, S%d\n", len(owner),
                   lambda start, stop: [(owner[start:stop] + 1).tolist(), side[start:stop].tolist()], block_rows)


def gmsh_physical_names(arrays):
    """[(dimension, tag, name)] of the materials (3) and the surfaces (2), sorted: names double quote
    free, one line each, a repeated name suffixed with its tag."""
    entries, used = [], set()
    for dimension, tags, names in ((3, arrays.ids, [arrays.names.get(m) or f"material_{m}" for m in arrays.ids]),
                                   (2, arrays.tags, arrays.sets.names)):
        for tag, name in zip(tags, names):
            name = name.replace('"', "'").replace("\n", " ")
            name = name if name not in used else f"{name}_{tag}"
            used.add(name)
            entries.append((dimension, tag, name))
    return sorted(entries)


def write_msh(f, arrays, block_rows=None):
    """Gmsh 2.2 ASCII: $PhysicalNames, $Nodes, $Elements (the tetrahedra with their material as
    physical and elementary tag, then the surface triangles with their surface tag)."""
    names = gmsh_physical_names(arrays)
    f.write(f"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n{len(names)}\n")
    f.writelines(f'{dimension} {tag} "{name}"\n' for dimension, tag, name in names)
    points, nodes, faces, material = arrays.points, arrays.nodes, arrays.face_nodes, arrays.material
    f.write(f"$EndPhysicalNames\n$Nodes\n{len(points)}\n")
    write_rows(f, "%d " + " ".join([GMSH_FLOAT] * 3) + "\n", len(points),
               lambda start, stop: [range(start + 1, stop + 1)] + _columns(points[start:stop]), block_rows)
    f.write(f"$EndNodes\n$Elements\n{len(nodes) + len(faces)}\n")
    volume, face, order = (11, 9, GMSH_TETRA10) if arrays.quadratic else (4, 2, slice(None))

    def tetrahedra(start, stop):
        tags = material[start:stop].tolist()
        return [range(start + 1, stop + 1), tags, tags] + _columns(nodes[start:stop][:, order] + 1)

    write_rows(f, f"%d {volume} 2 %d %d " + " ".join(["%d"] * nodes.shape[1]) + "\n", len(nodes), tetrahedra,
               block_rows)
    surface = arrays.surface_tag()

    def triangles(start, stop):
        tags = surface[start:stop].tolist()
        first = len(nodes) + 1
        return [range(first + start, first + stop), tags, tags] + _columns(faces[start:stop] + 1)

    write_rows(f, f"%d {face} 2 %d %d " + " ".join(["%d"] * faces.shape[1]) + "\n", len(faces), triangles,
               block_rows)
    f.write("$EndElements\n")


def write_medit(f, arrays, block_rows=None):
    """Medit: name comments, Vertices, Triangles (surface tags) and Tetrahedra (material ids), the P2
    keywords for 10-node tetrahedra."""
    f.write("# OracleMesh: tetrahedron references are material ids, triangle references surface tags\n")
    if arrays.quadratic:
        f.write("# OracleMesh: P2 nodes: corners, then the mid-edge nodes of edges 12 23 31 (triangles), "
                "12 23 31 14 24 34 (tetrahedra)\n")
    for m in arrays.ids:
        f.write(f"# material {m} {arrays.names.get(m, '')}".rstrip().replace("\n", " ") + "\n")
    for tag, name in zip(arrays.tags, arrays.sets.names):
        f.write(f"# surface {tag} {name}\n")
    points, nodes, faces = arrays.points, arrays.nodes, arrays.face_nodes
    f.write(f"MeshVersionFormatted 2\nDimension 3\nVertices\n{len(points)}\n")
    write_rows(f, " ".join([MEDIT_FLOAT] * 3) + " 0\n", len(points),
               lambda start, stop: _columns(points[start:stop]), block_rows)
    p2 = "P2" if arrays.quadratic else ""  # libMeshb's keywords of 6-node triangles, 10-node tetrahedra
    surface, material = arrays.surface_tag(), arrays.material
    f.write(f"Triangles{p2}\n{len(faces)}\n")
    write_rows(f, "%d " * faces.shape[1] + "%d\n", len(faces),
               lambda start, stop: _columns(faces[start:stop] + 1) + [surface[start:stop].tolist()], block_rows)
    f.write(f"Tetrahedra{p2}\n{len(nodes)}\n")
    write_rows(f, "%d " * nodes.shape[1] + "%d\n", len(nodes),
               lambda start, stop: _columns(nodes[start:stop] + 1) + [material[start:stop].tolist()], block_rows)
    f.write("End\n")
