//! The steps of a trace: every [`Step`] a ray can take, with its ray kind, pipeline stage and
//! random numbers. The tree that holds them, and its JSON, is [`super::trace`]; loading a trace
//! needs no scene (object names are stored in the steps).

use crate::shapes::{BoxTest, PlaneTest, SphereTest, TriangleTest};
use serde::{Deserialize, Serialize};

/// The trace format's version. Bump it when a field changes meaning.
pub const TRACE_VERSION: u32 = 1;

/// The kind of a ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum RayKind {
    /// From the camera through the pixel.
    Primary,
    /// From a hit point towards a light.
    Shadow,
    /// Mirror reflection.
    Reflection,
    /// Transmission through a transparent surface.
    Refraction,
    /// A Monte Carlo bounce off a diffuse surface (a direction sampled from its BSDF).
    Diffuse,
    /// A Monte Carlo bounce off a glossy surface (a direction sampled about the mirror direction).
    Glossy,
}

/// The stage of a GPU ray-tracing pipeline (Vulkan / DXR) that would run a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stage {
    /// The ray-generation shader: the camera makes the primary ray.
    RayGeneration,
    /// Fixed-function acceleration-structure traversal (box tests, BVH nodes).
    Traversal,
    /// The intersection shader (custom primitives) or built-in triangle test.
    Intersection,
    /// The any-hit shader: decides whether a candidate hit is accepted.
    AnyHit,
    /// The closest-hit shader: shading and spawning secondary rays.
    ClosestHit,
    /// The miss shader: the ray hit nothing.
    Miss,
}

/// One BVH node visit (recorded by the BVH traversal).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeVisit {
    /// Node index in the tree.
    pub node: u32,
    /// Depth (root = 0).
    pub depth: u32,
    /// The slab test against the node's box.
    pub test: BoxTest<f32>,
    /// Whether the node is a leaf.
    pub leaf: bool,
    /// An inner node's two children (node indices).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub children: Option<[u32; 2]>,
    /// What the traversal did with the node.
    pub action: NodeAction,
    /// The instance whose bottom-level BVH (its prototype's tree, in object space) this node
    /// belongs to; `None` for the world's own BVH.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
}

/// What the traversal did with a node after testing its box. Siblings are recorded in the order
/// they are visited: nearer first, except that a shadow ray (in the BVH and the bounding-sphere
/// tree) takes the farther first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NodeAction {
    /// The ray misses the box, or the box starts beyond the closest hit so far: skipped whole.
    Culled,
    /// An inner node: its children are tested next.
    Descend,
    /// An inner node whose sibling goes first (the nearer one; for a shadow ray, the farther):
    /// pushed on the stack for later.
    Pushed,
    /// A leaf: its primitives are tested (the tests follow).
    TestPrimitives,
}

/// One step of a ray's work.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case")]
pub enum Step {
    /// The camera made the primary ray.
    Camera {
        /// Pixel (x from the left, y from the top).
        pixel: [u32; 2],
        /// Sample index.
        sample: u32,
        /// Position inside the pixel, in [0, 1)² (0.5, 0.5 = the centre).
        #[serde(with = "crate::jsonf")]
        offset: [f32; 2],
        /// Screen coordinates sx, sy in [−1, 1].
        #[serde(with = "crate::jsonf")]
        screen: [f32; 2],
        /// The ray direction.
        #[serde(with = "crate::jsonf")]
        direction: [f32; 3],
    },
    /// A BVH node visit.
    Node(NodeVisit),
    /// A node of the bounding-sphere hierarchy: the ray–sphere test of its bounding sphere
    /// (lesson 2's test, used for culling).
    SphereNode {
        /// Node index in the tree.
        node: u32,
        /// Depth (root = 0).
        depth: u32,
        /// The bounding sphere's centre.
        #[serde(with = "crate::jsonf")]
        center: [f32; 3],
        /// The bounding sphere's radius.
        #[serde(with = "crate::jsonf")]
        radius: f32,
        /// The ray–sphere test against it (its two roots bound where the ray is inside).
        test: SphereTest<f32>,
        /// Whether the node is a leaf.
        leaf: bool,
        /// An inner node's two children (node indices).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        children: Option<[u32; 2]>,
        /// What the traversal did with the node.
        action: NodeAction,
    },
    /// The uniform grid's walk (3D-DDA) enters a cell.
    Cell {
        /// The cell's index on each axis.
        cell: [u32; 3],
        /// Where the ray enters the cell.
        #[serde(with = "crate::jsonf")]
        t_entry: f32,
        /// Where the ray leaves it (a hit is accepted only up to here).
        #[serde(with = "crate::jsonf")]
        t_exit: f32,
        /// The axis the walk stepped along to get here (none for the entry cell).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<u8>,
        /// How many primitives the cell lists.
        primitives: u32,
        /// The cell's box (for the diagrams).
        #[serde(with = "crate::jsonf")]
        min: [f32; 3],
        /// The cell's box.
        #[serde(with = "crate::jsonf")]
        max: [f32; 3],
    },
    /// The grid's mailbox: a primitive listed in this cell was already tested (and missed) in an
    /// earlier one, so it is not tested again.
    MailboxSkip {
        /// Object id.
        object: u32,
        /// Object name.
        name: String,
    },
    /// A ray–sphere test.
    Sphere {
        /// Object id.
        object: u32,
        /// Object name.
        name: String,
        /// Every intermediate.
        test: SphereTest<f32>,
    },
    /// A ray–plane test.
    Plane {
        /// Object id.
        object: u32,
        /// Object name.
        name: String,
        /// Every intermediate.
        test: PlaneTest<f32>,
    },
    /// A ray–triangle test.
    Triangle {
        /// Object id.
        object: u32,
        /// Object name.
        name: String,
        /// The vertices P0, P1, P2.
        #[serde(with = "crate::jsonf")]
        vertices: [[f32; 3]; 3],
        /// Every intermediate.
        test: TriangleTest<f32>,
    },
    /// A candidate hit became the closest so far (the ray's t_max shrinks to it).
    Accept {
        /// Object id.
        object: u32,
        /// Object name.
        name: String,
        /// The new closest t.
        #[serde(with = "crate::jsonf")]
        t: f32,
        /// The previous closest t (∞ at first).
        #[serde(with = "crate::jsonf")]
        previous: f32,
    },
    /// The ray hit nothing: the background colour.
    Miss {
        /// The background colour.
        #[serde(with = "crate::jsonf")]
        background: [f32; 3],
    },
    /// The surface interaction at the closest hit.
    Surface {
        /// Hit point.
        #[serde(with = "crate::jsonf")]
        point: [f32; 3],
        /// Unit normal, facing the incoming ray.
        #[serde(with = "crate::jsonf")]
        normal: [f32; 3],
        /// Whether the ray hit the surface from inside (normal flipped).
        inside: bool,
        /// Rounding-error bound of the hit point, per axis.
        #[serde(with = "crate::jsonf")]
        error_bound: [f32; 3],
        /// Where spawned rays on this side start (after the offset policy).
        #[serde(with = "crate::jsonf")]
        over_point: [f32; 3],
    },
    /// Smooth shading (after the `Surface` step of a triangle with vertex normals): the vertex
    /// normals blended with the hit's barycentrics, s = (1 − u − v)·n₀ + u·n₁ + v·n₂, and
    /// s / |s| turned to the side of the geometric normal.
    ShadingNormal {
        /// The unit vertex normals n₀, n₁, n₂.
        #[serde(with = "crate::jsonf")]
        vertex_normals: [[f32; 3]; 3],
        /// Barycentric u (the weight of n₁).
        #[serde(with = "crate::jsonf")]
        u: f32,
        /// Barycentric v (the weight of n₂).
        #[serde(with = "crate::jsonf")]
        v: f32,
        /// The unit shading normal that lighting, reflection, refraction and the BSDFs use.
        #[serde(with = "crate::jsonf")]
        normal: [f32; 3],
        /// The angle between the shading normal and the geometric normal, in degrees.
        #[serde(with = "crate::jsonf")]
        angle_deg: f32,
        /// Under `terminator = "hanika"`: the point P′ that rays leaving on the ray's side start
        /// from (before the offset), lifted towards the smooth surface (P′ = P where nothing
        /// lifts it).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        lifted: Option<[f32; 3]>,
    },
    /// A texture read at the hit (after the `Surface` step, and `ShadingNormal` if any, of an
    /// object whose material has a texture): the texture coordinates (u, v), the texel or
    /// texels read there, and the colour they give, which multiplies the material's colour.
    Texture {
        /// The texture's name.
        texture: String,
        /// How (u, v) was found.
        mapping: crate::record::texturing::UvMapping,
        /// A triangle's barycentric coordinates (b₁, b₂) at the hit (triangles only).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        barycentric: Option<[f32; 2]>,
        /// A triangle's vertex texture coordinates t₀, t₁, t₂ (`vertex-uvs` only).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        vertex_uvs: Option<[[f32; 2]; 3]>,
        /// A sphere's outward unit direction d at the hit (`sphere` only).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        direction: Option<[f32; 3]>,
        /// A plane's two in-plane axes, u along the first and v along the second (`plane`
        /// only): u = P·a₁, v = P·a₂.
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        axes: Option<[[f32; 3]; 2]>,
        /// The texture coordinates at the hit.
        #[serde(with = "crate::jsonf")]
        uv: [f32; 2],
        /// How the texture was read at (u, v).
        lookup: crate::record::texturing::TexelLookup,
        /// The texture's colour at (u, v) (linear RGB).
        #[serde(with = "crate::jsonf")]
        texel: [f32; 3],
        /// The surface colour: the material's colour × `texel` (a roughness texture's read:
        /// the roughness, in all three).
        #[serde(with = "crate::jsonf")]
        color: [f32; 3],
        /// Set where this is a glossy BSDF's roughness texture, not its colour.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        roughness: Option<crate::record::texturing::RoughnessRead>,
    },
    /// A shadow ray is about to be traced towards a light.
    ShadowRay {
        /// Light index.
        light: u32,
        /// Light name.
        name: String,
        /// Distance to the light.
        #[serde(with = "crate::jsonf")]
        distance: f32,
    },
    /// Phong lighting from one light.
    Light {
        /// Light index.
        light: u32,
        /// Light name.
        name: String,
        /// Whether the light is blocked.
        blocked: bool,
        /// The blocking object's name.
        blocker: Option<String>,
        /// l·n.
        #[serde(with = "crate::jsonf")]
        l_dot_n: f32,
        /// r·e (reflected light direction · eye direction).
        #[serde(with = "crate::jsonf")]
        r_dot_e: f32,
        /// Ambient term.
        #[serde(with = "crate::jsonf")]
        ambient: [f32; 3],
        /// Diffuse term (zero in shadow or when l·n < 0).
        #[serde(with = "crate::jsonf")]
        diffuse: [f32; 3],
        /// Specular term.
        #[serde(with = "crate::jsonf")]
        specular: [f32; 3],
        /// The unit light vector l = (L − P)/|L − P| (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        light_dir: Option<[f32; 3]>,
        /// The reflected light vector r = reflect(−l, n) (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        reflected: Option<[f32; 3]>,
        /// The unit eye vector e (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        eye: Option<[f32; 3]>,
        /// ambient + diffuse + specular, as the tracer summed them (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        total: Option<[f32; 3]>,
    },
    /// A reflection ray is spawned.
    Reflect {
        /// The material's reflectivity.
        #[serde(with = "crate::jsonf")]
        reflective: f32,
        /// The reflected direction r = d − 2(d·n)n.
        #[serde(with = "crate::jsonf")]
        direction: [f32; 3],
        /// d·n, as the reflection computed it (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        d_dot_n: Option<f32>,
    },
    /// Snell's law at a transparent surface.
    Refract {
        /// Index of refraction on the incoming side.
        #[serde(with = "crate::jsonf")]
        n1: f32,
        /// Index of refraction on the far side.
        #[serde(with = "crate::jsonf")]
        n2: f32,
        /// cos θᵢ = e·n.
        #[serde(with = "crate::jsonf")]
        cos_i: f32,
        /// sin² θₜ = (n1/n2)²(1 − cos² θᵢ).
        #[serde(with = "crate::jsonf")]
        sin2_t: f32,
        /// The critical angle in degrees, when n1 > n2.
        #[serde(with = "crate::jsonf")]
        critical_angle_deg: Option<f32>,
        /// Total internal reflection (sin² θₜ > 1): no refracted ray.
        total_internal_reflection: bool,
        /// The refracted direction, unless TIR.
        #[serde(with = "crate::jsonf")]
        direction: Option<[f32; 3]>,
        /// η = n1/n2 (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        eta: Option<f32>,
        /// The unit eye vector e (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        eye: Option<[f32; 3]>,
        /// cos θₜ = √(1 − sin² θₜ), unless TIR (absent in older traces).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        cos_t: Option<f32>,
    },
    /// Schlick's approximation blends reflection and refraction.
    Schlick {
        /// The reflectance R(θ).
        #[serde(with = "crate::jsonf")]
        reflectance: f32,
        /// R0 = ((n1 − n2)/(n1 + n2))², the reflectance head-on (absent in older traces and
        /// under total internal reflection).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        r0: Option<f32>,
        /// The cosine Schlick used: cos θᵢ, or cos θₜ when n1 > n2 (absent in older traces and
        /// under total internal reflection).
        #[serde(
            with = "crate::jsonf",
            skip_serializing_if = "Option::is_none",
            default
        )]
        cos: Option<f32>,
    },
    /// A secondary ray was not traced because the recursion limit was reached.
    DepthLimit {
        /// The limit.
        max_depth: u32,
    },
    /// A reflection or refraction ray was not spawned: its share of the pixel is below the
    /// cut-off (see [`crate::trace::tracer::WEIGHT_CUTOFF`]); its colour counts as black.
    WeightCutoff {
        /// The ray that was not spawned.
        kind: RayKind,
        /// Its share of the pixel: the product of the weights from the camera down to it.
        #[serde(with = "crate::jsonf")]
        contribution: f32,
        /// The cut-off.
        #[serde(with = "crate::jsonf")]
        cutoff: f32,
    },
    /// The recording stops here: the trace reached its step limit. The tracer went on (every
    /// colour in the trace, and the trace's colour, is the one the render computes), but its
    /// remaining steps and rays were not kept.
    Truncated {
        /// The limit, in steps.
        max_steps: u32,
    },
    /// The GPU's hardware walked its own acceleration structure (ray queries, a BLAS and a TLAS):
    /// the boxes it tested are not revealed to the shader, only the primitives whose boxes the
    /// ray entered (their tests follow). Only in GPU traces.
    HardwareTraversal {
        /// Primitive boxes in the hardware's structures (a prototype's counted once for each
        /// instance that places it).
        primitives: u32,
    },
    /// The thin lens: where on the lens the primary ray starts, and the point in focus it aims
    /// at (Monte Carlo integrators, `aperture` > 0).
    Lens {
        /// The two uniform numbers drawn, with their dimensions.
        random: Vec<Draw>,
        /// The point on the lens (the ray's origin).
        #[serde(with = "crate::jsonf")]
        lens_point: [f32; 3],
        /// Where the pinhole ray meets the plane in focus (every lens point aims here).
        #[serde(with = "crate::jsonf")]
        focus_point: [f32; 3],
        /// Density of the lens point, per unit area of the lens: 1/(π r²).
        #[serde(with = "crate::jsonf")]
        pdf: f32,
        /// The ray's direction.
        #[serde(with = "crate::jsonf")]
        direction: [f32; 3],
    },
    /// Next-event estimation: a point sampled on a light, a shadow ray to it (the child ray
    /// spawned just before), and the estimate f · L · cos / pdf with its MIS weight.
    LightSample {
        /// Index of the light in the scene's list of lights the integrator samples.
        light: u32,
        /// The light's name (an object's, or a point light's).
        name: String,
        /// The uniform numbers drawn, with their dimensions (pick a light, then a point on it).
        random: Vec<Draw>,
        /// The point sampled on the light.
        #[serde(with = "crate::jsonf")]
        point: [f32; 3],
        /// Unit direction from the shading point to it.
        #[serde(with = "crate::jsonf")]
        direction: [f32; 3],
        /// Distance to it.
        #[serde(with = "crate::jsonf")]
        distance: f32,
        /// Probability of having picked this light.
        #[serde(with = "crate::jsonf")]
        select_pdf: f32,
        /// Density of the direction, per steradian, the pick included (0 for a point light: a
        /// delta, its estimate divides by the pick's probability only).
        #[serde(with = "crate::jsonf")]
        pdf: f32,
        /// The light's radiance towards the point (a point light: intensity / distance²).
        #[serde(with = "crate::jsonf")]
        radiance: [f32; 3],
        /// The BSDF's value f(wo, wi).
        #[serde(with = "crate::jsonf")]
        bsdf: [f32; 3],
        /// |cos θ| between the direction and the normal.
        #[serde(with = "crate::jsonf")]
        cos: f32,
        /// The BSDF's density of sampling the same direction (the other strategy).
        #[serde(with = "crate::jsonf")]
        bsdf_pdf: f32,
        /// The MIS weight of this strategy (power heuristic; 1 without MIS).
        #[serde(with = "crate::jsonf")]
        mis_weight: f32,
        /// Whether the shadow ray found something in the way.
        blocked: bool,
        /// What it found.
        blocker: Option<String>,
        /// What the sample adds to the pixel: throughput · f · L · cos · w / pdf.
        #[serde(with = "crate::jsonf")]
        contribution: [f32; 3],
    },
    /// A direction sampled from the BSDF at the hit (the next bounce).
    BsdfSample {
        /// The BSDF ("diffuse", "mirror", "glass", "glossy").
        bsdf: String,
        /// Which lobe was taken ("reflection", "transmission").
        lobe: String,
        /// The uniform numbers drawn, with their dimensions.
        random: Vec<Draw>,
        /// The sampled direction.
        #[serde(with = "crate::jsonf")]
        direction: [f32; 3],
        /// Its density per steradian (None for a delta: mirror, glass).
        #[serde(with = "crate::jsonf")]
        pdf: Option<f32>,
        /// The BSDF's value f (for a delta, the weight below stands for f · cos / pdf).
        #[serde(with = "crate::jsonf")]
        value: [f32; 3],
        /// |cos θ| between the direction and the normal.
        #[serde(with = "crate::jsonf")]
        cos: f32,
        /// f · cos / pdf: what the next ray's radiance is multiplied by.
        #[serde(with = "crate::jsonf")]
        weight: [f32; 3],
        /// The path's throughput after this bounce (the product of the weights from the camera).
        #[serde(with = "crate::jsonf")]
        throughput: [f32; 3],
    },
    /// The hit surface emits: its radiance, weighted by MIS against light sampling.
    Emitted {
        /// Object id.
        object: u32,
        /// Object name.
        name: String,
        /// Emitted radiance towards the ray.
        #[serde(with = "crate::jsonf")]
        radiance: [f32; 3],
        /// Density of reaching this point by light sampling from the previous hit (0 when the
        /// previous bounce was the camera or a delta BSDF).
        #[serde(with = "crate::jsonf")]
        light_pdf: f32,
        /// Density of the BSDF sample that made this ray (0 from the camera or a delta).
        #[serde(with = "crate::jsonf")]
        bsdf_pdf: f32,
        /// The MIS weight of this strategy (power heuristic; 1 from the camera or a delta).
        #[serde(with = "crate::jsonf")]
        mis_weight: f32,
        /// What it adds to the pixel: throughput · w · Le.
        #[serde(with = "crate::jsonf")]
        contribution: [f32; 3],
    },
    /// Russian roulette: the path goes on with probability q (its weight divided by q) or ends.
    RussianRoulette {
        /// The uniform number drawn, with its dimension.
        random: Draw,
        /// The probability of going on: min(1, the throughput's largest channel).
        #[serde(with = "crate::jsonf")]
        probability: f32,
        /// Whether the path went on (the number was below the probability).
        survived: bool,
        /// The throughput after the roulette (divided by the probability when it survived).
        #[serde(with = "crate::jsonf")]
        throughput: [f32; 3],
    },
    /// A node of the top-level BVH, the tree over the instances' world-space boxes: its box
    /// tested with the world ray (a leaf's instances are entered next).
    TlasNode(NodeVisit),
    /// The ray carried into an instance's object space by its inverse matrix M⁻¹, before the
    /// prototype's bottom-level BVH is walked: origin S′ = M⁻¹S (a point), direction
    /// Q′ = M⁻¹Q (a vector, not renormalised, so that t means the same point in both spaces).
    Instance {
        /// Index into the scene's instances.
        instance: u32,
        /// The instance's name.
        name: String,
        /// The prototype's name (the mesh, triangle or sphere it places).
        prototype: String,
        /// M⁻¹, 3 × 4 by rows.
        #[serde(with = "crate::jsonf")]
        to_object: [[f32; 4]; 3],
        /// S′, the origin in object space.
        #[serde(with = "crate::jsonf")]
        origin: [f32; 3],
        /// Q′, the direction in object space.
        #[serde(with = "crate::jsonf")]
        direction: [f32; 3],
    },
    /// The closest hit lies on an instance: found in object space, carried back to the world —
    /// the point by M, the normal by the inverse transpose M⁻ᵀ (a normal must stay
    /// perpendicular to the carried surface; under a non-uniform scale M itself would tilt it).
    InstanceHit {
        /// Index into the scene's instances.
        instance: u32,
        /// The instance's name.
        name: String,
        /// M, 3 × 4 by rows.
        #[serde(with = "crate::jsonf")]
        to_world: [[f32; 4]; 3],
        /// M⁻¹, 3 × 4 by rows (its transpose carries the normal).
        #[serde(with = "crate::jsonf")]
        to_object: [[f32; 4]; 3],
        /// The hit point in object space.
        #[serde(with = "crate::jsonf")]
        point: [f32; 3],
        /// The unit normal in object space (facing the object-space ray).
        #[serde(with = "crate::jsonf")]
        normal: [f32; 3],
        /// M·point.
        #[serde(with = "crate::jsonf")]
        world_point: [f32; 3],
        /// M⁻ᵀ·normal, renormalised.
        #[serde(with = "crate::jsonf")]
        world_normal: [f32; 3],
        /// M·normal, renormalised: what the classic mistake computes (shown beside the right
        /// answer; nothing uses it).
        #[serde(with = "crate::jsonf")]
        wrong_normal: [f32; 3],
    },
    /// A child ray was traced here: index into the ray's `children`.
    Spawn {
        /// Index into `children`.
        child: u32,
    },
    /// The ray's final colour (the sum of the terms above).
    Color {
        /// Linear RGB.
        #[serde(with = "crate::jsonf")]
        color: [f32; 3],
    },
}

impl Step {
    /// The pipeline stage that would run this step.
    pub fn stage(&self) -> Stage {
        match self {
            Step::Camera { .. } | Step::Lens { .. } => Stage::RayGeneration,
            Step::Node(_)
            | Step::TlasNode(_)
            | Step::Instance { .. }
            | Step::SphereNode { .. }
            | Step::Cell { .. }
            | Step::MailboxSkip { .. }
            | Step::HardwareTraversal { .. } => Stage::Traversal,
            Step::Sphere { .. } | Step::Plane { .. } | Step::Triangle { .. } => Stage::Intersection,
            Step::Accept { .. } => Stage::AnyHit,
            Step::Miss { .. } => Stage::Miss,
            _ => Stage::ClosestHit,
        }
    }
}

/// One uniform random number and the dimension it was drawn from ([`crate::portable::random::uniform`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Draw {
    /// The dimension.
    pub dimension: u32,
    /// The number, in [0, 1).
    #[serde(with = "crate::jsonf")]
    pub value: f32,
}
