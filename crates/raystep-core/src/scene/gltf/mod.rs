//! glTF 2.0 scenes (`.gltf` and `.glb`), read through the `gltf` crate: its JSON and GLB
//! parsing, and its validation, which names the JSON path of a problem.
//!
//! What raystep takes from a file (book/scenes.md, *glTF scenes*): the default scene's node
//! hierarchy, each node's mesh placed by the product of the matrices from the root (a mesh one
//! node places as world triangles; a mesh several nodes place read once, as prototypes, with an
//! instance per node), positions, `NORMAL` (smooth shading) and `TEXCOORD_0` ([`data`]); the
//! materials ([`materials`]); the perspective cameras; `KHR_lights_punctual` point lights. What
//! it does not take is named in one warning, never silently dropped.
//!
//! Files are read through [`crate::io`] rather than the crate's own `import` (which opens them
//! itself), so that the browser build reads them as it reads every other file. The crate's
//! accessor reader assumes the accessor's data fits its buffer (a `debug_assert`, and an
//! overflowing `count − 1` for an empty accessor); [`data::check_accessor`] checks that first, so a
//! malformed file is an error naming its accessor, never a panic.

mod data;
mod materials;

use data::{load_buffers, read_primitive, read_uri};

use super::limits::MAX_OBJECTS;
use super::{Light, Material, Shape, Texture};
use glam::{DMat4, DQuat, DVec3, Vec3};
use std::collections::HashMap;
use std::path::Path;

/// The most bytes a glTF file (or one of its buffers) may hold.
pub const MAX_GLTF_BYTES: u64 = 512 << 20;

/// The deepest node hierarchy read (a deeper one, or a node that is its own ancestor, is an
/// error naming the node).
const MAX_NODE_DEPTH: usize = 256;

/// A glTF file that could not be read: the JSON path of the problem (e.g.
/// `meshes[0].primitives[1].indices`) when there is one, the line and column of a JSON syntax
/// error, and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfError {
    /// The JSON path, when the problem has one.
    pub json_path: Option<String>,
    /// 1-based line and column of a JSON syntax error.
    pub line_col: Option<(usize, usize)>,
    /// What is wrong.
    pub message: String,
}

impl GltfError {
    fn at(path: impl Into<String>, message: impl Into<String>) -> GltfError {
        GltfError {
            json_path: Some(path.into()),
            line_col: None,
            message: message.into(),
        }
    }
    fn whole(message: impl Into<String>) -> GltfError {
        GltfError {
            json_path: None,
            line_col: None,
            message: message.into(),
        }
    }
}

/// One primitive of one node's mesh, in world space.
#[derive(Debug, Clone)]
pub(crate) struct Part {
    /// The node's name (or `node i`), with `/p` for the mesh's p-th primitive when it has more
    /// than one.
    pub name: String,
    /// Its triangles.
    pub triangles: Vec<Shape>,
    /// Per triangle: its unit vertex normals where the primitive has `NORMAL` (empty if not).
    pub normals: Vec<Option<[Vec3; 3]>>,
    /// Per triangle: its texture coordinates where it has `TEXCOORD_0` (empty if not), v
    /// turned to raystep's convention (glTF's v runs down the image, raystep's up).
    pub uvs: Vec<Option<[[f32; 2]; 3]>>,
    /// Its material: an index into [`Imported::materials`].
    pub material: usize,
    /// A prototype: the primitive of a mesh that several nodes place, in the mesh's own space
    /// (drawn only where [`Imported::instances`] place it).
    pub prototype: bool,
}

/// A node's placement of a mesh that several nodes place: an instance of one of its primitives.
#[derive(Debug, Clone)]
pub(crate) struct GltfInstance {
    /// The node's name (or `node i`), with `/p` for the mesh's p-th primitive when it has more
    /// than one: the name its triangles would have had, copied into the world.
    pub name: String,
    /// The prototype: an index into [`Imported::parts`].
    pub part: usize,
    /// The node's world matrix (its ancestors' and the including table's placement composed, in
    /// f64).
    pub matrix: DMat4,
}

/// A glTF perspective camera, placed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GltfCamera {
    /// The camera's name, else its node's, else `camera i`.
    pub name: String,
    /// Eye, point looked at (one unit along −Z of the node) and up (+Y of the node).
    pub from: DVec3,
    /// The point one unit ahead.
    pub at: DVec3,
    /// The up direction.
    pub up: DVec3,
    /// Vertical field of view, degrees.
    pub fov: f64,
    /// Width over height, when the file gives it.
    pub aspect: Option<f64>,
}

impl GltfCamera {
    /// Whether a scene can look through it: a field of view strictly between 0° and 180°, and
    /// an up direction not along the view.
    pub(crate) fn usable(&self) -> bool {
        let sideways = (self.at - self.from).cross(self.up).length();
        self.fov > 0.0 && self.fov < 180.0 && sideways > 1e-9
    }
}

/// What a glTF file gave, ready for the scene: every name is prefixed by the include's.
#[derive(Debug, Clone)]
pub(crate) struct Imported {
    /// The primitives, in the order of a depth-first walk of the scene's nodes (a mesh that
    /// several nodes place: once, as prototypes, where its first node is met).
    pub parts: Vec<Part>,
    /// The nodes' placements of the meshes that several nodes place.
    pub instances: Vec<GltfInstance>,
    /// The materials the parts use (the glTF default material last, if a primitive has none).
    pub materials: Vec<Material>,
    /// The textures the materials use (indices in the materials count from 0 here).
    pub textures: Vec<Texture>,
    /// `KHR_lights_punctual` point lights.
    pub lights: Vec<Light>,
    /// The perspective cameras, in walk order.
    pub cameras: Vec<GltfCamera>,
    /// What was not read, one line each.
    pub warnings: Vec<String>,
    /// The world-space box of every vertex (None: no triangles).
    pub bounds: Option<(DVec3, DVec3)>,
    /// SHA-256 of the file's bytes (hex; empty from [`import_bytes`]), which names a glTF file
    /// opened as a scene.
    pub source_hash: String,
}

/// Reads a glTF file (`.gltf`, `.glb`): its buffers and images (embedded, `data:` URIs, or
/// files beside it), its default scene placed by `place`, every name prefixed by `prefix/`.
/// `texel_budget`: how many texels the scene's images may still take. `share`: a mesh that
/// several nodes place becomes prototypes and instances (else every node's copy is placed in
/// the world, as for a `[[gltf]]` whose `material` emits light).
pub(crate) fn import(
    path: &Path,
    prefix: &str,
    place: DMat4,
    texel_budget: u64,
    share: bool,
) -> Result<Imported, GltfError> {
    let bytes = crate::io::read_input(path, MAX_GLTF_BYTES, "glTF file").map_err(|e| {
        GltfError::whole(if e.kind() == std::io::ErrorKind::NotFound {
            format!("the glTF file {} does not exist", path.display())
        } else {
            format!("cannot read the glTF file {}: {e}", path.display())
        })
    })?;
    let mut imported = import_bytes(&bytes, path, prefix, place, texel_budget, share)?;
    imported.source_hash = crate::text::sha256_hex(&bytes);
    Ok(imported)
}

/// [`import`] of a file's bytes (`path` names it and is where relative URIs start).
pub(crate) fn import_bytes(
    bytes: &[u8],
    path: &Path,
    prefix: &str,
    place: DMat4,
    texel_budget: u64,
    share: bool,
) -> Result<Imported, GltfError> {
    let gltf = parse(bytes)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let buffers = load_buffers(&gltf, &base)?;
    let doc = &gltf.document;
    // What is not read, named in one warning at the end.
    let mut not_read = vec![];
    for ext in doc.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            not_read.push(format!("extension {ext}"));
        }
    }
    let mut mats = materials::Materials::new(doc, &buffers, &base, prefix, texel_budget);
    let mut out = Imported {
        parts: vec![],
        instances: vec![],
        materials: vec![],
        textures: vec![],
        lights: vec![],
        cameras: vec![],
        warnings: vec![],
        bounds: None,
        source_hash: String::new(),
    };
    let node_names = unique_names(doc.nodes().map(|n| n.name()), "node");
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => {
            // No scene: every node that is nobody's child is a root.
            let mut child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !child[n.index()]).collect()
        }
    };
    if doc.scenes().len() > 1 {
        not_read.push(format!(
            "scenes other than the default ({} in the file)",
            doc.scenes().len()
        ));
    }
    let mut visited = vec![false; doc.nodes().len()];
    // (node, mesh, the node's world matrix) of every node with a mesh, in walk order.
    let mut placed_meshes: Vec<(usize, usize, DMat4)> = vec![];
    let mut stack: Vec<(gltf::Node, DMat4, usize)> =
        roots.into_iter().rev().map(|n| (n, place, 0)).collect();
    let mut skipped = Skipped::default();
    while let Some((node, parent, depth)) = stack.pop() {
        let i = node.index();
        if visited[i] {
            return Err(GltfError::at(
                format!("nodes[{i}]"),
                "the node is reached twice (a node may have one parent, and no node is its own ancestor)",
            ));
        }
        visited[i] = true;
        if depth > MAX_NODE_DEPTH {
            return Err(GltfError::at(
                format!("nodes[{i}]"),
                format!("the node hierarchy is deeper than {MAX_NODE_DEPTH} levels"),
            ));
        }
        let world = parent * node_matrix(&node);
        if !world.is_finite() {
            return Err(GltfError::at(
                format!("nodes[{i}]"),
                "the node's transform is not finite",
            ));
        }
        if let Some(mesh) = node.mesh() {
            if node.skin().is_some() {
                skipped.skins += 1;
            }
            if mesh.weights().is_some() || node.weights().is_some() {
                skipped.morphs += 1;
            }
            placed_meshes.push((i, mesh.index(), world));
        }
        if let Some(camera) = node.camera() {
            match camera.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    let name = camera
                        .name()
                        .or(node.name())
                        .map_or_else(|| format!("camera {}", camera.index()), str::to_string);
                    out.cameras.push(GltfCamera {
                        name,
                        from: world.transform_point3(DVec3::ZERO),
                        at: world.transform_point3(DVec3::ZERO)
                            + world.transform_vector3(-DVec3::Z).normalize_or_zero(),
                        up: world.transform_vector3(DVec3::Y).normalize_or_zero(),
                        fov: f64::from(p.yfov()).to_degrees(),
                        aspect: p.aspect_ratio().map(f64::from),
                    });
                }
                gltf::camera::Projection::Orthographic(_) => skipped.orthographic += 1,
            }
        }
        if let Some(light) = node.light() {
            use gltf::khr_lights_punctual::Kind;
            match light.kind() {
                Kind::Point => {
                    let name = light
                        .name()
                        .map_or_else(|| format!("light {}", light.index()), str::to_string);
                    let color =
                        DVec3::from(light.color().map(f64::from)) * f64::from(light.intensity());
                    let position = world.transform_point3(DVec3::ZERO);
                    if !color.is_finite() || color.min_element() < 0.0 {
                        return Err(GltfError::at(
                            format!("extensions.KHR_lights_punctual.lights[{}]", light.index()),
                            "the light's colour times its intensity must be finite and not negative",
                        ));
                    }
                    out.lights.push(Light {
                        name: format!("{prefix}/{name}"),
                        position: position.as_vec3(),
                        color: color.as_vec3(),
                    });
                }
                Kind::Directional => skipped.directional += 1,
                Kind::Spot { .. } => skipped.spot += 1,
            }
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, depth + 1));
        }
    }
    // The meshes, placed: a mesh that one node places becomes world triangles; a mesh that
    // several place (the table's box: a top and four legs) becomes prototypes in its own space,
    // read once, and an instance per node, as a scene's `[[instance]]`s (lesson 20). A mesh with
    // an emitting material stays copied into the world (an instance cannot be an area light),
    // and so does a node whose matrix flattens it (an instance needs an inverse).
    let mut uses = vec![0usize; doc.meshes().len()];
    for &(_, m, world) in &placed_meshes {
        if instanceable(world) {
            uses[m] += 1;
        }
    }
    let mesh_names = unique_names(doc.meshes().map(|m| m.name()), "mesh");
    let meshes: Vec<gltf::Mesh> = doc.meshes().collect();
    let taken: std::collections::HashSet<&str> = node_names.iter().map(String::as_str).collect();
    // The first part of each mesh read as prototypes.
    let mut prototypes: Vec<Option<usize>> = vec![None; doc.meshes().len()];
    let mut triangles = 0usize;
    for (i, m, world) in placed_meshes {
        let Some(mesh) = meshes.get(m).cloned() else {
            continue;
        };
        let count = mesh.primitives().len();
        let emits = mesh
            .primitives()
            .any(|p| p.material().emissive_factor().iter().any(|&e| e > 0.0));
        let shared = share && uses[m] > 1 && !emits && instanceable(world);
        if shared && prototypes[m].is_none() {
            prototypes[m] = Some(out.parts.len());
            // Named after the mesh (and set apart from a node of that name).
            let mut base = format!("{prefix}/{}", mesh_names[m]);
            if taken.contains(mesh_names[m].as_str()) {
                base += " (mesh)";
            }
            for prim in mesh.primitives() {
                let name = if count > 1 {
                    format!("{base}/{}", prim.index())
                } else {
                    base.clone()
                };
                if let Some(part) = read_part(
                    &prim,
                    &mesh,
                    &buffers,
                    DMat4::IDENTITY,
                    name,
                    &mut mats,
                    &mut skipped,
                )? {
                    triangles += part.triangles.len();
                    check_triangles(triangles, &mesh, &prim)?;
                    out.parts.push(Part {
                        prototype: true,
                        ..part
                    });
                }
            }
        }
        let node_name = |prim: &gltf::Primitive| {
            if count > 1 {
                format!("{prefix}/{}/{}", node_names[i], prim.index())
            } else {
                format!("{prefix}/{}", node_names[i])
            }
        };
        if shared {
            let Some(first) = prototypes[m] else {
                continue;
            };
            // One instance per primitive read (the prototypes' parts lie side by side).
            let protos = out.parts[first..]
                .iter()
                .take_while(|p| p.prototype)
                .count();
            let read: Vec<gltf::Primitive> = mesh
                .primitives()
                .filter(|p| p.mode() == gltf::mesh::Mode::Triangles)
                .collect();
            for (k, prim) in read.iter().enumerate().take(protos) {
                out.instances.push(GltfInstance {
                    name: node_name(prim),
                    part: first + k,
                    matrix: world,
                });
                let part = &out.parts[first + k];
                if let Some((lo, hi)) = part_bounds(part) {
                    for c in 0..8 {
                        let corner = DVec3::new(
                            if c & 1 == 0 { lo.x } else { hi.x },
                            if c & 2 == 0 { lo.y } else { hi.y },
                            if c & 4 == 0 { lo.z } else { hi.z },
                        );
                        grow(&mut out.bounds, world.transform_point3(corner));
                    }
                }
            }
            continue;
        }
        for prim in mesh.primitives() {
            if let Some(part) = read_part(
                &prim,
                &mesh,
                &buffers,
                world,
                node_name(&prim),
                &mut mats,
                &mut skipped,
            )? {
                triangles += part.triangles.len();
                check_triangles(triangles, &mesh, &prim)?;
                if let Some((lo, hi)) = part_bounds(&part) {
                    grow(&mut out.bounds, lo);
                    grow(&mut out.bounds, hi);
                }
                out.parts.push(part);
            }
        }
    }
    skipped.name(&mut not_read);
    let (materials, textures) = mats.finish(&mut not_read);
    out.materials = materials;
    out.textures = textures;
    if !not_read.is_empty() {
        out.warnings
            .push(format!("not read: {}", not_read.join("; ")));
    }
    Ok(out)
}

/// Whether a node's matrix can place an instance: finite, with an inverse (a node scaled to
/// nothing is copied into the world instead, where its triangles simply cannot be hit).
fn instanceable(m: DMat4) -> bool {
    let det = m.determinant();
    det.is_finite() && det.abs() >= 1e-30 && m.inverse().is_finite()
}

/// A primitive read (placed by `world`), or None for one that is not made of triangles (named
/// in the warning).
fn read_part(
    prim: &gltf::Primitive,
    mesh: &gltf::Mesh,
    buffers: &[Vec<u8>],
    world: DMat4,
    name: String,
    mats: &mut materials::Materials,
    skipped: &mut Skipped,
) -> Result<Option<Part>, GltfError> {
    let at = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
    if prim.mode() != gltf::mesh::Mode::Triangles {
        if !skipped.modes.contains(&format!("{at} ({:?})", prim.mode())) {
            skipped.modes.push(format!("{at} ({:?})", prim.mode()));
        }
        return Ok(None);
    }
    let material = mats.material(&prim.material())?;
    read_primitive(prim, &at, buffers, world, name, material).map(Some)
}

/// The scene's limit on triangles, checked as a primitive is added.
fn check_triangles(
    triangles: usize,
    mesh: &gltf::Mesh,
    prim: &gltf::Primitive,
) -> Result<(), GltfError> {
    if triangles > MAX_OBJECTS {
        return Err(GltfError::at(
            format!("meshes[{}].primitives[{}]", mesh.index(), prim.index()),
            format!(
                "the file's scene holds more than {MAX_OBJECTS} triangles (raystep's limit for a scene)"
            ),
        ));
    }
    Ok(())
}

/// The box of a part's vertices (None: no triangles).
fn part_bounds(part: &Part) -> Option<(DVec3, DVec3)> {
    let mut b = None;
    for s in &part.triangles {
        if let Shape::Triangle { p } = s {
            for v in p {
                grow(&mut b, v.as_dvec3());
            }
        }
    }
    b
}

fn grow(b: &mut Option<(DVec3, DVec3)>, v: DVec3) {
    *b = Some(match *b {
        None => (v, v),
        Some((lo, hi)) => (lo.min(v), hi.max(v)),
    });
}

/// The extensions raystep reads (others in `extensionsUsed` are named in a warning; the crate
/// refuses a file that *requires* one it cannot parse).
const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_emissive_strength",
];

/// What the walk left out, counted, to be named in the file's warning.
#[derive(Default)]
struct Skipped {
    modes: Vec<String>,
    orthographic: usize,
    directional: usize,
    spot: usize,
    skins: usize,
    morphs: usize,
}

impl Skipped {
    fn name(self, w: &mut Vec<String>) {
        if !self.modes.is_empty() {
            w.push(format!(
                "primitives that are not triangles ({})",
                self.modes.join(", ")
            ));
        }
        let counted = [
            (
                self.orthographic,
                "orthographic camera",
                "raystep's camera is perspective",
            ),
            (
                self.directional,
                "directional light",
                "raystep's lights are points and emitting surfaces",
            ),
            (
                self.spot,
                "spot light",
                "raystep's lights are points and emitting surfaces",
            ),
            (self.skins, "skinned mesh", "drawn in its bind pose"),
            (self.morphs, "mesh with morph targets", "drawn without them"),
        ];
        for (n, what, why) in counted {
            if n > 0 {
                w.push(format!(
                    "{n} {what}{} ({why})",
                    if n == 1 { "" } else { "s" }
                ));
            }
        }
    }
}

/// A name for each item: its own where it is given and unique, else `what i`.
fn unique_names<'a>(names: impl Iterator<Item = Option<&'a str>>, what: &str) -> Vec<String> {
    let names: Vec<Option<&str>> = names.collect();
    let mut count: HashMap<&str, usize> = HashMap::new();
    for n in names.iter().flatten() {
        *count.entry(n).or_default() += 1;
    }
    names
        .iter()
        .enumerate()
        .map(|(i, n)| match n {
            Some(n) if count[n] == 1 && !n.is_empty() => n.to_string(),
            _ => format!("{what} {i}"),
        })
        .collect()
}

/// The node's local matrix, in f64 (a matrix as given; else T·R·S from its translation, unit
/// quaternion and scale, as the glTF specification composes them).
fn node_matrix(node: &gltf::Node) -> DMat4 {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = DQuat::from_array(rotation.map(f64::from));
            let q = if q.length_squared() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            DMat4::from_scale_rotation_translation(
                DVec3::from(scale.map(f64::from)),
                q,
                DVec3::from(translation.map(f64::from)),
            )
        }
    }
}

/// The file parsed and validated. gltf-json 1.4.1's validation indexes the accessors with a
/// primitive's POSITION before it checks that index (a panic on a file whose POSITION names an
/// accessor that does not exist), so raystep checks every attribute's index first, and the
/// images' sources (below); and a GLB's declared length.
fn parse(bytes: &[u8]) -> Result<gltf::Gltf, GltfError> {
    // The crate subtracts the 12-byte header from a GLB's declared length unchecked (an
    // overflow where overflow checks are on, as in the debug build): found by the fuzzer.
    if let Some(&[a, b, c, d]) = bytes.get(8..12)
        && bytes.starts_with(b"glTF")
        && u32::from_le_bytes([a, b, c, d]) < 12
    {
        return Err(GltfError::whole(format!(
            "not a valid GLB file: its header gives a length of {} bytes, less than the header's own 12",
            u32::from_le_bytes([a, b, c, d])
        )));
    }
    let unchecked = gltf::Gltf::from_slice_without_validation(bytes).map_err(parse_error)?;
    let json = unchecked.document.as_json();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= json.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "?".into(),
                    };
                    return Err(GltfError::at(
                        format!("meshes[{m}].primitives[{p}].attributes[\"{name}\"]"),
                        format!(
                            "accessor {} does not exist (the file has {})",
                            index.value(),
                            json.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    // The crate's `Image::source` unwraps the `mimeType` of an image in a buffer view and the
    // `uri` of one that is not: both required by the specification, neither validated.
    for (i, image) in json.images.iter().enumerate() {
        let missing = match (&image.buffer_view, &image.mime_type, &image.uri) {
            (Some(_), None, _) => Some("mimeType"),
            (None, _, None) => Some("uri"),
            _ => None,
        };
        if let Some(field) = missing {
            return Err(GltfError::at(
                format!("images[{i}].{field}"),
                "is required and missing (an image gives a uri, or a bufferView and its mimeType)",
            ));
        }
    }
    let gltf::Gltf { document, blob } = unchecked;
    let document = gltf::Document::from_json(document.into_json()).map_err(parse_error)?;
    Ok(gltf::Gltf { document, blob })
}

/// A JSON or GLB error as a [`GltfError`]: validation errors carry their JSON paths, syntax
/// errors their line and column.
fn parse_error(e: gltf::Error) -> GltfError {
    match e {
        gltf::Error::Validation(list) => {
            let mut list = list.into_iter();
            let Some((path, first)) = list.next() else {
                return GltfError::whole("the file is not valid glTF");
            };
            let more = list.len();
            let mut message = validation_words(&first);
            if more > 0 {
                message += &format!(
                    " (and {more} more problem{})",
                    if more == 1 { "" } else { "s" }
                );
            }
            GltfError::at(path.to_string(), message)
        }
        gltf::Error::Deserialize(j) => GltfError {
            json_path: None,
            line_col: (j.line() > 0).then(|| (j.line(), j.column())),
            message: format!("not valid glTF JSON: {j}"),
        },
        gltf::Error::Binary(b) => GltfError::whole(format!("not a valid GLB file: {b}")),
        other => GltfError::whole(format!("cannot read the glTF: {other}")),
    }
}

fn validation_words(e: &gltf::json::validation::Error) -> String {
    use gltf::json::validation::Error as E;
    match e {
        E::IndexOutOfBounds => "refers to an item that does not exist".into(),
        E::Invalid => "is not a valid value here".into(),
        E::Missing => "is required and missing".into(),
        E::Unsupported => {
            "is not supported by raystep (an extension it cannot read is required)".into()
        }
        E::Oversize => "is larger than the crate reading it allows".into(),
    }
}
