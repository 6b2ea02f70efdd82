//! The math panel's BVH node visits: the slab test of a node's box, per axis.

use super::*;

impl Ctx<'_> {
    /// `tree`: which tree the node is of ("BVH", "TLAS" or "BLAS"), for the title; a TLAS
    /// leaf holds instances, entered next.
    pub(super) fn node(&self, n: &crate::record::NodeVisit, tree: &str) -> Explanation {
        let test: &BoxTest<f32> = &n.test;
        let o = self.origin().to_array();
        let t_max_tested = self.node_t_max(n.node);
        let t_max_now = self.t_max();
        let mut lines = vec![];
        let robust = test.method == BoxMethod::Robust;
        // The kernel's factor 1 + 2γ₃, computed as `slab_axis` does.
        let enlarge = 1.0 + 2.0 * gamma::<f32>(3);
        for (i, ax) in test.axes.iter().enumerate() {
            let a = AXES[i];
            if robust {
                // The recorded plane distances (slab − S)·(1/Q); a trace saved before they were
                // recorded shows —.
                let planes = ax.planes;
                let [t0, t1] = planes.unwrap_or([f32::NAN; 2]);
                let shown = |x: f32| {
                    if planes.is_some() {
                        num(x)
                    } else {
                        "—".into()
                    }
                };
                let shown_p = |x: f32| if planes.is_some() { p(x) } else { "—".into() };
                lines.push(line(
                    &format!("1/Q{a}"),
                    &format!("1/Q{a}"),
                    format!("1/{}", p(self.dir()[i])),
                    num(ax.inv_dir),
                    None,
                ));
                lines.push(line(
                    &format!("t0{a}, t1{a}"),
                    &format!("(min{a} − S{a})·(1/Q{a}), (max{a} − S{a})·(1/Q{a})"),
                    format!(
                        "({} − {})·{}, ({} − {})·{}",
                        num(test.min[i]),
                        p(o[i]),
                        p(ax.inv_dir),
                        num(test.max[i]),
                        p(o[i]),
                        p(ax.inv_dir)
                    ),
                    format!("{}, {}", shown(t0), shown(t1)),
                    None,
                ));
                lines.push(line(
                    &format!("{a} slab"),
                    "entry, exit × (1 + 2γ₃)",
                    if ax.inv_dir.is_sign_negative() {
                        format!("{}, {}·{}", shown(t1), shown_p(t0), num(enlarge))
                    } else {
                        format!("{}, {}·{}", shown(t0), shown_p(t1), num(enlarge))
                    },
                    format!("[{}, {}]", num(ax.t_entry), num(ax.t_exit)),
                    Some(
                        if ax.t_entry.is_nan() || ax.t_exit.is_nan() {
                            "NaN (0·∞: the ray lies in a face plane): this slab sets no limit"
                        } else if ax.inv_dir.is_sign_negative() {
                            "Q is negative on this axis: the max plane is entered first"
                        } else {
                            "the exit is enlarged by 1 + 2γ₃ so rounding cannot lose a hit"
                        }
                        .into(),
                    ),
                ));
            } else {
                lines.push(line(
                    &format!("{a} slab"),
                    &format!("sort((min{a} − S{a})/Q{a}, (max{a} − S{a})/Q{a})"),
                    format!(
                        "sort(({} − {})/{}, ({} − {})/{})",
                        num(test.min[i]),
                        p(o[i]),
                        p(self.dir()[i]),
                        num(test.max[i]),
                        p(o[i]),
                        p(self.dir()[i])
                    ),
                    format!("[{}, {}]", num(ax.t_entry), num(ax.t_exit)),
                    None,
                ));
            }
        }
        lines.push(line(
            "t_near",
            "max(t_min, entry_x, entry_y, entry_z)",
            format!(
                "max({}, {}, {}, {})",
                num(self.ray.t_min),
                num(test.axes[0].t_entry),
                num(test.axes[1].t_entry),
                num(test.axes[2].t_entry)
            ),
            num(test.t_near),
            None,
        ));
        lines.push(line(
            "t_far",
            "min(t_max, exit_x, exit_y, exit_z)",
            format!(
                "min({}, {}, {}, {})",
                num(t_max_tested),
                num(test.axes[0].t_exit),
                num(test.axes[1].t_exit),
                num(test.axes[2].t_exit)
            ),
            num(test.t_far),
            None,
        ));
        let op = if robust { "≤" } else { "<" };
        lines.push(line(
            "overlap?",
            &format!("t_near {op} t_far"),
            format!("{} {op} {}", num(test.t_near), num(test.t_far)),
            yes_no(test.hit),
            Some(if test.hit {
                "the ray's interval meets the box".into()
            } else {
                "the ray misses the box (or reaches it only beyond t_max)".into()
            }),
        ));
        // The far sibling is re-checked against t_max, which the near one's leaf may have shrunk.
        let rechecked = test.hit && n.action == NodeAction::Culled;
        if rechecked || (t_max_now < t_max_tested && test.hit) {
            lines.push(line(
                "still in reach?",
                "t_near ≤ t_max (now)",
                format!("{} ≤ {}", num(test.t_near), num(t_max_now)),
                yes_no(!rechecked),
                Some("the nearer sibling's hit shrank t_max".into()),
            ));
        }
        let kind = if n.leaf { "leaf" } else { "inner" };
        let conclusion = match n.action {
            NodeAction::Culled if rechecked => {
                "Culled: a closer hit, found in the nearer sibling, lies before this box.".into()
            }
            NodeAction::Culled => {
                "Culled: the ray misses the box, so nothing inside is tested.".to_string()
            }
            NodeAction::Descend => match n.children {
                Some([a, b]) => format!("Hit: descend into children {a} and {b}."),
                None => "Hit: descend into its children.".into(),
            },
            NodeAction::Pushed if self.ray.kind == RayKind::Shadow => {
                "Hit, but nearer than its sibling: a shadow ray stops at any blocker and looks in \
                 the farther box first (the nearer mostly holds the surface it leaves); pushed \
                 on the stack for later."
                    .into()
            }
            NodeAction::Pushed => {
                "Hit, but farther than its sibling: pushed on the stack for later.".into()
            }
            NodeAction::TestPrimitives if tree == "TLAS" => {
                "Hit: enter the leaf's instances (next steps: the ray into each one's object \
                 space, then its BLAS)."
                    .into()
            }
            NodeAction::TestPrimitives => "Hit: test the leaf's primitives (next steps).".into(),
        };
        Explanation {
            title: format!(
                "{tree} node {} (depth {}, {kind}): {} slab test",
                n.node,
                n.depth,
                if robust { "robust" } else { "plain" }
            ),
            lines,
            conclusion,
        }
    }

    /// A bounding sphere tested, a grid cell entered, a mailbox skip: the recorded numbers and
    /// what the traversal did.
    pub(super) fn accel_step(&self, step: &Step) -> Explanation {
        match step {
            Step::SphereNode {
                node,
                depth,
                center,
                radius,
                test,
                leaf,
                children,
                action,
            } => {
                let mut lines = vec![
                    line("G", "the bounding sphere's centre", "", v3(*center), None),
                    line("r", "its radius", "", num(*radius), None),
                    line("Δ", "b² − 4ac", "", num(test.discriminant), None),
                ];
                if let Some([t0, t1]) = test.roots {
                    lines.push(line(
                        "t₀, t₁",
                        "the roots: the ray is inside the sphere between them",
                        "",
                        format!("{}, {}", num(t0), num(t1)),
                        None,
                    ));
                }
                let why = match (action, children) {
                    (NodeAction::Descend, Some([a, b])) => {
                        format!("Hit: descend into children {a} and {b}.")
                    }
                    _ => crate::record::words::sentence(crate::record::words::node_action(
                        *action,
                        self.ray.kind,
                    )),
                };
                Explanation {
                    title: format!(
                        "Bounding sphere {node} (depth {depth}, {}): lesson 2's ray–sphere test, used for culling",
                        if *leaf { "leaf" } else { "inner" }
                    ),
                    lines,
                    conclusion: format!(
                        "{why} (The sphere is culled when both roots lie outside (t_min, t_max) or there are none.)"
                    ),
                }
            }
            Step::Cell {
                cell,
                t_entry,
                t_exit,
                axis,
                primitives,
                ..
            } => Explanation {
                title: format!("Grid cell ({}, {}, {})", cell[0], cell[1], cell[2]),
                lines: vec![
                    line(
                        "t_entry",
                        "where the ray enters the cell",
                        "",
                        num(*t_entry),
                        None,
                    ),
                    line(
                        "t_exit",
                        "min over the axes of t_next (the next cell boundary)",
                        "",
                        num(*t_exit),
                        Some("a hit is accepted here only if t ≤ t_exit".into()),
                    ),
                    line(
                        "stepped along",
                        "the axis whose t_next was smallest",
                        "",
                        axis.map_or("— (the entry cell)".to_string(), |a| {
                            crate::record::words::axis(a).to_string()
                        }),
                        None,
                    ),
                ],
                conclusion: format!(
                    "The cell lists {primitives} primitive{}; each is tested unless the mailbox says it already missed.",
                    if *primitives == 1 { "" } else { "s" }
                ),
            },
            Step::MailboxSkip { name, .. } => Explanation {
                title: format!("Mailbox: \"{name}\""),
                lines: vec![],
                conclusion: format!(
                    "\"{name}\" spans several cells and was already tested (a miss) in an earlier one: a miss stays a miss as t_max only shrinks, so it is not tested again."
                ),
            },
            _ => Explanation::default(),
        }
    }
}
