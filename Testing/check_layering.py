#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks the layers of the source tree (ctest Core.layering):

- each core room (Filters/Core/<room>) includes only its own headers and those of the rooms before
  it: Geometry < Mesh < Domains < Features < Quality < Meshing (Meshing/Cgal is Meshing's private
  CGAL glue: no other room and no file outside the core includes it);
- the core includes no VTK header; the VTK adapters' headers (Filters/*.h) include no CGAL header.

    python3 Testing/check_layering.py [SOURCE_ROOT]

Prints each violation (file, line, what it includes) and exits 1 if there is one.
"""
import os
import re
import sys

ROOMS = ["Geometry", "Mesh", "Domains", "Features", "Quality", "Meshing"]
NEUTRAL = {"FieldDataKeys.h"}  # generated from Filters/FieldDataKeys.txt, a list of names
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def includes(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            m = INCLUDE.match(line)
            if m:
                yield number, m.group(1) == "<", m.group(2)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    core = os.path.join(root, "Filters", "Core")
    room_of = {}  # header name -> room ("Cgal" for Meshing's private glue)
    for room in ROOMS:
        for name in os.listdir(os.path.join(core, room)):
            if name.endswith(".h"):
                room_of[name] = room
    for name in os.listdir(os.path.join(core, "Meshing", "Cgal")):
        if name.endswith(".h"):
            room_of[name] = "Cgal"

    problems = []
    checked = 0
    for room in ROOMS + ["Cgal"]:
        folder = os.path.join(core, "Meshing", "Cgal") if room == "Cgal" else os.path.join(core, room)
        level = ROOMS.index("Meshing" if room == "Cgal" else room)
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".h", ".cxx")):
                continue
            path = os.path.join(folder, name)
            checked += 1
            for number, system, header in includes(path):
                where = f"{os.path.relpath(path, root)}:{number}"
                if system:
                    if header.startswith("vtk"):
                        problems.append(f"{where}: the core includes VTK <{header}>")
                    continue
                target = room_of.get(os.path.basename(header))
                if target is None or header in NEUTRAL:
                    continue
                if target == "Cgal":
                    if room not in ("Meshing", "Cgal"):
                        problems.append(f"{where}: {room} includes Meshing's private CGAL glue \"{header}\"")
                    continue
                if ROOMS.index(target) > level:
                    problems.append(f"{where}: {room} includes \"{header}\" of {target}, a room above it")
    adapters = os.path.join(root, "Filters")
    for name in sorted(os.listdir(adapters)):
        path = os.path.join(adapters, name)
        if not name.endswith((".h", ".cxx")) or not os.path.isfile(path):
            continue
        checked += 1
        for number, system, header in includes(path):
            where = f"{os.path.relpath(path, root)}:{number}"
            if system and header.startswith("CGAL/") and name.endswith(".h"):
                problems.append(f"{where}: an adapter header includes CGAL <{header}>")
            if not system and room_of.get(os.path.basename(header)) == "Cgal":
                problems.append(f"{where}: the VTK layer includes Meshing's private CGAL glue \"{header}\"")
    for p in problems:
        print(p)
    print(f"{checked} files checked, {len(problems)} layering problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
