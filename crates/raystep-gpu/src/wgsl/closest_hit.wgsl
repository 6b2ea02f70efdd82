// ---- closest-hit, part 2: shading the hit and spawning the secondary rays (crates/raystep-core/src/trace/whitted.rs
// `shade`, crates/raystep-core/src/trace/shading.rs). The CPU recurses; here each spawned ray is pushed on the ray
// stack with the weight its colour will be multiplied by, and ray generation pops it later. ----

//#if SHADOWS
// The terms of Phong lighting from one light (crates/raystep-core/src/trace/shading.rs `PhongTerms`).
struct PhongTerms {
    ambient: vec3f,
    diffuse: vec3f,
    specular: vec3f,
    l_dot_n: f32,
    r_dot_e: f32,
    light_dir: vec3f,
    reflected: vec3f,
}

// Phong lighting from one light (The Ray Tracer Challenge's `lighting`).
fn phong(m: Material, light: Light, point: vec3f, eye: vec3f, normal: vec3f, in_shadow: bool) -> PhongTerms {
    let effective = m.color * light.color;
    let to_light = light.position - point;
    let lightv = fdiv3(to_light, flen(to_light));
    let ambient = effective * m.ambient;
    let l_dot_n = fdot(lightv, normal);
    let reflectv = mirror_dir(-lightv, normal);
    let r_dot_e = fdot(reflectv, eye);
    var diffuse = vec3f(0.0);
    var specular = vec3f(0.0);
    if !in_shadow && l_dot_n >= 0.0 {
        diffuse = effective * (m.diffuse * l_dot_n);
        if r_dot_e > 0.0 {
            // Not WGSL's pow (exp2(y·log2(x)) at reduced precision): the CPU's portable_pow.
            specular = light.color * (m.specular * fpow(r_dot_e, m.shininess));
        }
    }
    return PhongTerms(ambient, diffuse, specular, l_dot_n, r_dot_e, lightv, reflectv);
}
//#endif

//#if REFRACTION
// Snell's law at a surface (crates/raystep-core/src/trace/shading.rs `Refraction`): the refracted direction (a zero
// vector under total internal reflection) and the quantities it came from.
struct Snell {
    dir: vec3f,
    eta: f32,
    cos_i: f32,
    sin2_t: f32,
    cos_t: f32,
    tir: bool,
}

fn refract_dir(eye: vec3f, n: vec3f, n1: f32, n2: f32) -> Snell {
    let ratio = fdiv(n1, n2);
    let cos_i = fdot(eye, n);
    let sin2_t = ratio * ratio * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return Snell(vec3f(0.0), ratio, cos_i, sin2_t, 0.0, true);
    }
    let cos_t = fsqrt(1.0 - sin2_t);
    return Snell(n * (ratio * cos_i - cos_t) - eye * ratio, ratio, cos_i, sin2_t, cos_t, false);
}

//#if REFLECTION
// Schlick's approximation of the Fresnel reflectance: (R, R0, the cosine used, 1) — or
// (1, 0, 0, 0) under total internal reflection.
fn schlick(cos_i: f32, n1: f32, n2: f32) -> vec4f {
    var cos = cos_i;
    if n1 > n2 {
        let ratio = fdiv(n1, n2);
        let sin2_t = ratio * ratio * (1.0 - cos * cos);
        if sin2_t > 1.0 {
            return vec4f(1.0, 0.0, 0.0, 0.0);
        }
        cos = fsqrt(1.0 - sin2_t);
    }
    let r = fdiv(n1 - n2, n1 + n2);
    let r0 = r * r;
    let x = 1.0 - cos;
    let x2 = x * x;
    return vec4f(r0 + (1.0 - r0) * (x2 * x2 * x), r0, cos, 1.0);
}
//#endif
//#endif

// A ray whose direction makes a valid `Ray` on the CPU (finite, non-zero, d·d finite).
fn valid_dir(d: vec3f) -> bool {
    let dd = fdot(d, d);
    return finite(d.x) && finite(d.y) && finite(d.z) && dd != 0.0 && finite(dd);
}

//#if TRACE
fn log_depth_limit() {
    log_open();
    log_u(params.max_depth);
    log_close(EV_DEPTH_LIMIT);
}

fn log_cutoff(kind: u32, contribution: f32) {
    log_open();
    log_u(kind);
    log_f(contribution);
    log_close(EV_CUTOFF);
}

// The spawned ray's id; the ray stack keeps it with its parent, kind and weight until it is traced.
fn take_ray_id(kind: u32, weight: f32) -> u32 {
    let id = next_ray_id;
    next_ray_id += 1u;
    log_spawn(id);
    pending_ray = vec4u(id, current_ray, kind, bitcast<u32>(weight));
    return id;
}
//#endif

// Shades `hit` of ray task `task` and returns its own (unweighted) colour; pushes the reflection
// and refraction rays with their weights. The steps run in the CPU's order (reflection, then
// refraction, then Schlick's blend); the rays are pushed refraction first, so the reflection ray
// is traced first, as the CPU's recursion does.
fn closest_hit(hit: Hit, task: Task) -> vec3f {
    let r = task.ray;
    var m = materials[objects[hit.object].material];
    let it = interact(hit, r);
//#if TRACE
//#if INSTANCES
    log_instance_hit(hit, it);
//#endif
    log_open();
    log_v(it.point);
    log_v(it.normal);
    log_b(it.inside);
    log_v(it.error);
    log_v(spawn_origin(it, it.normal));
    log_close(EV_SURFACE);
//#if SMOOTH
    log_shading_normal(hit, it);
//#endif
//#endif
//#if TEXTURES
    // The texture's colour multiplies the material's (Phong's ambient and diffuse terms use it).
    let cone_d = cone_reach(task.depth, hit, r);
    if m.texture != NO_TEXTURE {
        let th = texture_at(hit, it, m.texture, r, cone_d);
        m.color = m.color * th.texel;
//#if TRACE
        log_texture(hit, th, m.color);
//#endif
    }
//#endif
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
//#if TRACE
        var blocked_by = NO_OBJECT;
//#endif
        // A light behind the surface contributes only ambient: no shadow ray.
        if fdot(to_light, it.shading) > 0.0 {
//#if TRACE
            log_open();
            log_u(li);
            log_f(flen(to_light));
            log_close(EV_SHADOW_RAY);
//#endif
            let o = spawn_origin(it, to_light);
            let d = light.position - o;
            if valid_dir(d) {
//#if TRACE
                let parent = current_ray;
                let sid = next_ray_id;
                next_ray_id += 1u;
                log_spawn(sid);
                log_ray(sid, parent, KIND_SHADOW, task.depth + 1u, Ray(o, d, 0.0, SHADOW_T_MAX), 0.0);
                blocker = no_hit();
                current_ray = sid;
//#endif
                blocked = traversal_any(Ray(o, d, 0.0, SHADOW_T_MAX));
//#if TRACE
                log_end(blocker);
                current_ray = parent;
                blocked_by = blocker.object;
//#endif
            }
        }
        let terms = phong(m, light, it.point, it.eye, it.shading, blocked);
        let total = terms.ambient + terms.diffuse + terms.specular;
//#if TRACE
        log_open();
        log_u(li);
        log_b(blocked);
        log_u(blocked_by);
        log_f(terms.l_dot_n);
        log_f(terms.r_dot_e);
        log_v(terms.ambient);
        log_v(terms.diffuse);
        log_v(terms.specular);
        log_v(terms.light_dir);
        log_v(terms.reflected);
        log_v(it.eye);
        log_v(total);
        log_close(EV_LIGHT);
//#endif
        surface += total;
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
    var refract_weight = m.transparency;
    var n = vec2f(1.0, 1.0);
//#if REFLECTION
    var blend = false;
    var fresnel = vec4f(1.0, 0.0, 0.0, 0.0);
//#endif
    if m.transparency > 0.0 {
        n = media_indices(task.media, hit.object, m.refractive_index);
//#if REFLECTION
        if m.reflective > 0.0 {
            blend = true;
            fresnel = schlick(fdot(it.eye, it.shading), n.x, n.y);
            reflect_weight = m.reflective * fresnel.x;
            refract_weight = m.transparency * (1.0 - fresnel.x);
        }
//#endif
    }
//#endif
//#if REFLECTION
    // The reflection ray. The weight cut-off (crates/raystep-core/src/trace/tracer.rs WEIGHT_CUTOFF): a ray whose
    // share of the pixel is below it is not spawned. Written as "not below" so NaN compares as on
    // the CPU.
    var push_reflection = false;
    var reflect_d = vec3f(0.0);
//#if TRACE
    var reflect_info = vec4u(0u);
//#endif
    if m.reflective > 0.0 {
        if can_recurse {
            reflect_d = mirror_dir(r.dir, it.shading);
//#if TRACE
            log_open();
            log_f(m.reflective);
            log_v(reflect_d);
            log_f(fdot(r.dir, it.shading));
            log_close(EV_REFLECT);
//#endif
            if !(task.weight * reflect_weight < WEIGHT_CUTOFF) {
                push_reflection = true;
//#if TRACE
                _ = take_ray_id(KIND_REFLECTION, m.reflective);
                reflect_info = pending_ray;
//#endif
            }
//#if TRACE
            else {
                log_cutoff(KIND_REFLECTION, task.weight * reflect_weight);
            }
//#endif
        }
//#if TRACE
        else {
            log_depth_limit();
        }
//#endif
    }
//#endif
//#if REFRACTION
    var push_refraction = false;
    var refract_d = vec3f(0.0);
    if m.transparency > 0.0 {
        if can_recurse {
            let snell = refract_dir(it.eye, it.shading, n.x, n.y);
            refract_d = snell.dir;
//#if TRACE
            log_open();
            log_f(n.x);
            log_f(n.y);
            log_f(snell.cos_i);
            log_f(snell.sin2_t);
            log_b(snell.tir);
            log_v(snell.dir);
            log_f(snell.eta);
            log_v(it.eye);
            log_f(snell.cos_t);
            log_close(EV_REFRACT);
//#endif
            if valid_dir(refract_d) {
                if !(task.weight * refract_weight < WEIGHT_CUTOFF) {
                    push_refraction = true;
//#if TRACE
                    _ = take_ray_id(KIND_REFRACTION, m.transparency);
//#endif
                }
//#if TRACE
                else {
                    log_cutoff(KIND_REFRACTION, task.weight * refract_weight);
                }
//#endif
            }
        }
//#if TRACE
        else if m.reflective == 0.0 {
            log_depth_limit();
        }
//#endif
//#if REFLECTION
//#if TRACE
        if blend {
            log_open();
            log_v(fresnel.xyz);
            log_f(fresnel.w);
            log_close(EV_SCHLICK);
        }
//#endif
//#endif
    }
    if push_refraction {
        let media = media_crossed(task.media, hit.object);
        push_ray(Ray(spawn_origin(it, refract_d), refract_d, 0.0, params.inf), task.depth + 1u, task.weight * refract_weight, media, FOLD_REFRACTION);
    }
//#endif
//#if REFLECTION
    if push_reflection {
//#if TRACE
        pending_ray = reflect_info;
//#endif
//#if REFRACTION
        push_ray(Ray(spawn_origin(it, reflect_d), reflect_d, 0.0, params.inf), task.depth + 1u, task.weight * reflect_weight, task.media, FOLD_REFLECTION);
//#else
        push_ray(Ray(spawn_origin(it, reflect_d), reflect_d, 0.0, params.inf), task.depth + 1u, task.weight * reflect_weight, FOLD_REFLECTION);
//#endif
    }
//#endif
    // How trace() adds the children's colours to this one (crates/raystep-core/src/trace/whitted.rs `shade`).
    var coef = vec4f(0.0);
//#if REFLECTION
    coef.x = m.reflective;
//#endif
//#if REFRACTION
    coef.y = m.transparency;
//#if REFLECTION
    if blend {
        coef.z = fresnel.x;
        coef.w = 1.0;
    }
//#endif
//#endif
    hit_coef = coef;
    return surface;
}
