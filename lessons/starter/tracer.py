#!/usr/bin/env python3
"""A starter ray tracer for raystep's lessons: yours to finish.

    python3 tracer.py SCENE.toml X Y

reads a raystep scene file and prints what it computes for pixel (X, Y) in raystep's student
trace format (JSON Lines, see README.md next to this file), so that

    raystep grade-tracer --scene SCENE.toml --pixels "X,Y" --run "python3 tracer.py {scene} {x} {y}"

checks it step by step against raystep's own trace. The camera (lesson 1) is done: grade it with
`--upto camera`. Each TODO below is one lesson; after each, raise `--upto`.

Standard library only (Python 3.11+: `tomllib` reads the scene).
"""

import json
import math
import sys
import tomllib


# --- small vector helpers --------------------------------------------------------------------

def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def mul(a, k):
    return [a[0] * k, a[1] * k, a[2] * k]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normalize(a):
    length = math.sqrt(dot(a, a))
    return mul(a, 1.0 / length)


# --- raystep's random numbers (Monte Carlo lessons 13-16) -----------------------------------


def pcg_hash(x):
    """The PCG hash (Jarzynski and Olano 2020) of a 32-bit unsigned integer."""
    state = (x * 747796405 + 2891336453) & 0xFFFFFFFF
    word = (((state >> ((state >> 28) + 4)) ^ state) * 277803737) & 0xFFFFFFFF
    return ((word >> 22) ^ word) & 0xFFFFFFFF


def uniform(pixel, sample, dimension, seed=0):
    """raystep's random number `dimension` of sample `sample` of pixel (x, y): in [0, 1), the
    top 24 bits of a chain of PCG hashes over seed, sample, y, x and dimension. A path tracer
    that draws its numbers here draws the very numbers raystep's trace records (`u[16] = ...`):
    the lens takes dimensions 2 and 3, bounce b the block from 16 + 1024 b (slot 0 picks the
    light, 1-2 the point on it, 3 glass's lobe, 4-5 the BSDF's direction, 6 Russian roulette)."""
    x, y = pixel
    h = pcg_hash(dimension ^ pcg_hash(x ^ pcg_hash(y ^ pcg_hash(sample ^ pcg_hash(seed)))))
    return (h >> 8) / 16777216.0


def emit(record):
    """Prints one record of the student trace format."""
    print(json.dumps(record))


# --- lesson 1: the camera ----------------------------------------------------------------------

def camera_ray(camera, x, y):
    """The primary ray through the centre of pixel (x, y): (origin S, unit direction Q).

    The basis of Ray Tracing in One Weekend: w = normalize(from - at), u = normalize(up x w),
    v = w x u; screen coordinates sx = 2(x + 0.5)/width - 1, sy = 1 - 2(y + 0.5)/height (y counts
    from the top); Q = normalize(sx * half_width * u + sy * half_height * v - w) with
    half_height = tan(fov / 2) and half_width = half_height * width / height.
    """
    eye = camera.get("from", [0.0, 0.0, -5.0])
    at = camera.get("at", [0.0, 0.0, 0.0])
    up = camera.get("up", [0.0, 1.0, 0.0])
    fov = camera.get("fov", 60.0)
    width = camera.get("width", 320)
    height = camera.get("height", 240)
    w = normalize(sub(eye, at))
    u = normalize(cross(up, w))
    v = cross(w, u)
    half_height = math.tan(math.radians(fov) / 2.0)
    half_width = half_height * width / height
    sx = 2.0 * (x + 0.5) / width - 1.0
    sy = 1.0 - 2.0 * (y + 0.5) / height
    direction = normalize(sub(add(mul(u, sx * half_width), mul(v, sy * half_height)), w))
    return eye, direction


# --- the lessons still to do -------------------------------------------------------------------

def intersect_sphere(sphere, origin, direction):
    """Lesson 2. TODO: f = S - G, a = Q.Q, b = 2 f.Q, c = f.f - r^2, discriminant b^2 - 4ac;
    t = the nearest root in front of the origin, or None. Print
    {"type":"sphere","object":name,"a":..,"b":..,"c":..,"discriminant":..,"t":..} and return t."""
    return None


def intersect_plane(plane, origin, direction):
    """Lesson 3. TODO: denominator Q.n, t = (offset - S.n) / (Q.n); print a "plane" record."""
    return None


def intersect_triangle(triangle, origin, direction):
    """Lesson 4. TODO: Moller-Trumbore, D0 = det(-Q, E1, E2), u, v, t; print a "triangle"
    record (a mesh's triangles come from its OBJ file: see "The scene file" in README.md next to
    this file)."""
    return None


def closest_hit(tested, origin, direction):
    """Lesson 5. TODO: `tested` is every test trace() ran, as (t or None, kind, object) with kind
    "sphere", "plane" or "triangle": keep the nearest t; print
    {"type":"hit","object":name or None,"t":..,"point":..,"normal":..} (the unit normal facing
    the ray) and return what shade() needs (or None for a miss)."""
    return None


def shade(scene, hit, origin, direction, depth):
    """Lessons 7 to 9. TODO: Phong with a shadow ray per light ("ray" of kind "shadow", then
    {"type":"shadow","light":name,"blocked":..,"depth":depth}), reflection and refraction rays
    (kind "reflection" / "refraction", depth + 1), and finally
    {"type":"color","rgb":[r,g,b],"depth":depth}."""
    return [0.0, 0.0, 0.0]


def trace(scene, origin, direction, kind, depth):
    """One ray: print it, test every object (each test printed once), find the closest hit
    among those tests, shade it."""
    emit({"type": "ray", "kind": kind, "depth": depth, "origin": origin, "direction": direction})
    tested = []
    for sphere in scene.get("sphere", []):
        tested.append((intersect_sphere(sphere, origin, direction), "sphere", sphere))
    for plane in scene.get("plane", []):
        tested.append((intersect_plane(plane, origin, direction), "plane", plane))
    for triangle in scene.get("triangle", []):
        tested.append((intersect_triangle(triangle, origin, direction), "triangle", triangle))
    hit = closest_hit(tested, origin, direction)
    return shade(scene, hit, origin, direction, depth)


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: tracer.py SCENE.toml X Y")
    with open(sys.argv[1], "rb") as f:
        scene = tomllib.load(f)
    x, y = int(sys.argv[2]), int(sys.argv[3])
    emit({"type": "format", "version": 1})
    emit({"type": "pixel", "x": x, "y": y})
    origin, direction = camera_ray(scene.get("camera", {}), x, y)
    trace(scene, origin, direction, "primary", 0)


if __name__ == "__main__":
    main()
