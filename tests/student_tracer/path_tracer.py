#!/usr/bin/env python3
"""The model student's path tracer (lessons 13-16): the starter kit's path-tracing TODOs
(lessons/starter/tracer.py) filled in, in double precision, with raystep's random numbers.

    python3 path_tracer.py SCENE.toml X Y [--bug MISTAKE]

prints every sample of pixel (X, Y) in the student trace format, version 2 (path records: see
lessons/starter/README.md). The model Whitted tracer (tracer.py next to this file) hands a
scene with `integrator = "path"` over to this file. Diffuse and mirror materials, triangle
lights (emitting materials on triangles), next-event estimation with MIS (the power heuristic),
Russian roulette. `--bug` plants one of the classic mistakes grade-tracer names.
"""

import json
import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tracer as whitted  # noqa: E402  (the model's scene loader and ray-object tests)

BUGS = ("pdf-no-cosine", "area-pdf", "mis-balance-emission", "emission-twice",
        "roulette-no-divide", "wrong-hemisphere")
BUG = None

add, sub, scale, dot, cross, normalize = (whitted.add, whitted.sub, whitted.scale, whitted.dot,
                                          whitted.cross, whitted.normalize)


def mul(a, b):
    return (a[0] * b[0], a[1] * b[1], a[2] * b[2])


def emit(record):
    print(json.dumps(record))


# --- raystep's random numbers ------------------------------------------------------------------

def uniform(pixel, sample, dimension, seed):
    x, y = pixel
    h = whitted.pcg_hash(dimension ^ whitted.pcg_hash(
        x ^ whitted.pcg_hash(y ^ whitted.pcg_hash(sample ^ whitted.pcg_hash(seed)))))
    return (h >> 8) / 16777216.0


def dimension(depth, slot):
    """Bounce `depth`'s block of dimensions starts at 16 + 1024 depth."""
    return (16 + 1024 * depth + slot) & 0xFFFFFFFF


class Sampler:
    def __init__(self, pixel, sample, seed):
        self.pixel, self.sample, self.seed = pixel, sample, seed

    def draw(self, d):
        return {"dimension": d, "value": uniform(self.pixel, self.sample, d, self.seed)}


# --- warps (lessons 13-15) ---------------------------------------------------------------------

def concentric_disk(u0, u1):
    a, b = 2 * u0 - 1, 2 * u1 - 1
    if a == 0 and b == 0:
        return 0.0, 0.0
    if abs(a) > abs(b):
        r, theta = a, math.pi / 4 * (b / a)
    else:
        r, theta = b, math.pi / 2 - math.pi / 4 * (a / b)
    return r * math.cos(theta), r * math.sin(theta)


def cosine_hemisphere(u0, u1):
    """A direction about +z with density cos θ / π."""
    x, y = concentric_disk(u0, u1)
    z = math.sqrt(max(0.0, 1 - x * x - y * y))
    pdf = z / math.pi
    if BUG == "pdf-no-cosine":
        pdf = 1 / math.pi
    return (x, y, z), pdf


def frame(n):
    """Duff et al.'s orthonormal basis (s, t, n) around the unit vector n."""
    sign = math.copysign(1.0, n[2])
    a = -1.0 / (sign + n[2])
    b = n[0] * n[1] * a
    s = (1 + sign * n[0] * n[0] * a, sign * b, -sign * n[0])
    t = (b, sign + n[1] * n[1] * a, -n[1])
    return s, t, n


def to_world(f, v):
    s, t, n = f
    return add(add(scale(s, v[0]), scale(t, v[1])), scale(n, v[2]))


def power_heuristic(a, b):
    a2, b2 = a * a, b * b
    if a2 + b2 <= 0:
        return 1.0 if a > 0 else 0.0
    return a2 / (a2 + b2)


# --- the scene: materials' BSDFs and the lights ------------------------------------------------

class Lights:
    """Every triangle whose material emits: picked with probability ∝ power = mean(Le)·π·area."""

    def __init__(self, scene, materials):
        self.lights = []
        for obj in scene.objects:
            m = materials[id(obj)]
            if max(m["emission"]) <= 0 or obj.kind != "triangle":
                continue
            p0, p1, p2 = obj.p
            c = cross(sub(p1, p0), sub(p2, p0))
            area = 0.5 * math.sqrt(dot(c, c))
            if area <= 0:
                continue
            power = sum(m["emission"]) / 3 * math.pi * area
            self.lights.append({"obj": obj, "normal": normalize(c), "area": area,
                                "radiance": m["emission"], "power": power})
        self.total = sum(l["power"] for l in self.lights)

    def pick(self, u):
        """(light, probability) for the uniform number u: the first light whose running sum of
        powers exceeds u · total."""
        if self.total <= 0:
            return None, 0.0
        target, run = u * self.total, 0.0
        for light in self.lights:
            run += light["power"]
            if run > target:
                return light, light["power"] / self.total
        last = self.lights[-1]
        return last, last["power"] / self.total

    def of(self, obj):
        for light in self.lights:
            if light["obj"] is obj:
                return light
        return None

    def pdf(self, light, p, q):
        """Light sampling's density, per steradian, of point q seen from p (pick included)."""
        d = sub(q, p)
        d2 = dot(d, d)
        cos_l = abs(dot(normalize(d), light["normal"]))
        if cos_l <= 0:
            return 0.0
        return light["power"] / self.total * d2 / (light["area"] * cos_l)


def sample_triangle(light, p, u0, u1):
    """A point on the triangle light, uniform by area, and its density per steradian from p."""
    p0, p1, p2 = light["obj"].p
    s = math.sqrt(u0)
    b1, b2 = s * (1 - u1), s * u1
    q = add(add(scale(p0, 1 - b1 - b2), scale(p1, b1)), scale(p2, b2))
    d = sub(q, p)
    dist = math.sqrt(dot(d, d))
    wi = scale(d, 1 / dist)
    cos_l = -dot(wi, light["normal"])
    if cos_l <= 0:
        return q, wi, dist, 0.0, (0.0, 0.0, 0.0)
    pdf = dist * dist / (light["area"] * cos_l)
    if BUG == "area-pdf":
        pdf = 1 / light["area"]
    return q, wi, dist, pdf, light["radiance"]


def load(path):
    scene = whitted.load_scene(path)
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    by_name = {}
    for i, d in enumerate(doc.get("material", [])):
        by_name[d.get("name", f"material {i}")] = d
    render = doc.get("render", {})
    scene.rr_depth = int(render.get("rr_depth", 3))
    scene.max_depth = int(render.get("max_depth", 5))
    materials = {}
    for obj in scene.objects:
        d = by_name.get(obj.material.name, {})
        color = tuple(float(c) for c in d.get("color", (1, 1, 1)))
        materials[id(obj)] = {
            "bsdf": d.get("bsdf", "diffuse"),
            "color": color,
            "emission": tuple(float(c) for c in d.get("emission", (0, 0, 0))),
        }
    scene.materials = materials
    scene.light_list = Lights(scene, materials)
    return scene


# --- tracing -----------------------------------------------------------------------------------

def closest(scene, origin, direction):
    ray = whitted.Ray(origin, direction, "primary", 0)
    return whitted.closest_hit(scene, ray)


def blocked(scene, origin, target):
    ray = whitted.Ray(origin, sub(target, origin), "shadow", 1, 0.0, 1 - 1e-4)
    return whitted.any_hit(scene, ray)


def off(point, normal, direction, eps=1e-4):
    side = 1.0 if dot(direction, normal) >= 0 else -1.0
    return add(point, scale(normal, eps * side))


def trace_sample(scene, x, y, k):
    """Sample k of pixel (x, y): prints its records and returns its value."""
    rng = Sampler((x, y), k, scene.seed)
    lights = scene.light_list
    emit({"type": "path", "sample": k})
    whitted_ray = camera_ray(scene, x, y, k)
    origin, direction = whitted_ray
    throughput = (1.0, 1.0, 1.0)
    value = (0.0, 0.0, 0.0)
    prev_pdf, prev_point = None, None
    depth = 0
    while True:
        emit({"type": "ray", "depth": depth, "origin": list(origin), "direction": list(direction)})
        obj, t = closest(scene, origin, direction)
        if obj is None:
            emit({"type": "hit", "object": None})
            value = add(value, mul(throughput, scene.background))
            break
        s = whitted.surface_at(whitted.Ray(origin, direction, "primary", 0), obj, t)
        n, eye = s.normal, s.eye
        emit({"type": "hit", "object": obj.name, "point": list(s.point), "normal": list(n)})
        m = scene.materials[id(obj)]
        # Emission, weighed by MIS against the light sample of the previous hit.
        if max(m["emission"]) > 0 and not s.inside:
            light_pdf, w = 0.0, 1.0
            if prev_pdf is not None:
                light = lights.of(obj)
                light_pdf = lights.pdf(light, prev_point, s.point) if light else 0.0
                w = power_heuristic(prev_pdf, light_pdf)
                if BUG == "mis-balance-emission":
                    w = prev_pdf / (prev_pdf + light_pdf)
                if BUG == "emission-twice":
                    w = 1.0
            emit({"type": "emission", "radiance": list(m["emission"]), "mis_weight": w,
                  "light_pdf": light_pdf, "bsdf_pdf": prev_pdf or 0.0})
            value = add(value, scale(mul(throughput, m["emission"]), w))
        if depth >= scene.max_depth:
            break
        diffuse = m["bsdf"] == "diffuse"
        albedo = tuple(min(c, 1.0) for c in m["color"])
        # Next-event estimation: one light, one point on it.
        if diffuse and lights.lights:
            pick = rng.draw(dimension(depth, 0))
            u0, u1 = rng.draw(dimension(depth, 1)), rng.draw(dimension(depth, 2))
            light, select = lights.pick(pick["value"])
            q, wi, dist, lpdf, radiance = sample_triangle(light, s.point, u0["value"], u1["value"])
            cos = max(0.0, dot(wi, n))
            f = scale(albedo, 1 / math.pi) if cos > 0 and dot(eye, n) > 0 else (0.0, 0.0, 0.0)
            bsdf_pdf = cos / math.pi if cos > 0 else 0.0
            pdf = select * lpdf
            useful = max(radiance) > 0 and max(f) > 0 and cos > 0
            hidden = useful and blocked(scene, off(s.point, n, wi), q)
            w = power_heuristic(pdf, bsdf_pdf)
            if BUG == "emission-twice":
                w = 1.0
            estimate = (0.0, 0.0, 0.0)
            if useful and not hidden and pdf > 0:
                estimate = scale(mul(f, radiance), cos * w / pdf)
            contribution = mul(throughput, estimate)
            emit({"type": "light-sample", "light": light["obj"].name, "random": [pick, u0, u1],
                  "point": list(q), "pdf": pdf, "bsdf_pdf": bsdf_pdf, "mis_weight": w,
                  "blocked": bool(hidden), "contribution": list(contribution)})
            value = add(value, contribution)
        # The next direction.
        if diffuse:
            u0, u1 = rng.draw(dimension(depth, 4)), rng.draw(dimension(depth, 5))
            local, pdf = cosine_hemisphere(u0["value"], u1["value"])
            wi = normalize(to_world(frame(n), local))
            if BUG == "wrong-hemisphere":
                wi = normalize(to_world(frame(scale(n, -1)), local))
            cos = abs(dot(wi, n))
            if pdf <= 0:
                break
            f = scale(albedo, 1 / math.pi)
            weight = scale(f, cos / pdf)
            throughput = mul(throughput, weight)
            emit({"type": "sample", "random": [u0, u1], "direction": list(wi), "pdf": pdf})
            emit({"type": "bounce", "bsdf": list(f), "cos": cos, "throughput": list(throughput)})
            prev_pdf = pdf
        else:  # a mirror
            wi = sub(scale(n, 2 * dot(eye, n)), eye)
            throughput = mul(throughput, m["color"])
            emit({"type": "sample", "direction": list(wi), "pdf": None})
            emit({"type": "bounce", "cos": dot(eye, n), "throughput": list(throughput)})
            prev_pdf = None
        # Russian roulette after rr_depth bounces.
        if depth + 1 > scene.rr_depth:
            u = rng.draw(dimension(depth, 6))
            q = min(1.0, max(throughput))
            survived = u["value"] < q
            if survived and BUG != "roulette-no-divide":
                throughput = scale(throughput, 1 / q)
            emit({"type": "roulette", "random": u, "probability": q, "survived": survived,
                  "throughput": list(throughput)})
            if not survived:
                break
        prev_point = s.point
        origin, direction = off(s.point, n, wi), wi
        depth += 1
    emit({"type": "value", "rgb": list(value)})
    return value


def camera_ray(scene, x, y, k):
    """The camera ray of sample k: the pixel's jittered point (its own cell of a ⌈√spp⌉-column
    grid, as raystep's sample_offset)."""
    w = normalize(sub(scene.eye, scene.look_at))
    u = normalize(cross(scene.up, w))
    v = cross(w, u)
    half_h = math.tan(math.radians(scene.fov) / 2)
    half_w = half_h * scene.width / scene.height
    ox, oy = whitted.sample_offset(scene, x, y, k)
    sx = 2 * (x + ox) / scene.width - 1
    sy = 1 - 2 * (y + oy) / scene.height
    q = sub(add(scale(u, sx * half_w), scale(v, sy * half_h)), w)
    return scene.eye, normalize(q)


def main(argv=None):
    global BUG
    argv = sys.argv[1:] if argv is None else argv
    if "--bug" in argv:
        i = argv.index("--bug")
        BUG = argv[i + 1]
        if BUG not in BUGS:
            sys.exit(f"--bug: one of {', '.join(BUGS)}")
        argv = argv[:i] + argv[i + 2:]
    path, x, y = argv[0], int(argv[1]), int(argv[2])
    scene = load(path)
    whitted.emit = lambda record: None  # the ray-object tests print nothing here
    emit({"type": "format", "version": 2})
    emit({"type": "pixel", "x": x, "y": y})
    total = (0.0, 0.0, 0.0)
    for k in range(scene.spp):
        total = add(total, trace_sample(scene, x, y, k))
    emit({"type": "color", "rgb": list(scale(total, 1 / scene.spp))})


if __name__ == "__main__":
    main()
