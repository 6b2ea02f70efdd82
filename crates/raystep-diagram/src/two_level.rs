//! The two-level walk of a ray through a scene with instances, in the manner of AMD's Radeon
//! Raytracing Analyzer: the top-level BVH (TLAS, over the instances' world boxes) above, and
//! below it, side by side, the bottom-level BVH (BLAS) of each instance the ray entered — the
//! prototype's tree, walked in the instance's object space — joined to the TLAS leaf that
//! entered it. Every visit is numbered in the order the tracer made it, across both levels, so
//! the walk reads as one sequence: TLAS nodes, into an instance, its BLAS, back to the TLAS.
//!
//! Both trees are drawn from the recorded visits alone (with each visited inner node's two
//! children, visited or not, so the choice at every level shows): a trace records no outline of
//! the TLAS or of a BLAS.

use super::bvh_tree::{legend_swatches, node_glyph};
use super::canvas::{Anchor, Canvas, with_alpha};
use super::{ViewOptions, title_first_fitting};
use crate::record::{NodeAction, NodeVisit, RayRecord, Step, Trace};
use std::collections::{BTreeMap, BTreeSet};

/// Whether a ray walked a TLAS or entered an instance (under hardware ray queries the
/// hardware's walk is not recorded, only the instances entered).
fn walked(r: &RayRecord) -> bool {
    r.steps
        .iter()
        .any(|s| matches!(s.step, Step::TlasNode(_) | Step::Instance { .. }))
}

/// Whether some ray of the trace walked a TLAS (or entered an instance).
pub fn has_two_level(trace: &Trace) -> bool {
    trace.rays().into_iter().any(walked)
}

/// One recorded visit, numbered in the ray's walk (1-based).
#[derive(Debug, Clone, PartialEq)]
pub struct Visit {
    /// The visit's number in the walk, counting TLAS visits, instances entered and BLAS visits.
    pub number: usize,
    /// The node (numbered in its own tree).
    pub node: u32,
    /// Its depth in its tree.
    pub depth: u32,
    /// Whether it is a leaf.
    pub leaf: bool,
    /// An inner node's children.
    pub children: Option<[u32; 2]>,
    /// What the walk did.
    pub action: NodeAction,
}

impl Visit {
    fn of(v: &NodeVisit, number: usize) -> Visit {
        Visit {
            number,
            node: v.node,
            depth: v.depth,
            leaf: v.leaf,
            children: v.children,
            action: v.action,
        }
    }
}

/// An instance the ray entered, and its BLAS's visits.
#[derive(Debug, Clone, PartialEq)]
pub struct Entered {
    /// Index into the scene's instances.
    pub instance: u32,
    /// The instance's name.
    pub name: String,
    /// The prototype's name.
    pub prototype: String,
    /// The number of the "into object space" step in the walk.
    pub number: usize,
    /// The TLAS leaf whose test entered it.
    pub leaf: Option<u32>,
    /// The BLAS's visits.
    pub blas: Vec<Visit>,
    /// Primitive tests in its BLAS, and how many hit.
    pub tests: usize,
    /// See `tests`.
    pub hits: usize,
}

/// A ray's two-level walk, up to a step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Walk {
    /// The TLAS visits.
    pub tlas: Vec<Visit>,
    /// The instances entered, in order.
    pub entered: Vec<Entered>,
}

/// The walk of `ray`'s first `upto` steps (all of them for None).
pub fn walk(ray: &RayRecord, upto: Option<usize>) -> Walk {
    let mut w = Walk::default();
    let mut number = 0;
    let mut leaf = None;
    for (i, s) in ray.steps.iter().enumerate() {
        if upto.is_some_and(|u| i >= u) {
            break;
        }
        match &s.step {
            Step::TlasNode(v) => {
                number += 1;
                w.tlas.push(Visit::of(v, number));
                leaf = (v.action == NodeAction::TestPrimitives).then_some(v.node);
            }
            Step::Instance {
                instance,
                name,
                prototype,
                ..
            } => {
                number += 1;
                w.entered.push(Entered {
                    instance: *instance,
                    name: name.clone(),
                    prototype: prototype.clone(),
                    number,
                    leaf,
                    blas: vec![],
                    tests: 0,
                    hits: 0,
                });
            }
            Step::Node(v) if v.instance.is_some() => {
                number += 1;
                if let Some(e) = w.entered.last_mut() {
                    e.blas.push(Visit::of(v, number));
                }
            }
            Step::Sphere { test, .. } => count(&mut w, test.t.is_some()),
            Step::Triangle { test, .. } => count(&mut w, test.t.is_some()),
            // The world's own objects are tested before the TLAS: not an instance's.
            Step::Node(_) | Step::Plane { .. } => {}
            _ => {}
        }
    }
    w
}

/// A primitive test counts for the instance being walked (only while its BLAS is).
fn count(w: &mut Walk, hit: bool) {
    if let Some(e) = w.entered.last_mut()
        && !e.blas.is_empty()
    {
        e.tests += 1;
        e.hits += hit as usize;
    }
}

/// The ray whose walk is shown: the focused step's, if it walked a TLAS; else the first that
/// did. With the number of its steps up to and including the focus.
fn shown_ray(trace: &Trace, focus: Option<usize>) -> Option<(&RayRecord, Option<usize>)> {
    super::shown_ray(trace, focus, walked)
}

/// A node as drawn: its position, and its visit if the walk made one.
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    /// The node.
    pub node: u32,
    /// Centre in pixels.
    pub pos: [f32; 2],
    /// The visit.
    pub visit: Option<Visit>,
    /// Whether it is a leaf (a node never visited: not known, drawn as an inner node).
    pub leaf: bool,
}

/// A tree laid out from its visits in the box `[x0, x1] × [top, bottom]`: the visited nodes and
/// each visited inner node's children; leaves left to right in depth-first order, each inner
/// node above the middle of its children. Returns the nodes and the (parent, child) edges.
pub fn lay_out(
    visits: &[Visit],
    [x0, x1]: [f32; 2],
    [top, bottom]: [f32; 2],
) -> (BTreeMap<u32, Placed>, Vec<(u32, u32)>) {
    let mut children: BTreeMap<u32, [u32; 2]> = BTreeMap::new();
    let mut depth: BTreeMap<u32, u32> = BTreeMap::new();
    let mut seen: BTreeMap<u32, Visit> = BTreeMap::new();
    for v in visits {
        depth.insert(v.node, v.depth);
        if let Some(c) = v.children {
            children.insert(v.node, c);
            for k in c {
                depth.entry(k).or_insert(v.depth + 1);
            }
        }
        seen.insert(v.node, v.clone());
    }
    let mut xs: BTreeMap<u32, f32> = BTreeMap::new();
    let mut order = 0usize;
    // Depth first from the root; a node's children are the ones its visit named.
    // A trace read from a file may chain its nodes arbitrarily deep or in a cycle: each node is
    // placed once, and below the deepest tree a trace may record (validate::MAX_BVH_DEPTH) the
    // walk stops.
    fn place(
        n: u32,
        level: u32,
        children: &BTreeMap<u32, [u32; 2]>,
        order: &mut usize,
        xs: &mut BTreeMap<u32, f32>,
        guard: &mut BTreeSet<u32>,
    ) -> f32 {
        if !guard.insert(n) {
            return *xs.get(&n).unwrap_or(&0.0);
        }
        let kids = children
            .get(&n)
            .filter(|_| level < crate::record::validate::MAX_BVH_DEPTH);
        let x = match kids {
            Some(c) => {
                let a = place(c[0], level + 1, children, order, xs, guard);
                let b = place(c[1], level + 1, children, order, xs, guard);
                (a + b) / 2.0
            }
            None => {
                *order += 1;
                *order as f32 - 1.0
            }
        };
        xs.insert(n, x);
        x
    }
    if !depth.is_empty() {
        place(0, 0, &children, &mut order, &mut xs, &mut BTreeSet::new());
    }
    let slots = order.max(1) as f32;
    let deepest = xs
        .keys()
        .filter_map(|n| depth.get(n))
        .max()
        .copied()
        .unwrap_or(0);
    let level = (bottom - top) / deepest.max(1) as f32;
    let mut nodes = BTreeMap::new();
    let mut edges = vec![];
    for (&n, &x) in &xs {
        let d = depth.get(&n).copied().unwrap_or(0);
        let visit = seen.get(&n).cloned();
        nodes.insert(
            n,
            Placed {
                node: n,
                pos: [
                    x0 + (x + 0.5) / slots * (x1 - x0),
                    if deepest == 0 {
                        (top + bottom) / 2.0
                    } else {
                        top + d as f32 * level
                    },
                ],
                leaf: visit.as_ref().is_some_and(|v| v.leaf),
                visit,
            },
        );
    }
    for (&p, c) in &children {
        if xs.contains_key(&p) {
            for k in c {
                if xs.contains_key(k) {
                    edges.push((p, *k));
                }
            }
        }
    }
    (nodes, edges)
}

/// Draws the TLAS above and each entered instance's BLAS below it.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let th = c.theme;
    let ts = c.text_size;
    let (w, h) = (c.width(), c.height());
    let shown = shown_ray(trace, opts.focus);
    let walk = shown
        .map(|(r, upto)| self::walk(r, upto))
        .unwrap_or_default();
    let headings = match shown {
        Some((r, _)) => {
            let counts = format!(
                "{} TLAS nodes, {} instance{} entered",
                walk.tlas.len(),
                walk.entered.len(),
                if walk.entered.len() == 1 { "" } else { "s" }
            );
            vec![
                format!(
                    "TLAS and BLAS visits in order, {} ray (depth {}): {counts}",
                    r.kind.name(),
                    r.depth,
                ),
                format!("TLAS and BLAS, {} ray: {counts}", r.kind.name()),
                "TLAS and BLAS".to_string(),
            ]
        }
        None => vec!["TLAS and BLAS".to_string()],
    };
    let top = title_first_fitting(&mut c, &headings) + ts * 0.4;
    let last = walk
        .tlas
        .iter()
        .map(|v| v.number)
        .chain(walk.entered.iter().map(|e| e.number))
        .chain(
            walk.entered
                .iter()
                .flat_map(|e| e.blas.iter().map(|v| v.number)),
        )
        .max();
    let legend_top = h - ts * 1.6;
    // A short panel (the app's side panel) keeps the trees and drops the explanatory lines.
    let compact = legend_top - top < ts * 22.0;
    // The TLAS in the upper part, the BLAS row below.
    let split = top + (legend_top - top) * 0.42;
    if !compact {
        c.text(
            ts * 0.8,
            top,
            ts * 0.8,
            "TLAS: the instances' world boxes",
            th.muted,
            Anchor::TopLeft,
        );
    }
    let tlas_top = if compact {
        top + ts * 0.9
    } else {
        top + ts * 2.0
    };
    let radius = (ts * 0.75).max(4.0);
    let (tlas, tlas_edges) = lay_out(
        &walk.tlas,
        [w * 0.05, w * 0.95],
        [tlas_top, split - ts * 1.2],
    );
    draw_tree(
        &mut c,
        &tlas,
        &tlas_edges,
        radius,
        last,
        opts.focus.is_some(),
    );
    // The BLAS columns: as many as fit, in the order the instances were entered.
    let fit = ((w / (ts * 9.0)).floor() as usize).max(1);
    let columns = walk.entered.len().min(fit);
    let col_w = w * 0.96 / columns.max(1) as f32;
    let header = split + ts * 0.6;
    for (k, e) in walk.entered.iter().take(columns).enumerate() {
        let x0 = w * 0.02 + k as f32 * col_w;
        let mid = x0 + col_w / 2.0;
        // Joined to the TLAS leaf that entered it.
        if let Some(l) = e.leaf.and_then(|l| tlas.get(&l)) {
            c.line(
                [l.pos[0], l.pos[1] + radius],
                [mid, header - ts * 0.2],
                with_alpha(th.ink, 120),
                1.2,
            );
        }
        let name = c.elide(&e.name, ts * 0.75, col_w * 0.95);
        c.text(mid, header, ts * 0.75, &name, th.ink, Anchor::TopCenter);
        if !compact {
            let sub = format!("#{} into object space → {}", e.number, e.prototype);
            let sub = c.elide(&sub, ts * 0.6, col_w * 0.95);
            c.text(
                mid,
                header + ts * 0.95,
                ts * 0.6,
                &sub,
                th.muted,
                Anchor::TopCenter,
            );
        }
        let blas_top = header + if compact { ts * 1.9 } else { ts * 2.8 };
        let (blas, edges) = lay_out(
            &e.blas,
            [x0 + col_w * 0.06, x0 + col_w * 0.94],
            [blas_top, legend_top - ts * 2.6],
        );
        let r = radius.min(col_w / 10.0).max(3.0);
        draw_tree(&mut c, &blas, &edges, r, last, opts.focus.is_some());
        let found = format!(
            "BLAS: {} test{}, {} hit{}",
            e.tests,
            if e.tests == 1 { "" } else { "s" },
            e.hits,
            if e.hits == 1 { "" } else { "s" }
        );
        c.text(
            mid,
            legend_top - ts * 1.9,
            ts * 0.65,
            &found,
            if e.hits > 0 { th.ink } else { th.muted },
            Anchor::TopCenter,
        );
    }
    if walk.entered.len() > columns {
        c.text(
            w - ts * 0.8,
            header,
            ts * 0.65,
            &format!("+{} more", walk.entered.len() - columns),
            th.muted,
            Anchor::TopRight,
        );
    } else if walk.entered.is_empty() {
        // Before the focused step, or along the whole walk?
        let ever = shown.is_some_and(|(r, _)| !self::walk(r, None).entered.is_empty());
        let says = if !ever {
            "no instance entered: the ray missed every instance's box"
        } else {
            "no instance entered yet"
        };
        let says = c.elide(says, ts * 0.8, w * 0.94);
        c.text(
            w / 2.0,
            header + ts,
            ts * 0.8,
            &says,
            th.muted,
            Anchor::TopCenter,
        );
    }
    // Legend.
    let hit_name = if compact {
        "leaf"
    } else {
        "leaf: enter instances / test primitives"
    };
    legend_swatches(
        &mut c,
        &[vec![
            (th.ray, "descend"),
            (th.hit, hit_name),
            (th.faded, "culled"),
        ]],
        legend_top,
        ts * 0.75,
        ts * 1.0,
    );
    c
}

/// Draws one tree: edges (heavy where the walk went), nodes filled by what the walk did,
/// numbered by visit, the latest ringed when a step is focused.
fn draw_tree(
    c: &mut Canvas,
    nodes: &BTreeMap<u32, Placed>,
    edges: &[(u32, u32)],
    radius: f32,
    last: Option<usize>,
    focused: bool,
) {
    let th = c.theme;
    // Small enough that no two nodes overlap (a deep tree in a small panel).
    // (Pairwise, so only for trees a ray's walk makes; a huge one from a crafted trace is drawn
    // at the smallest size.)
    let pos: Vec<[f32; 2]> = nodes.values().map(|n| n.pos).collect();
    let mut nearest = if pos.len() > 4096 { 0.0 } else { f32::INFINITY };
    if pos.len() <= 4096 {
        for (i, a) in pos.iter().enumerate() {
            for b in &pos[i + 1..] {
                nearest = nearest.min((a[0] - b[0]).hypot(a[1] - b[1]));
            }
        }
    }
    let radius = radius.min(nearest * 0.42).max(2.0);
    for (p, k) in edges {
        let (Some(a), Some(b)) = (nodes.get(p), nodes.get(k)) else {
            continue;
        };
        let walked = b.visit.is_some();
        c.line(
            a.pos,
            b.pos,
            if walked { th.ink } else { th.faded },
            if walked { 2.0 } else { 1.0 },
        );
    }
    for n in nodes.values() {
        let current = focused && n.visit.as_ref().map(|v| v.number) == last;
        let visit = n.visit.as_ref().map(|v| (v.number, v.action));
        node_glyph(c, n.pos, radius, n.leaf, visit, current, 8.0);
    }
}
