// ---- the transparent objects a ray is inside (crates/raystep-core/src/trace/media.rs `Media`): the Ray Tracer
// Challenge's `containers`, carried along with the ray, innermost last. Only the object ids are
// kept; an object's index of refraction is read from its material. ----


struct Media {
    ids: array<u32, 8>,
    len: u32,
}

fn ior_of(id: u32) -> f32 {
    return materials[objects[id].material].refractive_index;
}

// The index of the innermost medium (air when there is none).
fn media_top(m: Media) -> f32 {
    var c = m;
    if c.len == 0u {
        return 1.0;
    }
    return ior_of(c.ids[c.len - 1u]);
}

fn media_position(m: Media, id: u32) -> u32 {
    var c = m;
    for (var k = 0u; k < c.len; k++) {
        if c.ids[k] == id {
            return k;
        }
    }
    return NO_OBJECT;
}

fn media_remove(m: Media, k: u32) -> Media {
    var c = m;
    for (var i = k; i + 1u < c.len; i++) {
        c.ids[i] = c.ids[i + 1u];
    }
    c.len -= 1u;
    return c;
}

// (n1, n2) for a ray crossing the surface of object `id` with index `ior`.
fn media_indices(m: Media, id: u32, ior: f32) -> vec2f {
    let n1 = media_top(m);
    let k = media_position(m, id);
    if k != NO_OBJECT {
        return vec2f(n1, media_top(media_remove(m, k)));
    }
    return vec2f(n1, ior);
}

// The media on the other side of the surface of `id`.
fn media_crossed(m: Media, id: u32) -> Media {
    var c = m;
    let k = media_position(m, id);
    if k != NO_OBJECT {
        return media_remove(m, k);
    }
    if c.len < MAX_MEDIA {
        c.ids[c.len] = id;
        c.len += 1u;
    }
    return c;
}
