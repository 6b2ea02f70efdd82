#!/usr/bin/env python3
"""Checks raystep's reading of a glTF file against an independent reader, trimesh (PyPI):
every triangle trimesh places in world space (each node's mesh by its world transform) must be
one of raystep's, in any vertex order, within `--tol`. raystep's triangles are read from the OBJ
files its Mitsuba export writes (`raystep scene mitsuba`): a mesh that several nodes place is
one `shapegroup` there (the prototype, in the mesh's own space), carried to the world by each
`instance` shape's matrix. Not part of CI (it needs trimesh):

    python3 -m pip install trimesh
    python3 tools/gltf-compare-trimesh.py scenes/gltf/table.gltf [--raystep target/debug/raystep]
"""
import argparse
import xml.etree.ElementTree as ET
import itertools
import os
import subprocess
import sys
import tempfile

import numpy as np
import trimesh

ap = argparse.ArgumentParser()
ap.add_argument("gltf")
ap.add_argument("--raystep", default="target/debug/raystep")
ap.add_argument("--tol", type=float, default=1e-6)
a = ap.parse_args()

with tempfile.TemporaryDirectory() as d:
    subprocess.run([a.raystep, "scene", "mitsuba", a.gltf, "-o", os.path.join(d, "scene.xml")],
                   check=True, stdout=subprocess.DEVNULL)
    def triangles(f):
        vs = [list(map(float, l.split()[1:4])) for l in open(os.path.join(d, f))
              if l.startswith("v ")]
        return [vs[i:i + 3] for i in range(0, len(vs), 3)]

    root = ET.parse(os.path.join(d, "scene.xml")).getroot()
    ours, groups = [], {}
    for shape in root.findall("shape"):
        kind = shape.get("type")
        if kind == "obj":
            ours += triangles(shape.find("string[@name='filename']").get("value"))
        elif kind == "shapegroup":
            groups[shape.get("id")] = [t for s in shape.findall("shape")
                                       for t in triangles(s.find("string[@name='filename']").get("value"))]
        elif kind == "instance":
            m = np.array(list(map(float, shape.find("transform/matrix").get("value").split())))
            m = m.reshape(4, 4)
            for t in groups[shape.find("ref").get("id")]:
                ours.append([list(m[:3, :3] @ np.array(v) + m[:3, 3]) for v in t])
ours = np.array(ours)

scene = trimesh.load(a.gltf, force="scene", process=False)
worst, count = 0.0, 0
for node in scene.graph.nodes_geometry:
    transform, name = scene.graph[node]
    mesh = scene.geometry[name].copy()
    mesh.apply_transform(transform)
    for t in mesh.triangles:
        d = min(np.abs(ours - t[list(p)]).max(axis=(1, 2)).min()
                for p in itertools.permutations(range(3)))
        worst, count = max(worst, d), count + 1
print(f"{count} triangles from trimesh, {len(ours)} from raystep; "
      f"largest distance to raystep's nearest: {worst:.3g}")
sys.exit(0 if count == len(ours) and worst <= a.tol else 1)
