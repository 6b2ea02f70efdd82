//! The records of the hit's surface in the GPU's step trace: the interaction (point, normal,
//! error bound), smooth shading's interpolated normal, and the texture lookup with a trilinear
//! read's level of detail, each turned into the CPU's step (`crates/raystep-core/src/trace/`
//! `interaction.rs`, `texture.rs`).

use super::Payload;
use crate::record::Step;
use crate::scene::Scene;

/// A surface record.
pub(super) fn surface_step(p: &mut Payload) -> Result<Step, String> {
    let (point, normal, inside) = (p.v()?, p.v()?, p.b()?);
    let (error_bound, over_point) = (p.v()?, p.v()?);
    Ok(Step::Surface {
        point,
        normal,
        inside,
        error_bound,
        over_point,
    })
}

/// A smooth-shading record: the object, u, v, the shading normal, the geometric normal and the
/// lifted point (the vertex normals are the scene's).
pub(super) fn shading_normal_step(scene: &Scene, p: &mut Payload) -> Result<Step, String> {
    let object = p.u()?;
    let (u, v) = (p.f()?, p.f()?);
    let (normal, geometric, lifted) = (p.v()?, p.v()?, p.v()?);
    let vertex_normals = scene
        .objects
        .get(object as usize)
        .and_then(|_| scene.vertex_normals_of(object))
        .ok_or_else(|| {
            format!("a shading normal on object {object}, which has no vertex normals")
        })?;
    Ok(Step::ShadingNormal {
        vertex_normals: vertex_normals.map(|n| n.to_array()),
        u,
        v,
        normal,
        angle_deg: crate::trace::interaction::angle_deg(
            glam::Vec3::from(normal),
            glam::Vec3::from(geometric),
        ),
        lifted: (scene.settings.terminator == crate::scene::Terminator::Hanika).then_some(lifted),
    })
}

/// A trilinear lookup's level-of-detail record, kept for the `TEXTURE` record that follows it.
pub(super) struct PendingLod {
    lod: crate::trace::texture::LevelOfDetail,
    texels: [crate::trace::texture::TexelRead; 4],
}

/// Reads a `TEXTURE_LOD` record (wgsl/texture.wgsl `log_texture`).
pub(super) fn texture_lod(p: &mut Payload) -> Result<PendingLod, String> {
    use crate::trace::texture::{Cone, LevelOfDetail, TexelRead};
    use glam::Vec3;
    let spread = p.f()?;
    let distance = p.f()?;
    let (width, cos, texels_per_area, footprint, lambda) = (p.f()?, p.f()?, p.f()?, p.f()?, p.f()?);
    let levels = [p.u()?, p.u()?];
    let count = (p.u()? as usize).clamp(1, 2);
    let fraction = p.f()?;
    let mut addresses = [[0.0f32; 2]; 2];
    let mut colors = [Vec3::ZERO; 2];
    for k in 0..2 {
        addresses[k] = [p.f()?, p.f()?];
        colors[k] = Vec3::from(p.v()?);
    }
    let mut texels = [TexelRead {
        level: levels[1],
        at: [0; 2],
        color: Vec3::ZERO,
        weight: 0.0,
    }; 4];
    for t in &mut texels {
        t.at = [p.u()?, p.u()?];
        t.color = Vec3::from(p.v()?);
        t.weight = p.f()?;
    }
    Ok(PendingLod {
        lod: LevelOfDetail {
            cone: Cone { spread, distance },
            width,
            cos,
            texels_per_area,
            footprint,
            lambda,
            levels,
            count,
            fraction,
            addresses,
            colors,
        },
        texels,
    })
}

/// A texture record as the CPU's `Texture` step: the numbers the GPU computed, with the
/// texture's name, kind and settings, a triangle's vertex texture coordinates and a plane's
/// axes taken from the scene (which the GPU read, not computed); a trilinear lookup's level of
/// detail from the `TEXTURE_LOD` record before it; a roughness texture's roughness from the
/// `ROUGHNESS` record before it.
pub(super) fn texture_step(
    scene: &Scene,
    p: &mut Payload,
    pending: Option<PendingLod>,
    roughness: Option<f32>,
) -> Result<Step, String> {
    use crate::interface::texture as code;
    use crate::record::texturing::UvMapping;
    use crate::scene::Shape;
    use crate::trace::texture::{Lookup, TexCoords, TexelRead, Texturing, texture_axes};
    use glam::Vec3;
    let object = p.u()?;
    let barycentric = [p.f()?, p.f()?];
    let mapping = match p.u()? {
        code::UV_VERTEX_UVS => UvMapping::VertexUvs,
        code::UV_BARYCENTRIC => UvMapping::Barycentric,
        code::UV_SPHERE => UvMapping::Sphere,
        code::UV_PLANE => UvMapping::Plane,
        other => return Err(format!("a texture record with mapping code {other}")),
    };
    let uv = [p.f()?, p.f()?];
    let direction = Vec3::from(p.v()?);
    let cell = [p.f()?, p.f()?];
    let odd = p.b()?;
    let wrapped = [p.f()?, p.f()?];
    let address = [p.f()?, p.f()?];
    let mut count = (p.u()? as usize).min(4);
    let first_level = pending.as_ref().map_or(0, |l| l.lod.levels[0]);
    let mut texels = [TexelRead {
        level: first_level,
        at: [0; 2],
        color: Vec3::ZERO,
        weight: 0.0,
    }; 8];
    for t in texels.iter_mut().take(4) {
        t.at = [p.u()?, p.u()?];
        t.color = Vec3::from(p.v()?);
        t.weight = p.f()?;
    }
    if let Some(l) = &pending
        && l.lod.count == 2
    {
        texels[4..].copy_from_slice(&l.texels);
        count += 4;
    }
    let (texel, color) = (Vec3::from(p.v()?), Vec3::from(p.v()?));
    let o = scene
        .objects
        .get(object as usize)
        .ok_or_else(|| format!("a texture on object {object}, which does not exist"))?;
    let material = scene.material_of(object);
    let texture = if roughness.is_some() {
        material.roughness_texture
    } else {
        material.texture
    }
    .filter(|t| (*t as usize) < scene.textures.len())
    .ok_or_else(|| format!("a texture on object {object}, whose material has none"))?;
    let t = Texturing {
        texture,
        coords: TexCoords {
            mapping,
            barycentric: matches!(o.shape, Shape::Triangle { .. }).then_some(barycentric),
            vertex_uvs: (mapping == UvMapping::VertexUvs)
                .then(|| scene.vertex_uvs_of(object).copied())
                .flatten(),
            direction: (mapping == UvMapping::Sphere).then_some(direction),
            axes: texture_axes(&o.shape),
            uv,
        },
        lookup: Lookup {
            color: texel,
            cell,
            odd,
            wrapped,
            address,
            texels,
            count,
            lod: pending.map(|l| l.lod),
        },
        color,
        roughness: roughness.map(|r| crate::record::texturing::RoughnessRead {
            material: material.roughness,
            roughness: r,
        }),
    };
    Ok(t.step(scene))
}
