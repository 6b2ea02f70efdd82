//! What only a browser has: downloads, the file picker, and files dropped on the page. A file
//! the user opens is read into the page's memory ([`super::files`]) under [`OPENED`] and then
//! handed to the app ([`arrived`]) by its path, so the app opens it as it opens any file.
//! Natively these do nothing: the app has its own open and save dialogs there.

use std::path::PathBuf;
use std::sync::Mutex;

/// The folder (in the page's memory) the files the user opens or drops are kept in.
pub const OPENED: &str = "/opened";

/// Files read in since the app last asked: each one's path, or why it could not be read.
static ARRIVED: Mutex<Vec<Result<PathBuf, String>>> = Mutex::new(Vec::new());

/// Keeps a file the user opened (`name`, its `bytes`) in the page's memory and queues it for
/// [`arrived`].
pub fn receive(name: &str, bytes: Result<Vec<u8>, String>) {
    let path = opened_path(name);
    let result = bytes.and_then(|b| super::files::write(&path, &b).map(|()| path));
    ARRIVED
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(result.map_err(|e| format!("{name}: {e}")));
}

/// Where a file the user opened named `name` is kept: only its own name under [`OPENED`] (a
/// browser gives no folders, and a name must not climb out).
pub fn opened_path(name: &str) -> PathBuf {
    let base = std::path::Path::new(name)
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    PathBuf::from(OPENED).join(base)
}

/// The files that arrived since the last call, in order.
pub fn arrived() -> Vec<Result<PathBuf, String>> {
    std::mem::take(&mut *ARRIVED.lock().unwrap_or_else(|e| e.into_inner()))
}

/// Offers `bytes` to the user as a download named `name` (the browser's save).
pub fn download(name: &str, bytes: &[u8]) -> Result<(), String> {
    #[cfg(target_arch = "wasm32")]
    {
        web::download(name, bytes).map_err(|e| format!("{name}: the download failed: {e:?}"))
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = (name, bytes);
        Ok(())
    }
}

/// Opens the browser's file picker (several files at once: a scene and its OBJ meshes); what
/// the user picks arrives through [`arrived`], and `wake` is called as each file arrives (the
/// app asks for a frame: an idle page draws none).
pub fn pick_files(wake: impl Fn() + 'static) -> Result<(), String> {
    #[cfg(target_arch = "wasm32")]
    {
        web::pick_files(wake).map_err(|e| format!("the file picker did not open: {e:?}"))
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = wake;
        Ok(())
    }
}

/// Runs `f` to completion on the page's event loop (natively: blocks until it is done).
pub fn spawn_local(f: impl std::future::Future<Output = ()> + 'static) {
    #[cfg(target_arch = "wasm32")]
    wasm_bindgen_futures::spawn_local(f);
    #[cfg(not(target_arch = "wasm32"))]
    pollster::block_on(f);
}

#[cfg(target_arch = "wasm32")]
mod web {
    use wasm_bindgen::JsCast;
    use wasm_bindgen::prelude::*;

    pub(super) fn download(name: &str, bytes: &[u8]) -> Result<(), JsValue> {
        let document = web_sys::window()
            .and_then(|w| w.document())
            .ok_or("no document")?;
        let parts = js_sys::Array::new();
        parts.push(&js_sys::Uint8Array::from(bytes));
        let options = web_sys::BlobPropertyBag::new();
        options.set_type("application/octet-stream");
        let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)?;
        let url = web_sys::Url::create_object_url_with_blob(&blob)?;
        let a: web_sys::HtmlAnchorElement = document.create_element("a")?.dyn_into()?;
        a.set_href(&url);
        a.set_download(name);
        a.click();
        // Released a minute later: the browser has started the download by then.
        let release = Closure::once_into_js(move || {
            let _ = web_sys::Url::revoke_object_url(&url);
        });
        if let Some(w) = web_sys::window() {
            w.set_timeout_with_callback_and_timeout_and_arguments_0(
                release.unchecked_ref(),
                60_000,
            )?;
        }
        Ok(())
    }

    pub(super) fn pick_files(wake: impl Fn() + 'static) -> Result<(), JsValue> {
        let wake = std::rc::Rc::new(wake);
        let document = web_sys::window()
            .and_then(|w| w.document())
            .ok_or("no document")?;
        let input: web_sys::HtmlInputElement = document.create_element("input")?.dyn_into()?;
        input.set_type("file");
        input.set_multiple(true);
        input.set_accept(".toml,.json,.obj,.mtl,.gltf,.glb,.bin,.png,.jpg,.jpeg,.md,.csv,.txt");
        let picked = input.clone();
        let on_change = Closure::once_into_js(move || {
            let Some(list) = picked.files() else {
                return;
            };
            for i in 0..list.length() {
                if let Some(file) = list.get(i) {
                    let wake = std::rc::Rc::clone(&wake);
                    wasm_bindgen_futures::spawn_local(async move {
                        let bytes = wasm_bindgen_futures::JsFuture::from(file.array_buffer())
                            .await
                            .map(|b| js_sys::Uint8Array::new(&b).to_vec())
                            .map_err(|e| format!("cannot be read: {e:?}"));
                        super::receive(&file.name(), bytes);
                        wake();
                    });
                }
            }
        });
        input.set_onchange(Some(on_change.unchecked_ref()));
        input.click();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_opened_file_is_kept_by_its_own_name_and_handed_on_once() {
        assert_eq!(
            opened_path("../../etc/cornell.toml"),
            PathBuf::from("/opened/cornell.toml")
        );
        assert_eq!(opened_path(".."), PathBuf::from("/opened/file"));
        receive("../x.toml", Err("cannot be read".into()));
        assert_eq!(
            arrived(),
            vec![Err("../x.toml: cannot be read".to_string())]
        );
        assert!(arrived().is_empty());
    }
}
