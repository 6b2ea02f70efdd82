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


QUIET = False  # the path tracer's intersection tests print nothing


def emit(record):
    """Prints one record of the student trace format."""
    if not QUIET:
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


def instance_matrix(instance):
    """An [[instance]]'s matrix M, 3 rows of 4 (the 4th row is 0 0 0 1): its `matrix`, or
    M = T * Rz * Ry * Rx * S from `scale` (one number or three), `rotate` (degrees about x, then
    y, then z) and `translate`. Done: this is the scene file's convention, not a lesson."""
    if "matrix" in instance:
        return [list(map(float, row)) for row in instance["matrix"][:3]]
    k = instance.get("scale", 1.0)
    k = [float(k)] * 3 if isinstance(k, (int, float)) else [float(c) for c in k]
    ax, ay, az = (math.radians(a) for a in instance.get("rotate", [0.0, 0.0, 0.0]))
    t = instance.get("translate", [0.0, 0.0, 0.0])
    c, s = math.cos, math.sin
    rx = [[1, 0, 0], [0, c(ax), -s(ax)], [0, s(ax), c(ax)]]
    ry = [[c(ay), 0, s(ay)], [0, 1, 0], [-s(ay), 0, c(ay)]]
    rz = [[c(az), -s(az), 0], [s(az), c(az), 0], [0, 0, 1]]

    def times3(a, b):
        return [[sum(a[i][m] * b[m][j] for m in range(3)) for j in range(3)] for i in range(3)]
    r = times3(rz, times3(ry, rx))
    return [[r[i][j] * k[j] for j in range(3)] + [float(t[i])] for i in range(3)]


def prototypes(scene):
    """The names of the objects that instances place: drawn only where an instance puts them,
    so trace() leaves them out of its loop over the world's objects."""
    return {instance["of"] for instance in scene.get("instance", [])}


def intersect_instance(scene, instance, origin, direction):
    """Lesson 20. TODO: carry the ray into the instance's object space by M^-1 (M from
    instance_matrix(instance)): S' = M^-1 S as a point (with M^-1's translation), Q' = M^-1 Q as
    a vector (without it, and not renormalised, so t is the world ray's t); print
    {"type":"instance","name":name,"origin":S',"direction":Q'}; then test the prototype (the
    sphere, triangle or mesh named instance["of"]) with S', Q' (its test records follow the
    instance record); return (t or None, "instance", (instance, kind, primitive)) of the nearest.
    closest_hit() then carries that hit back to the world: the point by M, the normal by the
    inverse transpose M^-T (normalized), and prints the hit with "instance": its name."""
    return (None, "instance", (instance, None, None))


def closest_hit(tested, origin, direction):
    """Lesson 5. TODO: `tested` is every test trace() ran, as (t or None, kind, object) with kind
    "sphere", "plane", "triangle" or "instance": keep the nearest t; print
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
    placed = prototypes(scene)
    for sphere in scene.get("sphere", []):
        if sphere.get("name") not in placed:
            tested.append((intersect_sphere(sphere, origin, direction), "sphere", sphere))
    for plane in scene.get("plane", []):
        tested.append((intersect_plane(plane, origin, direction), "plane", plane))
    for triangle in scene.get("triangle", []):
        if triangle.get("name") not in placed:
            tested.append((intersect_triangle(triangle, origin, direction), "triangle", triangle))
    # Instances after the world's objects (lesson 20).
    for instance in scene.get("instance", []):
        tested.append(intersect_instance(scene, instance, origin, direction))
    hit = closest_hit(tested, origin, direction)
    return shade(scene, hit, origin, direction, depth)


# --- lessons 13 to 16: a path tracer (scenes with [render] integrator = "path") ------------------
#
# A path-traced scene is graded sample by sample in format version 2 (README.md next to this
# file): each sample of the pixel is a `path` record, then per bounce its `ray`, `hit`,
# `emission`, `light-sample`, `sample`, `bounce` and `roulette` records, then its `value`. The
# loop in trace_path() is done; the TODOs are the lessons' pieces. It uses your intersection
# tests of lessons 2 to 4 (printing nothing), raystep's random numbers (uniform() above) and
# raystep's dimensions, so its samples can be compared with raystep's number for number.
# Diffuse and mirror materials; lights are the triangles whose material has an `emission`.

def sample_offset(render, x, y, sample):
    """Where in pixel (x, y) sample `sample` lies: with spp > 1, a jittered point in its own
    cell of a grid of ceil(sqrt(spp)) columns (raystep's antialiasing, lesson 10). When the
    rows do not hold spp cells exactly, each row is as tall as its cells' share of the pixel
    and the last row's cells are wider, so that every cell has the same area."""
    spp, seed = render.get("spp", 1), render.get("seed", 0)
    if spp <= 1:
        return 0.5, 0.5
    cols = math.ceil(math.sqrt(spp))
    rows = -(-spp // cols)
    cx, cy = sample % cols, sample // cols
    h1 = pcg_hash(x ^ pcg_hash(y ^ pcg_hash(sample ^ pcg_hash(seed))))
    h2 = pcg_hash(h1)
    u1, u2 = (h1 >> 8) / 16777216.0, (h2 >> 8) / 16777216.0
    if cols * rows == spp:
        return (cx + u1) / cols, (cy + u2) / rows
    width = spp - cols * (rows - 1) if cy + 1 >= rows else cols
    return (cx + u1) / width, (cy * cols + u2 * width) / spp


def path_camera_ray(camera, render, x, y, sample):
    """camera_ray() through sample `sample`'s point of the pixel instead of its centre."""
    eye, direction = camera_ray(camera, x, y)
    ox, oy = sample_offset(render, x, y, sample)
    width, height = camera.get("width", 320), camera.get("height", 240)
    half_height = math.tan(math.radians(camera.get("fov", 60.0)) / 2.0)
    half_width = half_height * width / height
    w = normalize(sub(eye, camera.get("at", [0.0, 0.0, 0.0])))
    u = normalize(cross(camera.get("up", [0.0, 1.0, 0.0]), w))
    v = cross(w, u)
    sx = 2.0 * (x + ox) / width - 1.0
    sy = 1.0 - 2.0 * (y + oy) / height
    return eye, normalize(sub(add(mul(u, sx * half_width), mul(v, sy * half_height)), w))


def dimension(depth, slot):
    """raystep's dimension of `slot` at bounce `depth`: 16 + 1024 depth + slot (slot 0 picks the
    light, 1-2 the point on it, 4-5 the BSDF's direction, 6 Russian roulette)."""
    return (16 + 1024 * depth + slot) & 0xFFFFFFFF


def frame(n):
    """An orthonormal basis (s, t, n) around the unit normal n (Duff et al. 2017, as raystep)."""
    sign = math.copysign(1.0, n[2])
    a = -1.0 / (sign + n[2])
    b = n[0] * n[1] * a
    return [1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]], [b, sign + n[1] * n[1] * a, -n[1]], n


def concentric_disk(u0, u1):
    """Shirley and Chiu's concentric map of the square [0,1)^2 onto the unit disk (as raystep)."""
    a, b = 2.0 * u0 - 1.0, 2.0 * u1 - 1.0
    if a == 0.0 and b == 0.0:
        return 0.0, 0.0
    if abs(a) > abs(b):
        r, theta = a, math.pi / 4.0 * (b / a)
    else:
        r, theta = b, math.pi / 2.0 - math.pi / 4.0 * (a / b)
    return r * math.cos(theta), r * math.sin(theta)


def cosine_hemisphere(u0, u1):
    """Lesson 15. TODO: a direction about +z with density cos(theta)/pi: the concentric_disk
    point (x, y), lifted to z = sqrt(1 - x^2 - y^2); return ([x, y, z], pdf)."""
    return [0.0, 0.0, 1.0], 1.0


def lights_of(scene, objects):
    """The lights a path tracer samples: every triangle whose material emits, with its power
    (mean of its emission x pi x area: raystep picks a light with probability proportional to it)."""
    materials = {m.get("name"): m for m in scene.get("material", [])}
    lights = []
    for kind, obj, name in objects:
        emission = materials.get(obj.get("material"), {}).get("emission", [0.0, 0.0, 0.0])
        if kind != "triangle" or max(emission) <= 0:
            continue
        p0, p1, p2 = obj["vertices"]
        c = cross(sub(p1, p0), sub(p2, p0))
        area = 0.5 * math.sqrt(dot(c, c))
        lights.append({"name": name, "vertices": (p0, p1, p2), "normal": normalize(c),
                       "area": area, "radiance": emission,
                       "power": sum(emission) / 3.0 * math.pi * area})
    return lights


def pick_light(lights, u):
    """Lesson 14. TODO: pick a light with probability proportional to its power: the first light
    whose running sum of powers exceeds u x (the total power). Return (light, probability)."""
    return lights[0], 1.0


def sample_triangle_light(light, p, u0, u1):
    """Lesson 14. TODO: a point q on the triangle, uniform by area (s = sqrt(u0), barycentric
    weights b1 = s(1 - u1) of P1 and b2 = s u1 of P2); wi = the unit direction from p to q, at
    distance d; the density per STERADIAN d^2 / (area |cos theta_light|) (0, with radiance 0, when
    the light faces away: -wi . normal <= 0). Return (q, wi, d, pdf, radiance)."""
    q = light["vertices"][0]
    to_q = sub(q, p)
    d = math.sqrt(dot(to_q, to_q))
    return q, mul(to_q, 1.0 / d), d, 1.0, light["radiance"]


def light_pdf(light, pick, p, q):
    """Lesson 16. TODO: the density with which light sampling from p would have chosen the point
    q of `light` (a BSDF sample's ray found it there): pick x d^2 / (area |cos theta_light|)."""
    return 0.0


def power_heuristic(a, b):
    """Lesson 16. TODO: Veach's power heuristic, a^2 / (a^2 + b^2) (1 when both are 0 and a > 0)."""
    return 1.0


def roulette(throughput, u):
    """Lesson 15. TODO: Russian roulette: q = min(1, the throughput's largest channel); the path
    goes on when u < q, and then its throughput is divided by q. Return (q, survived, throughput)."""
    return 1.0, True, throughput


def nearest(scene, objects, origin, direction):
    """The closest hit among your intersection tests (lessons 2 to 5), printing nothing:
    (t, kind, object, name) or None."""
    global QUIET
    was, QUIET = QUIET, True
    best = None
    try:
        for kind, obj, name in objects:
            test = {"sphere": intersect_sphere, "plane": intersect_plane,
                    "triangle": intersect_triangle}[kind]
            t = test(obj, origin, direction)
            if t is not None and (best is None or t < best[0]):
                best = (t, kind, obj, name)
    finally:
        QUIET = was
    return best


def blocked(scene, objects, origin, target):
    """Whether anything lies between origin and target (a shadow ray, t in (0, 1 - 1e-4))."""
    hit = nearest(scene, objects, origin, sub(target, origin))
    return hit is not None and hit[0] < 1.0 - 1e-4


def outward_normal(kind, obj, point):
    """The unit normal of the object at the point (before facing it to the ray)."""
    if kind == "sphere":
        return normalize(sub(point, obj.get("center", [0.0, 0.0, 0.0])))
    if kind == "plane":
        if "axis" in obj:
            return {"x": [1.0, 0.0, 0.0], "y": [0.0, 1.0, 0.0], "z": [0.0, 0.0, 1.0]}[obj["axis"]]
        return normalize(obj.get("normal", [0.0, 1.0, 0.0]))
    p0, p1, p2 = obj["vertices"]
    return normalize(cross(sub(p1, p0), sub(p2, p0)))


def off(point, normal, direction):
    """A spawned ray's origin: off the surface, on the side it leaves on."""
    return add(point, mul(normal, 1e-4 if dot(direction, normal) >= 0 else -1e-4))


def times(a, b):
    return [a[0] * b[0], a[1] * b[1], a[2] * b[2]]


def trace_path(scene, objects, lights, x, y, k):
    """Sample k of pixel (x, y): one path, its records printed; returns its value."""
    render = scene.get("render", {})
    seed, max_depth, rr_depth = render.get("seed", 0), render.get("max_depth", 5), render.get("rr_depth", 3)
    materials = {m.get("name"): m for m in scene.get("material", [])}

    def draw(d):
        return {"dimension": d, "value": uniform((x, y), k, d, seed)}

    emit({"type": "path", "sample": k})
    origin, direction = path_camera_ray(scene.get("camera", {}), render, x, y, k)
    throughput, value = [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]
    prev_pdf, prev_point = None, None  # the BSDF sample that made this ray (None: camera, mirror)
    depth = 0
    while True:
        emit({"type": "ray", "depth": depth, "origin": origin, "direction": direction})
        hit = nearest(scene, objects, origin, direction)
        if hit is None:
            emit({"type": "hit", "object": None})
            value = add(value, times(throughput, render.get("background", [0.0, 0.0, 0.0])))
            break
        t, kind, obj, name = hit
        point = add(origin, mul(direction, t))
        n = outward_normal(kind, obj, point)
        eye = normalize(mul(direction, -1.0))
        inside = dot(n, eye) < 0
        if inside:
            n = mul(n, -1.0)
        emit({"type": "hit", "object": name, "point": point, "normal": n})
        m = materials.get(obj.get("material"), {})
        emission = m.get("emission", [0.0, 0.0, 0.0])
        # Emission: counted in full from the camera and after a mirror; after a diffuse bounce,
        # weighed by MIS against the light sample at the previous hit (lesson 16).
        if max(emission) > 0 and not inside:
            lpdf, w = 0.0, 1.0
            if prev_pdf is not None:
                light = next((l for l in lights if l["name"] == name), None)
                if light is not None:
                    total = sum(l["power"] for l in lights)
                    lpdf = light_pdf(light, light["power"] / total, prev_point, point)
                w = power_heuristic(prev_pdf, lpdf)
            emit({"type": "emission", "radiance": emission, "mis_weight": w,
                  "light_pdf": lpdf, "bsdf_pdf": prev_pdf or 0.0})
            value = add(value, mul(times(throughput, emission), w))
        if depth >= max_depth:
            break
        diffuse = m.get("bsdf", "diffuse") == "diffuse"
        albedo = [min(c, 1.0) for c in m.get("color", [1.0, 1.0, 1.0])]
        # Next-event estimation (lesson 14), weighed by MIS (lesson 16).
        if diffuse and lights:
            pick, u0, u1 = draw(dimension(depth, 0)), draw(dimension(depth, 1)), draw(dimension(depth, 2))
            light, select = pick_light(lights, pick["value"])
            q, wi, dist, lpdf, radiance = sample_triangle_light(light, point, u0["value"], u1["value"])
            cos = max(0.0, dot(wi, n))
            f = mul(albedo, 1.0 / math.pi) if cos > 0 else [0.0, 0.0, 0.0]
            bsdf_pdf = cos / math.pi
            pdf = select * lpdf
            useful = max(radiance) > 0 and cos > 0 and max(f) > 0
            hidden = useful and blocked(scene, objects, off(point, n, wi), q)
            w = power_heuristic(pdf, bsdf_pdf)
            estimate = [0.0, 0.0, 0.0]
            if useful and not hidden and pdf > 0:
                estimate = mul(times(f, radiance), cos * w / pdf)
            contribution = times(throughput, estimate)
            emit({"type": "light-sample", "light": light["name"], "random": [pick, u0, u1],
                  "point": q, "pdf": pdf, "bsdf_pdf": bsdf_pdf, "mis_weight": w,
                  "blocked": bool(hidden), "contribution": contribution})
            value = add(value, contribution)
        # The next direction (lesson 15): cosine-weighted about the normal, or a mirror's.
        if diffuse:
            u0, u1 = draw(dimension(depth, 4)), draw(dimension(depth, 5))
            local, pdf = cosine_hemisphere(u0["value"], u1["value"])
            s_axis, t_axis, n_axis = frame(n)
            wi = normalize(add(add(mul(s_axis, local[0]), mul(t_axis, local[1])), mul(n_axis, local[2])))
            cos = abs(dot(wi, n))
            f = mul(albedo, 1.0 / math.pi)
            throughput = times(throughput, mul(f, cos / pdf))
            emit({"type": "sample", "random": [u0, u1], "direction": wi, "pdf": pdf})
            emit({"type": "bounce", "bsdf": f, "cos": cos, "throughput": throughput})
            prev_pdf = pdf
        else:
            wi = sub(mul(n, 2.0 * dot(eye, n)), eye)
            throughput = times(throughput, m.get("color", [1.0, 1.0, 1.0]))
            emit({"type": "sample", "direction": wi, "pdf": None})
            emit({"type": "bounce", "cos": dot(eye, n), "throughput": throughput})
            prev_pdf = None
        # Russian roulette after rr_depth bounces (lesson 15).
        if depth + 1 > rr_depth:
            u = draw(dimension(depth, 6))
            q, survived, throughput = roulette(throughput, u["value"])
            emit({"type": "roulette", "random": u, "probability": q, "survived": survived,
                  "throughput": throughput})
            if not survived:
                break
        prev_point = point
        origin, direction = off(point, n, wi), wi
        depth += 1
    emit({"type": "value", "rgb": value})
    return value


def path_main(scene, x, y):
    """Prints every sample of pixel (x, y) in format version 2."""
    objects = []
    for kind in ("sphere", "plane", "triangle"):
        for i, obj in enumerate(scene.get(kind, [])):
            objects.append((kind, obj, obj.get("name", f"{kind} {i}")))
    lights = lights_of(scene, objects)
    emit({"type": "format", "version": 2})
    emit({"type": "pixel", "x": x, "y": y})
    spp = scene.get("render", {}).get("spp", 1)
    total = [0.0, 0.0, 0.0]
    for k in range(spp):
        total = add(total, trace_path(scene, objects, lights, x, y, k))
    emit({"type": "color", "rgb": mul(total, 1.0 / spp)})


def write_stats(scene, out):
    """Renders the whole image with trace_path (printing nothing) and writes each pixel's sample
    count, mean and unbiased sample variance, per channel, for `raystep grade-tracer
    --statistical` (a tracer with its own random numbers is graded this way)."""
    global QUIET
    objects = []
    for kind in ("sphere", "plane", "triangle"):
        for i, obj in enumerate(scene.get(kind, [])):
            objects.append((kind, obj, obj.get("name", f"{kind} {i}")))
    lights = lights_of(scene, objects)
    camera, spp = scene.get("camera", {}), scene.get("render", {}).get("spp", 1)
    width, height = camera.get("width", 320), camera.get("height", 240)
    QUIET = True
    with open(out, "w", encoding="utf-8") as f:
        f.write(json.dumps({"type": "format", "version": 2}) + "\n")
        f.write(json.dumps({"type": "image", "width": width, "height": height}) + "\n")
        for y in range(height):
            for x in range(width):
                values = [trace_path(scene, objects, lights, x, y, k) for k in range(spp)]
                mean = [sum(v[c] for v in values) / spp for c in range(3)]
                var = [sum((v[c] - mean[c]) ** 2 for v in values) / (spp - 1) if spp > 1 else 0.0
                       for c in range(3)]
                f.write(json.dumps({"type": "pixel", "x": x, "y": y, "samples": spp,
                                    "mean": mean, "variance": var}) + "\n")
    QUIET = False


def main():
    if len(sys.argv) == 4 and sys.argv[2] == "--stats":
        with open(sys.argv[1], "rb") as f:
            write_stats(tomllib.load(f), sys.argv[3])
        return
    if len(sys.argv) != 4:
        sys.exit("usage: tracer.py SCENE.toml X Y  |  tracer.py SCENE.toml --stats OUT.jsonl")
    with open(sys.argv[1], "rb") as f:
        scene = tomllib.load(f)
    x, y = int(sys.argv[2]), int(sys.argv[3])
    if scene.get("render", {}).get("integrator") == "path":
        path_main(scene, x, y)
        return
    emit({"type": "format", "version": 1})
    emit({"type": "pixel", "x": x, "y": y})
    origin, direction = camera_ray(scene.get("camera", {}), x, y)
    trace(scene, origin, direction, "primary", 0)


if __name__ == "__main__":
    main()
