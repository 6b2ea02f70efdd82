//! Checking a trace read from a file before anything uses it. A trace file is input from outside:
//! serde checks the JSON's shape and types, this module checks what types cannot say — enums
//! stored as numbers, indices into the objects, the lights, a ray's children and the BVH, the
//! BVH outline being a tree, ranges and finite numbers where the readers rely on them, and the
//! size. Every error names the field by its JSON path (`root.children[0].steps[3].test.form.axis`).

use crate::record::{GridOutline, NodeVisit, RayKind, RayRecord, Step, Trace};
use crate::scene::{AccelChoice, Shape};
use crate::shapes::PlaneForm;
use std::collections::BTreeMap;

/// The deepest BVH node a trace may mention (root = 0), and the deepest the BVH builder makes
/// (it cuts a deeper tree here, see [`crate::accel::Bvh::build`]), so that every trace raystep
/// saves loads back. It bounds the diagram's walk down the tree.
pub const MAX_BVH_DEPTH: u32 = 256;
/// The most steps a recorded trace keeps (about 40 MB of JSON), and so the most a loaded one may
/// hold. Beyond it the recorder stops with a [`Step::Truncated`] step; the tracing itself goes
/// on, so colours stay exact.
pub const MAX_TRACE_STEPS: usize = 100_000;
/// The largest `max_depth` a scene (and so a trace) may have.
pub const MAX_RECURSION_DEPTH: u32 = 64;
/// The most cells the uniform grid has along one axis (the builder's limit, and a trace's).
pub const MAX_GRID_CELLS_PER_AXIS: u32 = 256;
/// The largest image side a scene (and so a trace) may have.
const MAX_DIMENSION: u32 = 16384;

/// A field of a trace that is out of range: its JSON path and what is wrong with it.
#[derive(Debug, Clone, PartialEq)]
pub struct Invalid {
    /// The JSON path of the field, e.g. `root.children[0].steps[3].test.form.axis`.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

type Check = Result<(), Invalid>;

fn bad(field: impl Into<String>, message: impl Into<String>) -> Check {
    Err(Invalid {
        field: field.into(),
        message: message.into(),
    })
}

fn finite(field: &str, v: &[f32]) -> Check {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        bad(field, format!("must be finite numbers, got {v:?}"))
    }
}

/// An accelerator's name as a scene file and a trace spell it (`grid`, `spheres`).
fn accel_name(a: AccelChoice) -> String {
    use clap::ValueEnum;
    a.to_possible_value()
        .map_or_else(|| format!("{a:?}"), |v| v.get_name().to_string())
}

fn unit_range(field: &str, x: f32) -> Check {
    if (0.0..=1.0).contains(&x) {
        Ok(())
    } else {
        bad(field, format!("must be between 0 and 1, got {x}"))
    }
}

/// Checks every field of `trace` that a reader indexes with or relies on.
pub fn validate(trace: &Trace) -> Check {
    let s = &trace.settings;
    if s.max_depth > MAX_RECURSION_DEPTH {
        return bad(
            "settings.max_depth",
            format!(
                "must be between 0 and {MAX_RECURSION_DEPTH}, got {}",
                s.max_depth
            ),
        );
    }
    if !(1..=65536).contains(&s.spp) {
        return bad(
            "settings.spp",
            format!("must be between 1 and 65536, got {}", s.spp),
        );
    }
    finite("settings.background", &s.background.to_array())?;
    if !(s.epsilon.is_finite() && s.epsilon > 0.0) {
        return bad(
            "settings.epsilon",
            format!("must be a positive finite number, got {}", s.epsilon),
        );
    }

    let c = &trace.camera;
    finite("camera.from", &c.from.to_array())?;
    finite("camera.at", &c.at.to_array())?;
    finite("camera.up", &c.up.to_array())?;
    if c.from == c.at {
        return bad("camera.at", "must differ from camera.from");
    }
    if !(c.fov > 0.0 && c.fov < 180.0) {
        return bad(
            "camera.fov",
            format!("must lie strictly between 0 and 180 degrees, got {}", c.fov),
        );
    }
    for (name, v) in [("camera.width", c.width), ("camera.height", c.height)] {
        if !(1..=MAX_DIMENSION).contains(&v) {
            return bad(
                name,
                format!("must be between 1 and {MAX_DIMENSION} pixels, got {v}"),
            );
        }
    }
    if trace.pixel[0] >= c.width || trace.pixel[1] >= c.height {
        return bad(
            "pixel",
            format!(
                "({}, {}) is outside the {}×{} image",
                trace.pixel[0], trace.pixel[1], c.width, c.height
            ),
        );
    }
    if trace.sample >= s.spp {
        return bad(
            "sample",
            format!(
                "must be below settings.spp = {}, got {}",
                s.spp, trace.sample
            ),
        );
    }

    for (i, l) in trace.lights.iter().enumerate() {
        finite(&format!("lights[{i}].position"), &l.position.to_array())?;
        finite(&format!("lights[{i}].color"), &l.color.to_array())?;
    }

    let mut ids = BTreeMap::new();
    for (i, o) in trace.objects.iter().enumerate() {
        let at = |f: &str| format!("objects[{i}].{f}");
        if let Some(j) = ids.insert(o.id, i) {
            return bad(at("id"), format!("{} is also the id of objects[{j}]", o.id));
        }
        match o.shape {
            Shape::Sphere { center, radius } => {
                finite(&at("shape.center"), &center.to_array())?;
                if !(radius.is_finite() && radius > 0.0) {
                    return bad(
                        at("shape.radius"),
                        format!("must be a positive finite number, got {radius}"),
                    );
                }
            }
            Shape::Plane { normal, offset } => {
                finite(&at("shape.normal"), &normal.to_array())?;
                finite(&at("shape.offset"), &[offset])?;
                if normal == glam::Vec3::ZERO {
                    return bad(at("shape.normal"), "must be a non-zero vector");
                }
            }
            Shape::AxisPlane { axis, offset } => {
                if axis > 2 {
                    return bad(
                        at("shape.axis"),
                        format!("must be 0, 1 or 2 (x, y, z), got {axis}"),
                    );
                }
                finite(&at("shape.offset"), &[offset])?;
            }
            Shape::Triangle { p } => {
                for (k, v) in p.iter().enumerate() {
                    finite(&at(&format!("shape.p[{k}]")), &v.to_array())?;
                }
            }
        }
        finite(&at("color"), &o.color)?;
        unit_range(&at("reflective"), o.reflective)?;
        unit_range(&at("transparency"), o.transparency)?;
        if !(o.refractive_index.is_finite() && o.refractive_index > 0.0) {
            return bad(
                at("refractive_index"),
                format!(
                    "must be a positive finite number, got {}",
                    o.refractive_index
                ),
            );
        }
    }

    let mut cx = Walk {
        trace,
        nodes: BTreeMap::new(),
        steps: 0,
        truncated: 0,
    };
    if let Some(outline) = &trace.bvh {
        for (i, n) in outline.iter().enumerate() {
            cx.node(
                &format!("bvh[{i}]"),
                n.node,
                n.depth,
                n.children,
                n.children.is_none(),
            )?;
        }
    }
    if let Some(g) = &trace.grid {
        finite("grid.min", &g.min)?;
        finite("grid.max", &g.max)?;
        if (0..3).any(|a| g.min[a] > g.max[a]) {
            return bad(
                "grid.max",
                format!("must not be below grid.min {:?}, got {:?}", g.min, g.max),
            );
        }
        if let Some(n) = g
            .cells
            .iter()
            .find(|n| !(1..=MAX_GRID_CELLS_PER_AXIS).contains(*n))
        {
            return bad(
                "grid.cells",
                format!("each axis has 1 to {MAX_GRID_CELLS_PER_AXIS} cells, got {n}"),
            );
        }
    }
    if trace.root.kind != RayKind::Primary {
        return bad("root.kind", "the root ray must be the primary ray");
    }
    if trace.root.depth != 0 {
        return bad(
            "root.depth",
            format!("the primary ray has depth 0, got {}", trace.root.depth),
        );
    }
    cx.ray("root", &trace.root)?;
    cx.tree()?;
    if let Some(mc) = &trace.monte_carlo {
        monte_carlo(mc, s.spp)?;
    }
    Ok(())
}

/// The Monte Carlo record: its counts, the lights' shapes, the indices its samples use.
fn monte_carlo(mc: &crate::record::samples::McRecord, spp: u32) -> Check {
    use crate::record::samples::LightShape;
    use crate::record::samples::MAX_PIXEL_SAMPLES;
    use crate::scene::Bsdf;
    if mc.spp != spp {
        return bad(
            "monte_carlo.spp",
            format!("must equal settings.spp = {spp}, got {}", mc.spp),
        );
    }
    let kept = (spp as usize).min(MAX_PIXEL_SAMPLES);
    if mc.samples.len() != kept {
        return bad(
            "monte_carlo.samples",
            format!(
                "must hold min(spp, {MAX_PIXEL_SAMPLES}) = {kept} samples, got {}",
                mc.samples.len()
            ),
        );
    }
    if mc.lights.len() > MAX_TRACE_STEPS {
        return bad(
            "monte_carlo.lights",
            format!("at most {MAX_TRACE_STEPS}, got {}", mc.lights.len()),
        );
    }
    let mut indices = std::collections::BTreeSet::new();
    for (i, l) in mc.lights.iter().enumerate() {
        let at = |f: &str| format!("monte_carlo.lights[{i}].{f}");
        finite(&at("radiance"), &l.radiance)?;
        if !indices.insert(l.index) {
            return bad(at("index"), format!("{} appears twice", l.index));
        }
        match l.shape {
            LightShape::Triangle { p, normal, area } => {
                for (k, v) in p.iter().enumerate() {
                    finite(&at(&format!("shape.p[{k}]")), &v.to_array())?;
                }
                finite(&at("shape.normal"), &normal.to_array())?;
                if !(area.is_finite() && area > 0.0) {
                    return bad(at("shape.area"), format!("must be positive, got {area}"));
                }
            }
            LightShape::Sphere { center, radius } => {
                finite(&at("shape.center"), &center.to_array())?;
                if !(radius.is_finite() && radius > 0.0) {
                    return bad(
                        at("shape.radius"),
                        format!("must be positive, got {radius}"),
                    );
                }
            }
            LightShape::Point { position } => {
                finite(&at("shape.position"), &position.to_array())?;
            }
        }
    }
    for (i, b) in mc.bsdfs.iter().enumerate() {
        let at = format!("monte_carlo.bsdfs[{i}].bsdf");
        match b.bsdf {
            Bsdf::Diffuse { albedo: c } | Bsdf::Mirror { tint: c } => finite(&at, &c.to_array())?,
            Bsdf::Glass { ior } if !(ior.is_finite() && ior > 0.0) => {
                return bad(at + ".ior", format!("must be positive, got {ior}"));
            }
            Bsdf::Glossy { tint, alpha } => {
                finite(&at, &tint.to_array())?;
                if !(alpha.is_finite() && alpha > 0.0 && alpha <= 1.0) {
                    return bad(at + ".alpha", format!("must be in (0, 1], got {alpha}"));
                }
            }
            Bsdf::Glass { .. } => {}
        }
    }
    let mut points = 0usize;
    for (i, smp) in mc.samples.iter().enumerate() {
        let at = |f: &str| format!("monte_carlo.samples[{i}].{f}");
        if smp.sample as usize != i {
            return bad(
                at("sample"),
                format!("must be {i} (in order), got {}", smp.sample),
            );
        }
        for (f, v) in [
            ("hit", smp.hit),
            ("normal", smp.normal),
            ("bounce", smp.bounce),
        ] {
            if let Some(v) = v {
                finite(&at(f), &v)?;
            }
        }
        points += smp.light_samples.len();
        if points > MAX_TRACE_STEPS {
            return bad(
                at("light_samples"),
                format!("the samples hold more than {MAX_TRACE_STEPS} light points"),
            );
        }
        for (k, l) in smp.light_samples.iter().enumerate() {
            let at = |f: &str| at(&format!("light_samples[{k}].{f}"));
            if !indices.contains(&l.light) {
                return bad(
                    at("light"),
                    format!("light {} is not in monte_carlo.lights", l.light),
                );
            }
            finite(&at("point"), &l.point)?;
            if !(l.pdf.is_finite() && l.pdf >= 0.0) {
                return bad(
                    at("pdf"),
                    format!("must be a finite density, got {}", l.pdf),
                );
            }
        }
    }
    Ok(())
}

/// What the walk over the rays collects.
struct Walk<'a> {
    trace: &'a Trace,
    /// Every BVH node mentioned: (depth, children), with the path of its first mention.
    nodes: BTreeMap<u32, (u32, Option<[u32; 2]>, String)>,
    steps: usize,
    truncated: usize,
}

impl<'a> Walk<'a> {
    fn object(&self, field: String, id: u32) -> Check {
        if self.trace.objects.iter().any(|o| o.id == id) {
            Ok(())
        } else {
            bad(
                field,
                format!("object {id} is not among the trace's objects"),
            )
        }
    }

    fn light(&self, field: String, index: u32) -> Check {
        if (index as usize) < self.trace.lights.len() {
            Ok(())
        } else {
            bad(
                field,
                format!(
                    "light {index} does not exist: the trace has {} light{}",
                    self.trace.lights.len(),
                    if self.trace.lights.len() == 1 {
                        ""
                    } else {
                        "s"
                    }
                ),
            )
        }
    }

    /// Records a BVH node; every mention of a node must agree on its depth and children.
    fn node(
        &mut self,
        at: &str,
        node: u32,
        depth: u32,
        children: Option<[u32; 2]>,
        leaf: bool,
    ) -> Check {
        if depth > MAX_BVH_DEPTH {
            return bad(
                format!("{at}.depth"),
                format!("must be at most {MAX_BVH_DEPTH}, got {depth}"),
            );
        }
        if leaf != children.is_none() {
            return bad(
                format!("{at}.children"),
                "a leaf has no children and an inner node has two",
            );
        }
        if let Some([a, b]) = children
            && (a == b || a == node || b == node)
        {
            return bad(
                format!("{at}.children"),
                format!("node {node}'s children [{a}, {b}] must be two other nodes"),
            );
        }
        match self.nodes.get(&node) {
            Some((d, c, first)) if (*d, *c) != (depth, children) => bad(
                at.to_string(),
                format!(
                    "node {node} has depth {depth} and children {children:?} here, but depth {d} and children {c:?} at {first}"
                ),
            ),
            Some(_) => Ok(()),
            None => {
                self.nodes.insert(node, (depth, children, at.to_string()));
                Ok(())
            }
        }
    }

    /// The BVH nodes form a tree: node 0 at depth 0, every other node one level below its only
    /// parent. Depth growing by one along every edge makes a cycle impossible.
    fn tree(&self) -> Check {
        let mut parent: BTreeMap<u32, u32> = BTreeMap::new();
        for (&n, (depth, children, at)) in &self.nodes {
            if n == 0 && *depth != 0 {
                return bad(
                    format!("{at}.depth"),
                    format!("node 0 is the root: depth 0, got {depth}"),
                );
            }
            if n != 0 && *depth == 0 {
                return bad(
                    format!("{at}.depth"),
                    format!("only node 0 (the root) has depth 0; node {n} has depth 0"),
                );
            }
            for c in children.iter().flatten() {
                if let Some(p) = parent.insert(*c, n) {
                    return bad(
                        format!("{at}.children"),
                        format!("node {c} is a child of both node {p} and node {n}"),
                    );
                }
                if *c == 0 {
                    return bad(
                        format!("{at}.children"),
                        "node 0 is the root: it is nobody's child",
                    );
                }
                if let Some((cd, _, _)) = self.nodes.get(c)
                    && *cd != depth + 1
                {
                    return bad(
                        format!("{at}.children"),
                        format!(
                            "node {n} at depth {depth} has child {c} at depth {cd}; a child is one level below its parent"
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    /// The grid a cell step or a mailbox skip at `at` belongs to: the trace's `grid` header.
    fn grid(&self, at: &str) -> Result<&'a GridOutline, Invalid> {
        self.trace.grid.as_ref().ok_or_else(|| Invalid {
            field: at.to_string(),
            message: "a step of the uniform grid's walk, but the trace has no `grid` header"
                .to_string(),
        })
    }

    /// A node's depth bound and children, without the world tree's numbering.
    fn shape_of(&mut self, at: &str, v: &NodeVisit) -> Check {
        if v.depth > MAX_BVH_DEPTH {
            return bad(
                format!("{at}.depth"),
                format!("must be at most {MAX_BVH_DEPTH}, got {}", v.depth),
            );
        }
        if v.leaf != v.children.is_none() {
            return bad(
                format!("{at}.children"),
                "a leaf has no children and an inner node has two",
            );
        }
        Ok(())
    }

    fn visit(&mut self, at: &str, v: &NodeVisit) -> Check {
        self.node(at, v.node, v.depth, v.children, v.leaf)
    }

    fn ray(&mut self, at: &str, r: &RayRecord) -> Check {
        let max = self.trace.settings.max_depth + 1;
        if r.depth > max {
            return bad(
                format!("{at}.depth"),
                format!(
                    "must be at most settings.max_depth + 1 = {max}, got {}",
                    r.depth
                ),
            );
        }
        let mut spawned = 0usize;
        for (k, s) in r.steps.iter().enumerate() {
            let sat = format!("{at}.steps[{k}]");
            self.steps += 1;
            if self.steps > MAX_TRACE_STEPS + 1 {
                return bad(
                    sat,
                    format!("a trace holds at most {MAX_TRACE_STEPS} steps"),
                );
            }
            match &s.step {
                // A BLAS's nodes (of a prototype's tree, numbered in it) and the TLAS's are
                // checked for shape; the world tree's numbering does not apply to them.
                Step::Node(v) if v.instance.is_some() => self.shape_of(&sat, v)?,
                Step::TlasNode(v) => self.shape_of(&sat, v)?,
                Step::Node(_) if self.trace.grid.is_some() => {
                    return bad(
                        sat,
                        "a BVH node in a trace of the uniform grid (it has a `grid` header)",
                    );
                }
                Step::Node(v) => self.visit(&sat, v)?,
                // A sphere tree follows the BVH's rules: depth bounded, two distinct children.
                Step::SphereNode {
                    node,
                    depth,
                    center,
                    radius,
                    children,
                    leaf,
                    ..
                } => {
                    if self.trace.grid.is_some() {
                        return bad(
                            sat,
                            "a bounding-sphere node in a trace of the uniform grid (it has a `grid` header)",
                        );
                    }
                    if self.trace.bvh.is_some() {
                        return bad(
                            sat,
                            "a bounding-sphere node in a trace of the BVH (it has a `bvh` outline)",
                        );
                    }
                    if self.trace.settings.accel != AccelChoice::Spheres {
                        return bad(
                            sat,
                            format!(
                                "a bounding-sphere node in a trace made with `settings.accel` = {}, not the sphere tree (spheres)",
                                accel_name(self.trace.settings.accel)
                            ),
                        );
                    }
                    finite(&format!("{sat}.center"), center)?;
                    if !(radius.is_finite() && *radius >= 0.0) {
                        return bad(
                            format!("{sat}.radius"),
                            format!("must be a finite number, 0 or more, got {radius}"),
                        );
                    }
                    self.node(&sat, *node, *depth, *children, *leaf)?
                }
                Step::MailboxSkip { object, .. } => {
                    self.grid(&sat)?;
                    self.object(format!("{sat}.object"), *object)?
                }
                Step::Cell {
                    cell,
                    axis,
                    min,
                    max,
                    ..
                } => {
                    let g = self.grid(&sat)?;
                    if (0..3).any(|a| cell[a] >= g.cells[a]) {
                        return bad(
                            format!("{sat}.cell"),
                            format!("cell {cell:?} lies outside the grid's {:?} cells", g.cells),
                        );
                    }
                    if let Some(a) = axis
                        && *a > 2
                    {
                        return bad(
                            format!("{sat}.axis"),
                            format!("must be 0, 1 or 2 (x, y, z), got {a}"),
                        );
                    }
                    finite(&format!("{sat}.min"), min)?;
                    finite(&format!("{sat}.max"), max)?;
                    if (0..3).any(|a| min[a] > max[a]) {
                        return bad(
                            format!("{sat}.max"),
                            format!("must not be below the cell's min {min:?}, got {max:?}"),
                        );
                    }
                }
                Step::Sphere { object, .. } => self.object(format!("{sat}.object"), *object)?,
                Step::Plane { object, test, .. } => {
                    self.object(format!("{sat}.object"), *object)?;
                    if let PlaneForm::Axis { axis, .. } = test.form
                        && axis > 2
                    {
                        return bad(
                            format!("{sat}.test.form.axis"),
                            format!("must be 0, 1 or 2 (x, y, z), got {axis}"),
                        );
                    }
                }
                Step::Triangle { object, test, .. } => {
                    self.object(format!("{sat}.object"), *object)?;
                    if !matches!(test.stopped_at, 2 | 5 | 8 | 11 | 12) {
                        return bad(
                            format!("{sat}.test.stopped_at"),
                            format!("must be 2, 5, 8, 11 or 12, got {}", test.stopped_at),
                        );
                    }
                    if let Some(p) = test.permutation {
                        let mut sorted = p;
                        sorted.sort_unstable();
                        if sorted != [0, 1, 2] {
                            return bad(
                                format!("{sat}.test.permutation"),
                                format!("must be an ordering of 0, 1, 2, got {p:?}"),
                            );
                        }
                    }
                }
                Step::Accept { object, .. } => self.object(format!("{sat}.object"), *object)?,
                Step::ShadowRay { light, .. } | Step::Light { light, .. } => {
                    self.light(format!("{sat}.light"), *light)?
                }
                Step::Spawn { child } => {
                    if *child as usize != spawned {
                        return bad(
                            format!("{sat}.child"),
                            format!(
                                "children are spawned in order, each once: expected {spawned}, got {child}"
                            ),
                        );
                    }
                    let Some(c) = r.children.get(spawned) else {
                        return bad(
                            format!("{sat}.child"),
                            format!(
                                "child {child} does not exist: the ray has {} children",
                                r.children.len()
                            ),
                        );
                    };
                    let cat = format!("{at}.children[{spawned}]");
                    if c.kind == RayKind::Primary {
                        return bad(format!("{cat}.kind"), "a child ray cannot be primary");
                    }
                    if c.depth != r.depth + 1 {
                        return bad(
                            format!("{cat}.depth"),
                            format!(
                                "a child is one level below its parent (depth {}), got {}",
                                r.depth, c.depth
                            ),
                        );
                    }
                    spawned += 1;
                    self.ray(&cat, c)?;
                }
                Step::Truncated { .. } => {
                    self.truncated += 1;
                    if self.truncated > 1 {
                        return bad(sat, "a trace is cut at most once");
                    }
                }
                _ => {}
            }
        }
        if spawned != r.children.len() {
            return bad(
                format!("{at}.children"),
                format!(
                    "the ray has {} children but its steps spawn {spawned}",
                    r.children.len()
                ),
            );
        }
        if let Some(h) = &r.hit {
            self.object(format!("{at}.hit.object"), h.object)?;
        }
        Ok(())
    }
}
