//! The BVH's lines: slab intervals recomputed from the printed numbers, which sibling a pushed
//! node sent first and why, and how an accepted hit shrinks t_max.

use super::*;

#[test]
fn bvh_slab_intervals_recompute_from_the_printed_numbers() {
    // t_near = max(t_min, entries) and t_far = min(t_max, exits): recomputing them from the printed
    // arguments must give the recorded values bit for bit — which also checks that the t_max the
    // panel prints is the one the box was tested against (it shrinks as hits are accepted, and a
    // far sibling is tested with the t_max from before its near sibling's leaf).
    let mut visits = 0;
    for name in ["three-spheres.toml", "triangles.toml", "cornell.toml"] {
        let mut scene = shipped(name);
        scene.settings.accel = AccelChoice::Bvh;
        for (x, y) in grid(&scene, 40) {
            let trace = record(&scene, x, y);
            for (ray, step, e) in explained(&trace) {
                let Step::Node(n) = step else {
                    continue;
                };
                visits += 1;
                let near = get(&e, "t_near");
                let far = get(&e, "t_far");
                assert_eq!(near.value, num(n.test.t_near));
                assert_eq!(far.value, num(n.test.t_far));
                let a = args(&near.substituted);
                assert!(same(a[0], ray.t_min));
                let t_near = a.iter().fold(a[0], |m, &x| m.max(x));
                assert!(same(t_near, n.test.t_near), "{e:#?}");
                let b = args(&far.substituted);
                let t_far = b.iter().fold(b[0], |m, &x| m.min(x));
                assert!(same(t_far, n.test.t_far), "{name} ({x}, {y}): {e:#?}");
                // The slab entries are where the ray crosses the box's planes (f64, loosely).
                for (i, ax) in n.test.axes.iter().enumerate() {
                    let q = ray.direction[i] as f64;
                    if q.abs() < 1e-3 {
                        continue;
                    }
                    let planes = [n.test.min[i] as f64, n.test.max[i] as f64]
                        .map(|s| (s - ray.origin[i] as f64) / q);
                    let entry = planes[0].min(planes[1]);
                    assert!(
                        (ax.t_entry as f64 - entry).abs() <= 1e-4 * (1.0 + entry.abs()),
                        "{entry} vs {}",
                        ax.t_entry
                    );
                }
                // The recorded plane distances are (slab − S)·(1/Q) in f32 bit for bit, the entry
                // is one of them, and the panel prints them as recorded.
                for (i, ax) in n.test.axes.iter().enumerate() {
                    let [t0, t1] = ax.planes.expect("the robust test records its planes");
                    let o = ray.origin[i];
                    assert_eq!(t0.to_bits(), ((n.test.min[i] - o) * ax.inv_dir).to_bits());
                    assert_eq!(t1.to_bits(), ((n.test.max[i] - o) * ax.inv_dir).to_bits());
                    let entry = if ax.inv_dir.is_sign_negative() {
                        t1
                    } else {
                        t0
                    };
                    assert_eq!(ax.t_entry.to_bits(), entry.to_bits());
                    let a = ["x", "y", "z"][i];
                    assert_eq!(
                        get(&e, &format!("t0{a}, t1{a}")).value,
                        format!("{}, {}", num(t0), num(t1))
                    );
                }
                assert_eq!(get(&e, "overlap?").value == "yes", n.test.hit);
                if n.test.hit && n.action == NodeAction::Culled {
                    assert_eq!(get(&e, "still in reach?").value, "no");
                }
            }
        }
    }
    assert!(visits > 100, "{visits}");
}

#[test]
fn accept_shrinks_t_max_for_later_tests() {
    // In three-spheres the floor is tested first; a sphere hit in front of it is then tested
    // against the floor's t, which the panel prints as t_max.
    let scene = shipped("three-spheres.toml");
    let mut found = false;
    for (x, y) in grid(&scene, 20) {
        let trace = record(&scene, x, y);
        let r = &trace.root;
        let Some(first) = r
            .steps
            .iter()
            .position(|s| matches!(s.step, Step::Accept { .. }))
        else {
            continue;
        };
        let Step::Accept { t, .. } = r.steps[first].step else {
            unreachable!()
        };
        for s in &r.steps[first + 1..] {
            if let Step::Sphere { test, .. } = &s.step
                && test.t.is_some()
            {
                let e = explain(&trace, r, &s.step);
                let sub = &get(&e, "t").substituted;
                assert!(sub.ends_with(&format!("< {}", num(t))), "{sub}");
                found = true;
                break;
            }
        }
        if found {
            break;
        }
    }
    assert!(found, "no sphere hit after the floor's");
}

/// A node left for later says why: a closest-hit ray goes to the nearer sibling first, a shadow
/// ray to the farther (the teapot's pixel (160, 150) under the BVH has both kinds).
#[test]
fn a_pushed_node_says_which_sibling_went_first_and_why() {
    use raystep_core::record::RayKind;
    let trace = teapot_under_the_bvh();
    let mut seen = [false; 2];
    for (ray, step, e) in explained(&trace) {
        let Step::Node(n) = step else { continue };
        if n.action != NodeAction::Pushed {
            continue;
        }
        if ray.kind == RayKind::Shadow {
            assert!(
                e.conclusion.starts_with("Hit, but nearer than its sibling")
                    && e.conclusion.contains("farther box first"),
                "{}",
                e.conclusion
            );
            seen[1] = true;
        } else {
            assert_eq!(
                e.conclusion,
                "Hit, but farther than its sibling: pushed on the stack for later."
            );
            seen[0] = true;
        }
    }
    assert_eq!(seen, [true, true], "pushed nodes of both kinds of ray");
}

/// The one-line words (the command line's trace tree, the app's step list and captions) say
/// the same as the math panel, and say what the recorded numbers show: a pushed node's t_near
/// is at least its sibling's on a closest-hit ray, at most on a shadow ray.
#[test]
fn the_trace_line_of_a_pushed_node_says_which_sibling_and_the_numbers_agree() {
    use raystep_core::explain::describe::describe;
    use raystep_core::record::RayKind;
    let trace = teapot_under_the_bvh();
    let mut seen = [false; 2];
    for (ray, s) in trace.timeline() {
        let Step::Node(n) = &s.step else { continue };
        if n.action != NodeAction::Pushed {
            continue;
        }
        // Siblings are numbered (1, 2), (3, 4), …: the other of the pair, visited by the same ray
        // just before or after.
        let sibling = if n.node % 2 == 1 {
            n.node + 1
        } else {
            n.node - 1
        };
        let other = ray
            .steps
            .iter()
            .find_map(|x| match &x.step {
                Step::Node(m) if m.node == sibling => Some(m.test.t_near),
                _ => None,
            })
            .expect("the sibling's visit is recorded");
        let line = describe(&s.step, ray.kind);
        if ray.kind == RayKind::Shadow {
            assert!(n.test.t_near <= other, "{} > {other}", n.test.t_near);
            assert!(
                line.ends_with(
                    "hit, but nearer than its sibling, and a shadow ray looks in the farther first: pushed for later"
                ),
                "{line}"
            );
            seen[1] = true;
        } else {
            assert!(n.test.t_near >= other, "{} < {other}", n.test.t_near);
            assert!(
                line.ends_with("hit, but farther than its sibling: pushed for later"),
                "{line}"
            );
            seen[0] = true;
        }
    }
    assert_eq!(seen, [true, true], "pushed nodes of both kinds of ray");
}
