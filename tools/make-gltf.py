#!/usr/bin/env python3
"""Writes raystep's glTF test and example models, by hand (Python's standard library only):
nothing is downloaded. Run from the repository root:

    python3 tools/make-gltf.py

- scenes/gltf/table.gltf (+ table.bin): a table (one box mesh placed five times by a node
  hierarchy: a top and four legs), a steel ball (a smooth UV sphere), a glass pane
  (KHR_materials_transmission and KHR_materials_ior), a textured top (../textures/tiles-8x8.png,
  nearest, repeat), a camera and a point light (KHR_lights_punctual).
- tests/gltf/table.glb: the same file as one GLB (its buffer in the binary chunk, the image in a
  buffer view), for the test that both read alike.
- tests/gltf/lamp.gltf: one quad, emissive (KHR_materials_emissive_strength), its buffer a data:
  URI, a node with a 4 x 4 matrix; and its parent scaled non-uniformly, so that normals must go
  by the inverse transpose.

Each file passes Khronos's glTF validator with no error and no warning:
`npm install gltf-validator && node tools/gltf-validate.mjs FILE...` (README.md, *glTF scenes*).
"""
import base64
import json
import math
import os
import struct

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class Buffer:
    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def _align(self):
        while len(self.data) % 4:
            self.data.append(0)

    def view(self, raw, target=None):
        self._align()
        v = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if target:
            v["target"] = target
        self.data += raw
        self.views.append(v)
        return len(self.views) - 1

    def floats(self, rows, kind, minmax=False):
        n = len(rows[0])
        raw = b"".join(struct.pack("<%df" % n, *r) for r in rows)
        a = {"bufferView": self.view(raw, 34962), "componentType": 5126, "count": len(rows), "type": kind}
        if minmax:
            a["min"] = [min(r[k] for r in rows) for k in range(n)]
            a["max"] = [max(r[k] for r in rows) for k in range(n)]
        self.accessors.append(a)
        return len(self.accessors) - 1

    def indices(self, idx):
        raw = struct.pack("<%dH" % len(idx), *idx)
        a = {"bufferView": self.view(raw, 34963), "componentType": 5123, "count": len(idx), "type": "SCALAR"}
        self.accessors.append(a)
        return len(self.accessors) - 1


def box():
    """A unit cube about the origin: 24 vertices, each face its own normal and uv square."""
    pos, nor, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            # Two tangent axes, wound so that (a × b) = n: counter-clockwise seen from outside.
            a = [0.0, 0.0, 0.0]
            b = [0.0, 0.0, 0.0]
            a[(axis + 1) % 3] = 1.0
            b[(axis + 2) % 3] = 1.0
            if sign < 0:
                a, b = b, a
            base = len(pos)
            for (s, t) in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append([0.5 * (n[k] + s * a[k] + t * b[k]) for k in range(3)])
                nor.append(n)
                uv.append([(s + 1) / 2, (1 - t) / 2])
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nor, uv, idx


def sphere(cols=12, rows=8):
    """A unit UV sphere with smooth (unit radial) normals."""
    pos, nor, uv, idx = [], [], [], []
    for r in range(rows + 1):
        th = math.pi * r / rows
        for c in range(cols + 1):
            ph = 2 * math.pi * c / cols
            p = [math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph)]
            pos.append(p)
            nor.append(p)
            uv.append([c / cols, r / rows])
    for r in range(rows):
        for c in range(cols):
            a = r * (cols + 1) + c
            b = a + cols + 1
            if r > 0:
                idx += [a, b, a + 1]
            if r < rows - 1:
                idx += [a + 1, b, b + 1]
    return pos, nor, uv, idx


def quad():
    pos = [[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]]
    nor = [[0.0, 0.0, 1.0]] * 4
    uv = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]
    return pos, nor, uv, [0, 1, 2, 0, 2, 3]


def mesh(buf, name, geometry, material):
    pos, nor, uv, idx = geometry
    attrs = {
        "POSITION": buf.floats(pos, "VEC3", minmax=True),
        "NORMAL": buf.floats(nor, "VEC3"),
        "TEXCOORD_0": buf.floats(uv, "VEC2"),
    }
    return {"name": name, "primitives": [{"attributes": attrs, "indices": buf.indices(idx), "material": material}]}


def quat_y(deg):
    h = math.radians(deg) / 2
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def quat_x(deg):
    h = math.radians(deg) / 2
    return [math.sin(h), 0.0, 0.0, math.cos(h)]


def table(glb):
    buf = Buffer()
    meshes = [
        mesh(buf, "box", box(), 0),
        mesh(buf, "ball", sphere(), 1),
        mesh(buf, "pane", quad(), 2),
    ]
    png = open(os.path.join(ROOT, "scenes/textures/tiles-8x8.png"), "rb").read()
    if glb:
        image = {"bufferView": buf.view(png), "mimeType": "image/png", "name": "tiles"}
    else:
        image = {"uri": "../textures/tiles-8x8.png", "name": "tiles"}
    leg = lambda x, z: {"name": "leg %+d%+d" % (x, z), "mesh": 0, "translation": [0.5 * x, 0.35, 0.3 * z], "scale": [0.08, 0.7, 0.08]}
    doc = {
        "asset": {"version": "2.0", "generator": "raystep tools/make-gltf.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_ior", "KHR_materials_transmission"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"name": "lamp", "type": "point", "color": [1.0, 0.95, 0.9], "intensity": 6.0}]}},
        "scene": 0,
        "scenes": [{"name": "table", "nodes": [0, 8, 9]}],
        "nodes": [
            {"name": "table", "children": [1, 2, 3, 4, 5, 6, 7]},
            {"name": "top", "mesh": 0, "translation": [0.0, 0.74, 0.0], "scale": [1.2, 0.08, 0.8]},
            leg(1, 1), leg(1, -1), leg(-1, 1), leg(-1, -1),
            {"name": "ball", "mesh": 1, "translation": [0.25, 0.93, 0.05], "scale": [0.15, 0.15, 0.15]},
            {"name": "pane", "mesh": 2, "translation": [-0.25, 0.98, 0.0], "rotation": quat_y(30.0), "scale": [0.35, 0.4, 1.0]},
            {"name": "camera", "camera": 0, "translation": [0.0, 1.3, 2.6], "rotation": quat_x(-12.0)},
            {"name": "lamp", "translation": [1.0, 2.2, 1.5], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "cameras": [{"name": "front", "type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 4 / 3, "znear": 0.05}}],
        "meshes": meshes,
        "materials": [
            {"name": "wood", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.75, 0.55, 1.0], "baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.8}},
            {"name": "steel", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.95, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.3}},
            {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.0},
             "doubleSided": True,
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.45}}},
        ],
        "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 10497, "wrapT": 10497}],
        "images": [image],
        "textures": [{"name": "tiles", "source": 0, "sampler": 0}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
    }
    while len(buf.data) % 4:
        buf.data.append(0)
    if glb:
        doc["buffers"] = [{"byteLength": len(buf.data)}]
        js = json.dumps(doc, separators=(",", ":")).encode()
        js += b" " * ((4 - len(js) % 4) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(buf.data), 0x004E4942) + bytes(buf.data)
        return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body
    doc["buffers"] = [{"byteLength": len(buf.data), "uri": "table.bin"}]
    return json.dumps(doc, indent=1).encode() + b"\n", bytes(buf.data)


def lamp():
    buf = Buffer()
    m = mesh(buf, "panel", quad(), 0)
    while len(buf.data) % 4:
        buf.data.append(0)
    uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()
    # Column-major: translate by (0, 2, 0) after turning the panel to face down (-y), by
    # a rotation of +90 degrees about x: y -> z, z -> -y.
    matrix = [1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 2, 0, 1]
    doc = {
        "asset": {"version": "2.0", "generator": "raystep tools/make-gltf.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "stretch", "scale": [2.0, 1.0, 0.5], "children": [1]},
            {"name": "panel", "mesh": 0, "matrix": matrix},
        ],
        "meshes": [m],
        "materials": [{"name": "glow", "emissiveFactor": [1.0, 0.5, 0.25], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}},
                       "pbrMetallicRoughness": {"metallicFactor": 0.0}}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data), "uri": uri}],
    }
    return json.dumps(doc, indent=1).encode() + b"\n"


def write(rel, data):
    path = os.path.join(ROOT, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)
    print("wrote", rel, len(data), "bytes")


if __name__ == "__main__":
    text, binary = table(glb=False)
    write("scenes/gltf/table.gltf", text)
    write("scenes/gltf/table.bin", binary)
    write("tests/gltf/table.glb", table(glb=True))
    write("tests/gltf/lamp.gltf", lamp())
