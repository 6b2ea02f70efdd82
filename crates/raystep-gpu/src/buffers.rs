//! The scene flattened into the byte layouts of `wgsl/common.wgsl` (WGSL's uniform and storage
//! layout rules: a `vec3f` is 16-byte aligned, so each one is followed by a scalar that fills its
//! fourth slot). Written by hand, little-endian, so no unsafe casting is needed.

use crate::accel::{Bvh, TwoLevel};
use crate::interface::{NO_TEXTURE, texture};
use crate::scene::camera::CameraRays;
use crate::scene::{Filter, NO_UVS, Scene, Shape, TextureKind, Wrap};
use glam::Vec3;

/// A little-endian byte writer.
#[derive(Default)]
pub(crate) struct Bytes(pub Vec<u8>);

impl Bytes {
    fn f32(&mut self, v: f32) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn u32(&mut self, v: u32) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn vec3(&mut self, v: Vec3) -> &mut Self {
        self.f32(v.x).f32(v.y).f32(v.z)
    }
    /// At least one element: a storage buffer may not be empty.
    fn non_empty(mut self, element: usize) -> Vec<u8> {
        if self.0.is_empty() {
            self.0.resize(element, 0);
        }
        self.0
    }
}

/// Size of `Params` in bytes.
pub(crate) const PARAMS_SIZE: u64 = 160;
/// Size of `DebugRecord` in bytes.
pub(crate) const DEBUG_SIZE: u64 = 48;

/// The storage buffers' contents.
pub(crate) struct SceneData {
    pub objects: Vec<u8>,
    pub materials: Vec<u8>,
    pub lights: Vec<u8>,
    pub nodes: Vec<u8>,
    pub leaf_objects: Vec<u8>,
    pub planes: Vec<u8>,
    /// The Monte Carlo integrators' data ([`mc_data`]).
    pub mc: Vec<u8>,
    pub n_nodes: u32,
    pub n_planes: u32,
    /// The objects the world's own accelerator holds (all but the prototypes').
    pub n_world: u32,
    /// The instances, and where their records, the TLAS's nodes and its leaves' lists start
    /// (`wgsl/traversal_instances.wgsl`).
    pub n_instances: u32,
    pub inst_at: u32,
    pub tlas_at: u32,
    pub tlas_leaves: u32,
}

/// Flattens the scene (and its BVH, when it has one; with instances, `two` the TLAS and each
/// prototype's BLAS, after the world's tree).
pub(crate) fn scene_data(scene: &Scene, bvh: Option<&Bvh>, two: Option<&TwoLevel>) -> SceneData {
    // Records after the objects (each the size of an Object): the smooth triangles' vertex
    // normals, the triangles' texture coordinates, the textures, the images' texels.
    let n = |len: usize| len as u32;
    let uvs_at = n(scene.objects.len()) + n(scene.vertex_normals.len());
    let textures_at = uvs_at + n(scene.vertex_uvs.len());
    let mut texels_at = vec![];
    let mut next = textures_at + n(scene.textures.len());
    for t in &scene.textures {
        texels_at.push(next);
        if let TextureKind::Image { texels, .. } = &t.kind {
            next += n(texels.len().div_ceil(4));
        }
    }
    let mut objects = Bytes::default();
    for o in &scene.objects {
        let (kind, axis, a, b, c) = match o.shape {
            Shape::Sphere { center, radius } => (
                0,
                0,
                center.extend(radius),
                glam::Vec4::ZERO,
                glam::Vec4::ZERO,
            ),
            Shape::Plane { normal, offset } => (
                1,
                0,
                normal.extend(offset),
                glam::Vec4::ZERO,
                glam::Vec4::ZERO,
            ),
            Shape::AxisPlane { axis, offset } => (
                2,
                axis as u32,
                glam::Vec4::new(offset, 0.0, 0.0, 0.0),
                glam::Vec4::ZERO,
                glam::Vec4::ZERO,
            ),
            Shape::Triangle { p } => (
                3,
                if o.uvs == NO_UVS {
                    NO_UVS
                } else {
                    uvs_at + o.uvs
                },
                p[0].extend(0.0),
                p[1].extend(0.0),
                p[2].extend(0.0),
            ),
        };
        for v in [a, b, c] {
            objects.vec3(v.truncate()).f32(v.w);
        }
        objects.u32(kind).u32(o.material).u32(axis).u32(o.normals);
    }
    // A smooth triangle's vertex normals, one Object-sized record each after the objects
    // (`objects[params.n_objects + normals]`, n₀ n₁ n₂ in a b c): no binding of their own.
    for n in &scene.vertex_normals {
        for v in n {
            objects.vec3(*v).f32(0.0);
        }
        objects.u32(0).u32(0).u32(0).u32(0);
    }
    // A triangle's texture coordinates: t₀ in a.xy, t₁ in a.zw, t₂ in b.xy.
    for t in &scene.vertex_uvs {
        objects.f32(t[0][0]).f32(t[0][1]).f32(t[1][0]).f32(t[1][1]);
        objects.f32(t[2][0]).f32(t[2][1]).f32(0.0).f32(0.0);
        objects.vec3(Vec3::ZERO).f32(0.0);
        objects.u32(0).u32(0).u32(0).u32(0);
    }
    // The textures (wgsl/texture.wgsl reads these records).
    for (t, first) in scene.textures.iter().zip(&texels_at) {
        match &t.kind {
            TextureKind::Checker { squares, colors } => {
                objects.vec3(colors[0]).f32(squares[0] as f32);
                objects.vec3(colors[1]).f32(squares[1] as f32);
                objects.vec3(Vec3::ZERO).f32(0.0);
                objects.u32(texture::TEX_CHECKER).u32(0).u32(0).u32(*first);
            }
            TextureKind::Image {
                width,
                height,
                filter,
                wrap,
                levels,
                ..
            } => {
                objects.vec3(Vec3::ZERO).f32(0.0);
                objects.vec3(Vec3::ZERO).f32(0.0);
                objects
                    .f32(*width as f32)
                    .f32(*height as f32)
                    .f32(levels.len() as f32)
                    .f32(0.0);
                let filter = match filter {
                    Filter::Nearest => texture::FILTER_NEAREST,
                    Filter::Bilinear => texture::FILTER_BILINEAR,
                    Filter::Trilinear => texture::FILTER_TRILINEAR,
                };
                let wrap = match wrap {
                    Wrap::Repeat => texture::WRAP_REPEAT,
                    Wrap::Clamp => texture::WRAP_CLAMP,
                    Wrap::Mirror => texture::WRAP_MIRROR,
                };
                objects
                    .u32(texture::TEX_IMAGE)
                    .u32(filter)
                    .u32(wrap)
                    .u32(*first);
            }
        }
    }
    // The images' texels, four to a record: a.xyz, b.xyz, c.xyz, then (a.w, b.w, c.w).
    for t in &scene.textures {
        if let TextureKind::Image { texels, .. } = &t.kind {
            for four in texels.chunks(4) {
                let c = |k: usize| four.get(k).copied().unwrap_or(Vec3::ZERO);
                let last = c(3);
                objects.vec3(c(0)).f32(last.x);
                objects.vec3(c(1)).f32(last.y);
                objects.vec3(c(2)).f32(last.z);
                objects.u32(0).u32(0).u32(0).u32(0);
            }
        }
    }
    let mut materials = Bytes::default();
    for m in &scene.materials {
        materials
            .vec3(m.color)
            .f32(m.ambient)
            .f32(m.diffuse)
            .f32(m.specular)
            .f32(m.shininess)
            .f32(m.reflective)
            .f32(m.transparency)
            .f32(m.refractive_index)
            .u32(m.texture.map_or(NO_TEXTURE, |t| textures_at + t))
            .u32(
                m.roughness_texture
                    .filter(|_| m.reads_roughness())
                    .map_or(NO_TEXTURE, |t| textures_at + t),
            );
    }
    let mut lights = Bytes::default();
    for l in &scene.lights {
        lights.vec3(l.position).f32(0.0).vec3(l.color).f32(0.0);
    }
    let mut nodes = Bytes::default();
    let mut leaf_objects = Bytes::default();
    let mut planes = Bytes::default();
    let (mut n_nodes, mut n_planes) = (0, 0);
    let tree = |nodes: &mut Bytes, list: &[crate::accel::bvh::Node]| {
        for n in list {
            nodes
                .vec3(Vec3::from(n.min))
                .u32(n.first)
                .vec3(Vec3::from(n.max))
                .u32(n.count);
        }
    };
    if let Some(bvh) = bvh {
        tree(&mut nodes, &bvh.nodes);
        for &id in &bvh.leaf_objects {
            leaf_objects.u32(id);
        }
        for &id in &bvh.planes {
            planes.u32(id);
        }
        n_nodes = bvh.nodes.len() as u32;
        n_planes = bvh.planes.len() as u32;
    }
    // Each prototype's BLAS after the world's tree (its nodes' `first` counting from its own
    // root, as on the CPU), then the TLAS; the instances' records after every other record.
    let (mut tlas_at, mut tlas_leaves) = (0, 0);
    let mut inst_at = 0;
    if let Some(two) = two.filter(|_| !scene.instances.is_empty()) {
        let mut roots = vec![];
        for b in &two.blas {
            roots.push((
                (nodes.0.len() / 32) as u32,
                (leaf_objects.0.len() / 4) as u32,
            ));
            tree(&mut nodes, &b.nodes);
            for &id in &b.leaf_objects {
                leaf_objects.u32(id);
            }
        }
        tlas_at = (nodes.0.len() / 32) as u32;
        tlas_leaves = (leaf_objects.0.len() / 4) as u32;
        tree(&mut nodes, &two.tlas.nodes);
        for &i in &two.tlas.leaf_instances {
            leaf_objects.u32(i);
        }
        inst_at = (objects.0.len() / 64) as u32;
        instance_records(scene, &mut objects, &roots);
    }
    SceneData {
        objects: objects.non_empty(64),
        materials: materials.non_empty(48),
        lights: lights.non_empty(32),
        nodes: nodes.non_empty(32),
        leaf_objects: leaf_objects.non_empty(4),
        planes: planes.non_empty(4),
        mc: mc_data(scene),
        n_nodes,
        n_planes,
        n_world: scene.world_objects,
        n_instances: scene.instances.len() as u32,
        inst_at,
        tlas_at,
        tlas_leaves,
    }
}

/// Two records per instance (`wgsl/traversal_instances.wgsl`): M⁻¹'s rows with the BLAS's root
/// node and first leaf entry (`roots`, by prototype: for ray queries, the first entry of its
/// primitives' object ids), then M's rows.
fn instance_records(scene: &Scene, objects: &mut Bytes, roots: &[(u32, u32)]) {
    for inst in &scene.instances {
        let (root, leaves) = roots
            .get(inst.prototype as usize)
            .copied()
            .unwrap_or_default();
        for row in inst.to_object.0 {
            objects.f32(row[0]).f32(row[1]).f32(row[2]).f32(row[3]);
        }
        objects.u32(root).u32(leaves).u32(inst.prototype).u32(0);
        for row in inst.to_world.0 {
            objects.f32(row[0]).f32(row[1]).f32(row[2]).f32(row[3]);
        }
        objects.u32(0).u32(0).u32(0).u32(0);
    }
}

/// One bottom-level structure for hardware ray queries: its procedural primitives' boxes (six
/// f32 each) and their count.
pub(crate) struct RqBlas {
    pub aabbs: Vec<u8>,
    pub count: u32,
}

/// The scene for hardware ray queries: every finite world object a procedural primitive of the
/// world's BLAS (its box), and each prototype's objects one BLAS in object space (their boxes
/// widened a little: the hardware carries the ray into object space with its own arithmetic,
/// and a box must not turn away a hit raystep's arithmetic finds on its edge).
/// `leaf_objects` maps a primitive to its object id: the world's from 0 (`n_nodes` of them),
/// each prototype's from the first entry its instances' records name. Planes apart, as with
/// the BVH.
pub(crate) fn ray_query_data(scene: &Scene) -> (SceneData, Vec<RqBlas>) {
    let mut data = scene_data(scene, None, None);
    let mut world = Bytes::default();
    let mut ids = Bytes::default();
    let mut planes = Bytes::default();
    let (mut n, mut n_planes) = (0, 0);
    for (id, o) in scene.world().iter().enumerate() {
        match crate::accel::bvh::shape_bounds(&o.shape) {
            Some((lo, hi)) => {
                world.vec3(lo).vec3(hi);
                ids.u32(id as u32);
                n += 1;
            }
            None => {
                planes.u32(id as u32);
                n_planes += 1;
            }
        }
    }
    let mut blas = vec![RqBlas {
        aabbs: world.0,
        count: n,
    }];
    let mut roots = vec![];
    for p in &scene.prototypes {
        let g = &scene.groups[p.group as usize];
        roots.push((0, (ids.0.len() / 4) as u32));
        let mut aabbs = Bytes::default();
        let mut count = 0;
        for id in g.first..g.first + g.count {
            let Some((lo, hi)) = scene
                .objects
                .get(id as usize)
                .and_then(|o| crate::accel::bvh::shape_bounds(&o.shape))
            else {
                continue;
            };
            let pad = (hi - lo).max_element() * 1e-4
                + lo.abs().max(hi.abs()).max_element() * 8.0 * f32::EPSILON;
            aabbs
                .vec3(lo - Vec3::splat(pad))
                .vec3(hi + Vec3::splat(pad));
            ids.u32(id);
            count += 1;
        }
        blas.push(RqBlas {
            aabbs: aabbs.0,
            count,
        });
    }
    if !scene.instances.is_empty() {
        data.inst_at = (data.objects.len() / 64) as u32;
        let mut objects = Bytes(std::mem::take(&mut data.objects));
        instance_records(scene, &mut objects, &roots);
        data.objects = objects.0;
    }
    data.leaf_objects = ids.non_empty(4);
    data.planes = planes.non_empty(4);
    data.n_nodes = n;
    data.n_planes = n_planes;
    (data, blas)
}

/// The uniform `Params` for a camera.
pub(crate) fn params(
    scene: &Scene,
    cam: &CameraRays,
    data: &SceneData,
    use_bvh: bool,
    debug_pixel: [u32; 2],
    trace_sample: u32,
    pass: [u32; 2],
) -> Vec<u8> {
    let s = &scene.settings;
    let mut b = Bytes::default();
    b.vec3(cam.origin)
        .f32(cam.half_width)
        .vec3(cam.u)
        .f32(cam.half_height)
        .vec3(cam.v)
        .f32(s.epsilon)
        .vec3(cam.w)
        .u32(s.seed)
        .vec3(s.background)
        .u32(s.spp)
        .u32(cam.width)
        .u32(cam.height)
        .u32(s.max_depth)
        .u32(scene.objects.len() as u32)
        .u32(scene.lights.len() as u32)
        .u32(data.n_planes)
        .u32(use_bvh as u32)
        .u32(data.n_nodes)
        .u32(debug_pixel[0])
        .u32(debug_pixel[1])
        .f32(f32::INFINITY)
        .u32(trace_sample)
        .u32(pass[0])
        .u32(pass[1])
        .f32(cam.spread)
        .u32(data.n_world)
        .u32(data.n_instances)
        .u32(data.inst_at)
        .u32(data.tlas_at)
        .u32(data.tlas_leaves);
    debug_assert_eq!(b.0.len() as u64, PARAMS_SIZE);
    b.0
}

use crate::interface::mc_header::{
    LIGHT_WORDS as MC_LIGHT_WORDS, MATERIAL_WORDS as MC_MATERIAL_WORDS, WORDS as MC_HEADER_WORDS,
};
use crate::interface::{bsdf as bsdf_code, integrator as integrator_code, light as light_code};

/// The Monte Carlo integrators' data (`wgsl/mc_integrator.wgsl` reads it as `mc`, one array of
/// 32-bit words): a header (the integrator, the strategy, the sampler, `rr_depth`, the counts and
/// the sections' offsets, the lens), each material's BSDF and emission, the lights of
/// [`crate::mc::lights::Lights`], their running sum of powers, which light each object is, and
/// the light groups (each: its members' offset and count; the members; their running sum of
/// areas). A Whitted scene gets the header alone.
pub(crate) fn mc_data(scene: &Scene) -> Vec<u8> {
    use crate::mc::lights::{LightShape, Lights};
    use crate::scene::{Bsdf, Integrator, SamplerKind, Strategy};
    let s = &scene.settings;
    let lights = if !s.integrator.is_monte_carlo() {
        Lights::default()
    } else {
        Lights::new(scene)
    };
    let n_lights = lights.lights.len() as u32;
    let n_materials = scene.materials.len() as u32;
    let n_objects = scene.objects.len() as u32;
    let n_groups = lights.groups.len() as u32;
    let n_members: u32 = lights.groups.iter().map(|g| g.members.len() as u32).sum();
    let off_materials = MC_HEADER_WORDS;
    let off_lights = off_materials + MC_MATERIAL_WORDS * n_materials;
    let off_cdf = off_lights + MC_LIGHT_WORDS * n_lights;
    let off_by_object = off_cdf + n_lights;
    let off_groups = off_by_object + n_objects;
    let off_members = off_groups + 2 * n_groups;
    let off_group_cdf = off_members + n_members;
    // The header, word by word where the shaders read it (`interface::mc_header`).
    let mut header = [0u32; MC_HEADER_WORDS as usize];
    {
        use crate::interface::{mc_header as h, strategy};
        let mut put = |at: u32, v: u32| header[at as usize] = v;
        put(
            h::INTEGRATOR,
            match s.integrator {
                Integrator::Whitted => integrator_code::WHITTED,
                Integrator::Distribution => integrator_code::DISTRIBUTION,
                Integrator::Path => integrator_code::PATH,
            },
        );
        put(
            h::STRATEGY,
            match s.strategy {
                Strategy::Mis => strategy::MIS,
                Strategy::Light => strategy::LIGHT,
                Strategy::Bsdf => strategy::BSDF,
            },
        );
        put(h::STRATIFIED, (s.sampler == SamplerKind::Stratified) as u32);
        put(h::RR_DEPTH, s.rr_depth);
        put(h::N_LIGHTS, n_lights);
        put(h::N_GROUPS, n_groups);
        put(h::OFF_MATERIALS, off_materials);
        put(h::OFF_LIGHTS, off_lights);
        put(h::OFF_CDF, off_cdf);
        put(h::OFF_BY_OBJECT, off_by_object);
        put(h::OFF_GROUPS, off_groups);
        put(h::OFF_MEMBERS, off_members);
        put(h::OFF_GROUP_CDF, off_group_cdf);
        put(h::APERTURE, scene.camera.aperture.to_bits());
        put(h::FOCUS_DISTANCE, scene.camera.focus_distance.to_bits());
        put(h::MIN_ROUGHNESS, crate::scene::MIN_ROUGHNESS.to_bits());
    }
    let mut b = Bytes::default();
    for w in header {
        b.u32(w);
    }
    for m in &scene.materials {
        let (kind, c, param) = match m.bsdf() {
            Bsdf::Diffuse { albedo } => (bsdf_code::DIFFUSE, albedo, 0.0),
            Bsdf::Mirror { tint } => (bsdf_code::MIRROR, tint, 0.0),
            Bsdf::Glass { ior } => (bsdf_code::GLASS, Vec3::ZERO, ior),
            Bsdf::Glossy { tint, alpha } => (bsdf_code::GLOSSY, tint, alpha),
        };
        b.u32(kind)
            .vec3(c)
            .f32(param)
            .vec3(m.emission)
            .f32(m.roughness);
    }
    let mut by_object = vec![u32::MAX; scene.objects.len()];
    for (i, l) in lights.lights.iter().enumerate() {
        let (kind, a, bb, c, n, area, radius) = match l.shape {
            LightShape::Triangle { p, normal, area } => {
                (light_code::TRIANGLE, p[0], p[1], p[2], normal, area, 0.0)
            }
            LightShape::Sphere { center, radius } => (
                light_code::SPHERE,
                center,
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::ZERO,
                0.0,
                radius,
            ),
            LightShape::Point { position } => (
                light_code::POINT,
                position,
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::ZERO,
                0.0,
                0.0,
            ),
        };
        let object = l.object.unwrap_or(u32::MAX);
        if let Some(slot) = by_object.get_mut(object as usize) {
            *slot = i as u32;
        }
        b.u32(kind)
            .u32(object)
            .vec3(a)
            .vec3(bb)
            .vec3(c)
            .vec3(n)
            .f32(area)
            .f32(radius)
            .vec3(l.radiance)
            .f32(l.power);
    }
    let mut total = 0.0f32;
    for l in &lights.lights {
        total += l.power;
        b.f32(total);
    }
    for o in by_object {
        b.u32(o);
    }
    let mut at = 0;
    for g in &lights.groups {
        b.u32(at).u32(g.members.len() as u32);
        at += g.members.len() as u32;
    }
    for g in &lights.groups {
        for &m in &g.members {
            b.u32(m);
        }
    }
    for g in &lights.groups {
        for &c in &g.cdf {
            b.f32(c);
        }
    }
    b.0
}
