//! A glTF file's data: its buffers (the GLB's binary chunk, `data:` URIs, files beside it), the
//! accessors checked against them before the `gltf` crate reads them, and a primitive's
//! triangles, normals and texture coordinates placed by a matrix.

use super::{GltfError, MAX_GLTF_BYTES, Part};
use crate::scene::Shape;
use crate::scene::limits::{MAX_OBJECTS, MAX_VERTEX};
use glam::{DMat3, DMat4, DVec3, Vec3};
use gltf::accessor::{DataType, Dimensions};
use std::path::{Path, PathBuf};

/// Every buffer's bytes: the GLB's binary chunk, a `data:` URI, or a file beside the glTF.
pub(super) fn load_buffers(gltf: &gltf::Gltf, base: &Path) -> Result<Vec<Vec<u8>>, GltfError> {
    let mut out = vec![];
    for b in gltf.document.buffers() {
        let at = format!("buffers[{}]", b.index());
        let data = match b.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                GltfError::at(
                    &at,
                    "refers to the GLB's binary chunk, and the file has none",
                )
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(uri, base, &format!("{at}.uri"), "buffer")?,
        };
        if data.len() < b.length() {
            return Err(GltfError::at(
                format!("{at}.byteLength"),
                format!("says {} bytes; the data holds {}", b.length(), data.len()),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// The bytes a URI names: a base64 `data:` URI, or a file relative to `base` (percent-decoded).
pub(super) fn read_uri(uri: &str, base: &Path, at: &str, what: &str) -> Result<Vec<u8>, GltfError> {
    use base64::Engine;
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_, data)) = rest.split_once(";base64,") else {
            return Err(GltfError::at(
                at,
                "a data: URI must be base64 (`data:…;base64,…`)",
            ));
        };
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| GltfError::at(at, format!("the base64 data does not decode: {e}")));
    }
    if uri.contains("://") {
        return Err(GltfError::at(
            at,
            format!(
                "{uri}: raystep reads files beside the glTF and data: URIs, nothing over a network"
            ),
        ));
    }
    let file = urlencoding::decode(uri).map_err(|e| GltfError::at(at, format!("{uri}: {e}")))?;
    let path: PathBuf = base.join(file.as_ref());
    crate::io::read_input(&path, MAX_GLTF_BYTES, what).map_err(|e| {
        GltfError::at(
            at,
            if e.kind() == std::io::ErrorKind::NotFound {
                format!("the {what} file {} does not exist", path.display())
            } else {
                format!("cannot read the {what} file {}: {e}", path.display())
            },
        )
    })
}

/// Checks that an accessor's data lies inside its buffer view and buffer and has one of the
/// expected shapes, so that the crate's reader (which assumes so) cannot fail.
pub(super) fn check_accessor(
    acc: &gltf::Accessor,
    buffers: &[Vec<u8>],
    dims: Dimensions,
    types: &[DataType],
    at: &str,
) -> Result<(), GltfError> {
    let path = format!("accessors[{}]", acc.index());
    let what = format!("{at} (accessor {})", acc.index());
    if acc.dimensions() != dims || !types.contains(&acc.data_type()) {
        return Err(GltfError::at(
            format!("{path}.type"),
            format!(
                "{what}: expected {dims:?} of {}, found {:?} of {:?}",
                types
                    .iter()
                    .map(|t| format!("{t:?}"))
                    .collect::<Vec<_>>()
                    .join(" or "),
                acc.dimensions(),
                acc.data_type()
            ),
        ));
    }
    if acc.sparse().is_some() {
        return Err(GltfError::at(
            format!("{path}.sparse"),
            format!("{what}: sparse accessors are not read by raystep"),
        ));
    }
    if acc.count() == 0 || acc.count() > 3 * MAX_OBJECTS {
        return Err(GltfError::at(
            format!("{path}.count"),
            format!(
                "{what}: count must lie in 1 … {}, got {}",
                3 * MAX_OBJECTS,
                acc.count()
            ),
        ));
    }
    let Some(view) = acc.view() else {
        return Err(GltfError::at(
            format!("{path}.bufferView"),
            format!("{what}: an accessor without a bufferView (all zeros) is not read by raystep"),
        ));
    };
    let elem = acc.data_type().size() * dims.multiplicity();
    let stride = view.stride().unwrap_or(elem);
    let end = (acc.count() - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(acc.offset()));
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset().checked_add(view.length());
    match (end, view_end) {
        (Some(end), Some(view_end))
            if stride >= elem && end <= view.length() && view_end <= buffer_len =>
        {
            Ok(())
        }
        _ => Err(GltfError::at(
            format!("{path}.byteOffset"),
            format!(
                "{what}: {} items of {elem} bytes (stride {stride}) from byte {} do not fit in bufferView {} ({} bytes from byte {} of a {buffer_len}-byte buffer)",
                acc.count(),
                acc.offset(),
                view.index(),
                view.length(),
                view.offset()
            ),
        )),
    }
}

/// One primitive's triangles in world space.
pub(super) fn read_primitive(
    prim: &gltf::Primitive,
    at: &str,
    buffers: &[Vec<u8>],
    world: DMat4,
    name: String,
    material: usize,
) -> Result<Part, GltfError> {
    let get = |b: gltf::Buffer| buffers.get(b.index()).map(Vec::as_slice);
    let reader = prim.reader(get);
    let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
        return Err(GltfError::at(
            format!("{at}.attributes.POSITION"),
            "a primitive needs POSITION",
        ));
    };
    check_accessor(
        &pos_acc,
        buffers,
        Dimensions::Vec3,
        &[DataType::F32],
        &format!("{at}.attributes.POSITION"),
    )?;
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .map(Iterator::collect)
        .unwrap_or_default();
    let normals: Option<Vec<[f32; 3]>> = match prim.get(&gltf::Semantic::Normals) {
        Some(acc) => {
            check_accessor(
                &acc,
                buffers,
                Dimensions::Vec3,
                &[DataType::F32],
                &format!("{at}.attributes.NORMAL"),
            )?;
            reader.read_normals().map(Iterator::collect)
        }
        None => None,
    };
    let uvs: Option<Vec<[f32; 2]>> = match prim.get(&gltf::Semantic::TexCoords(0)) {
        Some(acc) => {
            check_accessor(
                &acc,
                buffers,
                Dimensions::Vec2,
                &[DataType::F32, DataType::U8, DataType::U16],
                &format!("{at}.attributes.TEXCOORD_0"),
            )?;
            reader.read_tex_coords(0).map(|t| t.into_f32().collect())
        }
        None => None,
    };
    let indices: Vec<u32> = match prim.indices() {
        Some(acc) => {
            check_accessor(
                &acc,
                buffers,
                Dimensions::Scalar,
                &[DataType::U8, DataType::U16, DataType::U32],
                &format!("{at}.indices"),
            )?;
            reader
                .read_indices()
                .map(|i| i.into_u32().collect())
                .unwrap_or_default()
        }
        None => (0..positions.len() as u32).collect(),
    };
    for (name, len) in [
        ("NORMAL", normals.as_ref().map(Vec::len)),
        ("TEXCOORD_0", uvs.as_ref().map(Vec::len)),
    ] {
        if let Some(len) = len
            && len != positions.len()
        {
            return Err(GltfError::at(
                format!("{at}.attributes.{name}"),
                format!("holds {len} items; POSITION holds {}", positions.len()),
            ));
        }
    }
    let world_positions: Vec<Vec3> = positions
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let w = world.transform_point3(DVec3::from(p.map(f64::from)));
            if !w.is_finite() || w.abs().max_element() > MAX_VERTEX {
                return Err(GltfError::at(
                    format!("{at}.attributes.POSITION"),
                    format!("vertex {k} {p:?} is at {w:?} once placed: not finite, or past ±{MAX_VERTEX}"),
                ));
            }
            Ok(w.as_vec3())
        })
        .collect::<Result<_, _>>()?;
    // Normals go by the inverse transpose of the matrix's linear part (book/scenes.md, *glTF
    // scenes*: a non-uniform scale would otherwise tilt them), renormalised in f64.
    let normal_matrix = DMat3::from_mat4(world).inverse().transpose();
    let world_normals: Option<Vec<Option<Vec3>>> = normals.map(|ns| {
        ns.iter()
            .map(|n| {
                let w = (normal_matrix * DVec3::from(n.map(f64::from))).try_normalize()?;
                Some(w.as_vec3())
            })
            .collect()
    });
    let mut part = Part {
        name,
        triangles: vec![],
        normals: vec![],
        uvs: vec![],
        material,
        prototype: false,
    };
    let n = positions.len();
    for (f, tri) in indices.chunks_exact(3).enumerate() {
        let [a, b, c] = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        if a >= n || b >= n || c >= n {
            return Err(GltfError::at(
                format!("{at}.indices"),
                format!(
                    "triangle {f} refers to vertex {}, and POSITION holds {n}",
                    a.max(b).max(c)
                ),
            ));
        }
        part.triangles.push(Shape::Triangle {
            p: [world_positions[a], world_positions[b], world_positions[c]],
        });
        if let Some(ns) = &world_normals {
            part.normals.push(match (ns[a], ns[b], ns[c]) {
                (Some(x), Some(y), Some(z)) => Some([x, y, z]),
                _ => None,
            });
        }
        if let Some(ts) = &uvs {
            // glTF's (0, 0) is the image's top-left corner; raystep's v = 1 is its top row.
            let t = |k: usize| [ts[k][0], 1.0 - ts[k][1]];
            part.uvs.push(Some([t(a), t(b), t(c)]));
        }
    }
    Ok(part)
}
