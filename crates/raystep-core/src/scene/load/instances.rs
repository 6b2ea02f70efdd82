//! `[[instance]]` tables: each places a named mesh, triangle or sphere (its prototype) by a
//! matrix. Prototypes move to the end of the object list, after [`Scene::world_objects`], where
//! the world's own accelerators do not see them: they are reached only through their instances.

use super::*;
use crate::scene::instance::{Affine, Instance, Prototype, world_box};
use glam::{DMat4, DQuat, DVec3};

/// The most instances a scene may hold.
pub const MAX_INSTANCES: usize = 1_000_000;

/// A glTF node's placement of a shared mesh's primitive, to become an instance: its name, its
/// prototype's group, its world matrix, and the `[[gltf]]` table it came from (for errors).
pub(super) struct Placement {
    pub(super) name: String,
    pub(super) group: u32,
    pub(super) matrix: DMat4,
    pub(super) what: String,
    pub(super) span: Option<Range<usize>>,
}

/// What the instance tables add to a scene.
pub(super) struct Placed {
    pub(super) instances: Vec<Instance>,
    pub(super) prototypes: Vec<Prototype>,
    pub(super) world_objects: u32,
}

impl Ctx<'_> {
    /// Reads the `[[instance]]` tables (then places `gltf`, the glTF files' nodes that place a
    /// shared mesh), and reorders `objects` (updating `groups`) so that the prototypes' objects
    /// come last.
    pub(super) fn instances(
        &self,
        f: &SceneFile,
        gltf: Vec<Placement>,
        objects: &mut Vec<Object>,
        groups: &mut [Group],
        materials: &[Material],
    ) -> Result<Placed, SceneError> {
        let mut instances: Vec<Instance> = vec![];
        let mut prototypes: Vec<Prototype> = vec![];
        let mut proto_of_group: HashMap<u32, u32> = HashMap::new();
        if f.instance.len() > MAX_INSTANCES {
            let loc = self.loc("instance".into(), &f.instance[MAX_INSTANCES]);
            return Err(loc.err(
                "",
                format!(
                    "a scene holds at most {MAX_INSTANCES} instances, this one {}",
                    f.instance.len()
                ),
            ));
        }
        if let Some(p) = gltf.get(MAX_INSTANCES.saturating_sub(f.instance.len())) {
            return Err(Loc {
                what: p.what.clone(),
                span: p.span.clone(),
                ctx: self,
            }
            .err(
                "file",
                format!(
                    "a scene holds at most {MAX_INSTANCES} instances, this one {} (its glTF files' nodes place {} of them)",
                    f.instance.len() + gltf.len(),
                    gltf.len()
                ),
            ));
        }
        enum Source<'t> {
            Table(usize, &'t toml::Spanned<InstanceDef>),
            Gltf(Placement),
        }
        let sources = f
            .instance
            .iter()
            .enumerate()
            .map(|(i, t)| Source::Table(i, t))
            .chain(gltf.into_iter().map(Source::Gltf));
        for source in sources {
            // The instance's name, where it is written, its prototype's group, its matrix, and
            // the field a bad matrix is reported on.
            let (name, loc, g, m, field) = match source {
                Source::Table(i, t) => {
                    let d = t.get_ref();
                    let name = d.name.clone().unwrap_or_else(|| format!("instance {i}"));
                    let loc = self.loc(format!("instance \"{name}\""), t);
                    if instances.iter().any(|x| x.name == name) {
                        return Err(loc.err(
                            "name",
                            format!("an instance named \"{name}\" is already defined"),
                        ));
                    }
                    let Some(g) = groups.iter().position(|g| g.name == d.of) else {
                        let mut known: Vec<String> = groups
                            .iter()
                            .filter(|g| !is_plane_group(objects, g))
                            .take(12)
                            .map(|g| format!("\"{}\"", g.name))
                            .collect();
                        if known.is_empty() {
                            known
                                .push("none: define a [[mesh]], [[triangle]] or [[sphere]]".into());
                        }
                        return Err(loc.err(
                            "of",
                            format!(
                                "no mesh, triangle or sphere is named \"{}\" (known: {})",
                                d.of,
                                known.join(", ")
                            ),
                        ));
                    };
                    let m = self.instance_matrix(&loc, d)?;
                    let field = if d.matrix.is_some() {
                        ["matrix", "matrix"]
                    } else {
                        ["scale", "translate"]
                    };
                    (name, loc, g, m, field)
                }
                Source::Gltf(p) => {
                    let loc = Loc {
                        what: p.what,
                        span: p.span,
                        ctx: self,
                    };
                    if instances.iter().any(|x| x.name == p.name) {
                        return Err(loc.err(
                            "name",
                            format!(
                                "an instance named \"{}\" is already defined (a node of the glTF file places one of that name: give the [[gltf]] another `name`)",
                                p.name
                            ),
                        ));
                    }
                    (p.name, loc, p.group as usize, p.matrix, ["file", "file"])
                }
            };
            let of = &groups[g].name;
            let group = &groups[g];
            if is_plane_group(objects, group) {
                return Err(loc.err(
                    "of",
                    format!(
                        "\"{of}\" is a plane: an instance places a mesh, a triangle or a sphere (a plane is infinite, and has no box for the top-level BVH)"
                    ),
                ));
            }
            let range = group.first as usize..(group.first + group.count) as usize;
            if let Some(o) = objects[range.clone()]
                .iter()
                .find(|o| materials[o.material as usize].emission.max_element() > 0.0)
            {
                return Err(loc.err(
                    "of",
                    format!(
                        "\"{of}\" emits light (material \"{}\"): an instanced object cannot be an area light (the Monte Carlo integrators sample lights in world space); place a copy without instancing it",
                        materials[o.material as usize].name
                    ),
                ));
            }
            let det = m.determinant();
            if !det.is_finite() || det.abs() < 1e-30 {
                return Err(loc.err(
                    field[0],
                    format!("the matrix is singular (determinant {det:e}): it flattens the object"),
                ));
            }
            let inverse = m.inverse();
            let to_world = Affine::from_dmat4(&m);
            let to_object = Affine::from_dmat4(&inverse);
            if to_object.0.iter().flatten().any(|x| !x.is_finite())
                || to_world.0.iter().flatten().any(|x| !x.is_finite())
            {
                return Err(loc.err(
                    field[0],
                    "the matrix or its inverse does not fit in single precision (f32)",
                ));
            }
            let p = *proto_of_group.entry(g as u32).or_insert_with(|| {
                let (min, max) = objects[range.clone()]
                    .iter()
                    .filter_map(|o| crate::accel::bvh::shape_bounds(&o.shape))
                    .fold(
                        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
                    );
                prototypes.push(Prototype {
                    group: g as u32,
                    min,
                    max,
                });
                prototypes.len() as u32 - 1
            });
            let proto = &prototypes[p as usize];
            let (min, max) = world_box(&m, proto.min, proto.max);
            if min.abs().max(max.abs()).max_element() as f64 > MAX_COORD
                || !min.is_finite()
                || !max.is_finite()
            {
                return Err(loc.err(
                    field[1],
                    format!(
                        "it places \"{of}\" beyond ±{MAX_COORD:e}, where single-precision (f32) tracing stays finite"
                    ),
                ));
            }
            instances.push(Instance {
                name,
                group: g as u32,
                prototype: p,
                to_world,
                to_object,
                min,
                max,
            });
        }
        let world_objects = if prototypes.is_empty() {
            objects.len() as u32
        } else {
            move_prototypes_last(objects, groups, &prototypes)
        };
        Ok(Placed {
            instances,
            prototypes,
            world_objects,
        })
    }

    /// The matrix of an `[[instance]]`: `matrix`, or scale, then rotate, then translate.
    fn instance_matrix(&self, loc: &Loc, d: &InstanceDef) -> Result<DMat4, SceneError> {
        if let Some(rows) = d.matrix {
            if d.translate.is_some() || d.rotate.is_some() || d.scale.is_some() {
                return Err(loc.err(
                    "matrix",
                    "give either `matrix` or `translate`, `rotate` and `scale`, not both",
                ));
            }
            for row in &rows {
                for &x in row {
                    loc.num("matrix", x)?;
                }
            }
            if rows[3] != [0.0, 0.0, 0.0, 1.0] {
                return Err(loc.err(
                    "matrix",
                    format!(
                        "the fourth row must be [0, 0, 0, 1] (an affine placement), got {:?}",
                        rows[3]
                    ),
                ));
            }
            return Ok(DMat4::from_cols_array_2d(&rows).transpose());
        }
        let translate = loc.vec3("translate", d.translate.unwrap_or([0.0; 3]))?;
        let rotate = loc.vec3("rotate", d.rotate.unwrap_or([0.0; 3]))?;
        let scale = match &d.scale {
            None => DVec3::ONE,
            Some(InstanceScale::Uniform(s)) => DVec3::splat(f64::from(loc.num("scale", *s)?)),
            Some(InstanceScale::PerAxis(s)) => loc.vec3("scale", *s)?.as_dvec3(),
        };
        let r = rotate.as_dvec3().to_array().map(f64::to_radians);
        Ok(DMat4::from_scale_rotation_translation(
            scale,
            DQuat::from_rotation_z(r[2])
                * DQuat::from_rotation_y(r[1])
                * DQuat::from_rotation_x(r[0]),
            translate.as_dvec3(),
        ))
    }
}

fn is_plane_group(objects: &[Object], g: &Group) -> bool {
    objects
        .get(g.first as usize)
        .is_some_and(|o| o.shape.is_infinite())
}

/// Moves the prototypes' objects after every other object (keeping each part's order) and
/// updates the groups' `first`; returns the number of world objects.
fn move_prototypes_last(
    objects: &mut Vec<Object>,
    groups: &mut [Group],
    prototypes: &[Prototype],
) -> u32 {
    let is_proto: Vec<bool> = {
        let mut v = vec![false; groups.len()];
        for p in prototypes {
            v[p.group as usize] = true;
        }
        v
    };
    let old = std::mem::take(objects);
    let mut world: Vec<u32> = vec![];
    let mut protos: Vec<u32> = vec![];
    for (gi, g) in groups.iter().enumerate() {
        let ids = g.first..g.first + g.count;
        if is_proto[gi] {
            protos.extend(ids);
        } else {
            world.extend(ids);
        }
    }
    let world_objects = world.len() as u32;
    let order: Vec<u32> = world.into_iter().chain(protos).collect();
    let mut new_first = vec![0u32; groups.len()];
    let mut seen = vec![false; groups.len()];
    for (new, &old_id) in order.iter().enumerate() {
        let o = old[old_id as usize];
        let g = o.group as usize;
        if !seen[g] {
            seen[g] = true;
            new_first[g] = new as u32;
        }
        objects.push(o);
    }
    for (g, first) in groups.iter_mut().zip(new_first) {
        g.first = first;
    }
    world_objects
}
