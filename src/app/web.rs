//! The app in a web page (the `wasm32` build, `web/`): [`start`] runs it on a canvas.
//!
//! The page's address can name the moment to open on, so a teacher links to the exact step of a
//! lesson: `#scene=cornell&pixel=160,120&step=7` (any of the three; `scene` a built-in scene's
//! name, as `raystep open` takes it).

/// What the page's address asks for (its part after `#`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Link {
    /// A built-in scene's name.
    pub scene: Option<String>,
    /// The pixel to select.
    pub pixel: Option<[u32; 2]>,
    /// The step to go to.
    pub step: Option<usize>,
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
                "step" => match value.parse() {
                    Ok(k) => link.step = Some(k),
                    Err(_) => {
                        warnings.push(format!("the link's step \"{value}\" is not a whole number"));
                    }
                },
                _ => warnings.push(format!(
                    "the link's \"{key}\" is not understood (it takes scene, pixel and step)"
                )),
            }
        }
        (link, warnings)
    }
}

/// Starts the app on `canvas`, opening what `fragment` (the page's address after `#`) names.
#[cfg(target_arch = "wasm32")]
pub async fn start(
    canvas: web_sys::HtmlCanvasElement,
    fragment: String,
) -> Result<(), wasm_bindgen::JsValue> {
    let options = eframe::WebOptions::default();
    let runner = eframe::WebRunner::new();
    runner
        .start(
            canvas,
            options,
            Box::new(move |cc| {
                let (link, warnings) = Link::parse(&fragment);
                let file = link
                    .scene
                    .as_deref()
                    .and_then(|n| crate::assets::builtin_scene_path(n).ok().flatten());
                let mut app = super::RaystepApp::new(cc, file.clone());
                if let Some(f) = &file
                    && (link.pixel.is_some() || link.step.is_some())
                {
                    app.state
                        .open_prepared(f, None, link.pixel, link.step.unwrap_or(0));
                }
                if !warnings.is_empty() {
                    app.state.message = Some(super::state::Message {
                        text: warnings.join("; "),
                        error: true,
                    });
                }
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
                step: Some(7)
            }
        );
        assert!(w.is_empty());
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
