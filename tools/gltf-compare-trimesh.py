#!/usr/bin/env python3
"""Checks raystep's reading of a glTF file against an independent reader, trimesh (PyPI):
every triangle trimesh places in world space (each node's mesh by its world transform) must be
one of raystep's, in any vertex order, within `--tol`. raystep's triangles are read from the OBJ
files its Mitsuba export writes (`raystep scene mitsuba`). Not part of CI (it needs trimesh):

    python3 -m pip install trimesh
    python3 tools/gltf-compare-trimesh.py scenes/gltf/table.gltf [--raystep target/debug/raystep]
"""
import argparse
import glob
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
    ours = []
    for f in sorted(glob.glob(os.path.join(d, "scene-g*.obj"))):
        vs = [list(map(float, l.split()[1:4])) for l in open(f) if l.startswith("v ")]
        ours += [vs[i:i + 3] for i in range(0, len(vs), 3)]
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
