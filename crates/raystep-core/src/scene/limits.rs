//! The limits a scene's numbers are held to, and why (docs/NUMERICS.md): the loader
//! (`load/`) checks the scene file's numbers, the OBJ reader (`obj.rs`) each mesh vertex.

/// The largest magnitude of any number in a scene (coordinates, radii, offsets, colours,
/// coefficients), and of every mesh vertex after scaling. The tracer works in f32, and its
/// highest-degree terms are cubic in coordinate differences: the watertight triangle test's
/// scaled distance e·z sums three products of a 2D edge function (≤ 2·(4C)² after the shear)
/// and a scaled z (≤ 2C·√3), at most ≈ 333·C³ for coordinates within ±C, and Möller–Trumbore's
/// 3×3 determinants are ≤ 48·C³. With C = 1e11 these stay below 3.4e35, a thousand times under
/// f32::MAX (3.4e38); at 1e12 they would reach it. Squared terms (sphere c = f·f − r², lengths)
/// are far smaller. Colours and coefficients multiply at most three deep (light × colour ×
/// coefficient ≤ 1e33), so one bound serves every number.
pub const MAX_MAGNITUDE: f64 = 1e11;

/// The largest magnitude of a triangle's (or a mesh's, once scaled and moved) vertex. The
/// triangle tests stay finite up to [`MAX_MAGNITUDE`], but their answer loses the plane: the
/// ray's distance to it is a sum of products of about C³ that cancels to det · t, so in f32 a
/// triangle of vertices at ±C places its plane only to within about C · 1e-7 of where it is. With
/// vertices at ±1e9 a camera ray 5 units from a slanted triangle's plane gets t = −51 (a miss),
/// at ±1e11 t = −0; at ±1e8 the same ray still hits (t off by 73 %: the stability lab's S18
/// shows the conditioning), and geometry a few units across stays within a fraction of a unit.
pub const MAX_VERTEX: f64 = 1e8;

/// Why a vertex past [`MAX_VERTEX`] is refused.
pub fn vertex_too_large(v: &str) -> String {
    format!(
        "{v} has a component too large: triangle and mesh vertices lie within ±{MAX_VERTEX:e}, beyond which single-precision (f32) triangle tests lose the plane's position (at ±1e9 a camera ray 5 units from a slanted triangle misses it)"
    )
}

/// The largest magnitude of a sphere's centre and radius, a plane's point and offset, a light's
/// position and the camera's points. These enter the kernels only through squares and
/// products of two (sphere: f·f and r², with |f| ≤ 2C), which stay finite in f32 up to
/// C = 1e19 (r² = 1e38 < 3.4e38). A triangle's vertices stay within [`MAX_MAGNITUDE`]: its
/// tests are cubic. (Far-apart geometry past 1e11 may then miss a triangle's test, which
/// overflows to a clean miss, never NaN.)
pub const MAX_COORD: f64 = 1e19;

/// The most primitives a scene may hold, meshes expanded to triangles (about 100 MB of objects,
/// and as much again for the BVH).
pub const MAX_OBJECTS: usize = 2_000_000;
