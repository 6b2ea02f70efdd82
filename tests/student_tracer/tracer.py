#!/usr/bin/env python3
"""A model student's Whitted ray tracer, in plain Python (standard library only).

What it is
----------
This is the ray tracer a student of the raystep course could write by following the lessons
(camera, ray–sphere, ray–plane, ray–triangle, the naive closest-hit loop, shadows, reflection,
refraction, Phong shading).  It is *independent* of raystep: it reads the same scene file
(TOML, with OBJ meshes) and computes everything itself, in double precision, with the formulas
of the lessons.  It traces one pixel and prints that pixel's trace in raystep's *student trace
format* (JSON Lines: `format`, `pixel`, `ray`, `sphere`, `plane`, `triangle`, `hit`, `shadow`,
`color` records; see `crates/raystep-course/src/student/format.rs`).

How the tests use it
--------------------
The test suite runs it as the "student" of `raystep grade-tracer`:

    raystep grade-tracer --scene scenes/mirror-glass.toml --pixels "200,150;10,10" \\
        --run "python3 tests/student_tracer/tracer.py {scene} {x} {y}"

raystep traces the same pixel, lines the two traces up ray by ray and test by test, and scores
one test per pixel and stage (camera, sphere, plane-triangle, closest-hit, surface, shadows, secondary,
color).  Without `--bug` this tracer gets full marks (but see "Known limits").  With
`--bug NAME` it makes one classic student mistake, so the tests can check that the grader takes
marks off and names the mistake:

    half-b               b = f·Q instead of 2 f·Q in the sphere test
    unnormalized-normal  the sphere's normal P − G is not divided by the radius (no effect on
                         spheres of radius 1)
    no-shadow-offset     shadow rays start exactly on the surface, t_min = 0 (shadow acne)
    reflect-sign         reflect(d, n) = d + 2(d·n)n instead of d − 2(d·n)n (the one helper is
                         used for mirror rays and for Phong's highlight, as in a student's code)
    snell-inverted       η = n2/n1 instead of n1/n2
    normal-weights       a smooth triangle's vertex normals blended u·n0 + v·n1 + (1 − u − v)·n2
    v-flipped            an image's row from v·h instead of (1 − v)·h (row 0 is the image's top)
    half-texel           bilinear filtering from (⌊x⌋, ⌊y⌋) with f = x − ⌊x⌋: texel centres at
                         integers instead of at i + ½
    srgb-not-decoded     an image's 8-bit sRGB values used as linear (c/255)
    normal-by-m          an instance's normal carried back to the world by M instead of the
                         inverse transpose M⁻ᵀ (lesson 20)
    origin-as-vector     the ray's origin carried into an instance's object space without M⁻¹'s
                         translation (as a vector, w = 0)
    renormalized-q       the direction carried into object space renormalised (t then differs
                         from the world ray's)

Usage:  python3 tracer.py SCENE.toml X Y [--bug NAME] [--epsilon E]

Known limits
------------
raystep traces in single precision (f32); this tracer in double.  Where raystep's answer is
decided by f32 rounding, an exact student cannot agree with it:
- scenes/acne.toml (offset = "none"): raystep's shadow rays hit their own surface at t ≈ 1e-10
  (acne), and c = f·f − r² of the ball (r = 5000) comes out as −2, 0 or 2 (f32 spacing 2).
- scenes/leaky-edge.toml, centre row (y = 100): the rays run along shared triangle edges and
  which triangle raystep's f32 Möller–Trumbore picks (or none: the leak) is rounding noise.

(Two other places where f32 and f64 part ways are absorbed by the checker: the test of the
surface a spawned ray leaves is compared by its t only, since its b and c depend on the offset,
e.g. on scenes/far-sphere.toml; and the tolerance grows with the depth of the ray, so long
chains of bounces inside mirror-glass's bubble pass.)

Conventions (the ones raystep uses, so the numbers can be compared):
- A ray is P(t) = S + t·Q for t in (t_min, t_max); S the origin, Q the direction.
- Every primitive's test is printed with the nearest t past t_min, *ignoring* the closest hit
  found so far; the closest hit is chosen afterwards (lesson 5).
- Normals are unit vectors facing the incoming ray.
- Each ray's `color` record is the colour that ray returns, before its parent weighs it.
"""

import argparse
import json
import math
import os
import re
import sys
import tomllib
import zlib

BUGS = ("half-b", "unnormalized-normal", "no-shadow-offset", "reflect-sign", "snell-inverted",
        "normal-weights", "v-flipped", "half-texel", "srgb-not-decoded", "normal-by-m",
        "origin-as-vector", "renormalized-q")
BUG = None  # set from --bug

# How far spawned rays (shadow, reflection, refraction) start off the surface, along the normal,
# on the side the new ray leaves (The Ray Tracer Challenge's over_point / under_point).
#
# Why this small: the checker compares the tests of the spawned rays too, and the test of the
# sphere a ray leaves has c = f·f − r² ≈ 2·r·EPSILON and b = 2 f·Q off by ≈ 2·EPSILON·|Q|, which
# are compared to raystep's (whose own offset is a rounding-error bound, ~1e-7) with an absolute
# tolerance of 1e-4.  EPSILON = 1e-4 would fail that for spheres of radius ≥ 0.5.  In double
# precision 1e-6 is still far above the rounding error of the shipped scenes' coordinates.
EPSILON = 1e-6

# Shadow rays stop just short of the light: t_max = 1 − SHADOW_EPSILON for Q = L − S.
SHADOW_EPSILON = 1e-4

# Reflection and refraction rays whose share of the pixel (the product of the weights down from
# the camera) is below 1/512 are not traced: their colour counts as black (raystep does the same).
WEIGHT_CUTOFF = 1.0 / 512.0


# ---------------------------------------------------------------------------------------------
# Vectors: plain tuples (x, y, z).
# ---------------------------------------------------------------------------------------------

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, k):
    return (a[0] * k, a[1] * k, a[2] * k)


def mul(a, b):
    """Component-wise product (colours)."""
    return (a[0] * b[0], a[1] * b[1], a[2] * b[2])


def add_all(vs):
    out = BLACK
    for v in vs:
        out = add(out, v)
    return out


def sub2(a, b):
    return (a[0] - b[0], a[1] - b[1])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    return scale(a, 1.0 / length(a))


def neg(a):
    return (-a[0], -a[1], -a[2])


BLACK = (0.0, 0.0, 0.0)


# ---------------------------------------------------------------------------------------------
# The scene file (raystep's schema and defaults: crates/raystep-core/src/scene/model.rs, load.rs).
# ---------------------------------------------------------------------------------------------

class Material:
    """A Phong material with The Ray Tracer Challenge's defaults."""

    def __init__(self, d=None):
        d = d or {}
        self.name = d.get("name", "default")
        self.color = tuple(float(c) for c in d.get("color", (1.0, 1.0, 1.0)))
        self.ambient = float(d.get("ambient", 0.1))
        self.diffuse = float(d.get("diffuse", 0.9))
        self.specular = float(d.get("specular", 0.9))
        self.shininess = float(d.get("shininess", 200.0))
        self.reflective = float(d.get("reflective", 0.0))
        self.transparency = float(d.get("transparency", 0.0))
        self.refractive_index = float(d.get("refractive_index", 1.0))
        self.texture = None  # lesson 18: a Texture whose colour multiplies `color`


class Sphere:
    kind = "sphere"

    def __init__(self, name, center, radius, material):
        self.name, self.center, self.radius, self.material = name, center, radius, material


class Plane:
    """The plane X·n = offset (n a unit vector; for `axis` planes, the unit axis)."""
    kind = "plane"

    def __init__(self, name, normal, offset, material):
        self.name, self.normal, self.offset, self.material = name, normal, offset, material


class Triangle:
    kind = "triangle"

    def __init__(self, name, p0, p1, p2, material, normals=None, uvs=None):
        self.name, self.p, self.material = name, (p0, p1, p2), material
        # Smooth shading (lesson 17): unit vertex normals n0, n1, n2, or None (flat).
        self.normals = normals
        # Lesson 18: the corners' texture coordinates t0, t1, t2, or None (the barycentrics).
        self.uvs = uvs


# ---------------------------------------------------------------------------------------------
# Lesson 18: textures.  A checker's square (⌊u·s1⌋, ⌊v·s2⌋) takes its second colour when the
# sum is odd; an image (8-bit RGB PNG, decoded here) is read at x = u·w, y = (1 − v)·h after
# the wrap (repeat keeps the fraction, clamp holds to [0, 1], mirror folds), nearest at
# (⌊x⌋, ⌊y⌋), bilinear from the four texels around (x − ½, y − ½); texels are sRGB, decoded
# to linear light.
# Lesson 19: trilinear images are mip-mapped: each level halves the one below (rounded down, at
# least 1), each texel the mean of the 2 × 2 below it. A ray cone of spread
# γ = atan(2·tan(fov/2)/height) is W = γ·d wide at a hit d along the path from the eye; the
# footprint is L = W·√ρ / |n·d̂| texels (ρ: texels per unit of surface), λ = log₂ L, and levels
# ⌊λ⌋ and ⌊λ⌋ + 1 (held to the pyramid) are read bilinearly and blended by λ − ⌊λ⌋.
# ---------------------------------------------------------------------------------------------

def srgb_to_linear(c):
    c = c / 255.0
    if BUG == "srgb-not-decoded":
        return c  # BUG: the stored sRGB value used as linear
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def read_png(path):
    """An 8-bit RGB or RGBA, non-interlaced PNG's texels, row 0 at the top, as linear RGB."""
    with open(path, "rb") as f:
        data = f.read()
    pos, idat = 8, b""
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h = int.from_bytes(body[0:4], "big"), int.from_bytes(body[4:8], "big")
            channels = {2: 3, 6: 4}[body[9]]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride = zlib.decompress(idat), w * channels
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append([tuple(srgb_to_linear(line[x * channels + k]) for k in range(3))
                     for x in range(w)])
        prev = line
    return w, h, rows


class Texture:
    def __init__(self, d, base):
        if "checker" in d:
            self.kind, self.squares = "checker", d["checker"]
            self.colors = [vec(c) for c in d.get("colors", ((0.9, 0.9, 0.9), (0.15, 0.15, 0.15)))]
        else:
            self.kind = "image"
            self.w, self.h, self.rows = read_png(os.path.join(base, d["image"]))
            self.filter, self.wrap = d.get("filter", "bilinear"), d.get("wrap", "repeat")
            self.levels = [(self.w, self.h, self.rows)]
            while self.filter == "trilinear" and (self.levels[-1][0] > 1 or self.levels[-1][1] > 1):
                w, h, rows = self.levels[-1]
                sx, sy = (2 if w > 1 else 1), (2 if h > 1 else 1)
                nw, nh = max(w // 2, 1), max(h // 2, 1)
                up = [[scale(add_all([rows[j * sy + b][i * sx + a] for b in range(sy)
                                      for a in range(sx)]), 1.0 / (sx * sy))
                       for i in range(nw)] for j in range(nh)]
                self.levels.append((nw, nh, up))

    def wrap_coord(self, t):
        if self.wrap == "repeat":
            return t - math.floor(t)
        if self.wrap == "clamp":
            return min(max(t, 0.0), 1.0)
        m = t - 2 * math.floor(t / 2)
        return 2 - m if m > 1 else m

    def texel(self, i, size):
        if i < 0:
            return size - 1 if self.wrap == "repeat" else 0
        if i > size - 1:
            return 0 if self.wrap == "repeat" else size - 1
        return i

    def at(self, u, v, footprint=None):
        """The colour at (u, v) and the texel read (an image's first texel, a checker's square);
        `footprint`: a trilinear read's L in level-0 texels."""
        if self.kind == "checker":
            i, j = math.floor(u * self.squares[0]), math.floor(v * self.squares[1])
            return self.colors[(i + j) % 2], (i, j)
        u, v = self.wrap_coord(u), self.wrap_coord(v)
        if self.filter == "nearest":
            x, y = u * self.w, (v if BUG == "v-flipped" else 1 - v) * self.h
            i, j = self.texel(math.floor(x), self.w), self.texel(math.floor(y), self.h)
            return self.rows[j][i], (i, j)
        if self.filter != "trilinear" or footprint is None:
            return self.bilinear(0, u, v)
        last = len(self.levels) - 1
        lam = math.log2(footprint) if footprint > 0 else -math.inf
        lam = min(max(lam, 0.0), last) if lam == lam else 0.0
        k, f = math.floor(lam), lam - math.floor(lam)
        if f == 0:
            return self.bilinear(k, u, v)
        (c0, first), (c1, _) = self.bilinear(k, u, v), self.bilinear(k + 1, u, v)
        return add(scale(c0, 1 - f), scale(c1, f)), first

    def bilinear(self, level, u, v):
        """The bilinear colour of `level` at (u, v), and the first of its four texels."""
        w, h, rows = self.levels[level]
        x, y = u * w, (v if BUG == "v-flipped" else 1 - v) * h
        half = 0.0 if BUG == "half-texel" else 0.5  # texel (i, j)'s centre is at (i + ½, j + ½)
        x0, y0 = math.floor(x - half), math.floor(y - half)
        fx, fy = x - half - x0, y - half - y0
        out = BLACK
        for dx, dy, wt in ((0, 0, (1 - fx) * (1 - fy)), (1, 0, fx * (1 - fy)),
                           (0, 1, (1 - fx) * fy), (1, 1, fx * fy)):
            c = rows[self.texel(y0 + dy, h)][self.texel(x0 + dx, w)]
            out = add(out, scale(c, wt))
        return out, (self.texel(x0, w), self.texel(y0, h))

    def per_area(self, obj, outward):
        """ρ: level-0 texels per unit of the surface at the hit."""
        texels = self.w * self.h
        if obj.kind == "triangle":
            p0, p1, p2 = obj.p
            area = length(cross(sub(p1, p0), sub(p2, p0)))
            uv_area = 1.0
            if obj.uvs is not None:
                t0, t1, t2 = obj.uvs
                a, b = sub2(t1, t0), sub2(t2, t0)
                uv_area = abs(a[0] * b[1] - a[1] * b[0])
            return texels * uv_area / area
        if obj.kind == "sphere":
            sin = math.sqrt(outward[0] ** 2 + outward[2] ** 2)
            return texels / (2 * math.pi ** 2 * obj.radius ** 2 * sin) if sin > 0 else math.inf
        return texels


def texture_coords(ray, obj, point, outward):
    """(u, v) of the hit: a triangle's corners' coordinates blended with its barycentrics (or
    the barycentrics), a sphere's longitude and latitude, a plane's own coordinates."""
    if obj.kind == "triangle":
        p0, p1, p2 = obj.p
        e1, e2 = sub(p1, p0), sub(p2, p0)
        mq, tv = neg(ray.direction), sub(ray.origin, p0)
        d0 = det3(mq, e1, e2)
        u, v = det3(mq, tv, e2) / d0, det3(mq, e1, tv) / d0
        if obj.uvs is None:
            return u, v
        t0, t1, t2 = obj.uvs
        return tuple((1 - u - v) * t0[k] + u * t1[k] + v * t2[k] for k in range(2))
    if obj.kind == "sphere":
        d = outward
        return ((math.atan2(-d[2], d[0]) + math.pi) / (2 * math.pi),
                math.atan2(math.sqrt(d[0] ** 2 + d[2] ** 2), -d[1]) / math.pi)
    n = obj.normal
    if n in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)):
        i, j = {0: (1, 2), 1: (0, 2), 2: (0, 1)}[n.index(1.0)]
        return point[i], point[j]
    sgn = 1.0 if n[2] >= 0 else -1.0
    a = -1.0 / (sgn + n[2])
    b = n[0] * n[1] * a
    a1 = (1 + sgn * n[0] * n[0] * a, sgn * b, -sgn * n[0])
    a2 = (b, sgn + n[1] * n[1] * a, -n[1])
    return dot(point, a1), dot(point, a2)


# ---------------------------------------------------------------------------------------------
# Lesson 20: instances.  An instance places a prototype (a mesh, triangle or sphere defined in
# its own object space) in the world by a 3 × 4 matrix M = T·Rz·Ry·Rx·S (scale, then rotate
# x → y → z, then translate) or a given `matrix`.  A ray is carried into object space by M⁻¹ —
# S′ = M⁻¹S as a point (w = 1), Q′ = M⁻¹Q as a vector (w = 0), not renormalised, so t means
# the same point in both spaces — tested there, and the hit carried back: the point by M, the
# normal by the inverse transpose M⁻ᵀ (then normalized), which keeps it perpendicular to the
# carried surface.
# ---------------------------------------------------------------------------------------------

def affine_point(m, p):
    return tuple(r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3] for r in m)


def affine_vector(m, v):
    return tuple(r[0] * v[0] + r[1] * v[1] + r[2] * v[2] for r in m)


def transpose_vector(m, n):
    return tuple(m[0][j] * n[0] + m[1][j] * n[1] + m[2][j] * n[2] for j in range(3))


def affine_inverse(m):
    """M⁻¹ of a 3 × 4 affine matrix: the 3 × 3 part's adjugate over its determinant, and the
    translation −A⁻¹t."""
    a = [row[:3] for row in m]
    cof = [[a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3]
            - a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3] for j in range(3)]
           for i in range(3)]
    det = sum(a[0][j] * cof[0][j] for j in range(3))
    inv = [[cof[j][i] / det for j in range(3)] for i in range(3)]
    t = [row[3] for row in m]
    return tuple(tuple(inv[i]) + (-sum(inv[i][j] * t[j] for j in range(3)),) for i in range(3))


def instance_matrix(d):
    if "matrix" in d:
        return tuple(tuple(float(x) for x in row) for row in d["matrix"][:3])
    sc = d.get("scale", 1.0)
    sc = (float(sc),) * 3 if isinstance(sc, (int, float)) else vec(sc)
    rx, ry, rz = (math.radians(float(a)) for a in d.get("rotate", (0, 0, 0)))
    t = vec(d.get("translate", (0, 0, 0)))

    def matmul(x, y):
        return [[sum(x[i][k] * y[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    c, s_ = math.cos, math.sin
    rot_x = [[1, 0, 0], [0, c(rx), -s_(rx)], [0, s_(rx), c(rx)]]
    rot_y = [[c(ry), 0, s_(ry)], [0, 1, 0], [-s_(ry), 0, c(ry)]]
    rot_z = [[c(rz), -s_(rz), 0], [s_(rz), c(rz), 0], [0, 0, 1]]
    r = matmul(rot_z, matmul(rot_y, rot_x))
    return tuple(tuple(r[i][j] * sc[j] for j in range(3)) + (t[i],) for i in range(3))


class Instance:
    kind = "instance"

    def __init__(self, name, m, prims):
        self.name, self.m, self.prims = name, m, prims
        self.inv = affine_inverse(m)
        self.placed = {}  # prototype primitive → its Placed (one object per pair)
        self.last = None  # the primitive the latest intersect() hit

    def local_ray(self, ray):
        origin = affine_point(self.inv, ray.origin)
        if BUG == "origin-as-vector":
            origin = affine_vector(self.inv, ray.origin)  # BUG: the translation left out
        direction = affine_vector(self.inv, ray.direction)
        if BUG == "renormalized-q":
            direction = normalize(direction)  # BUG: t no longer the world ray's
        return Ray(origin, direction, ray.kind, ray.depth, ray.t_min, ray.t_max,
                   travelled=ray.travelled)

    def place(self, prim):
        return self.placed.setdefault(id(prim), Placed(self, prim))


class Placed:
    """A prototype's primitive where an instance places it (what a ray hits)."""
    kind = "placed"

    def __init__(self, instance, prim):
        self.instance, self.prim = instance, prim
        self.name, self.material = prim.name, prim.material


def intersect_instance(ray, inst):
    local = inst.local_ray(ray)
    emit({"type": "instance", "name": inst.name, "origin": list(local.origin),
          "direction": list(local.direction)})
    best, best_t = None, None
    for prim in inst.prims:
        t = intersect(local, prim)
        if t is not None and (best_t is None or t < best_t):
            best, best_t = prim, t
    inst.last = best
    return best_t


def placed_surface(ray, obj, t, scene):
    """The surface of an instance's primitive: found in object space, carried back."""
    inst = obj.instance
    s = surface_at(inst.local_ray(ray), obj.prim, t, scene)

    def carry(n):
        if BUG == "normal-by-m":
            return normalize(affine_vector(inst.m, n))  # BUG: M instead of M⁻ᵀ
        return normalize(transpose_vector(inst.inv, n))
    s.obj = obj
    s.point = affine_point(inst.m, s.point)
    # (M⁻ᵀn)·(M·Q′) = n·Q′: the carried normal still faces the ray.
    s.normal = carry(s.normal)
    s.shading = carry(s.shading)
    if "normal" in s.record:
        s.record["normal"] = list(s.shading)
    s.eye = normalize(neg(ray.direction))
    s.distance = ray.travelled + t * length(ray.direction)
    return s


class Light:
    def __init__(self, name, position, color):
        self.name, self.position, self.color = name, position, color


class Scene:
    pass


def vec(v):
    return (float(v[0]), float(v[1]), float(v[2]))


def load_obj(path, translate, k, shading=None):
    """The triangles of an OBJ file (faces fanned into triangles), scaled by k then moved, each
    with its vertex normals for smooth shading (lesson 17) or None: the file's `vn` where every
    face has them (unless shading = "flat"); with shading = "smooth" and no `vn`, the sum of the
    cross products E1 × E2 of the faces around each vertex, normalized."""
    vertices, normals, faces = [], [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                vertices.append(add(scale(vec(words[1:4]), k), translate))
            elif words[0] == "vn":
                normals.append(normalize(vec(words[1:4])))
            elif words[0] == "f":
                idx = []
                for w in words[1:]:
                    parts = w.split("/")
                    i = int(parts[0])
                    n = int(parts[2]) if len(parts) == 3 and parts[2] else None
                    idx.append((i - 1 if i > 0 else len(vertices) + i,
                                None if n is None else (n - 1 if n > 0 else len(normals) + n)))
                for j in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[j], idx[j + 1]))
    with_vn = all(c[1] is not None for f in faces for c in f)
    sums = {}
    if shading == "smooth" and not with_vn:
        for f in faces:
            p0, p1, p2 = (vertices[c[0]] for c in f)
            c = cross(sub(p1, p0), sub(p2, p0))
            for corner in f:
                sums[corner[0]] = add(sums.get(corner[0], (0.0, 0.0, 0.0)), c)
    triangles = []
    for f in faces:
        p = tuple(vertices[c[0]] for c in f)
        if shading == "flat":
            n = None
        elif with_vn:
            n = tuple(normals[c[1]] for c in f)
        elif shading == "smooth":
            n = tuple(normalize(sums[c[0]]) for c in f)
        else:
            n = None
        triangles.append((p, n))
    return triangles


def object_order(text, counts):
    """The kinds of the scene's objects in file order ([[sphere]], [[plane]], … interleaved):
    raystep numbers and tests objects in the order they appear in the file."""
    kinds = re.findall(r"(?m)^\s*\[\[\s*(sphere|plane|triangle|mesh)\s*\]\]", text)
    if all(kinds.count(k) == counts[k] for k in counts):
        return kinds
    # Tables written some other way: kind by kind.
    return [k for k in ("sphere", "plane", "triangle", "mesh") for _ in range(counts[k])]


def load_scene(path):
    with open(path, "rb") as f:
        raw = f.read()
    doc = tomllib.loads(raw.decode("utf-8"))
    scene = Scene()

    cam = doc.get("camera", {})
    scene.eye = vec(cam.get("from", (0, 0, -5)))
    scene.look_at = vec(cam.get("at", (0, 0, 0)))
    scene.up = vec(cam.get("up", (0, 1, 0)))
    scene.fov = float(cam.get("fov", 60.0))
    scene.width = int(cam.get("width", 320))
    scene.height = int(cam.get("height", 240))

    render = doc.get("render", {})
    scene.max_depth = int(render.get("max_depth", 5))
    scene.spp = int(render.get("spp", 1))
    scene.seed = int(render.get("seed", 0))
    scene.background = vec(render.get("background", (0, 0, 0)))

    scene.lights = []
    for i, d in enumerate(doc.get("light", [])):
        scene.lights.append(Light(d.get("name", f"light {i}"),
                                  vec(d.get("position", (-10, 10, -10))),
                                  vec(d.get("color", (1, 1, 1)))))

    textures = {d.get("name", f"texture {i}"): Texture(d, os.path.dirname(path))
                for i, d in enumerate(doc.get("texture", []))}
    materials = {}
    for i, d in enumerate(doc.get("material", [])):
        m = Material(d)
        m.name = d.get("name", f"material {i}")
        m.texture = textures[d["texture"]] if "texture" in d else None
        materials[m.name] = m
    default = Material()

    def material(d):
        return materials[d["material"]] if "material" in d else default

    tables = {k: doc.get(k, []) for k in ("sphere", "plane", "triangle", "mesh")}
    seen = {k: 0 for k in tables}
    scene.objects = []
    for kind in object_order(raw.decode("utf-8"), {k: len(v) for k, v in tables.items()}):
        i = seen[kind]
        seen[kind] += 1
        d = tables[kind][i]
        name = d.get("name", f"{kind} {i}")
        if kind == "sphere":
            scene.objects.append(Sphere(name, vec(d.get("center", (0, 0, 0))),
                                        float(d.get("radius", 1.0)), material(d)))
        elif kind == "plane":
            if "axis" in d:
                normal = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}[d["axis"]]
                offset = float(d.get("offset", 0.0))
            else:
                normal = normalize(vec(d.get("normal", (0, 1, 0))))
                offset = dot(vec(d.get("point", (0, 0, 0))), normal)
            scene.objects.append(Plane(name, normal, offset, material(d)))
        elif kind == "triangle":
            p = [vec(v) for v in d["vertices"]]
            n = tuple(normalize(vec(v)) for v in d["normals"]) if "normals" in d else None
            uvs = tuple(tuple(float(c) for c in t) for t in d["uvs"]) if "uvs" in d else None
            scene.objects.append(Triangle(name, p[0], p[1], p[2], material(d), n, uvs))
        else:
            obj = os.path.join(os.path.dirname(path), d["obj"])
            tris = load_obj(obj, vec(d.get("translate", (0, 0, 0))), float(d.get("scale", 1.0)),
                            d.get("shading"))
            # A mesh's triangles are named after the mesh: `icosahedron[5]` (one triangle: no index).
            for k, ((p0, p1, p2), n) in enumerate(tris):
                tname = name if len(tris) == 1 else f"{name}[{k}]"
                scene.objects.append(Triangle(tname, p0, p1, p2, material(d), n))
                scene.objects[-1].mesh = name
    # Lesson 20: an object an instance names is a prototype, drawn only where instances place
    # it; the instances are tested after the world's objects.
    instances = []
    for i, d in enumerate(doc.get("instance", [])):
        of = d["of"]
        prims = [o for o in scene.objects if getattr(o, "mesh", o.name) == of]
        instances.append(Instance(d.get("name", f"instance {i}"), instance_matrix(d), prims))
    protos = {id(o) for inst in instances for o in inst.prims}
    scene.objects = [o for o in scene.objects if id(o) not in protos] + instances
    return scene


# ---------------------------------------------------------------------------------------------
# Printing the trace (JSON Lines).
# ---------------------------------------------------------------------------------------------

def emit(record):
    print(json.dumps(record))


class Ray:
    """P(t) = S + t·Q for t in (t_min, t_max)."""

    def __init__(self, origin, direction, kind, depth, t_min=0.0, t_max=math.inf, light=None,
                 travelled=0.0):
        self.origin, self.direction = origin, direction
        self.kind, self.depth = kind, depth
        # The path's length from the eye to the origin (lesson 19's ray cone).
        self.travelled = travelled
        self.t_min, self.t_max = t_min, t_max
        self.light = light

    def at(self, t):
        return add(self.origin, scale(self.direction, t))

    def print(self):
        r = {"type": "ray", "kind": self.kind, "depth": self.depth,
             "origin": list(self.origin), "direction": list(self.direction)}
        if self.light is not None:
            r["light"] = self.light
        emit(r)


# ---------------------------------------------------------------------------------------------
# Lesson 1: the camera (Ray Tracing in One Weekend's basis).
# ---------------------------------------------------------------------------------------------

def pcg_hash(v):
    """PCG hash (Jarzynski & Olano 2020), 32-bit: raystep's jitter for spp > 1."""
    state = (v * 747796405 + 2891336453) & 0xFFFFFFFF
    word = (((state >> ((state >> 28) + 4)) ^ state) * 277803737) & 0xFFFFFFFF
    return (word >> 22) ^ word


def sample_offset(scene, x, y, sample=0):
    """Where in pixel (x, y) the sample lies: its centre (0.5, 0.5) with one sample per pixel;
    otherwise a jittered cell of a ⌈√spp⌉-column grid (lesson 10), each row as tall as its
    cells' share when the last row is short."""
    if scene.spp <= 1:
        return (0.5, 0.5)
    cols = math.ceil(math.sqrt(scene.spp))
    rows = -(-scene.spp // cols)
    cx, cy = sample % cols, sample // cols
    h1 = pcg_hash(x ^ pcg_hash(y ^ pcg_hash(sample ^ pcg_hash(scene.seed))))
    h2 = pcg_hash(h1)
    u1, u2 = (h1 >> 8) / 16777216.0, (h2 >> 8) / 16777216.0
    if cols * rows == scene.spp:
        return ((cx + u1) / cols, (cy + u2) / rows)
    width = scene.spp - cols * (rows - 1) if cy + 1 >= rows else cols
    return ((cx + u1) / width, (cy * cols + u2 * width) / scene.spp)


def camera_ray(scene, x, y):
    """The primary ray through pixel (x, y).

    w = normalize(from − at), u = normalize(up × w), v = w × u;
    sx = 2(x + ox)/width − 1, sy = 1 − 2(y + oy)/height (rows count down from the top);
    Q = normalize(sx·tan(fov/2)·(width/height)·u + sy·tan(fov/2)·v − w).
    """
    w = normalize(sub(scene.eye, scene.look_at))
    u = normalize(cross(scene.up, w))
    v = cross(w, u)
    half_h = math.tan(math.radians(scene.fov) / 2)
    half_w = half_h * scene.width / scene.height
    ox, oy = sample_offset(scene, x, y)
    sx = 2 * (x + ox) / scene.width - 1
    sy = 1 - 2 * (y + oy) / scene.height
    q = sub(add(scale(u, sx * half_w), scale(v, sy * half_h)), w)
    return Ray(scene.eye, normalize(q), "primary", 0)


# ---------------------------------------------------------------------------------------------
# Lesson 2: ray–sphere.  |S + tQ − G|² = r²  ⇔  a t² + b t + c = 0 with f = S − G,
# a = Q·Q, b = 2 f·Q, c = f·f − r², discriminant b² − 4ac, t = (−b ± √(b² − 4ac)) / 2a.
# ---------------------------------------------------------------------------------------------

def intersect_sphere(ray, s):
    f = sub(ray.origin, s.center)
    a = dot(ray.direction, ray.direction)
    b = 2 * dot(f, ray.direction)
    if BUG == "half-b":
        b = dot(f, ray.direction)  # BUG: the factor 2 is missing
    c = dot(f, f) - s.radius * s.radius
    disc = b * b - 4 * a * c
    t = None
    if disc >= 0:
        root = math.sqrt(disc)
        for cand in ((-b - root) / (2 * a), (-b + root) / (2 * a)):
            if cand > ray.t_min:  # the nearest root in front of the origin
                t = cand
                break
    emit({"type": "sphere", "object": s.name, "a": a, "b": b, "c": c,
          "discriminant": disc, "t": t})
    return t


# ---------------------------------------------------------------------------------------------
# Lesson 3: ray–plane.  (S + tQ)·n = offset  ⇒  t = (offset − S·n) / (Q·n); Q·n = 0: parallel.
# ---------------------------------------------------------------------------------------------

def intersect_plane(ray, p):
    denom = dot(ray.direction, p.normal)
    t = None
    if denom != 0:
        cand = (p.offset - dot(ray.origin, p.normal)) / denom
        if cand > ray.t_min:
            t = cand
    emit({"type": "plane", "object": p.name, "denominator": denom, "t": t})
    return t


# ---------------------------------------------------------------------------------------------
# Lesson 4: ray–triangle, Möller–Trumbore.  S + tQ = (1 − u − v)P0 + u·P1 + v·P2, i.e.
# [−Q, E1, E2]·(t, u, v) = S − P0 with E1 = P1 − P0, E2 = P2 − P0, solved by Cramer's rule:
# D0 = det(−Q, E1, E2), t = det(T, E1, E2)/D0, u = det(−Q, T, E2)/D0, v = det(−Q, E1, T)/D0,
# with T = S − P0 and det(a, b, c) = a·(b × c).  A hit: t > t_min, u ≥ 0, v ≥ 0, u + v ≤ 1.
# ---------------------------------------------------------------------------------------------

def det3(a, b, c):
    return dot(a, cross(b, c))


def intersect_triangle(ray, tri):
    p0, p1, p2 = tri.p
    e1, e2 = sub(p1, p0), sub(p2, p0)
    mq = neg(ray.direction)
    d0 = det3(mq, e1, e2)
    rec = {"type": "triangle", "object": tri.name, "det": d0}
    t = None
    if d0 != 0:
        tv = sub(ray.origin, p0)
        cand = det3(tv, e1, e2) / d0
        u = det3(mq, tv, e2) / d0
        v = det3(mq, e1, tv) / d0
        rec["u"], rec["v"] = u, v
        if cand > ray.t_min and u >= 0 and v >= 0 and u + v <= 1:
            t = cand
    rec["t"] = t
    emit(rec)
    return t


def intersect(ray, obj):
    if obj.kind == "instance":
        return intersect_instance(ray, obj)
    if obj.kind == "sphere":
        return intersect_sphere(ray, obj)
    if obj.kind == "plane":
        return intersect_plane(ray, obj)
    return intersect_triangle(ray, obj)


# ---------------------------------------------------------------------------------------------
# Lesson 5: the naive loop — test every object, keep the smallest t in (t_min, t_max).
# ---------------------------------------------------------------------------------------------

def closest_hit(scene, ray):
    best, best_t = None, ray.t_max
    for obj in scene.objects:
        t = intersect(ray, obj)
        if t is not None and t < best_t:  # ties go to the object listed first
            best, best_t = (obj.place(obj.last) if obj.kind == "instance" else obj), t
    return best, best_t


def any_hit(scene, ray):
    """Whether anything lies on the ray in (t_min, t_max) (shadow rays need no more)."""
    blocked = False
    for obj in scene.objects:
        t = intersect(ray, obj)
        if t is not None and t < ray.t_max:
            blocked = True
    return blocked


class Surface:
    """Where a ray met an object: point P, unit normal n facing the ray, unit eye vector e."""


def surface_at(ray, obj, t, scene=None):
    if obj.kind == "placed":
        return placed_surface(ray, obj, t, scene)
    s = Surface()
    s.obj = obj
    s.point = ray.at(t)  # P = S + t·Q
    s.distance = ray.travelled + t * length(ray.direction)
    if obj.kind == "sphere":
        outward = sub(s.point, obj.center)
        if BUG != "unnormalized-normal":
            outward = scale(outward, 1.0 / obj.radius)  # n = (P − G)/r
    elif obj.kind == "plane":
        outward = obj.normal
    else:
        p0, p1, p2 = obj.p
        outward = normalize(cross(sub(p1, p0), sub(p2, p0)))  # n = E1 × E2, normalized
    s.eye = normalize(neg(ray.direction))
    # Flip the normal when the ray meets the surface from behind (Q·n > 0).
    s.inside = dot(outward, s.eye) < 0
    s.normal = neg(outward) if s.inside else outward
    # Lesson 17: a smooth triangle is lit with its vertex normals blended at the hit's u, v,
    # (1 − u − v)·n0 + u·n1 + v·n2 normalized, on the side of the (flipped) normal. Sides and
    # spawned rays keep the flat normal.
    # Lesson 18: the surface's colour, the material's times its texture's at (u, v).
    s.color = obj.material.color
    s.record = {}  # the `surface` record: what the surface gives shading here
    if obj.material.texture is not None:
        u, v = texture_coords(ray, obj, s.point, outward)
        tex, footprint = obj.material.texture, None
        if getattr(tex, "filter", None) == "trilinear" and scene is not None:
            # Lesson 19: the ray cone's footprint in texels.
            spread = math.atan(2 * math.tan(math.radians(scene.fov) / 2) / scene.height)
            cos = abs(dot(outward, normalize(ray.direction)))
            rho = tex.per_area(obj, outward)
            footprint = spread * s.distance * math.sqrt(rho) / cos if cos > 0 else math.inf
        texture, texel = tex.at(u, v, footprint)
        s.color = mul(s.color, texture)
        s.record.update(uv=[u, v], texel=list(texel), texture=list(texture))
    s.shading = s.normal
    if obj.kind == "triangle" and obj.normals is not None:
        p0, p1, p2 = obj.p
        e1, e2 = sub(p1, p0), sub(p2, p0)
        mq, tv = neg(ray.direction), sub(ray.origin, p0)
        d0 = det3(mq, e1, e2)
        u, v = det3(mq, tv, e2) / d0, det3(mq, e1, tv) / d0
        n0, n1, n2 = obj.normals
        if BUG == "normal-weights":
            blend = add(add(scale(n0, u), scale(n1, v)), scale(n2, 1 - u - v))  # BUG: weights
        else:
            blend = add(add(scale(n0, 1 - u - v), scale(n1, u)), scale(n2, v))
        if dot(blend, blend) > 0:
            ns = normalize(blend)
            s.shading = neg(ns) if dot(ns, s.normal) < 0 else ns
        s.record["normal"] = list(s.shading)
    return s


def spawn_origin(s, direction):
    """Where a ray leaving the surface starts: the hit point moved EPSILON along the normal, to
    the side the new ray leaves on (outside for reflection, inside for refraction)."""
    side = 1.0 if dot(direction, s.normal) >= 0 else -1.0
    return add(s.point, scale(s.normal, EPSILON * side))


# ---------------------------------------------------------------------------------------------
# Lesson 7: shadows.  A shadow ray from the hit point towards the light: Q = L − S, so the light
# is at t = 1; anything hit for t in (0, 1 − ε) blocks it.  Lights behind the surface
# ((L − P)·n ≤ 0) light only the ambient term: no shadow ray.
# ---------------------------------------------------------------------------------------------

def light_blocked(scene, s, light, depth):
    to_light = sub(light.position, s.point)
    if dot(to_light, s.shading) <= 0:
        return False  # the light is behind the surface
    if BUG == "no-shadow-offset":
        origin = s.point  # BUG: starts exactly on the surface (and t_min = 0)
    else:
        origin = spawn_origin(s, to_light)
    shadow = Ray(origin, sub(light.position, origin), "shadow", depth + 1,
                 t_min=0.0, t_max=1.0 - SHADOW_EPSILON, light=light.name)
    shadow.print()
    return any_hit(scene, shadow)


# ---------------------------------------------------------------------------------------------
# Lesson 8: reflection.  The mirror direction of d about the unit normal n (used for mirror
# rays, weighted by the material's `reflective`, and for Phong's highlight).
# ---------------------------------------------------------------------------------------------

def reflect(v, n):
    """Mirror v about the unit normal n: v − 2(v·n)n."""
    if BUG == "reflect-sign":
        return add(v, scale(n, 2 * dot(v, n)))  # BUG: wrong sign
    return sub(v, scale(n, 2 * dot(v, n)))


# ---------------------------------------------------------------------------------------------
# Phong shading (The Ray Tracer Challenge, ch. 6), summed over the lights.
# ---------------------------------------------------------------------------------------------


def phong(m, light, s, in_shadow):
    """ambient + diffuse + specular from one light:
    ambient = c·I·k_a; diffuse = c·I·k_d·(l·n) when l·n ≥ 0;
    specular = I·k_s·(r·e)^shininess when r·e > 0, with r = reflect(−l, n);
    in shadow, ambient only."""
    effective = mul(s.color, light.color)
    l = normalize(sub(light.position, s.point))
    color = scale(effective, m.ambient)
    l_dot_n = dot(l, s.shading)
    if not in_shadow and l_dot_n >= 0:
        color = add(color, scale(effective, m.diffuse * l_dot_n))
        r_dot_e = dot(reflect(neg(l), s.shading), s.eye)
        if r_dot_e > 0:
            color = add(color, scale(light.color, m.specular * r_dot_e ** m.shininess))
    return color


# ---------------------------------------------------------------------------------------------
# Lesson 9: refraction.  Snell: η = n1/n2, cos θi = e·n, sin² θt = η²(1 − cos² θi); total
# internal reflection when sin² θt > 1; otherwise cos θt = √(1 − sin² θt) and
# t = n(η cos θi − cos θt) − η e.  Fresnel by Schlick: R0 = ((n1 − n2)/(n1 + n2))²,
# R = R0 + (1 − R0)(1 − cos)^5 with cos = cos θi, or cos θt when n1 > n2 (1 under TIR).
# ---------------------------------------------------------------------------------------------

def refract(eye, n, n1, n2):
    eta = n1 / n2
    if BUG == "snell-inverted":
        eta = n2 / n1  # BUG: the ratio upside down
    cos_i = dot(eye, n)
    sin2_t = eta * eta * (1 - cos_i * cos_i)
    if sin2_t > 1:
        return None  # total internal reflection
    cos_t = math.sqrt(1 - sin2_t)
    return sub(scale(n, eta * cos_i - cos_t), scale(eye, eta))


def schlick(cos_i, n1, n2):
    cos = cos_i
    if n1 > n2:
        ratio = n1 / n2
        sin2_t = ratio * ratio * (1 - cos * cos)
        if sin2_t > 1:
            return 1.0
        cos = math.sqrt(1 - sin2_t)
    r0 = ((n1 - n2) / (n1 + n2)) ** 2
    return r0 + (1 - r0) * (1 - cos) ** 5


class Media:
    """The transparent objects the ray is inside, innermost last, with their indices
    (The Ray Tracer Challenge's `containers`), carried down the recursion."""

    def __init__(self, stack=()):
        self.stack = tuple(stack)  # ((object, index), ...)

    def top(self, stack=None):
        stack = self.stack if stack is None else stack
        return stack[-1][1] if stack else 1.0  # air outside everything

    def indices(self, obj, ior):
        """(n1, n2) for crossing obj's surface: leaving it if we are inside it."""
        n1 = self.top()
        if any(o is obj for o, _ in self.stack):
            return n1, self.top(tuple(e for e in self.stack if e[0] is not obj))
        return n1, ior

    def crossed(self, obj, ior):
        if any(o is obj for o, _ in self.stack):
            return Media(e for e in self.stack if e[0] is not obj)
        return Media(self.stack + ((obj, ior),))


# ---------------------------------------------------------------------------------------------
# The recursive Whitted tracer.
# ---------------------------------------------------------------------------------------------

def trace(scene, ray, throughput=1.0, media=None):
    """Traces `ray`, printing its records, and returns the colour it brings back.
    `throughput`: what this colour is multiplied by on its way to the pixel; `media`: the
    transparent objects the ray travels inside (none for a primary ray)."""
    media = media or Media()
    ray.print()
    d = ray.depth
    obj, t = closest_hit(scene, ray)
    if obj is None:
        emit({"type": "hit", "object": None, "depth": d})
        emit({"type": "color", "rgb": list(scene.background), "depth": d})
        return scene.background
    s = surface_at(ray, obj, t, scene)
    hit = {"type": "hit", "object": obj.name, "t": t, "point": list(s.point),
           "normal": list(s.normal), "depth": d}
    if obj.kind == "placed":
        hit["instance"] = obj.instance.name  # the object is its prototype's primitive
    emit(hit)
    if s.record:
        # Lessons 17–19: the shading normal, and the texture's coordinates, texel and colour.
        emit({"type": "surface", **s.record, "depth": d})
    m = obj.material

    # Direct light: Phong from each light (ambient only when its shadow ray is blocked).
    if not scene.lights:
        surface = scale(s.color, m.ambient)  # no lights: show the ambient colour
    else:
        surface = BLACK
        for light in scene.lights:
            blocked = light_blocked(scene, s, light, d)
            emit({"type": "shadow", "light": light.name, "blocked": blocked, "depth": d})
            surface = add(surface, phong(m, light, s, blocked))

    can_recurse = d < scene.max_depth  # the primary ray has depth 0
    transparent = m.transparency > 0
    # A surface both reflective and transparent blends the two by Schlick's reflectance R:
    # colour = surface + R·reflected + (1 − R)·refracted.  (Computed first: the reflection's
    # share of the pixel depends on it.)
    blend = transparent and m.reflective > 0
    n1 = n2 = None
    if transparent:
        n1, n2 = media.indices(obj, m.refractive_index)  # from the side the ray comes from
    reflectance = schlick(dot(s.eye, s.shading), n1, n2) if blend else 1.0

    # Lesson 8: reflection, r = d − 2(d·n)n, weighted by `reflective` (not traced past max_depth
    # or when its share of the pixel is below the cut-off).
    reflected = BLACK
    if m.reflective > 0 and can_recurse:
        direction = reflect(ray.direction, s.shading)
        share = m.reflective * reflectance if blend else m.reflective
        if throughput * share >= WEIGHT_CUTOFF:
            child = Ray(spawn_origin(s, direction), direction, "reflection", d + 1,
                        travelled=s.distance)
            reflected = scale(trace(scene, child, throughput * share, media), m.reflective)

    # Lesson 9: refraction, weighted by `transparency`.
    refracted = BLACK
    if transparent and can_recurse:
        direction = refract(s.eye, s.shading, n1, n2)
        share = m.transparency * (1 - reflectance) if blend else m.transparency
        if direction is not None and throughput * share >= WEIGHT_CUTOFF:
            child = Ray(spawn_origin(s, direction), direction, "refraction", d + 1,
                        travelled=s.distance)
            inner = media.crossed(obj, m.refractive_index)
            refracted = scale(trace(scene, child, throughput * share, inner), m.transparency)

    if blend:
        color = add(surface, add(scale(reflected, reflectance), scale(refracted, 1 - reflectance)))
    else:
        color = add(surface, add(reflected, refracted))
    # A recursive tracer prints a ray's colour after its children's: name the depth.
    emit({"type": "color", "rgb": list(color), "depth": d})
    return color


def integrator_of(path):
    """The scene's `[render] integrator` (a path-traced scene goes to path_tracer.py)."""
    try:
        with open(path, "rb") as f:
            return tomllib.load(f).get("render", {}).get("integrator", "whitted")
    except (OSError, tomllib.TOMLDecodeError):
        return "whitted"


def main(argv=None):
    global BUG, EPSILON
    args_in = sys.argv[1:] if argv is None else argv
    if args_in and integrator_of(args_in[0]) == "path":
        import path_tracer
        return path_tracer.main(args_in)
    ap = argparse.ArgumentParser(description="A model student's Whitted ray tracer: prints the "
                                 "trace of one pixel in raystep's student trace format.")
    ap.add_argument("scene")
    ap.add_argument("x", type=int)
    ap.add_argument("y", type=int)
    ap.add_argument("--bug", choices=BUGS, default=None, help="make one classic mistake")
    ap.add_argument("--epsilon", type=float, default=EPSILON,
                    help=f"how far spawned rays start off the surface (default {EPSILON})")
    args = ap.parse_args(argv)
    BUG = args.bug
    EPSILON = args.epsilon
    sys.setrecursionlimit(10000)
    scene = load_scene(args.scene)
    emit({"type": "format", "version": 1})
    emit({"type": "pixel", "x": args.x, "y": args.y})
    trace(scene, camera_ray(scene, args.x, args.y))


if __name__ == "__main__":
    try:
        main()
    except BrokenPipeError:  # piped into `head`: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(1)
