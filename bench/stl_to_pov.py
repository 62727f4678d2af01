#!/usr/bin/env python3
"""The same scene for POV-Ray (make bench-bigmesh, bench/bigmesh.sh):

  stl_to_pov.py SCENE.txt MESH.stl OUT.pov [--smooth-angle DEG]

SCENE.txt is `sumi eval scene.npr --scene` (camera, first light (or sumi's default), first
style's base colour, image size, background); MESH.stl is `sumi export
scene.npr -o MESH.stl`, the triangles sumi renders, in world space. OUT.pov
draws them as one mesh2 (vertices shared, smooth normals) with sumi's
camera and a parallel light along the scene's light.

Normals: area-weighted vertex normals, as a subdivided surface shades
smoothly everywhere. --smooth-angle DEG gives a corner whose faces meet at
more than DEG the average of only the faces within DEG of its own (sumi's
rule for a polygon mesh without normals, 45 there): a CAD mesh keeps its
hard edges.

sumi is right-handed and z-up, POV-Ray left-handed: the camera's sky is
+z and its right vector points along -x, which turns POV-Ray's frame into
sumi's (the image is not mirrored). sumi's fov is vertical, POV-Ray's
angle horizontal: angle = 2 atan(tan(fov / 2) * width / height).

The module's read_stl and smooth_normals serve bench/bigmesh_blender.py
too, so both peers draw the same vertices."""
import math
import re
import sys

import numpy as np


def read_scene(path):
    """The `sumi eval --scene` lines as a dict of key -> value text."""
    out = {}
    with open(path) as f:
        for line in f:
            k, _, v = line.rstrip("\n").partition(" ")
            out[k] = v
    return out


def vec(text):
    return [float(x) for x in re.findall(r"[-+0-9.eE]+", text)]


def colour(text):
    """#rrggbb[aa] -> sRGB floats in [0, 1]."""
    h = text.strip().lstrip("#")
    return [int(h[i:i + 2], 16) / 255 for i in (0, 2, 4)]


def light_direction(sc):
    """Where the first light's rays go, or None for a point light. Without a
    light sumi's default key light: from over the camera's right shoulder,
    towards -(-forward + 0.6 right + 0.8 up) (render/render.c)."""
    if "light[0].direction" in sc:
        return vec(sc["light[0].direction"])
    if "light[0].position" in sc:
        return None
    pos, at, up = (np.array(vec(sc[k])) for k in ("camera.position", "camera.look_at", "camera.up"))
    f = (at - pos) / np.linalg.norm(at - pos)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    return list(-(-f + 0.6 * r + 0.8 * u))


def read_stl(path):
    """A binary STL's triangles welded: (vertices float64 N x 3, faces int T x 3).
    Corners with the same float coordinates are one vertex."""
    with open(path, "rb") as f:
        f.read(80)
        n = int(np.frombuffer(f.read(4), "<u4")[0])
        rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
        tris = np.frombuffer(f.read(n * rec.itemsize), rec, n)
    corners = np.ascontiguousarray(tris["v"].reshape(-1, 3))
    keys = corners.view(np.dtype((np.void, 12))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    return corners[first].astype(np.float64), inverse.reshape(-1, 3)


def smooth_normals(verts, faces, max_angle=None):
    """(normals M x 3, per-corner index T x 3 into them). Without max_angle
    one area-weighted normal per vertex; with it, a corner on an edge sharper
    than max_angle degrees averages only the faces within max_angle of its own."""
    a, b, c = (verts[faces[:, k]] for k in range(3))
    fn = np.cross(b - a, c - a)                        # area-weighted face normals
    nv = np.zeros_like(verts)
    for k in range(3):
        for d in range(3):
            nv[:, d] += np.bincount(faces[:, k], fn[:, d], len(verts))
    unit = lambda x: x / np.maximum(np.linalg.norm(x, axis=-1, keepdims=True), 1e-30)
    nv, fu = unit(nv), unit(fn)
    index = faces.copy()
    if max_angle is None:
        return nv, index
    # A vertex whose faces all lie within max_angle / 2 of its normal has no
    # two faces more than max_angle apart: it keeps the one normal.
    dots = np.einsum("tkd,td->tk", nv[faces], fu)
    worst = np.ones(len(verts))
    np.minimum.at(worst, faces.ravel(), dots.ravel())
    sharp = worst < math.cos(math.radians(max_angle) / 2)
    if not sharp.any():
        return nv, index
    cos_max = math.cos(math.radians(max_angle))
    around = {}
    for t, k in zip(*np.nonzero(sharp[faces])):
        around.setdefault(int(faces[t, k]), []).append((int(t), int(k)))
    extra = []
    for corners in around.values():
        ts = np.array([t for t, _ in corners])
        near = fu[ts] @ fu[ts].T >= cos_max               # faces within max_angle of each other
        sums = near.astype(np.float64) @ fn[ts]
        for (t, k), s in zip(corners, sums):
            index[t, k] = len(nv) + len(extra)
            extra.append(s)
    return np.vstack([nv, unit(np.array(extra))]), index


def fmt_vectors(a):
    return ",\n".join("<%.7g,%.7g,%.7g>" % tuple(r) for r in a.tolist())


def fmt_indices(a):
    return ",\n".join("<%d,%d,%d>" % tuple(r) for r in a.tolist())


def main():
    args = sys.argv[1:]
    angle = None
    if "--smooth-angle" in args:
        i = args.index("--smooth-angle")
        angle = float(args[i + 1])
        del args[i:i + 2]
    if len(args) != 3:
        sys.exit(__doc__)
    sc = read_scene(args[0])
    verts, faces = read_stl(args[1])
    nrm, nidx = smooth_normals(verts, faces, angle)
    w, h = (int(x) for x in sc["output.size"].split())
    if sc.get("camera.kind") != "perspective":
        sys.exit("stl_to_pov.py: only a perspective camera")
    fov = float(sc["camera.fov"])
    hangle = math.degrees(2 * math.atan(math.tan(math.radians(fov) / 2) * w / h))
    pos, at, up = vec(sc["camera.position"]), vec(sc["camera.look_at"]), vec(sc["camera.up"])
    d = light_direction(sc)
    if d is not None:
        far = 1e4 / math.sqrt(sum(x * x for x in d))
        light = "<%g,%g,%g> color rgb 1 parallel point_at <0,0,0> shadowless" % tuple(-x * far for x in d)
    else:
        light = "<%g,%g,%g> color rgb 1 shadowless" % tuple(vec(sc["light[0].position"]))
    base = colour(sc.get("style[0].base", "#ffffff"))
    bg = colour(sc.get("output.background", "#ffffff"))
    same = np.array_equal(nidx, faces)
    with open(args[2], "w") as f:
        f.write("// %s: %d vertices, %d triangles (bench/stl_to_pov.py)\n" % (args[1], len(verts), len(faces)))
        f.write("#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n")
        f.write("background { srgb <%g,%g,%g> }\n" % tuple(bg))
        f.write("camera { perspective location <%g,%g,%g> sky <%g,%g,%g> up <%g,%g,%g> direction <0,1,0>\n"
                "  right <%g,0,0> angle %.6f look_at <%g,%g,%g> }\n"
                % (*pos, *up, *up, w / h, hangle, *at))
        f.write("light_source { %s }\n" % light)
        f.write("mesh2 {\n  vertex_vectors { %d,\n%s }\n" % (len(verts), fmt_vectors(verts)))
        f.write("  normal_vectors { %d,\n%s }\n" % (len(nrm), fmt_vectors(nrm)))
        f.write("  face_indices { %d,\n%s }\n" % (len(faces), fmt_indices(faces)))
        if not same:
            f.write("  normal_indices { %d,\n%s }\n" % (len(nidx), fmt_indices(nidx)))
        f.write("  texture { pigment { srgb <%g,%g,%g> } finish { ambient 0.1 diffuse 0.9 "
                "specular 0.5 roughness 1/32 } }\n}\n" % tuple(base))


if __name__ == "__main__":
    main()
