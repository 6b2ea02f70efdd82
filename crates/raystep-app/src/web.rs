//! The app in a web page (the `wasm32` build, `web/`): [`start`] runs it on a canvas.
//!
//! The page's address can name the moment to open on, so a teacher links to the exact step of a
//! lesson: `#scene=cornell&pixel=160,120&step=7` (any of the three; `scene` a built-in scene's
//! name, as `raystep open` takes it). `embed` asks for the compact window a page embeds (the
//! book's live figures): the render, the stepper and the diagram, with a link to the full app.

/// What the page's address asks for (its part after `#`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Link {
    /// A built-in scene's name.
    pub scene: Option<String>,
    /// The pixel to select.
    pub pixel: Option<[u32; 2]>,
    /// The step to go to.
    pub step: Option<usize>,
    /// The compact window for embedding in a page.
    pub embed: bool,
}

impl Link {
    /// Reads `scene=…&pixel=x,y&step=k` (a leading `#` allowed). Unknown keys and malformed
    /// values are ignored, each named in the returned warnings (shown in the app), never fatal.
    pub fn parse(fragment: &str) -> (Link, Vec<String>) {
        let mut link = Link::default();
        let mut warnings = vec![];
        for part in fragment.trim_start_matches('#').split('&') {
            if part.is_empty() {
                continue;
            }
            let (key, value) = part.split_once('=').unwrap_or((part, ""));
            match key {
                "scene" if crate::assets::builtin_scene(value).is_some() => {
                    link.scene = Some(value.to_string());
                }
                "scene" => warnings.push(format!(
                    "the link's scene \"{value}\" is not a built-in scene (they are: {})",
                    crate::assets::scene_names().join(", ")
                )),
                "pixel" => match value
                    .split_once(',')
                    .and_then(|(x, y)| Some([x.trim().parse().ok()?, y.trim().parse().ok()?]))
                {
                    Some(p) => link.pixel = Some(p),
                    None => warnings.push(format!(
                        "the link's pixel \"{value}\" is not two whole numbers x,y"
                    )),
                },
                "embed" if matches!(value, "" | "1" | "true") => link.embed = true,
                "step" => match value.parse() {
                    Ok(k) => link.step = Some(k),
                    Err(_) => {
                        warnings.push(format!("the link's step \"{value}\" is not a whole number"));
                    }
                },
                _ => warnings.push(format!(
                    "the link's \"{key}\" is not understood (it takes scene, pixel, step and embed)"
                )),
            }
        }
        (link, warnings)
    }

    /// The same moment in the full app: `fragment` without its `embed` (for the embedded
    /// window's link out), with its `#`.
    pub fn full_app(fragment: &str) -> String {
        let kept: Vec<&str> = fragment
            .trim_start_matches('#')
            .split('&')
            .filter(|p| !p.is_empty() && p.split_once('=').map_or(*p, |(k, _)| k) != "embed")
            .collect();
        format!("#{}", kept.join("&"))
    }
}

/// What the page shows now, kept in a hidden `<div id="raystep-status" aria-live="polite">`
/// ([`publish`]): a screen reader announces the step, and a script (the browser test,
/// `web/check.py`) reads the app's state from outside through its `data-` attributes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Status {
    /// The open scene's name (`data-scene`).
    pub scene: String,
    /// The selected pixel, `x,y`, or empty (`data-pixel`).
    pub pixel: String,
    /// The current step, or empty (`data-step`).
    pub step: String,
    /// How many steps the pixel's trace has (`data-steps`).
    pub steps: usize,
    /// Which panel beside the render shows: `render`, `lesson` or `exercise` (`data-view`).
    pub view: &'static str,
    /// The open lesson's title, or empty (`data-lesson`).
    pub lesson: String,
    /// The shown question's last check: `right`, `wrong: …`, or empty (`data-feedback`).
    pub feedback: String,
    /// Whether a render has finished (`data-ready`).
    pub ready: bool,
    /// The finished render's threads (`data-threads`; in the page 1, or its Web Workers),
    /// empty before one has finished.
    pub threads: String,
    /// The finished render's time from its start, in milliseconds (`data-render-ms`), empty
    /// before one has finished.
    pub render_ms: String,
    /// The message shown in the status bar, if any (`data-message`).
    pub message: String,
    /// The GPU view ([`super::state::gpu::GpuState::status`]): `data-gpu` (empty until its tab
    /// opens, then `waiting`, `ready`, `no-webgpu` or `error: …`), `data-gpu-adapter`,
    /// `data-gpu-pick` (the debug pixel), `data-gpu-diff` (the CPU − GPU summary).
    pub gpu: super::state::gpu::GpuStatus,
}

impl Status {
    /// The status of `state` and the GPU view `gpu`.
    pub fn of(state: &super::state::AppState) -> Status {
        use super::learn::LearnTab;
        use super::state::Document;
        let learn = &state.learn;
        let (view, lesson, feedback) = if !state.prefs.show_learn {
            ("render", String::new(), String::new())
        } else if learn.tab == LearnTab::Lesson {
            let title = learn
                .lessons
                .get(learn.lesson)
                .map_or(String::new(), |l| l.title.clone());
            ("lesson", title, String::new())
        } else {
            let feedback = learn
                .attempts
                .get(learn.question)
                .and_then(|a| a.mark.as_ref())
                .map_or(String::new(), |m| {
                    if m.right {
                        "right".to_string()
                    } else {
                        format!("wrong: {}", m.note.as_deref().unwrap_or(""))
                    }
                });
            ("exercise", String::new(), feedback)
        };
        Status {
            scene: match &state.doc {
                Document::Scene { scene, .. } => scene.name.clone(),
                Document::Trace { path } => format!("trace {}", path.display()),
                Document::Empty => String::new(),
            },
            pixel: state
                .pixel
                .map_or(String::new(), |[x, y]| format!("{x},{y}")),
            step: if state.stepping.is_some() {
                state.step.to_string()
            } else {
                String::new()
            },
            steps: state.stepping.as_ref().map_or(0, |s| s.index.len()),
            view,
            lesson,
            feedback,
            ready: state.rendered.is_some(),
            threads: state
                .rendered
                .as_ref()
                .map_or(String::new(), |r| r.output.stats.threads.to_string()),
            render_ms: state.rendered.as_ref().map_or(String::new(), |r| {
                format!("{:.1}", r.wall.as_secs_f64() * 1e3)
            }),
            message: state
                .message
                .as_ref()
                .map_or(String::new(), |m| m.text.clone()),
            gpu: state.gpu.status(),
        }
    }

    /// The sentence a screen reader announces.
    pub fn sentence(&self) -> String {
        let mut s = self.scene.clone();
        if !self.pixel.is_empty() {
            s += &format!(", pixel {}", self.pixel);
        }
        if !self.step.is_empty() {
            s += &format!(", step {} of {}", self.step, self.steps);
        }
        if !self.lesson.is_empty() {
            s += &format!(", lesson: {}", self.lesson);
        }
        if !self.feedback.is_empty() {
            s += &format!(", answer {}", self.feedback);
        }
        s
    }

    /// The `data-` attributes, by name.
    pub fn attributes(&self) -> [(&'static str, String); 15] {
        [
            ("data-scene", self.scene.clone()),
            ("data-pixel", self.pixel.clone()),
            ("data-step", self.step.clone()),
            ("data-steps", self.steps.to_string()),
            ("data-view", self.view.to_string()),
            ("data-lesson", self.lesson.clone()),
            ("data-feedback", self.feedback.clone()),
            ("data-ready", if self.ready { "1" } else { "0" }.to_string()),
            ("data-threads", self.threads.clone()),
            ("data-render-ms", self.render_ms.clone()),
            ("data-message", self.message.clone()),
            ("data-gpu", self.gpu.state.clone()),
            ("data-gpu-adapter", self.gpu.adapter.clone()),
            ("data-gpu-pick", self.gpu.pick.clone()),
            ("data-gpu-diff", self.gpu.diff.clone()),
        ]
    }
}

/// Writes `status` into the page's `#raystep-status` (made on first use), touching the page
/// only when something changed.
#[cfg(target_arch = "wasm32")]
pub fn publish(status: &Status) {
    use std::cell::RefCell;
    thread_local! {
        static SHOWN: RefCell<Option<Status>> = const { RefCell::new(None) };
    }
    if SHOWN.with(|s| s.borrow().as_ref() == Some(status)) {
        return;
    }
    let Some(document) = web_sys::window().and_then(|w| w.document()) else {
        return;
    };
    let element = document.get_element_by_id("raystep-status").or_else(|| {
        let e = document.create_element("div").ok()?;
        e.set_id("raystep-status");
        let _ = e.set_attribute("aria-live", "polite");
        // Visually hidden, still read by screen readers.
        let _ = e.set_attribute(
            "style",
            "position:absolute;width:1px;height:1px;overflow:hidden;clip:rect(0 0 0 0)",
        );
        document.body()?.append_child(&e).ok()?;
        Some(e)
    });
    if let Some(e) = element {
        for (k, v) in status.attributes() {
            let _ = e.set_attribute(k, &v);
        }
        e.set_text_content(Some(&status.sentence()));
    }
    SHOWN.with(|s| *s.borrow_mut() = Some(status.clone()));
}

/// Goes where the link `fragment` (the page address's part after `#`) says, if it changed
/// since the last call: its scene (a built-in one), pixel and step. What it does not understand
/// is said in the status bar; nothing else changes then.
pub fn follow(app: &mut super::RaystepApp, fragment: &str) {
    if app.link == fragment {
        return;
    }
    app.link = fragment.to_string();
    let (link, warnings) = Link::parse(fragment);
    let file = match link.scene.as_deref() {
        Some(n) => crate::assets::builtin_scene_path(n).ok().flatten(),
        None => app.state.path().map(std::path::Path::to_path_buf),
    };
    if let Some(f) = &file
        && (link.scene.is_some() || link.pixel.is_some() || link.step.is_some())
    {
        let pixel = link.pixel.or(app.state.pixel);
        app.state
            .open_prepared(f, None, pixel, link.step.unwrap_or(0));
    }
    if link.embed {
        // An embedded figure neither reads nor keeps the reader's preferences: it shows the
        // moment as the book means it, and what is changed in it is not remembered.
        if app.state.embed.is_none() {
            app.state.prefs = super::prefs::Prefs::default();
        }
        app.state.embed = Some(Link::full_app(fragment));
    }
    if !warnings.is_empty() {
        app.state.message = Some(super::state::Message {
            text: warnings.join("; "),
            error: true,
        });
    }
}

/// Starts the app on `canvas`, opening what `fragment` (the page's address after `#`) names.
#[cfg(target_arch = "wasm32")]
pub async fn start(
    canvas: web_sys::HtmlCanvasElement,
    fragment: String,
) -> Result<(), wasm_bindgen::JsValue> {
    let mut options = eframe::WebOptions::default();
    // The page draws with WebGL2, which every browser offers (and whose canvas a headless
    // browser can screenshot). The GPU view traces on a WebGPU device of its own where the
    // browser has one (`gpu_view`), and shows its image as an egui texture.
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(create) = &mut options.wgpu_options.wgpu_setup {
        create.instance_descriptor.backends = eframe::wgpu::Backends::GL;
    }
    let runner = eframe::WebRunner::new();
    runner
        .start(
            canvas,
            options,
            Box::new(move |cc| {
                let (link, _) = Link::parse(&fragment);
                let file = link
                    .scene
                    .as_deref()
                    .and_then(|n| crate::assets::builtin_scene_path(n).ok().flatten());
                let mut app = super::RaystepApp::new(cc, file);
                follow(&mut app, &fragment);
                Ok(Box::new(app))
            }),
        )
        .await
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_link_names_a_scene_a_pixel_and_a_step() {
        let (l, w) = Link::parse("#scene=cornell&pixel=160,120&step=7");
        assert_eq!(
            l,
            Link {
                scene: Some("cornell".into()),
                pixel: Some([160, 120]),
                step: Some(7),
                embed: false,
            }
        );
        assert!(w.is_empty());
    }

    #[test]
    fn an_embedded_moment_links_out_to_the_same_moment_in_the_full_app() {
        let (l, w) = Link::parse("#embed&scene=instances&pixel=186,110&step=12");
        assert!(l.embed && w.is_empty(), "{w:?}");
        assert_eq!(l.step, Some(12));
        assert_eq!(
            Link::full_app("#embed&scene=instances&pixel=186,110&step=12"),
            "#scene=instances&pixel=186,110&step=12"
        );
        assert_eq!(Link::full_app("scene=cornell&embed=1"), "#scene=cornell");
        // Only a bare flag (or 1, true) asks for it.
        let (l, w) = Link::parse("embed=no");
        assert!(!l.embed);
        assert_eq!(w.len(), 1, "{w:?}");
    }

    #[test]
    fn a_bad_link_is_named_and_ignored() {
        let (l, w) = Link::parse("scene=nowhere&pixel=1;2&step=-1&zoom=3");
        assert_eq!(l, Link::default());
        assert_eq!(w.len(), 4, "{w:?}");
        assert!(
            w[0].contains("\"nowhere\" is not a built-in scene"),
            "{}",
            w[0]
        );
        assert!(w[1].contains("\"1;2\""), "{}", w[1]);
        assert!(w[2].contains("\"-1\""), "{}", w[2]);
        assert!(w[3].contains("\"zoom\""), "{}", w[3]);
    }
}
