// ---- any-hit: decides whether a candidate hit counts. Every raystep surface is opaque, so every
// candidate is accepted; a shadow ray's search ends at its first accepted candidate. ----

fn any_hit(c: Cand) -> bool {
    return c.hit;
}
