#!/usr/bin/env python3
"""The starter kit (lessons/starter/tracer.py) with the TODOs a path tracer needs filled in:
the ray-object tests of lessons 2 to 4 and the path-tracing pieces of lessons 14 to 16. It
imports the kit unchanged, sets each TODO function to a solution and runs the kit's main(), so
a test can check that the kit's path tracer, once completed, gets full marks.

    python3 starter_completed.py SCENE.toml X Y
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "lessons", "starter"))
import tracer as kit  # noqa: E402

sub, add, mul, dot, cross, normalize = kit.sub, kit.add, kit.mul, kit.dot, kit.cross, kit.normalize


def intersect_sphere(sphere, origin, direction):
    f = sub(origin, sphere.get("center", [0.0, 0.0, 0.0]))
    r = sphere.get("radius", 1.0)
    a, b, c = dot(direction, direction), 2.0 * dot(f, direction), dot(f, f) - r * r
    disc = b * b - 4.0 * a * c
    t = None
    if disc >= 0:
        for root in ((-b - math.sqrt(disc)) / (2 * a), (-b + math.sqrt(disc)) / (2 * a)):
            if root > 0:
                t = root
                break
    kit.emit({"type": "sphere", "object": sphere.get("name"), "a": a, "b": b, "c": c,
              "discriminant": disc, "t": t})
    return t


def intersect_plane(plane, origin, direction):
    if "axis" in plane:
        n = {"x": [1.0, 0.0, 0.0], "y": [0.0, 1.0, 0.0], "z": [0.0, 0.0, 1.0]}[plane["axis"]]
        offset = plane.get("offset", 0.0)
    else:
        n = normalize(plane.get("normal", [0.0, 1.0, 0.0]))
        offset = dot(plane.get("point", [0.0, 0.0, 0.0]), n)
    den = dot(direction, n)
    t = None
    if den != 0:
        t = (offset - dot(origin, n)) / den
        if t <= 0:
            t = None
    kit.emit({"type": "plane", "object": plane.get("name"), "denominator": den, "t": t})
    return t


def intersect_triangle(triangle, origin, direction):
    p0, p1, p2 = triangle["vertices"]
    e1, e2 = sub(p1, p0), sub(p2, p0)
    nq = mul(direction, -1.0)

    def det(a, b, c):
        return dot(a, cross(b, c))

    d0 = det(nq, e1, e2)
    t = None
    if d0 != 0:
        tv = sub(origin, p0)
        tt, u, v = det(tv, e1, e2) / d0, det(nq, tv, e2) / d0, det(nq, e1, tv) / d0
        if tt > 0 and u >= 0 and v >= 0 and u + v <= 1:
            t = tt
    kit.emit({"type": "triangle", "object": triangle.get("name"), "det": d0, "t": t})
    return t


def cosine_hemisphere(u0, u1):
    x, y = kit.concentric_disk(u0, u1)
    z = math.sqrt(max(0.0, 1.0 - x * x - y * y))
    return [x, y, z], z / math.pi


def pick_light(lights, u):
    total = sum(light["power"] for light in lights)
    target, run = u * total, 0.0
    for light in lights:
        run += light["power"]
        if run > target:
            return light, light["power"] / total
    return lights[-1], lights[-1]["power"] / total


def sample_triangle_light(light, p, u0, u1):
    p0, p1, p2 = light["vertices"]
    s = math.sqrt(u0)
    b1, b2 = s * (1.0 - u1), s * u1
    q = add(add(mul(p0, 1.0 - b1 - b2), mul(p1, b1)), mul(p2, b2))
    to_q = sub(q, p)
    d = math.sqrt(dot(to_q, to_q))
    wi = mul(to_q, 1.0 / d)
    cos_l = -dot(wi, light["normal"])
    if cos_l <= 0:
        return q, wi, d, 0.0, [0.0, 0.0, 0.0]
    return q, wi, d, d * d / (light["area"] * cos_l), light["radiance"]


def light_pdf(light, pick, p, q):
    to_q = sub(q, p)
    d2 = dot(to_q, to_q)
    cos_l = abs(dot(normalize(to_q), light["normal"]))
    if cos_l <= 0:
        return 0.0
    return pick * d2 / (light["area"] * cos_l)


def power_heuristic(a, b):
    a2, b2 = a * a, b * b
    if a2 + b2 <= 0:
        return 1.0 if a > 0 else 0.0
    return a2 / (a2 + b2)


def roulette(throughput, u):
    q = min(1.0, max(throughput))
    survived = u < q
    if survived:
        throughput = kit.mul(throughput, 1.0 / q)
    return q, survived, throughput


for fn in (intersect_sphere, intersect_plane, intersect_triangle, cosine_hemisphere, pick_light,
           sample_triangle_light, light_pdf, power_heuristic, roulette):
    setattr(kit, fn.__name__, fn)

if __name__ == "__main__":
    kit.main()
