#!/usr/bin/env python3
"""A careful student's answers to the Monte Carlo exercise sheets (13-16), in double precision,
computed from the scene files and raystep's documented random numbers — never from raystep's
trace. tests/it/sheets_mc.rs hands it every student's variant and grades what it answers.

    python3 sheet_answers.py < variants.json > answers.json

Each input item is {"question", "scene" (a path), "pixel": [x, y]}; each output item is
{"answer": number or [r, g, b] or null, "surfaces": [{"name", "material", "bsdf"}, ...] (the
path's surfaces from the camera), "light": the first light sample's light, "mistakes": {id:
answer}} — the classic mistakes' answers, worked out the wrong way on purpose.
"""

import json
import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import path_tracer as pt  # noqa: E402  (the model path tracer: scene, rays, random numbers)
import tracer as whitted  # noqa: E402

add, sub, scale, dot, cross, normalize = pt.add, pt.sub, pt.scale, pt.dot, pt.cross, pt.normalize


def reflect(wo, n):
    return sub(scale(n, 2 * dot(wo, n)), wo)


def ggx_d(alpha, cos_h):
    a2 = alpha * alpha
    t = (a2 - 1) * cos_h * cos_h + 1
    return a2 / (math.pi * t * t)


def ggx_pdf(alpha, wo, wi, n):
    """The reflected direction's density: D(h) cos θh / (4 ωo·h)."""
    if dot(wo, n) <= 0 or dot(wi, n) <= 0:
        return 0.0
    h = normalize(add(wo, wi))
    return ggx_d(alpha, dot(h, n)) * dot(h, n) / (4 * dot(wo, h))


class Scene:
    """The scene with what the Monte Carlo integrators read: BSDFs and the lights in object
    order (emitting spheres and triangles)."""

    def __init__(self, path):
        self.s = whitted.load_scene(path)
        with open(path, "rb") as f:
            doc = tomllib.load(f)
        self.render = doc.get("render", {})
        mats = {d.get("name", f"material {i}"): d for i, d in enumerate(doc.get("material", []))}
        self.mat = {}
        for obj in self.s.objects:
            d = mats.get(obj.material.name, {})
            self.mat[id(obj)] = {
                "name": obj.material.name,
                "bsdf": d.get("bsdf", "diffuse"),
                "color": tuple(float(c) for c in d.get("color", (1, 1, 1))),
                "emission": tuple(float(c) for c in d.get("emission", (0, 0, 0))),
                "roughness": float(d.get("roughness", 0.5)),
            }
        self.lights = []
        for obj in self.s.objects:
            m = self.mat[id(obj)]
            if max(m["emission"]) <= 0 or obj.kind == "plane":
                continue
            if obj.kind == "sphere":
                area = 4 * math.pi * obj.radius ** 2
            else:
                c = cross(sub(obj.p[1], obj.p[0]), sub(obj.p[2], obj.p[0]))
                area = 0.5 * math.sqrt(dot(c, c))
            self.lights.append({"obj": obj, "area": area, "radiance": m["emission"],
                                "power": sum(m["emission"]) / 3 * math.pi * area})
        self.total = sum(l["power"] for l in self.lights)

    def pick(self, u):
        target, run = u * self.total, 0.0
        for light in self.lights:
            run += light["power"]
            if run > target:
                return light, light["power"] / self.total
        return self.lights[-1], self.lights[-1]["power"] / self.total

    def sample(self, light, p, u0, u1):
        """(point, direction, density per steradian given the light, radiance)."""
        obj = light["obj"]
        if obj.kind == "sphere":
            to_c = sub(obj.center, p)
            dc = math.sqrt(dot(to_c, to_c))
            sin2 = (obj.radius / dc) ** 2
            cos_max = math.sqrt(1 - sin2)
            cos = 1 - u0 * (1 - cos_max)
            sin = math.sqrt(max(0.0, 1 - cos * cos))
            phi = 2 * math.pi * u1
            local = (sin * math.cos(phi), sin * math.sin(phi), cos)
            wi = normalize(pt.to_world(pt.frame(scale(to_c, 1 / dc)), local))
            b = dot(wi, to_c)
            dist = b - math.sqrt(max(0.0, obj.radius ** 2 - (dc * dc - b * b)))
            return add(p, scale(wi, dist)), wi, 1 / (2 * math.pi * (1 - cos_max)), light["radiance"]
        p0, p1, p2 = obj.p
        s = math.sqrt(u0)
        b1, b2 = s * (1 - u1), s * u1
        q = add(add(scale(p0, 1 - b1 - b2), scale(p1, b1)), scale(p2, b2))
        d = sub(q, p)
        dist = math.sqrt(dot(d, d))
        wi = scale(d, 1 / dist)
        normal = normalize(cross(sub(p1, p0), sub(p2, p0)))
        cos_l = -dot(wi, normal)
        if cos_l <= 0:
            return q, wi, 0.0, (0.0, 0.0, 0.0)
        return q, wi, dist * dist / (light["area"] * cos_l), light["radiance"]


def surface(sc, origin, direction):
    obj, t = pt.closest(sc.s, origin, direction)
    if obj is None:
        return None
    return whitted.surface_at(whitted.Ray(origin, direction, "primary", 0), obj, t)


def describe(sc, s):
    m = sc.mat[id(s.obj)]
    return {"name": s.obj.name, "material": m["name"], "bsdf": m["bsdf"]}


def light_sample(sc, s, rng, depth, distribution):
    """The first light sample at surface s: a dict of its numbers (None where there is none)."""
    m = sc.mat[id(s.obj)]
    if distribution:
        # Every light group once; group g draws 8 + 3g (a member), then a point.
        light, select = sc.lights[0], 1.0
        u0 = rng.draw(pt.dimension(depth, 9))["value"]
        u1 = rng.draw(pt.dimension(depth, 10))["value"]
    else:
        light, select = sc.pick(rng.draw(pt.dimension(depth, 0))["value"])
        u0 = rng.draw(pt.dimension(depth, 1))["value"]
        u1 = rng.draw(pt.dimension(depth, 2))["value"]
    q, wi, lpdf, radiance = sc.sample(light, s.point, u0, u1)
    n, wo = s.normal, s.eye
    cos = max(0.0, dot(wi, n))
    if m["bsdf"] == "diffuse":
        f = scale(m["color"], 1 / math.pi) if cos > 0 else (0.0, 0.0, 0.0)
        bsdf_pdf = cos / math.pi
    else:
        alpha = m["roughness"] ** 2
        bsdf_pdf = ggx_pdf(alpha, wo, wi, n)
        f = (0.0, 0.0, 0.0)  # not asked for at glossy surfaces
    pdf = select * lpdf
    useful = max(radiance) > 0 and cos > 0 and max(f + (bsdf_pdf,)) > 0
    blocked = useful and pt.blocked(sc.s, pt.off(s.point, n, wi), q)
    mis = not distribution
    w = pt.power_heuristic(pdf, bsdf_pdf) if mis else 1.0
    unblocked = scale(pt.mul(f, radiance), cos * w / pdf) if pdf > 0 else (0.0, 0.0, 0.0)
    return {"light": light["obj"].name, "select": select, "pdf": pdf, "bsdf_pdf": bsdf_pdf,
            "w": w, "cos": cos, "f": f, "radiance": radiance, "area": light["area"],
            "blocked": blocked, "unblocked": unblocked, "kind": light["obj"].kind,
            "contribution": (0.0, 0.0, 0.0) if blocked else unblocked}


def bsdf_sample(sc, s, rng, depth):
    """The direction the BSDF at s samples and its density (None for a delta)."""
    m = sc.mat[id(s.obj)]
    u0 = rng.draw(pt.dimension(depth, 4))["value"]
    u1 = rng.draw(pt.dimension(depth, 5))["value"]
    n, wo = s.normal, s.eye
    if m["bsdf"] == "diffuse":
        local, pdf = pt.cosine_hemisphere(u0, u1)
        return normalize(pt.to_world(pt.frame(n), local)), pdf
    if m["bsdf"] == "glossy":
        alpha = m["roughness"] ** 2
        tan2 = alpha * alpha * u0 / (1 - u0)
        cos = 1 / math.sqrt(1 + tan2)
        sin = math.sqrt(tan2) * cos
        phi = 2 * math.pi * u1
        h = normalize(pt.to_world(pt.frame(n), (sin * math.cos(phi), sin * math.sin(phi), cos)))
        wi = reflect(wo, h)
        return wi, ggx_pdf(alpha, wo, wi, n)
    return reflect(wo, n), None


def answer(item):
    sc = Scene(item["scene"])
    x, y = item["pixel"]
    q = item["question"]
    rng = pt.Sampler((x, y), 0, sc.s.seed)
    distribution = sc.render.get("integrator") == "distribution"
    origin, direction = pt.camera_ray(sc.s, x, y, 0)
    s = surface(sc, origin, direction)
    out = {"answer": None, "surfaces": [], "light": None, "mistakes": {}}
    if s is None:
        return out
    out["surfaces"].append(describe(sc, s))
    ls = light_sample(sc, s, rng, 0, distribution)
    out["light"] = ls["light"]
    wi, pdf = bsdf_sample(sc, s, rng, 0)
    m0 = sc.mat[id(s.obj)]
    albedo0 = tuple(min(c, 1.0) for c in m0["color"])
    # The path's second surface, along the sampled direction.
    s2 = surface(sc, pt.off(s.point, s.normal, wi), wi)
    if s2 is not None:
        out["surfaces"].append(describe(sc, s2))
    mk = out["mistakes"]
    if q in ("cone-pdf", "area-pdf"):
        out["answer"] = ls["pdf"]
        if ls["kind"] == "triangle":
            mk["area-pdf"] = ls["select"] / ls["area"]
        if ls["select"] < 1:
            mk["no-pick"] = ls["pdf"] / ls["select"]
    elif q in ("estimate", "blocked"):
        c = ls["contribution"]
        out["answer"] = list(c)
        if ls["blocked"]:
            mk["ignored-shadow"] = list(ls["unblocked"])
        elif ls["cos"] > 0:
            mk["no-cosine"] = list(scale(c, 1 / ls["cos"]))
    elif q == "power-heuristic":
        out["answer"] = ls["w"]
        p, b = ls["pdf"], ls["bsdf_pdf"]
        mk["balance-heuristic"] = p / (p + b)
        mk["no-mis"] = 1.0
    elif q == "cosine-pdf":
        out["answer"] = pdf
        mk["pdf-no-cosine"] = 1 / math.pi
        mk["pdf-no-pi"] = pdf * math.pi
    elif q == "glossy-pdf":
        out["answer"] = pdf
        h = normalize(add(s.eye, wi))
        mk["half-vector-pdf"] = pdf * 4 * dot(s.eye, h)
    elif q == "throughput" and s2 is not None:
        rng2 = pt.Sampler((x, y), 0, sc.s.seed)
        m2 = sc.mat[id(s2.obj)]
        if m2["bsdf"] == "diffuse":
            # Each cosine-weighted diffuse bounce's weight is the surface's albedo (the second
            # bounce needs a direction only to exist; its weight does not depend on it).
            del rng2
            albedo2 = tuple(min(c, 1.0) for c in m2["color"])
            out["answer"] = list(pt.mul(albedo0, albedo2))
    elif q == "roulette":
        out["answer"] = min(1.0, max(albedo0))
    return out


def main():
    # The model tracers print their records as they go: nothing of that here.
    whitted.emit = pt.emit = lambda record: None
    items = json.load(sys.stdin)
    json.dump([answer(it) for it in items], sys.stdout)


if __name__ == "__main__":
    main()
