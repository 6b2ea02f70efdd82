//! The walk over both traces' JSON trees, in timeline order, collecting the differences.

use super::*;

pub(super) struct Walker {
    pub(super) tol: Tolerance,
    pub(super) diffs: Vec<Difference>,
    pub(super) count: usize,
    pub(super) numeric_count: usize,
    pub(super) first_numeric: Option<Difference>,
    pub(super) numbers: usize,
    pub(super) largest: Option<(f64, String)>,
    pub(super) tl_e: HashMap<Vec<usize>, Vec<usize>>,
    pub(super) tl_a: HashMap<Vec<usize>, Vec<usize>>,
}

impl Walker {
    pub(super) fn new(tol: Tolerance, root_e: &J, root_a: &J) -> Walker {
        Walker {
            tol,
            diffs: vec![],
            count: 0,
            numeric_count: 0,
            first_numeric: None,
            numbers: 0,
            largest: None,
            tl_e: timeline_map(root_e),
            tl_a: timeline_map(root_a),
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn push(
        &mut self,
        loc: &Loc,
        kind: DiffKind,
        field: Option<&str>,
        e: &J,
        a: &J,
        difference: Option<f64>,
        body: String,
    ) {
        let mut message = loc.prefix();
        if !message.is_empty() {
            message += ": ";
        }
        message += &body;
        let d = Difference {
            kind,
            step: loc.step,
            actual_step: loc.actual_step,
            place: loc.place.clone(),
            stage: loc.stage.clone(),
            subject: loc.subject.clone(),
            field: field.map(field_name),
            expected: e.to_value(),
            actual: a.to_value(),
            difference,
            message,
        };
        self.count += 1;
        if kind == DiffKind::Number {
            self.numeric_count += 1;
            if self.first_numeric.is_none() {
                self.first_numeric = Some(d.clone());
            }
        }
        if self.diffs.len() < MAX_KEPT {
            self.diffs.push(d);
        }
    }

    /// Compares two JSON values field by field.
    pub(super) fn values(&mut self, loc: &Loc, path: &str, e: &J, a: &J) {
        let key = path.rsplit(['.', '[']).next().unwrap_or(path);
        match (e, a) {
            (J::Obj(me), J::Obj(ma)) => {
                for k in union_keys(me, ma) {
                    self.values(loc, &join(path, &k), get(me, &k), get(ma, &k));
                }
            }
            (J::Arr(ve), J::Arr(va)) if ve.len() == va.len() => {
                for (i, (x, y)) in ve.iter().zip(va).enumerate() {
                    self.values(loc, &format!("{path}[{i}]"), x, y);
                }
            }
            (J::Arr(ve), J::Arr(va)) => {
                let body = format!("{}: {} entries vs {}", field_name(path), ve.len(), va.len());
                self.push(loc, DiffKind::Value, Some(path), e, a, None, body);
            }
            _ if is_integer(e) && is_integer(a) => {
                if e != a {
                    let body = format!("{} {} vs {}", field_name(path), show(e), show(a));
                    self.push(loc, DiffKind::Value, Some(path), e, a, None, body);
                }
            }
            _ => match (float_of(e, key), float_of(a, key)) {
                (Some(x), Some(y)) => self.number(loc, path, e, a, x, y),
                _ => {
                    if e != a {
                        let body = format!("{} {} vs {}", field_name(path), show(e), show(a));
                        self.push(loc, DiffKind::Value, Some(path), e, a, None, body);
                    }
                }
            },
        }
    }

    pub(super) fn number(&mut self, loc: &Loc, path: &str, e: &J, a: &J, x: f64, y: f64) {
        self.numbers += 1;
        let d = (x - y).abs();
        if self.tol.allows(x, y) {
            if d > 0.0 && self.largest.as_ref().is_none_or(|(m, _)| d > *m) {
                let at = format!("{}: {}", loc.prefix(), field_name(path));
                self.largest = Some((d, at));
            }
            return;
        }
        let finite = x.is_finite() && y.is_finite();
        let mut body = format!("{} {} vs {}", field_name(path), show(e), show(a));
        if finite {
            let _ = write!(
                body,
                " (differs by {}, tolerance {})",
                small(d),
                super::describe_tolerance(&self.tol)
            );
        }
        let diff = finite.then_some(d);
        self.push(loc, DiffKind::Number, Some(path), e, a, diff, body);
    }

    /// Compares two arrays entry by entry (lights, objects, the BVH outline); entries only one
    /// trace has are reported as missing or extra.
    pub(super) fn by_index(&mut self, e: &J, a: &J, place: &str, what: &str) {
        let empty = vec![];
        let ve = e.as_array().unwrap_or(&empty);
        let va = a.as_array().unwrap_or(&empty);
        let label = |v: &J, i: usize| match v.get("name").and_then(J::as_str) {
            Some(n) => format!("{what} \"{n}\""),
            None => format!("{what} {i}"),
        };
        for i in 0..ve.len().max(va.len()) {
            match (ve.get(i), va.get(i)) {
                (Some(x), Some(y)) => {
                    let loc = Loc {
                        subject: Some(label(x, i)),
                        ..Loc::place(place)
                    };
                    self.values(&loc, "", x, y);
                }
                (Some(x), None) => {
                    let body = format!(
                        "the expected trace has {} here; the actual trace has none",
                        label(x, i)
                    );
                    self.push(
                        &Loc::place(place),
                        DiffKind::Missing,
                        None,
                        x,
                        &J::Null,
                        None,
                        body,
                    );
                }
                (None, Some(y)) => {
                    let body = format!(
                        "the actual trace has {} here; the expected trace has none",
                        label(y, i)
                    );
                    self.push(
                        &Loc::place(place),
                        DiffKind::Extra,
                        None,
                        &J::Null,
                        y,
                        None,
                        body,
                    );
                }
                (None, None) => {}
            }
        }
    }

    /// Compares two rays: their own fields (at `start`, the spawn step, if any), their steps in
    /// order with the children where they were spawned, then their result.
    pub(super) fn ray(
        &mut self,
        e: &J,
        a: &J,
        path_e: &mut Vec<usize>,
        path_a: &mut Vec<usize>,
        label: String,
        start: Option<Loc>,
    ) {
        let empty_map = Vec::new();
        let oe = e.as_object().unwrap_or(&empty_map);
        let oa = a.as_object().unwrap_or(&empty_map);
        let start = start.unwrap_or_else(|| Loc::place(&label));
        let start = Loc {
            subject: Some(format!("the {label}")),
            ..start
        };
        let later = ["steps", "children", "hit", "weight", "color"];
        for k in union_keys(oe, oa) {
            if later.contains(&k.as_str()) {
                continue;
            }
            // t_max: null is ∞.
            let fix = |v: &J| {
                if k == "t_max" && v.is_null() {
                    J::Str("inf".into())
                } else {
                    v.clone()
                }
            };
            self.values(&start, &k, &fix(get(oe, &k)), &fix(get(oa, &k)));
        }

        let empty = vec![];
        let se = e.get("steps").and_then(J::as_array).unwrap_or(&empty);
        let sa = a.get("steps").and_then(J::as_array).unwrap_or(&empty);
        let ke: Vec<String> = se.iter().map(|s| step_key(s, e)).collect();
        let ka: Vec<String> = sa.iter().map(|s| step_key(s, a)).collect();
        let tl_e = self
            .tl_e
            .get(path_e.as_slice())
            .cloned()
            .unwrap_or_default();
        let tl_a = self
            .tl_a
            .get(path_a.as_slice())
            .cloned()
            .unwrap_or_default();
        let mut spawned_e = vec![];
        let mut spawned_a = vec![];
        for op in align(&ke, &ka) {
            match op {
                Op::Match(i, j) => {
                    let (x, y) = (&se[i], &sa[j]);
                    let loc = Loc {
                        place: label.clone(),
                        step: tl_e.get(i).copied(),
                        actual_step: tl_a.get(j).copied(),
                        stage: x.get("stage").and_then(J::as_str).map(String::from),
                        subject: Some(subject(x)),
                    };
                    let (mx, my) = match (x.as_object(), y.as_object()) {
                        (Some(mx), Some(my)) => (mx, my),
                        _ => {
                            self.values(&loc, "", x, y);
                            continue;
                        }
                    };
                    let is_spawn = str_of(x, "type") == "spawn";
                    for k in union_keys(mx, my) {
                        if k == "type" || (is_spawn && k == "child") {
                            continue;
                        }
                        self.values(&loc, &k, get(mx, &k), get(my, &k));
                    }
                    if is_spawn
                        && let (Some(ci), Some(cj)) = (child_index(x), child_index(y))
                        && let (Some(cx), Some(cy)) = (child_of(x, e), child_of(y, a))
                    {
                        spawned_e.push(ci);
                        spawned_a.push(cj);
                        path_e.push(ci);
                        path_a.push(cj);
                        let child = format!("{label} → {}", child_label(e, ci));
                        let spawn_loc = Loc {
                            place: child.clone(),
                            ..loc
                        };
                        self.ray(cx, cy, path_e, path_a, child, Some(spawn_loc));
                        path_e.pop();
                        path_a.pop();
                    }
                }
                Op::Gap(re, ra) => {
                    // The gap's own spawned rays are part of it, not loose children.
                    spawned_e.extend(se[re.clone()].iter().filter_map(child_index));
                    spawned_a.extend(sa[ra.clone()].iter().filter_map(child_index));
                    let first = if re.is_empty() {
                        sa.get(ra.start)
                    } else {
                        se.get(re.start)
                    };
                    let loc = Loc {
                        place: label.clone(),
                        step: tl_e.get(re.start).copied(),
                        actual_step: tl_a.get(ra.start).copied(),
                        stage: first
                            .and_then(|f| f.get("stage"))
                            .and_then(J::as_str)
                            .map(String::from),
                        subject: None,
                    };
                    let ev = J::Arr(se[re.clone()].to_vec());
                    let av = J::Arr(sa[ra.clone()].to_vec());
                    let (kind, body) = match (re.is_empty(), ra.is_empty()) {
                        (false, true) => (
                            DiffKind::Missing,
                            format!(
                                "the expected trace has {}; the actual trace has none",
                                phrases(se, &re, e)
                            ),
                        ),
                        (true, false) => (
                            DiffKind::Extra,
                            format!(
                                "the actual trace has {}; the expected trace has none",
                                phrases(sa, &ra, a)
                            ),
                        ),
                        _ => (
                            DiffKind::Replaced,
                            format!(
                                "the expected trace has {}; the actual trace has {} instead",
                                phrases(se, &re, e),
                                phrases(sa, &ra, a)
                            ),
                        ),
                    };
                    self.push(&loc, kind, None, &ev, &av, None, body);
                }
            }
        }

        // Children no step spawned (not in the timeline): compared in order.
        let ce = e.get("children").and_then(J::as_array).unwrap_or(&empty);
        let ca = a.get("children").and_then(J::as_array).unwrap_or(&empty);
        let loose_e: Vec<usize> = (0..ce.len()).filter(|i| !spawned_e.contains(i)).collect();
        let loose_a: Vec<usize> = (0..ca.len()).filter(|i| !spawned_a.contains(i)).collect();
        for k in 0..loose_e.len().max(loose_a.len()) {
            match (loose_e.get(k), loose_a.get(k)) {
                (Some(&i), Some(&j)) => {
                    path_e.push(i);
                    path_a.push(j);
                    let child = format!("{label} → {} (not spawned by a step)", child_label(e, i));
                    self.ray(&ce[i], &ca[j], path_e, path_a, child, None);
                    path_e.pop();
                    path_a.pop();
                }
                (Some(&i), None) => {
                    let body = format!(
                        "the expected trace has a {} that no step spawned; the actual trace has none",
                        child_label(e, i)
                    );
                    let loc = Loc::place(&label);
                    self.push(&loc, DiffKind::Missing, None, &ce[i], &J::Null, None, body);
                }
                (None, Some(&j)) => {
                    let body = format!(
                        "the actual trace has a {} that no step spawned; the expected trace has none",
                        child_label(a, j)
                    );
                    let loc = Loc::place(&label);
                    self.push(&loc, DiffKind::Extra, None, &J::Null, &ca[j], None, body);
                }
                (None, None) => {}
            }
        }

        // The result.
        let end = Loc {
            subject: Some("result".into()),
            ..Loc::place(&label)
        };
        let (he, ha) = (get(oe, "hit"), get(oa, "hit"));
        if he.is_null() != ha.is_null() {
            let shadow = str_of(e, "kind") == "shadow";
            let words = |h: &J| match (h.is_null(), shadow) {
                (true, true) => "nothing in the way".to_string(),
                (true, false) => "hits nothing".to_string(),
                (false, true) => format!(
                    "blocked by \"{}\" at t = {}",
                    str_of(h, "name"),
                    show(h.get("t").unwrap_or(&J::Null))
                ),
                (false, false) => format!(
                    "hits \"{}\" at t = {}",
                    str_of(h, "name"),
                    show(h.get("t").unwrap_or(&J::Null))
                ),
            };
            let body = format!(
                "the expected ray {}; the actual ray {}",
                words(he),
                words(ha)
            );
            self.push(&end, DiffKind::Value, Some("hit"), he, ha, None, body);
        } else {
            self.values(&end, "hit", he, ha);
        }
        self.values(&end, "weight", get(oe, "weight"), get(oa, "weight"));
        self.values(&end, "color", get(oe, "color"), get(oa, "color"));
    }
}
