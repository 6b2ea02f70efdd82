//! The BVH as a node-link tree: the top levels from the trace's outline, every node the focused
//! ray visited (however deep), each visit numbered, hit or culled, leaves with their tests.
//!
//! The bounding-sphere tree is drawn the same way: it is a bounding-volume hierarchy too (built
//! over the BVH's topology, so its nodes carry the same numbers), and its recorded visits
//! ([`Step::SphereNode`]) read like the BVH's. A sphere-tree trace has no outline: its tree is
//! drawn from the visits alone (each inner visit names both children, so the culled sibling at
//! every level is shown).

use super::canvas::{Anchor, Canvas, Rgba, with_alpha};
use super::{ViewOptions, title};
use crate::record::{NodeAction, RayKind, RayRecord, Step, Trace};
use std::collections::{BTreeMap, BTreeSet};

/// One node as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnNode {
    /// Node index.
    pub node: u32,
    /// Depth.
    pub depth: u32,
    /// Centre in pixels.
    pub pos: [f32; 2],
    /// Visit number (1-based) and what the traversal did, if the ray visited it by the focus.
    pub visit: Option<(usize, NodeAction)>,
    /// Whether it is a leaf.
    pub leaf: bool,
}

/// The tree's layout: nodes and edges (parent, child) by node index.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TreeLayout {
    /// Nodes by index.
    pub nodes: BTreeMap<u32, DrawnNode>,
    /// Parent → child edges.
    pub edges: Vec<(u32, u32)>,
    /// The ray whose visits are shown.
    pub ray: Option<(RayKind, u32)>,
}

/// One recorded visit of a tree node, BVH box or bounding sphere alike.
struct Visit {
    node: u32,
    depth: u32,
    leaf: bool,
    children: Option<[u32; 2]>,
    action: NodeAction,
}

/// The node visit a step records, if it is one.
fn visit(step: &Step) -> Option<Visit> {
    match step {
        // The world tree's visits; a BLAS's (numbered in its prototype's tree) are not.
        Step::Node(v) if v.instance.is_none() => Some(Visit {
            node: v.node,
            depth: v.depth,
            leaf: v.leaf,
            children: v.children,
            action: v.action,
        }),
        Step::SphereNode {
            node,
            depth,
            leaf,
            children,
            action,
            ..
        } => Some(Visit {
            node: *node,
            depth: *depth,
            leaf: *leaf,
            children: *children,
            action: *action,
        }),
        _ => None,
    }
}

/// Whether `step` is a visit of a tree node (BVH or sphere tree).
pub fn is_node_visit(step: &Step) -> bool {
    matches!(step, Step::Node(v) if v.instance.is_none()) || matches!(step, Step::SphereNode { .. })
}

/// The ray whose traversal the diagram shows: the one owning the focused step, else the first
/// ray with node visits.
fn shown_ray(trace: &Trace, focus: Option<usize>) -> Option<(&RayRecord, Option<usize>)> {
    super::shown_ray(trace, focus, |r| {
        r.steps.iter().any(|s| is_node_visit(&s.step))
    })
}

/// Lays the tree out in a `width`×`height` area below `top`, its deepest level at 86 % of the
/// height.
pub fn layout(trace: &Trace, opts: &ViewOptions, top: f32) -> TreeLayout {
    layout_to(trace, opts, top, opts.height as f32 * 0.86)
}

/// Lays the tree out between `top` and `bottom` (the deepest level's centre).
fn layout_to(trace: &Trace, opts: &ViewOptions, top: f32, bottom: f32) -> TreeLayout {
    let mut children: BTreeMap<u32, [u32; 2]> = BTreeMap::new();
    let mut depth: BTreeMap<u32, u32> = BTreeMap::new();
    let mut leaf: BTreeMap<u32, bool> = BTreeMap::new();
    for n in trace.bvh.iter().flatten() {
        depth.insert(n.node, n.depth);
        leaf.insert(n.node, n.children.is_none());
        if let Some(c) = n.children {
            children.insert(n.node, c);
        }
    }
    let mut visits: BTreeMap<u32, (usize, NodeAction)> = BTreeMap::new();
    let shown = shown_ray(trace, opts.focus);
    if let Some((ray, upto)) = shown {
        let mut count = 0;
        for (i, s) in ray.steps.iter().enumerate() {
            if upto.is_some_and(|u| i >= u) {
                break;
            }
            if let Some(v) = visit(&s.step) {
                count += 1;
                visits.insert(v.node, (count, v.action));
                depth.insert(v.node, v.depth);
                leaf.insert(v.node, v.leaf);
                if let Some(c) = v.children {
                    children.insert(v.node, c);
                    // A child not visited (yet) is still drawn, one level down (the sphere
                    // tree has no outline to name it).
                    for k in c {
                        depth.entry(k).or_insert(v.depth + 1);
                    }
                }
            }
        }
    }
    // Which nodes to draw: the outline down to a depth that fits, plus every visited node and its
    // sibling (so the choice at each level is visible).
    let fit_depth = ((opts.width as f32 / 26.0).log2().floor() as u32).clamp(1, 6);
    let mut drawn: BTreeSet<u32> = depth
        .iter()
        .filter(|(_, d)| **d <= fit_depth)
        .map(|(n, _)| *n)
        .collect();
    drawn.extend(visits.keys().copied());
    // The children of every node the ray descended into, visited or not (yet).
    for (n, (_, action)) in &visits {
        if *action == NodeAction::Descend
            && let Some(c) = children.get(n)
        {
            drawn.extend(c.iter().filter(|k| depth.contains_key(k)));
        }
    }
    drawn.insert(0);
    // Keep only nodes whose parent is drawn (the tree stays connected).
    let mut parent: BTreeMap<u32, u32> = BTreeMap::new();
    for (p, c) in &children {
        parent.insert(c[0], *p);
        parent.insert(c[1], *p);
    }
    let connected = |n: u32, drawn: &BTreeSet<u32>| {
        let mut cur = n;
        while let Some(p) = parent.get(&cur) {
            if !drawn.contains(p) {
                return false;
            }
            cur = *p;
        }
        cur == 0
    };
    let drawn: BTreeSet<u32> = drawn
        .iter()
        .copied()
        .filter(|n| connected(*n, &drawn))
        .collect();
    // Leaf order by depth-first walk; inner nodes centred over their drawn children.
    let max_depth = drawn
        .iter()
        .filter_map(|n| depth.get(n))
        .max()
        .copied()
        .unwrap_or(0);
    let mut order = 0usize;
    let mut xs: BTreeMap<u32, f32> = BTreeMap::new();
    fn place(
        n: u32,
        children: &BTreeMap<u32, [u32; 2]>,
        drawn: &BTreeSet<u32>,
        order: &mut usize,
        xs: &mut BTreeMap<u32, f32>,
    ) -> f32 {
        let kids: Vec<u32> = children
            .get(&n)
            .map(|c| c.iter().copied().filter(|k| drawn.contains(k)).collect())
            .unwrap_or_default();
        let x = if kids.is_empty() {
            *order += 1;
            *order as f32 - 1.0
        } else {
            let v: Vec<f32> = kids
                .iter()
                .map(|k| place(*k, children, drawn, order, xs))
                .collect();
            v.iter().sum::<f32>() / v.len() as f32
        };
        xs.insert(n, x);
        x
    }
    place(0, &children, &drawn, &mut order, &mut xs);
    let slots = order.max(1) as f32;
    let margin = opts.width as f32 * 0.05;
    let usable_w = opts.width as f32 - 2.0 * margin;
    let level_h = (bottom - top) / (max_depth.max(1) as f32);
    let mut out = TreeLayout {
        ray: shown.map(|(r, _)| (r.kind, r.depth)),
        ..Default::default()
    };
    for n in &drawn {
        let d = depth.get(n).copied().unwrap_or(0);
        let x = margin + (xs.get(n).copied().unwrap_or(0.0) + 0.5) / slots * usable_w;
        let y = top + d as f32 * level_h;
        out.nodes.insert(
            *n,
            DrawnNode {
                node: *n,
                depth: d,
                pos: [x, y],
                visit: visits.get(n).copied(),
                leaf: leaf.get(n).copied().unwrap_or(false),
            },
        );
        if let Some(p) = parent.get(n)
            && drawn.contains(p)
        {
            out.edges.push((*p, *n));
        }
    }
    out
}

/// Draws the tree.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let th = c.theme;
    let ts = c.text_size;
    let shown = shown_ray(trace, opts.focus);
    let spheres = shown.is_some_and(|(r, _)| {
        r.steps
            .iter()
            .any(|s| matches!(s.step, Step::SphereNode { .. }))
    });
    let tree = if spheres {
        "Bounding-sphere tree"
    } else {
        "BVH"
    };
    let heading = match shown {
        Some((r, _)) => format!(
            "{tree} visits in order, {} ray (depth {})",
            r.kind.name(),
            r.depth
        ),
        None => tree.to_string(),
    };
    let top = title(&mut c, &heading) + ts * 1.2;
    let legend = legend_rows(&c);
    let legend_top = opts.height as f32 - ts * 0.4 - legend.len() as f32 * ts * 1.3;
    // The deepest level leaves room for a leaf's label ("3 tests, 1 hit") above the legend.
    let bottom = (opts.height as f32 * 0.86).min(legend_top - ts * 2.4);
    let lay = layout_to(trace, opts, top, bottom.max(top));
    let leaves = lay
        .nodes
        .values()
        .filter(|n| !lay.edges.iter().any(|(p, _)| *p == n.node))
        .count()
        .max(1);
    let radius = (ts * 0.85)
        .min(opts.width as f32 * 0.9 / (leaves as f32 * 2.6))
        .max(4.0);
    let last_visit = lay
        .nodes
        .values()
        .filter_map(|n| n.visit.map(|v| v.0))
        .max();
    for (p, ch) in &lay.edges {
        let (a, b) = (lay.nodes[p].pos, lay.nodes[ch].pos);
        let on_path = lay.nodes[ch].visit.is_some();
        let (col, w) = if on_path {
            (th.ink, 2.0)
        } else {
            (th.faded, 1.0)
        };
        c.line(a, b, col, w);
    }
    for n in lay.nodes.values() {
        let current = n.visit.is_some_and(|v| Some(v.0) == last_visit) && opts.focus.is_some();
        node_glyph(&mut c, n.pos, radius, n.leaf, n.visit, current, 9.0);
        if lay.nodes.len() <= 40 {
            c.text(
                n.pos[0] + radius * 1.25,
                n.pos[1] - radius * 0.9,
                ts * 0.6,
                &format!("#{}", n.node),
                th.muted,
                Anchor::TopLeft,
            );
        }
    }
    // Leaf notes: what the focused ray found there.
    if let Some((ray, upto)) = shown {
        let mut leaf_tests: BTreeMap<u32, (usize, usize)> = BTreeMap::new();
        let mut current_leaf = None;
        for (i, s) in ray.steps.iter().enumerate() {
            if upto.is_some_and(|u| i >= u) {
                break;
            }
            if let Some(v) = visit(&s.step) {
                current_leaf = (v.action == NodeAction::TestPrimitives).then_some(v.node);
                continue;
            }
            match &s.step {
                Step::Sphere { test, .. } => bump(&mut leaf_tests, current_leaf, test.t.is_some()),
                Step::Triangle { test, .. } => {
                    bump(&mut leaf_tests, current_leaf, test.t.is_some())
                }
                Step::Plane { test, .. } => bump(&mut leaf_tests, current_leaf, test.t.is_some()),
                _ => {}
            }
        }
        for (node, (tests, hits)) in leaf_tests {
            if let Some(n) = lay.nodes.get(&node) {
                let txt = format!(
                    "{tests} test{}, {hits} hit{}",
                    if tests == 1 { "" } else { "s" },
                    if hits == 1 { "" } else { "s" }
                );
                c.label(
                    n.pos[0],
                    n.pos[1] + radius * 1.3,
                    ts * 0.7,
                    &txt,
                    th.muted,
                    Anchor::TopCenter,
                );
            }
        }
    }
    // Legend, in as many rows as the width needs.
    legend_swatches(&mut c, &legend, legend_top, ts * 0.8, ts * 1.2);
    c
}

/// A tree node as the tree diagrams draw it: a circle (a square for a leaf) filled by what the
/// walk did there (hollow if it was not visited), ringed heavier when it is the focused visit,
/// its visit number inside (at least `min_text` pixels).
pub(crate) fn node_glyph(
    c: &mut Canvas,
    pos: [f32; 2],
    radius: f32,
    leaf: bool,
    visit: Option<(usize, NodeAction)>,
    current: bool,
    min_text: f32,
) {
    let th = c.theme;
    let (fill, ring) = match visit {
        None => (None, th.faded),
        Some((_, NodeAction::Culled)) => (Some(th.faded), th.muted),
        Some((_, NodeAction::TestPrimitives)) => (Some(th.hit), th.ink),
        Some(_) => (Some(th.ray), th.ink),
    };
    let width = if current { 3.5 } else { 1.5 };
    if leaf {
        let r = radius * 0.9;
        let pts = [
            [pos[0] - r, pos[1] - r],
            [pos[0] + r, pos[1] - r],
            [pos[0] + r, pos[1] + r],
            [pos[0] - r, pos[1] + r],
        ];
        c.polygon(&pts, fill.or(Some(th.background)), Some(ring), width);
    } else {
        c.circle(pos, radius, fill.or(Some(th.background)), Some(ring), width);
    }
    if let Some((k, _)) = visit {
        c.text(
            pos[0],
            pos[1],
            (radius * 1.05).max(min_text),
            &k.to_string(),
            th.background,
            Anchor::Center,
        );
    }
}

/// A legend of coloured swatches and names, row by row from `top` (`size`: the names' text,
/// `gap`: the space after each entry).
pub(crate) fn legend_swatches(
    c: &mut Canvas,
    rows: &[Vec<(Rgba, &str)>],
    top: f32,
    size: f32,
    gap: f32,
) {
    let th = c.theme;
    let ts = c.text_size;
    for (row, entries) in rows.iter().enumerate() {
        let y = top + row as f32 * ts * 1.3;
        let mut x = ts;
        for &(col, name) in entries {
            c.circle(
                [x + ts * 0.4, y + ts * 0.5],
                ts * 0.4,
                Some(col),
                Some(th.muted),
                1.0,
            );
            x += ts * 1.1;
            x += c.text(x, y, size, name, th.ink, Anchor::TopLeft) + gap;
        }
    }
}

/// The legend's entries, flowed into rows that fit the canvas's width.
fn legend_rows(c: &Canvas) -> Vec<Vec<(Rgba, &'static str)>> {
    let th = c.theme;
    let ts = c.text_size;
    let mut rows: Vec<Vec<(Rgba, &'static str)>> = vec![vec![]];
    let mut x = ts;
    for entry in [
        (th.ray, "hit: descend / push"),
        (th.hit, "leaf: test primitives"),
        (th.faded, "culled"),
        (with_alpha(th.faded, 90), "not visited"),
    ] {
        let w = ts * 1.1 + c.text_width(entry.1, ts * 0.8) + ts * 1.2;
        if x + w > c.width() && rows.last().is_some_and(|r| !r.is_empty()) {
            rows.push(vec![]);
            x = ts;
        }
        x += w;
        if let Some(r) = rows.last_mut() {
            r.push(entry);
        }
    }
    rows
}

fn bump(m: &mut BTreeMap<u32, (usize, usize)>, leaf: Option<u32>, hit: bool) {
    if let Some(l) = leaf {
        let e = m.entry(l).or_default();
        e.0 += 1;
        e.1 += hit as usize;
    }
}
