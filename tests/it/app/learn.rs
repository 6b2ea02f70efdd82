//! Lessons and exercises in the app: opened at their pixel, marked, explained, and their panels' snapshots.

use super::*;

/// The lessons panel: the lesson text (Markdown) is on screen, its button opens the lesson's
/// scene with the lesson's settings at its pixel on its first step, the step buttons jump, and a
/// link to the next lesson shows that lesson instead of opening a browser.
#[test]
fn a_lesson_opens_its_scene_at_its_pixel_and_steps() {
    let mut h = harness(Some(&scene_path("first-sphere.toml")));
    wait_for(&mut h, "the first render", rendered);
    open_learn(&mut h);
    let lessons =
        raystep::lesson::load_lessons(&Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons"))
            .unwrap();
    // Lesson 4 (index 3) sets the triangle method: Möller–Trumbore, not the default.
    let l = &lessons[3];
    assert_eq!(
        l.settings.triangle_method,
        Some(raystep::shapes::TriangleMethod::MollerTrumbore)
    );
    for _ in 0..3 {
        h.get_by_label("▶").click();
        h.run_steps(2);
    }
    assert_eq!(h.state().state.learn.lesson, 3);
    let all = labels(&h);
    assert!(
        all.iter()
            .any(|t| t.contains("Möller–Trumbore as Cramer") || t.contains("Cramer")),
        "the lesson's Markdown is on screen: {all:?}"
    );
    h.get_by_label_contains("Open scenes/triangles.toml at pixel (80, 130)")
        .click();
    h.step();
    wait_for(&mut h, "the lesson's scene", |a| {
        a.state
            .path()
            .is_some_and(|p| p.ends_with("scenes/triangles.toml"))
            && rendered(a)
            && a.state.stepping.is_some()
    });
    let st = &h.state().state;
    assert_eq!(st.pixel, Some(l.pixel));
    assert_eq!(st.step, l.steps[0]);
    assert_eq!(
        st.settings.triangle_method,
        raystep::shapes::TriangleMethod::MollerTrumbore,
        "the lesson's [settings] are in force"
    );
    // The trace is the tracer's for the scene with the lesson's settings.
    let mut scene = raystep::scene::load_file(&l.scene_path()).unwrap();
    l.settings.apply(&mut scene).unwrap();
    let (accel, _) = raystep::accel::SceneAccel::build(&scene);
    let want = raystep::trace::Tracer::new(&scene, &accel).record(l.pixel[0], l.pixel[1], 0);
    assert_eq!(
        st.stepping.as_ref().unwrap().trace.to_json(),
        want.to_json()
    );
    let k = l.steps[2];
    h.get_by_label(&k.to_string()).click();
    h.run_steps(2);
    assert_eq!(h.state().state.step, k, "a step button jumps to its step");

    // The link at the end of lesson 4 goes to lesson 5, in the app.
    // (Through accessibility: the link is far down the lesson, under the step controls.)
    h.get_by_label("the naive loop").click_accesskit();
    h.run_steps(3);
    assert_eq!(h.state().state.learn.lesson, 4);
}

/// Exercise mode: a student's own variant, a wrong answer marked wrong with how far off, the
/// right one (computed by the library's tracer for this student's variant) marked right, hints
/// one at a time, and "Show me in the tracer" opens the variant on the step with the answer.
#[test]
fn an_exercise_is_marked_and_explained() {
    let mut h = harness(Some(&scene_path("first-sphere.toml")));
    wait_for(&mut h, "the first render", rendered);
    open_learn(&mut h);
    h.get_by_label("Exercises").click();
    h.run_steps(2);
    let sheet_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons/exercises/02-sphere.toml");
    h.state_mut()
        .state
        .apply(Command::Learn(raystep::app::learn::LearnCmd::OpenSheet(
            sheet_path.clone(),
        )));
    h.run_steps(2);
    let field = h.get_by_role_and_label(Role::TextInput, "Student id:");
    field.focus();
    field.type_text("alice");
    h.run_steps(2);
    assert_eq!(h.state().state.learn.student, "alice");

    let sheet = raystep::lesson::load_exercise_sheet(&sheet_path).unwrap();
    let q = &sheet.questions[0];
    assert_eq!(q.quantity, raystep::lesson::Quantity::Discriminant);
    let v = sheet.variant(q, "alice");
    let labels_now = labels(&h);
    assert!(
        labels_now
            .iter()
            .any(|t| t.contains(v.text.trim().lines().next().unwrap())),
        "alice's variant of the question is shown"
    );
    let raystep::lesson::Answer::Number(want) = sheet.expected(q, &v).unwrap() else {
        panic!("the discriminant is a number for alice's pixel");
    };

    let answer = |h: &mut Harness<'static, RaystepApp>, text: &str| {
        let field = h.get_by_role_and_label(Role::TextInput, "Answer:");
        field.focus();
        field.type_text(text);
        h.run_steps(2);
        h.get_by_label("Check").click();
        h.run_steps(1);
        wait_for_check(h);
        h.run_steps(2);
    };
    answer(&mut h, &format!("{}", want * 2.0 + 1.0));
    let a = &h.state().state.learn.attempts[0];
    assert!(!a.mark.as_ref().unwrap().right);
    assert!(
        labels(&h)
            .iter()
            .any(|t| t.starts_with("✘ Not right: not within the tolerance")),
        "a wrong answer says why, not how far off (the sheet's default feedback): {:?}",
        labels(&h)
    );
    // A non-numeric answer is wrong, with the reason.
    h.state_mut()
        .state
        .apply(Command::Learn(raystep::app::learn::LearnCmd::Answer(
            String::new(),
        )));
    h.run_steps(1);
    answer(&mut h, "about ten");
    assert!(
        labels(&h).iter().any(|t| t.contains("is not a number")),
        "{:?}",
        labels(&h)
    );
    h.state_mut()
        .state
        .apply(Command::Learn(raystep::app::learn::LearnCmd::Answer(
            String::new(),
        )));
    h.run_steps(1);
    answer(&mut h, &format!("{want}"));
    assert!(
        h.state().state.learn.attempts[0]
            .mark
            .as_ref()
            .unwrap()
            .right
    );
    assert!(labels(&h).iter().any(|t| t.starts_with("✔ Right")));

    // Hints, one at a time.
    h.get_by_label_contains("Hint (0 of").click();
    h.run_steps(2);
    assert!(labels(&h).iter().any(|t| t.starts_with("Hint 1:")));
    assert!(!labels(&h).iter().any(|t| t.starts_with("Hint 2:")));

    // The explanation: the variant's scene, the pixel, the sphere test with that discriminant.
    h.get_by_label("Show me in the tracer").click();
    h.step();
    wait_for(&mut h, "the question's scene", |a| {
        matches!(&a.state.doc, Document::Scene { path: None, .. })
            && rendered(a)
            && a.state.stepping.is_some()
    });
    let st = &h.state().state;
    assert_eq!(st.pixel, Some(v.pixel));
    let s = st.stepping.as_ref().unwrap();
    let (_, step) = s.at(st.step).unwrap();
    match &step.step {
        Step::Sphere { name, test, .. } => {
            assert_eq!(name, "ball");
            assert_eq!(f64::from(test.discriminant), want);
        }
        other => panic!("the explaining step is the sphere test, got {other:?}"),
    }
}

/// Snapshots of the lessons panel (a lesson's Markdown beside its scene) and of exercise mode
/// after a wrong answer and a hint, on the software adapter.
#[test]
fn snapshots_of_the_lesson_and_exercise_panels() {
    let Some(mut h) = wgpu_harness("snapshots_of_the_lesson_and_exercise_panels", None, false)
    else {
        return;
    };
    wait_for(&mut h, "the built-in render", rendered);
    open_learn(&mut h);
    use raystep::app::learn::LearnCmd;
    h.state_mut()
        .state
        .apply(Command::Learn(LearnCmd::Lesson(1)));
    h.state_mut()
        .state
        .apply(Command::Learn(LearnCmd::OpenLesson));
    h.step();
    wait_for(&mut h, "the lesson's scene", |a| {
        rendered(a) && a.state.stepping.is_some()
    });
    settle_layout(&mut h);
    mask_timings(&mut h);
    let options = egui_kittest::SnapshotOptions::new()
        .threshold(2.0)
        .max_failed_pixels(200);
    let mut failures = vec![];
    if let Err(e) = h.try_snapshot_options("app-lesson-2", &options) {
        failures.push(e.to_string());
    }
    let sheet = Path::new("lessons/exercises/02-sphere.toml").to_path_buf();
    for c in [
        LearnCmd::OpenSheet(sheet),
        LearnCmd::Student("student-7".into()),
        LearnCmd::Answer("42".into()),
        LearnCmd::Check,
        LearnCmd::Hint,
    ] {
        h.state_mut().state.apply(Command::Learn(c));
    }
    wait_for_check(&mut h);
    settle_layout(&mut h);
    mask_timings(&mut h);
    if let Err(e) = h.try_snapshot_options("app-exercise", &options) {
        failures.push(e.to_string());
    }
    assert!(
        failures.is_empty(),
        "snapshots differ:\n{}",
        failures.join("\n")
    );
}
