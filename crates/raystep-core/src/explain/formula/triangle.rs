//! The math panel's ray–triangle tests: Möller–Trumbore as Cramer's rule, and the watertight test.

use super::*;

impl Ctx<'_> {
    /// Möller–Trumbore: E1, E2, T = S − P0, the determinants and the quotients are the recorded
    /// ones (−Q is the recorded direction negated, which is exact); nothing is recomputed here.
    pub(super) fn moller_trumbore(
        &self,
        name: &str,
        vertices: &[[f32; 3]; 3],
        test: &TriangleTest<f32>,
    ) -> Explanation {
        let pv = vertices.map(Vec3::from);
        // Recorded; a trace saved before they were recorded shows —.
        let rec = |v: Option<[f32; 3]>| v.map_or("—".to_string(), |v| vv(Vec3::from(v)));
        let (e1, e2, tv) = (rec(test.e1), rec(test.e2), rec(test.t_vec));
        // −Q: the recorded direction negated (exact).
        let nq = -self.dir();
        let stop = test.stopped_at;
        let mut lines = vec![
            line(
                "E1",
                "P1 − P0",
                format!("{} − {}", vv(pv[1]), vv(pv[0])),
                e1.clone(),
                Some("step 1".into()),
            ),
            line(
                "E2",
                "P2 − P0",
                format!("{} − {}", vv(pv[2]), vv(pv[0])),
                e2.clone(),
                Some("step 1".into()),
            ),
            line(
                "D0",
                "det(−Q, E1, E2)",
                format!("det({}, {}, {})", vv(nq), e1.clone(), e2.clone()),
                num(test.det),
                Some(if stop == 2 {
                    "step 2: zero (or not finite): the ray is parallel to the plane — stop".into()
                } else {
                    "step 2: non-zero, so the system has one solution".into()
                }),
            ),
        ];
        let q = |x: Option<f32>| x.map_or("—".to_string(), num);
        if stop > 2 {
            lines.push(line(
                "T",
                "S − P0",
                format!("{} − {}", vv(self.origin()), vv(pv[0])),
                tv.clone(),
                Some("step 3".into()),
            ));
            lines.push(line(
                "Dt",
                "det(T, E1, E2)",
                format!("det({}, {}, {})", tv.clone(), e1.clone(), e2.clone()),
                q(test.dt),
                Some("step 4".into()),
            ));
            let t = test.t_star.unwrap_or(f32::NAN);
            lines.push(line(
                "t*",
                "Dt/D0",
                format!("{}/{}", p(test.dt.unwrap_or(f32::NAN)), p(test.det)),
                num(t),
                Some("step 5".into()),
            ));
            let mut range = self.range_line(t);
            if stop == 5 {
                range.note = range.note.map(|n| format!("{n} — stop"));
            }
            lines.push(range);
        }
        if stop > 5 {
            lines.push(line(
                "Du",
                "det(−Q, T, E2)",
                format!("det({}, {}, {})", vv(nq), tv.clone(), e2.clone()),
                q(test.du),
                Some("step 6".into()),
            ));
            let u = test.u.unwrap_or(f32::NAN);
            lines.push(line(
                "u*",
                "Du/D0",
                format!("{}/{}", p(test.du.unwrap_or(f32::NAN)), p(test.det)),
                num(u),
                Some("step 7: the weight of P1".into()),
            ));
            // The kernel's verdict (it stops when u* < 0 or u* > 1).
            let ok = stop > 8;
            lines.push(line(
                "u in [0, 1]?",
                "0 ≤ u* ≤ 1",
                format!("0 ≤ {} ≤ 1", num(u)),
                yes_no(ok),
                Some(if ok {
                    "step 8".into()
                } else {
                    "step 8: outside the triangle — stop".into()
                }),
            ));
        }
        if stop > 8 {
            lines.push(line(
                "Dv",
                "det(−Q, E1, T)",
                format!("det({}, {}, {})", vv(nq), e1.clone(), tv.clone()),
                q(test.dv),
                Some("step 9".into()),
            ));
            let (u, v) = (test.u.unwrap_or(f32::NAN), test.v.unwrap_or(f32::NAN));
            lines.push(line(
                "v*",
                "Dv/D0",
                format!("{}/{}", p(test.dv.unwrap_or(f32::NAN)), p(test.det)),
                num(v),
                Some("step 10: the weight of P2".into()),
            ));
            // The kernel's own sum of the recorded u* and v*.
            let uv = u + v;
            // The kernel's verdict (it stops when v* < 0 or u* + v* > 1).
            let ok = stop > 11;
            lines.push(line(
                "v ≥ 0, u + v ≤ 1?",
                "v* ≥ 0 and u* + v* ≤ 1",
                format!(
                    "{} ≥ 0 and {} + {} = {} ≤ 1",
                    num(v),
                    num(u),
                    num(v),
                    num(uv)
                ),
                yes_no(ok),
                Some(if ok {
                    "step 11".into()
                } else {
                    "step 11: outside the triangle — stop".into()
                }),
            ));
        }
        if stop == 12 {
            let (u, v) = (test.u.unwrap_or(f32::NAN), test.v.unwrap_or(f32::NAN));
            lines.push(line(
                "(b0, b1, b2)",
                "(1 − u* − v*, u*, v*)",
                format!("(1 − {} − {}, {}, {})", num(u), num(v), num(u), num(v)),
                format!("({}, {}, {})", num(1.0 - u - v), num(u), num(v)),
                Some("step 12: the barycentric weights of P0, P1, P2".into()),
            ));
        }
        let conclusion = if stop == 12 {
            format!(
                "Hit at t = {} (step 12), with u = {}, v = {}.",
                q(test.t),
                q(test.u),
                q(test.v)
            )
        } else {
            format!("Stopped at step {stop}: {}. A miss.", test.stop_reason())
        };
        Explanation {
            title: format!("Ray–triangle \"{name}\" (Möller–Trumbore, Cramer's rule)"),
            lines,
            conclusion,
        }
    }

    /// The watertight test: every number shown is the recorded one (permutation, shear, sheared
    /// vertices, edge functions, det, scaled z and t, t, u, v); nothing is recomputed here. A
    /// value the record lacks (a trace saved before it was recorded) shows as —.
    pub(super) fn watertight(
        &self,
        name: &str,
        vertices: &[[f32; 3]; 3],
        test: &TriangleTest<f32>,
    ) -> Explanation {
        let pv = vertices.map(Vec3::from);
        let d = self.dir();
        let o = self.origin();
        let [kx, ky, kz] = test.permutation.unwrap_or([0, 1, 2]).map(|k| k.min(2));
        let perm = |v: Vec3| [v[kx], v[ky], v[kz]];
        let dp = perm(d);
        let [sx, sy, sz] = test.shear.unwrap_or([f32::NAN; 3]);
        let q = test.sheared.unwrap_or([[f32::NAN; 3]; 3]);
        // A trace saved before the shear was recorded has none: its values show as —.
        let missing = test.shear.is_none() || test.sheared.is_none();
        let nq = |x: f32| if missing { "—".to_string() } else { num(x) };
        let pq = |x: f32| if missing { "—".to_string() } else { p(x) };
        let stop = test.stopped_at;
        let name_of = |k: usize| AXES[k];
        let mut lines = vec![
            line(
                "(kx, ky, kz)",
                "z = the axis of the largest |Q| component",
                format!("|Q| = {}", vv(d.abs())),
                format!("({}, {}, {})", name_of(kx), name_of(ky), name_of(kz)),
                Some("the ray is turned into +z".into()),
            ),
            line(
                "Sx, Sy, Sz",
                "−Qx/Qz, −Qy/Qz, 1/Qz (permuted)",
                format!(
                    "−{}/{}, −{}/{}, 1/{}",
                    p(dp[0]),
                    p(dp[2]),
                    p(dp[1]),
                    p(dp[2]),
                    p(dp[2])
                ),
                format!("{}, {}, {}", nq(sx), nq(sy), nq(sz)),
                Some("the shear that makes the ray run along +z".into()),
            ),
        ];
        for (i, v) in q.iter().enumerate() {
            lines.push(line(
                &format!("P′{i}"),
                &format!("shear(permute(P{i} − S)): (x + Sx·z, y + Sy·z, z)"),
                format!("permute({} − {})", vv(pv[i]), vv(o)),
                format!("({}, {}, {})", nq(v[0]), nq(v[1]), nq(v[2])),
                None,
            ));
        }
        let edges = test.edges.unwrap_or([f32::NAN; 3]);
        let pairs = [(1, 2), (2, 0), (0, 1)];
        for (i, (a, b)) in pairs.into_iter().enumerate() {
            lines.push(line(
                &format!("e{i}"),
                &format!("x′{a}·y′{b} − y′{a}·x′{b}"),
                format!(
                    "{}·{} − {}·{}",
                    pq(q[a][0]),
                    pq(q[b][1]),
                    pq(q[a][1]),
                    pq(q[b][0])
                ),
                num(edges[i]),
                (i == 0).then(|| {
                    "2D edge functions: which side of each edge the ray passes (one rounding, by FMA; an exact 0 is redone in f64)".into()
                }),
            ));
        }
        let mixed = edges.iter().any(|&e| e < 0.0) && edges.iter().any(|&e| e > 0.0);
        lines.push(line(
            "same signs?",
            "e0, e1, e2 all ≥ 0 or all ≤ 0",
            format!("{}, {}, {}", num(edges[0]), num(edges[1]), num(edges[2])),
            yes_no(!mixed),
            Some(if stop == 8 {
                "mixed signs: the ray passes outside an edge — stop".into()
            } else {
                "the ray passes inside (or on) all three edges".into()
            }),
        ));
        if stop != 8 {
            lines.push(line(
                "det",
                "e0 + e1 + e2",
                format!("{} + {} + {}", num(edges[0]), p(edges[1]), p(edges[2])),
                num(test.det),
                Some(if stop == 2 {
                    "zero (or not finite): the ray is parallel to the triangle — stop".into()
                } else {
                    "non-zero".into()
                }),
            ));
        }
        if stop > 2 && stop != 8 {
            let z = test.z_scaled.unwrap_or([f32::NAN; 3]);
            let pz = |x: f32| {
                if test.z_scaled.is_none() {
                    "—".to_string()
                } else {
                    p(x)
                }
            };
            lines.push(line(
                "t_scaled",
                "e0·z′0 + e1·z′1 + e2·z′2, z′ = z·Sz",
                format!(
                    "{}·{} + {}·{} + {}·{}",
                    p(edges[0]),
                    pz(z[0]),
                    p(edges[1]),
                    pz(z[1]),
                    p(edges[2]),
                    pz(z[2])
                ),
                test.dt.map_or("—".into(), num),
                None,
            ));
            let t = test.t_star.unwrap_or(f32::NAN);
            lines.push(line(
                "t",
                "t_scaled/det",
                format!("{}/{}", p(test.dt.unwrap_or(f32::NAN)), p(test.det)),
                num(t),
                None,
            ));
            lines.push(line(
                "u",
                "e1/det",
                format!("{}/{}", p(edges[1]), p(test.det)),
                test.u.map_or("—".into(), num),
                Some("the weight of P1".into()),
            ));
            lines.push(line(
                "v",
                "e2/det",
                format!("{}/{}", p(edges[2]), p(test.det)),
                test.v.map_or("—".into(), num),
                Some("the weight of P2".into()),
            ));
            lines.push(self.range_line(t));
        }
        let in_range = test.t_star.is_some_and(|t| self.in_range(t));
        let conclusion = match stop {
            12 => format!(
                "Hit at t = {}, with u = {}, v = {}.",
                test.t.map_or("?".into(), num),
                test.u.map_or("?".into(), num),
                test.v.map_or("?".into(), num)
            ),
            5 if in_range => "t is no larger than its own rounding-error bound (pbrt-v4): too close to the origin to trust — a miss.".into(),
            _ => format!("{} — a miss.", upper_first(test.stop_reason())),
        };
        Explanation {
            title: format!("Ray–triangle \"{name}\" (watertight, Woop–Benthin–Wald)"),
            lines,
            conclusion,
        }
    }
}
