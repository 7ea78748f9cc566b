#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""Exact surface area of IFC products whose 'Body' is faceted breps, from the STEP text alone.

An engine-independent reference for the IFC ingest (issue 38): per face, the area of its outer
loop (IfcFaceOuterBound; without one, the largest loop) minus its holes, each loop's area by
Newell's formula (half the norm of the sum of p_i x p_i+1); through IfcMappedItem (times the
square of its operator's Scale), times the square of the length unit. Products with any other
body item (extrusions, CSG, ...) are left out: their area depends on tessellation and openings.

    faceted_brep_area.py FILE.ifc UNIT_M [IFCCLASS,...]     e.g. SampleHouse4.ifc 0.001 IFCWINDOW

Prints "CLASS GLOBALID AREA_M2" per product. Minimal STEP reading: one entity per statement,
no strings holding ");" (enough for the exporters' geometry, not a general parser).
"""
import math
import re
import sys


def split_args(text):
    """Top-level comma split of an entity's argument list."""
    out, depth, cur, quoted = [], 0, "", False
    for c in text:
        if c == "'":
            quoted = not quoted
        if not quoted and c == "(":
            depth += 1
        if not quoted and c == ")":
            depth -= 1
        if not quoted and c == "," and depth == 0:
            out.append(cur)
            cur = ""
            continue
        cur += c
    out.append(cur)
    return out


def refs(text):
    return [int(x) for x in re.findall(r"#(\d+)", text)]


class NotFaceted(Exception):
    pass


def main():
    path, unit = sys.argv[1], float(sys.argv[2])
    classes = set(sys.argv[3].upper().split(",")) if len(sys.argv) > 3 else None
    text = open(path, encoding="latin-1").read()
    ents = {}
    for m in re.finditer(r"#(\d+)\s*=\s*([A-Z0-9]+)\s*\((.*?)\);\s*$", text, re.M | re.S):
        ents[int(m.group(1))] = (m.group(2), m.group(3))

    def point(i):
        kind, args = ents[i]
        assert kind == "IFCCARTESIANPOINT", kind
        v = [float(x) for x in args.strip("()").split(",")]
        return v + [0.0] * (3 - len(v))

    def loop_area(i):
        kind, args = ents[i]
        if kind != "IFCPOLYLOOP":
            raise NotFaceted(kind)
        p = [point(r) for r in refs(args)]
        n = [0.0, 0.0, 0.0]
        for k in range(len(p)):
            a, b = p[k], p[(k + 1) % len(p)]
            n[0] += a[1] * b[2] - a[2] * b[1]
            n[1] += a[2] * b[0] - a[0] * b[2]
            n[2] += a[0] * b[1] - a[1] * b[0]
        return 0.5 * math.sqrt(sum(x * x for x in n))

    def face_area(i):
        bounds = [(ents[b][0], loop_area(refs(ents[b][1])[0])) for b in refs(ents[i][1])]
        outer = [a for kind, a in bounds if kind == "IFCFACEOUTERBOUND"]
        largest = outer[0] if len(outer) == 1 else max(a for _, a in bounds)
        return 2 * largest - sum(a for _, a in bounds)

    def item_area(i, scale):
        kind, args = ents[i]
        if kind == "IFCFACETEDBREP":
            shell = refs(args)[0]
            return sum(face_area(f) for f in refs(ents[shell][1])) * scale * scale
        if kind == "IFCMAPPEDITEM":
            source, target = refs(args)[:2]
            operator = split_args(ents[target][1])
            s = float(operator[3]) if operator[3] not in ("$", "") else 1.0
            representation = refs(ents[source][1])[1]
            items = refs(split_args(ents[representation][1])[3])
            return sum(item_area(r, scale * s) for r in items)
        raise NotFaceted(kind)

    for i, (kind, args) in sorted(ents.items()):
        if classes is not None and kind not in classes:
            continue
        a = split_args(args)
        if len(a) < 7 or not a[6].startswith("#"):
            continue
        shape = ents.get(int(a[6][1:]))
        if shape is None or shape[0] != "IFCPRODUCTDEFINITIONSHAPE":
            continue
        area, body = 0.0, False
        try:
            for r in refs(split_args(shape[1])[2]):
                ra = split_args(ents[r][1])
                if ra[1].strip("'").lower() != "body":
                    continue
                body = True
                area += sum(item_area(x, 1.0) for x in refs(ra[3]))
        except NotFaceted:
            continue
        if body:
            print("%s %s %.7f" % (kind, a[0].strip("'"), area * unit * unit))


if __name__ == "__main__":
    main()
