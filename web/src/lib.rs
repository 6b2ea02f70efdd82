//! raystep in a web page: the entry point `web/build.sh` builds for `wasm32-unknown-unknown`.
//! The app itself is raystep's (`raystep::app`); this crate only finds the page's canvas and
//! address, tells the app whether the page started Web Workers for its renders, and starts it.
//! Natively it is empty.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen::prelude::*;

/// `initThreadPool(n)`, for the page: starts `n` Web Workers sharing the page's memory, rayon's
/// global pool on them (the renders' workers). Only in a build with WebAssembly threads.
#[cfg(all(target_arch = "wasm32", target_feature = "atomics"))]
pub use wasm_bindgen_rayon::init_thread_pool;

/// Called by the page (web/static/index.html) once the module is loaded, and on the page's
/// thread only (a Web Worker loads the module too, and must not start the app): starts the app
/// on the canvas `raystep`. `workers` is how many Web Workers the page started for renders
/// (`initThreadPool`); with 0, `why` says why it has none, and the render settings say so.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen]
pub fn start(workers: usize, why: String) {
    raystep_core::platform::set_browser_workers(workers, &why);
    wasm_bindgen_futures::spawn_local(async {
        let window = web_sys::window().expect("a page has a window");
        let document = window.document().expect("a page has a document");
        let fragment = window.location().hash().unwrap_or_default();
        let canvas = document
            .get_element_by_id("raystep")
            .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
            .expect("index.html has a canvas with id raystep");
        if let Err(e) = raystep_app::web::start(canvas, fragment).await {
            show_error(&document, &format!("raystep could not start: {e:?}"));
        }
    });
}

/// Replaces the loading text with `message` (the app could not start).
#[cfg(target_arch = "wasm32")]
fn show_error(document: &web_sys::Document, message: &str) {
    if let Some(e) = document.get_element_by_id("loading") {
        e.set_text_content(Some(message));
    }
}
