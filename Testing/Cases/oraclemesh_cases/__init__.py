# SPDX-License-Identifier: GPL-3.0-or-later
"""Generators of the test and benchmark cases (not part of the user package `oraclemesh`; in the
build tree's site-packages only): `cases` (bone/implant label maps and surfaces from fixed seeds)
and `cad_cases` (flat-faced CAD assemblies on a 1 mm grid)."""
