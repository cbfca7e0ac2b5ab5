#!/usr/bin/env python3
"""Regenerates Data/body.vtk from Debian's assimp-testmodels package.

Source: /usr/share/assimp/models/Collada/human.zae, the MakeHuman adult (MakeHuman assets
are CC0; Debian's copyright file lists the folder as BSD-3-clause). See Data/README.md.

  assimp export human.zae out.obj -fobjnomtl -ptv -jiv -tri   (keep -tri: assimp 5.2.5
  crashes on this file without it)

then this script keeps the body group only (the separate eye meshes are dropped), drops
texture coordinates and normals (a reader that honours them splits vertices at seams and
the surface is no longer closed), removes unused vertices, checks that what is left is a
closed genus-0 triangle surface, and writes it as legacy VTK polydata (ASCII), which both
VTK and HairDynamics' Core reader read.

Usage: Data/make_body.py [output.vtk]   (default: Data/body.vtk beside this script)
"""
import os
import subprocess
import sys
import tempfile
from collections import Counter

SOURCE = "/usr/share/assimp/models/Collada/human.zae"
BODY_GROUP = "human-baseMesh"


def export_obj(workdir):
    if not os.path.exists(SOURCE):
        sys.exit(f"make_body: {SOURCE} is missing; install it with 'apt-get install assimp-testmodels assimp-utils'")
    obj = os.path.join(workdir, "human.obj")
    subprocess.run(["assimp", "export", SOURCE, obj, "-fobjnomtl", "-ptv", "-jiv", "-tri"],
                   check=True, stdout=subprocess.DEVNULL)
    return obj


def read_body(obj):
    points, faces, group = [], [], None
    with open(obj) as f:
        for line in f:
            tok = line.split()
            if not tok:
                continue
            if tok[0] == "v":
                points.append(tuple(float(x) for x in tok[1:4]))
            elif tok[0] == "g":
                group = tok[1] if len(tok) > 1 else None
            elif tok[0] == "f" and group == BODY_GROUP:
                # "v", "v/vt", "v//vn" or "v/vt/vn": keep the position index only
                idx = [int(t.split("/")[0]) for t in tok[1:]]
                idx = [i - 1 if i > 0 else len(points) + i for i in idx]
                if len(idx) != 3:
                    sys.exit(f"make_body: a face with {len(idx)} corners; export with -tri")
                faces.append(tuple(idx))
    used = sorted({i for face in faces for i in face})
    remap = {old: new for new, old in enumerate(used)}
    return [points[i] for i in used], [tuple(remap[i] for i in face) for face in faces]


def check_closed_genus0(points, faces):
    edges = Counter()
    for a, b, c in faces:
        for u, v in ((a, b), (b, c), (c, a)):
            edges[(min(u, v), max(u, v))] += 1
    bad = [e for e, n in edges.items() if n != 2]
    if bad:
        sys.exit(f"make_body: {len(bad)} edges are not shared by exactly two triangles")
    euler = len(points) - len(edges) + len(faces)
    if euler != 2:
        sys.exit(f"make_body: Euler characteristic {euler}, expected 2 (genus 0)")
    return len(edges)


def write_vtk(path, points, faces):
    with open(path, "w") as f:
        f.write("# vtk DataFile Version 3.0\n")
        f.write("MakeHuman adult body (assimp-testmodels human.zae), metres, Y up, face +Z; see Data/README.md\n")
        f.write("ASCII\nDATASET POLYDATA\n")
        f.write(f"POINTS {len(points)} double\n")
        for p in points:
            f.write("%.6f %.6f %.6f\n" % p)
        f.write(f"POLYGONS {len(faces)} {4 * len(faces)}\n")
        for a, b, c in faces:
            f.write(f"3 {a} {b} {c}\n")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "body.vtk")
    with tempfile.TemporaryDirectory() as tmp:
        points, faces = read_body(export_obj(tmp))
    nedges = check_closed_genus0(points, faces)
    ys = [p[1] for p in points]
    write_vtk(out, points, faces)
    print(f"make_body: {len(points)} vertices, {len(faces)} triangles, {nedges} edges, closed, genus 0, "
          f"y from {min(ys):.4f} to {max(ys):.4f} m -> {out}")


if __name__ == "__main__":
    main()
