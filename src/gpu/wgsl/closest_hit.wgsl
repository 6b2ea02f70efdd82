// ---- closest-hit, part 2: shading the hit and spawning the secondary rays (src/trace/whitted.rs
// `shade`, src/trace/shading.rs). The CPU recurses; here each spawned ray is pushed on the ray
// stack with the weight its colour will be multiplied by, and ray generation pops it later. ----

//#if SHADOWS
// Phong lighting from one light (The Ray Tracer Challenge's `lighting`).
fn phong(m: Material, light: Light, point: vec3f, eye: vec3f, normal: vec3f, in_shadow: bool) -> vec3f {
    let effective = m.color * light.color;
    let to_light = light.position - point;
    let lightv = fdiv3(to_light, flen(to_light));
    let ambient = effective * m.ambient;
    let l_dot_n = dot(lightv, normal);
    let reflectv = mirror_dir(-lightv, normal);
    let r_dot_e = dot(reflectv, eye);
    var diffuse = vec3f(0.0);
    var specular = vec3f(0.0);
    if !in_shadow && l_dot_n >= 0.0 {
        diffuse = effective * (m.diffuse * l_dot_n);
        if r_dot_e > 0.0 {
            // Not WGSL's pow (exp2(y·log2(x)) at reduced precision): the CPU's portable_pow.
            specular = light.color * (m.specular * fpow(r_dot_e, m.shininess));
        }
    }
    return ambient + diffuse + specular;
}
//#endif

//#if REFRACTION
// Snell's law: the refracted direction, or a zero vector under total internal reflection.
fn refract_dir(eye: vec3f, n: vec3f, n1: f32, n2: f32) -> vec3f {
    let ratio = fdiv(n1, n2);
    let cos_i = dot(eye, n);
    let sin2_t = ratio * ratio * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return vec3f(0.0);
    }
    let cos_t = fsqrt(1.0 - sin2_t);
    return n * (ratio * cos_i - cos_t) - eye * ratio;
}

//#if REFLECTION
// Schlick's approximation of the Fresnel reflectance, 1 under total internal reflection.
fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
    var cos = cos_i;
    if n1 > n2 {
        let ratio = fdiv(n1, n2);
        let sin2_t = ratio * ratio * (1.0 - cos * cos);
        if sin2_t > 1.0 {
            return 1.0;
        }
        cos = fsqrt(1.0 - sin2_t);
    }
    let r = fdiv(n1 - n2, n1 + n2);
    let r0 = r * r;
    let x = 1.0 - cos;
    let x2 = x * x;
    return r0 + (1.0 - r0) * (x2 * x2 * x);
}
//#endif
//#endif

// A ray whose direction makes a valid `Ray` on the CPU (finite, non-zero, d·d finite).
fn valid_dir(d: vec3f) -> bool {
    let dd = dot(d, d);
    return finite(d.x) && finite(d.y) && finite(d.z) && dd != 0.0 && finite(dd);
}

// Shades `hit` of ray task `task` and returns its own (unweighted) colour; pushes the reflection
// and refraction rays with their weights.
fn closest_hit(hit: Hit, task: Task) -> vec3f {
    let r = task.ray;
    let m = materials[objects[hit.object].material];
    let it = interact(hit, r);
    var surface = vec3f(0.0);
//#if SHADOWS
//#if FULL
    if params.n_lights == 0u {
        surface = m.color * m.ambient;
    }
//#endif
    // Direct light: Phong from each light, ambient only where a shadow ray is blocked.
    for (var li = 0u; li < params.n_lights; li++) {
        let light = lights[li];
        let to_light = light.position - it.point;
        var blocked = false;
        // A light behind the surface contributes only ambient: no shadow ray.
        if dot(to_light, it.normal) > 0.0 {
            let o = spawn_origin(it, to_light);
            let d = light.position - o;
            if valid_dir(d) {
                blocked = traversal_any(Ray(o, d, 0.0, SHADOW_T_MAX));
            }
        }
        surface += phong(m, light, it.point, it.eye, it.normal, blocked);
    }
//#else
    // No lights: the ambient colour rather than black.
    surface = m.color * m.ambient;
//#endif
    let can_recurse = task.depth < params.max_depth;
//#if REFLECTION
    var reflect_weight = m.reflective;
//#endif
//#if REFRACTION
    if m.transparency > 0.0 {
        let n = media_indices(task.media, hit.object, m.refractive_index);
        var refract_weight = m.transparency;
//#if REFLECTION
        if m.reflective > 0.0 {
            let reflectance = schlick(dot(it.eye, it.normal), n.x, n.y);
            reflect_weight = m.reflective * reflectance;
            refract_weight = m.transparency * (1.0 - reflectance);
        }
//#endif
        if can_recurse {
            let dir = refract_dir(it.eye, it.normal, n.x, n.y);
            // The weight cut-off (src/trace/whitted.rs WEIGHT_CUTOFF): a ray whose share of the
            // pixel is below it is not spawned. Written as "not below" so NaN compares as on the CPU.
            if valid_dir(dir) && !(task.weight * refract_weight < WEIGHT_CUTOFF) {
                let media = media_crossed(task.media, hit.object);
                push_ray(Ray(spawn_origin(it, dir), dir, 0.0, params.inf), task.depth + 1u, task.weight * refract_weight, media);
            }
        }
    }
//#endif
//#if REFLECTION
    if m.reflective > 0.0 && can_recurse && !(task.weight * reflect_weight < WEIGHT_CUTOFF) {
        let dir = mirror_dir(r.dir, it.normal);
//#if REFRACTION
        push_ray(Ray(spawn_origin(it, dir), dir, 0.0, params.inf), task.depth + 1u, task.weight * reflect_weight, task.media);
//#else
        push_ray(Ray(spawn_origin(it, dir), dir, 0.0, params.inf), task.depth + 1u, task.weight * reflect_weight);
//#endif
    }
//#endif
    return surface;
}
