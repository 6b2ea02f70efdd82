//! The transparent media a ray travels through: the objects it is inside, with their indices
//! of refraction, carried down the Whitted recursion (the refraction's η₁ and η₂ come from here).

/// Nesting depth of transparent media a ray can be inside (deeper nesting is ignored).
/// How many media a ray can be inside at once (nested glass); the GPU's stack is as deep.
pub const MAX_MEDIA: usize = 8;

/// The transparent objects a ray is inside, innermost last, with their indices of refraction.
/// This is the Ray Tracer Challenge's `containers` list, carried down the recursion instead of
/// rebuilt from every intersection along the ray.
#[derive(Debug, Clone, Copy, Default)]
pub struct Media {
    ids: [u32; MAX_MEDIA],
    iors: [f32; MAX_MEDIA],
    len: usize,
}

impl Media {
    pub(crate) fn top_ior(&self) -> f32 {
        if self.len == 0 {
            1.0
        } else {
            self.iors[self.len - 1]
        }
    }
    pub(crate) fn position(&self, id: u32) -> Option<usize> {
        self.ids[..self.len].iter().position(|&i| i == id)
    }
    /// (n1, n2) for a ray crossing the surface of object `id` with index `ior`.
    pub(crate) fn indices(&self, id: u32, ior: f32) -> (f32, f32) {
        let n1 = self.top_ior();
        match self.position(id) {
            Some(k) => {
                // Leaving `id`: the far side is whatever encloses us once `id` is removed.
                let mut rest = *self;
                rest.remove(k);
                (n1, rest.top_ior())
            }
            None => (n1, ior),
        }
    }
    pub(crate) fn remove(&mut self, k: usize) {
        self.ids.copy_within(k + 1..self.len, k);
        self.iors.copy_within(k + 1..self.len, k);
        self.len -= 1;
    }
    /// The media on the other side of the surface of `id`.
    pub(crate) fn crossed(&self, id: u32, ior: f32) -> Media {
        let mut m = *self;
        match m.position(id) {
            Some(k) => m.remove(k),
            None if m.len < MAX_MEDIA => {
                m.ids[m.len] = id;
                m.iors[m.len] = ior;
                m.len += 1;
            }
            None => {}
        }
        m
    }
}
