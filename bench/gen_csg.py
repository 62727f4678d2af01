#!/usr/bin/env python3
"""Write the CSG bench's program in both languages: the difference of two
closed triangle meshes of about N triangles each (latitude-longitude
spheres, the second moved and turned so that no vertex or face of one
lies on the other), as polyhedron literals, faces clockwise seen from
outside as OpenSCAD (and sumi's polyhedron) take them.

    gen_csg.py N OUT.npr OUT.scad
"""
import math
import sys


def sphere(n, r, centre, turn):
    """(points, faces) of a sphere of about n triangles: nu around, nv rings."""
    nv = max(3, int(round(math.sqrt(n / 4))))
    nu = max(3, int(round(n / (2 * (nv - 1)))))
    ca, sa = math.cos(turn), math.sin(turn)
    pts = [(0.0, 0.0, r)]
    for j in range(1, nv):
        th = math.pi * j / nv
        for i in range(nu):
            ph = 2 * math.pi * i / nu
            pts.append((r * math.sin(th) * math.cos(ph), r * math.sin(th) * math.sin(ph), r * math.cos(th)))
    pts.append((0.0, 0.0, -r))
    pts = [(ca * x + sa * z, y, -sa * x + ca * z) for x, y, z in pts]  # turn about y
    pts = [(x + centre[0], y + centre[1], z + centre[2]) for x, y, z in pts]
    top, bot = 0, len(pts) - 1
    ring = lambda j, i: 1 + (j - 1) * nu + i % nu
    faces = []  # counter-clockwise from outside first, reversed below
    for i in range(nu):
        faces.append((top, ring(1, i), ring(1, i + 1)))
        faces.append((bot, ring(nv - 1, i + 1), ring(nv - 1, i)))
    for j in range(1, nv - 1):
        for i in range(nu):
            a, b, c, d = ring(j, i), ring(j + 1, i), ring(j + 1, i + 1), ring(j, i + 1)
            faces.append((a, b, c))
            faces.append((a, c, d))
    return pts, [tuple(reversed(f)) for f in faces]


def literal(pts, faces):
    p = ", ".join("[%.9g, %.9g, %.9g]" % q for q in pts)
    f = ", ".join("[%d, %d, %d]" % t for t in faces)
    return "polyhedron([%s],\n  [%s])" % (p, f)


def main():
    n, npr, scad = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    a = sphere(n, 1.0, (0, 0, 0), 0.0)
    b = sphere(n, 0.8, (0.7, 0.1, 0.2), 0.3)
    body = "difference() {\n%s;\n%s;\n}\n" % (literal(*a), literal(*b))
    open(npr, "w").write("// %d and %d triangles\n" % (len(a[1]), len(b[1])) + body)
    open(scad, "w").write(body)
    print("%d and %d triangles" % (len(a[1]), len(b[1])))


main()
