//! OBJ meshes, read through `tobj` (bounded read, regular files only), with the line of the
//! first problem found when tobj rejects a file.

use super::*;
use std::path::Path;

/// tobj reports what is wrong with an OBJ file but not where; find the first line it would
/// reject (a vertex that does not parse, a face index out of range) to say so.
fn locate_obj_problem(path: &Path, text: &str) -> Option<String> {
    let mut vertices: i64 = 0;
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<&str> = words.collect();
                if coords.len() < 3 || coords.iter().take(3).any(|c| c.parse::<f32>().is_err()) {
                    return Some(format!(
                        "{}:{}: `{}` is not a vertex (v X Y Z)",
                        path.display(),
                        n + 1,
                        line.trim()
                    ));
                }
                vertices += 1;
            }
            Some("f") => {
                for w in words {
                    let idx = w.split('/').next().unwrap_or("");
                    let ok = match idx.parse::<i64>() {
                        Ok(i) if i > 0 => i <= vertices,
                        Ok(i) if i < 0 => -i <= vertices,
                        _ => false,
                    };
                    if !ok {
                        return Some(format!(
                            "{}:{}: face refers to vertex {idx}, but only {vertices} vertices are defined above it",
                            path.display(),
                            n + 1
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// How a mesh's triangles are shaded (`[[mesh]] shading`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum MeshShading {
    /// Smooth where the file gives every face its vertex normals (`vn`), flat otherwise.
    Auto,
    /// The geometric normal.
    Flat,
    /// Vertex normals: the file's, else computed ([`computed_normals`]).
    Smooth,
}

/// Each triangle's vertex normals (none for a flat one), or empty when the mesh is flat.
pub(super) type FaceNormals = Vec<Option<[Vec3; 3]>>;

/// Each triangle's vertex texture coordinates (none where its face has no `vt`), or empty.
pub(super) type FaceUvs = Vec<Option<[[f32; 2]; 3]>>;

/// The line of the `k`-th (from 0) `vn` of an OBJ file, for error messages.
fn vn_line(text: &str, k: usize) -> Option<usize> {
    nth_line(text, "vn", k)
}

/// The line of the `k`-th (from 0) statement `keyword` of an OBJ file.
fn nth_line(text: &str, keyword: &str, k: usize) -> Option<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.split_whitespace().next() == Some(keyword))
        .nth(k)
        .map(|(n, _)| n + 1)
}

/// Vertex normals for a mesh whose file has none: at each vertex, the sum of E1 × E2 over the
/// faces around it (a face's cross product is twice its area along its normal, so larger faces
/// weigh more), normalised, in f64. A vertex whose faces cancel (or are all degenerate) has
/// none, and its faces are shaded flat.
fn computed_normals(positions: &[Vec3], faces: &[[usize; 3]]) -> FaceNormals {
    let mut sum = vec![glam::DVec3::ZERO; positions.len()];
    for f in faces {
        let p = f.map(|i| positions[i].as_dvec3());
        let c = (p[1] - p[0]).cross(p[2] - p[0]);
        for &i in f {
            sum[i] += c;
        }
    }
    let unit: Vec<Option<Vec3>> = sum
        .iter()
        .map(|s| crate::math::unit_f64(s.to_array()).map(|u| glam::DVec3::from(u).as_vec3()))
        .collect();
    faces
        .iter()
        .map(|f| Some([unit[f[0]]?, unit[f[1]]?, unit[f[2]]?]))
        .collect()
}

/// Loads an OBJ file's faces (triangulated) as triangles, scaled then translated, with each
/// face's vertex normals where `shading` asks for them (one entry per triangle, or none) and
/// its texture coordinates (`f v/vt`, likewise).
///
/// The OBJ file and any material library it names (`mtllib`) are read through
/// [`crate::io::read_input`]: regular files only, within [`crate::io::limits`]. raystep takes
/// materials from the scene, so a material library that is missing or does not parse is ignored
/// (as tobj does), but one that is not a regular file or is too large is an error.
pub(super) fn load_obj(
    path: &Path,
    translate: Vec3,
    scale: f32,
    shading: MeshShading,
) -> Result<(Vec<Shape>, FaceNormals, FaceUvs), String> {
    use crate::io::{limits, read_input};
    let bytes = read_input(path, limits::OBJ, "OBJ file").map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            format!("OBJ file {} does not exist", path.display())
        } else {
            format!("cannot read OBJ file {}: {e}", path.display())
        }
    })?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let dir = path.parent();
    let mtl_problem: std::cell::RefCell<Option<(std::path::PathBuf, String)>> = None.into();
    let material_loader = |mtl: &Path| -> tobj::MTLLoadResult {
        let full = dir.map_or_else(|| mtl.to_path_buf(), |d| d.join(mtl));
        match read_input(&full, limits::MTL, "MTL file") {
            Ok(b) => tobj::load_mtl_buf(&mut b.as_slice()),
            Err(e) => {
                if e.kind() != std::io::ErrorKind::NotFound {
                    mtl_problem
                        .borrow_mut()
                        .get_or_insert((mtl.to_path_buf(), e.to_string()));
                }
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    let loaded = tobj::load_obj_buf(&mut bytes.as_slice(), &opts, material_loader);
    if let Some((mtl, e)) = mtl_problem.into_inner() {
        let text = String::from_utf8_lossy(&bytes);
        let line = text
            .lines()
            .position(|l| {
                l.trim_start()
                    .strip_prefix("mtllib")
                    .is_some_and(|r| Path::new(r.trim()) == mtl)
            })
            .map_or(String::new(), |n| format!(":{}", n + 1));
        return Err(format!(
            "{}{line}: material library {}: {e}",
            path.display(),
            mtl.display()
        ));
    }
    let (models, _) =
        loaded.map_err(
            |e| match locate_obj_problem(path, &String::from_utf8_lossy(&bytes)) {
                Some(at) => format!("cannot load OBJ file: {at} ({e})"),
                None => format!("cannot load OBJ file {}: {e}", path.display()),
            },
        )?;
    let faces: usize = models.iter().map(|m| m.mesh.indices.len() / 3).sum();
    if faces > MAX_OBJECTS {
        return Err(format!(
            "{} has {faces} triangles, more than the limit of {MAX_OBJECTS} objects in a scene",
            path.display()
        ));
    }
    let mut tris = Vec::with_capacity(faces);
    let mut normals: FaceNormals = vec![];
    let mut uvs: FaceUvs = vec![];
    // Every face has its file normals (OBJ `f v//vn`): tobj gives a normal index per index.
    let file_normals = models
        .iter()
        .all(|m| !m.mesh.indices.is_empty() && m.mesh.normal_indices.len() == m.mesh.indices.len());
    let text = std::cell::OnceCell::new();
    for model in &models {
        let m = &model.mesh;
        let pos = |i: u32| -> Result<Vec3, String> {
            let i = i as usize * 3;
            let p = m.positions.get(i..i + 3).ok_or_else(|| {
                format!(
                    "{}: object \"{}\" refers to vertex {} which does not exist",
                    path.display(),
                    model.name,
                    i / 3 + 1
                )
            })?;
            let v = Vec3::new(p[0], p[1], p[2]) * scale + translate;
            if !v.is_finite() || v.abs().max_element() as f64 > MAX_VERTEX {
                return Err(format!(
                    "{}: vertex {} {p:?} is too large once scaled and moved: {}",
                    path.display(),
                    i / 3 + 1,
                    super::limits::vertex_too_large(&format!("{v:?}"))
                ));
            }
            Ok(v)
        };
        let first = tris.len();
        for f in m.indices.chunks_exact(3) {
            tris.push(Shape::Triangle {
                p: [pos(f[0])?, pos(f[1])?, pos(f[2])?],
            });
        }
        if !m.texcoord_indices.is_empty() && m.texcoord_indices.len() == m.indices.len() {
            // A `vt u v` must be finite (v up: the image's bottom row is v = 0).
            let uv = |i: u32| -> Result<[f32; 2], String> {
                let k = i as usize;
                let t = m.texcoords.get(2 * k..2 * k + 2).ok_or_else(|| {
                    format!(
                        "{}: object \"{}\" refers to texture coordinate {} which does not exist",
                        path.display(),
                        model.name,
                        k + 1
                    )
                })?;
                if t.iter()
                    .all(|c| c.is_finite() && f64::from(c.abs()) <= MAX_MAGNITUDE)
                {
                    return Ok([t[0], t[1]]);
                }
                let line = nth_line(
                    text.get_or_init(|| String::from_utf8_lossy(&bytes).into_owned()),
                    "vt",
                    k,
                )
                .map_or(String::new(), |l| format!(":{l}"));
                Err(format!(
                    "{}{line}: texture coordinate {} (vt {} {}) must be two finite numbers within ±{MAX_MAGNITUDE:e}",
                    path.display(),
                    k + 1,
                    t[0],
                    t[1]
                ))
            };
            uvs.resize(first, None);
            for f in m.texcoord_indices.chunks_exact(3) {
                uvs.push(Some([uv(f[0])?, uv(f[1])?, uv(f[2])?]));
            }
        }
        match shading {
            MeshShading::Flat => {}
            MeshShading::Auto | MeshShading::Smooth if file_normals => {
                // Unit length in f64 (a uniform scale and a translation leave normals as they
                // are); a zero or non-finite `vn` is an error naming its line.
                let normal = |i: u32| -> Result<Vec3, String> {
                    let k = i as usize;
                    let n = m.normals.get(3 * k..3 * k + 3).ok_or_else(|| {
                        format!(
                            "{}: object \"{}\" refers to normal {} which does not exist",
                            path.display(),
                            model.name,
                            k + 1
                        )
                    })?;
                    let v = [n[0] as f64, n[1] as f64, n[2] as f64];
                    crate::math::unit_f64(v)
                        .map(|u| glam::DVec3::from(u).as_vec3())
                        .ok_or_else(|| {
                            let line = vn_line(
                                text.get_or_init(|| String::from_utf8_lossy(&bytes).into_owned()),
                                k,
                            )
                            .map_or(String::new(), |l| format!(":{l}"));
                            format!(
                                "{}{line}: normal {} (vn {} {} {}) must be a non-zero, finite vector",
                                path.display(),
                                k + 1,
                                n[0],
                                n[1],
                                n[2]
                            )
                        })
                };
                normals.resize(first, None);
                for f in m.normal_indices.chunks_exact(3) {
                    normals.push(Some([normal(f[0])?, normal(f[1])?, normal(f[2])?]));
                }
            }
            MeshShading::Auto => {}
            MeshShading::Smooth => {
                let positions: Vec<Vec3> = m
                    .positions
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2]))
                    .collect();
                let faces: Vec<[usize; 3]> = m
                    .indices
                    .chunks_exact(3)
                    .map(|f| [f[0] as usize, f[1] as usize, f[2] as usize])
                    .collect();
                normals.resize(first, None);
                normals.extend(computed_normals(&positions, &faces));
            }
        }
    }
    if tris.is_empty() {
        return Err(format!("OBJ file {} has no faces", path.display()));
    }
    if !normals.is_empty() {
        normals.resize(tris.len(), None);
    }
    if !uvs.is_empty() {
        uvs.resize(tris.len(), None);
    }
    Ok((tris, normals, uvs))
}
