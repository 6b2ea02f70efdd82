//! Files, the one way both builds reach them. Natively these are the disk's (`std::fs`). In the
//! browser a page has no disk: the files live in memory for the page's lifetime — the built-in
//! scenes, lessons and sheets (unpacked there as natively into the cache folder), the files the
//! user opens with the file picker or drops on the page, and what the app writes (an edited
//! scene, a student's progress), which the user keeps with a download.

#[cfg(target_arch = "wasm32")]
use std::io::{Error, ErrorKind};
use std::path::{Path, PathBuf};

/// The folder the built-in files are unpacked under: the user's cache natively
/// (`$XDG_CACHE_HOME/raystep`, else `~/.cache/raystep`, else the temporary folder), `/raystep`
/// in the page's memory.
pub fn cache_base() -> PathBuf {
    #[cfg(not(target_arch = "wasm32"))]
    {
        let from_env = |k: &str| {
            std::env::var_os(k)
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
        };
        from_env("XDG_CACHE_HOME")
            .filter(|p| p.is_absolute())
            .or_else(|| from_env("HOME").map(|h| h.join(".cache")))
            .unwrap_or_else(std::env::temp_dir)
            .join("raystep")
    }
    #[cfg(target_arch = "wasm32")]
    PathBuf::from("/raystep")
}

/// Whether `path` names a file (not a folder).
pub fn is_file(path: &Path) -> bool {
    #[cfg(not(target_arch = "wasm32"))]
    return path.is_file();
    #[cfg(target_arch = "wasm32")]
    web::with(|m| m.contains_key(&web::normal(path)))
}

/// The whole of the file `path` (no limit: callers that read user files use
/// [`crate::io::read_input`], which keeps to one).
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    #[cfg(not(target_arch = "wasm32"))]
    return std::fs::read(path);
    #[cfg(target_arch = "wasm32")]
    web::with(|m| m.get(&web::normal(path)).map(|b| b.to_vec()))
        .ok_or_else(|| Error::new(ErrorKind::NotFound, "no such file"))
}

/// The size of the file `path` in bytes.
pub fn len(path: &Path) -> std::io::Result<u64> {
    #[cfg(not(target_arch = "wasm32"))]
    return std::fs::metadata(path).map(|m| m.len());
    #[cfg(target_arch = "wasm32")]
    web::with(|m| m.get(&web::normal(path)).map(|b| b.len() as u64))
        .ok_or_else(|| Error::new(ErrorKind::NotFound, "no such file"))
}

/// Writes `bytes` to `path`, whole or not at all, making its folder first (natively through
/// [`super::atomic::write_atomic`]).
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
        }
        super::atomic::write_atomic(path, bytes)
    }
    #[cfg(target_arch = "wasm32")]
    {
        web::with(|m| m.insert(web::normal(path), bytes.into()));
        Ok(())
    }
}

/// The files directly in the folder `dir` (full paths, in no particular order).
pub fn list(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        Ok(std::fs::read_dir(dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect())
    }
    #[cfg(target_arch = "wasm32")]
    {
        let dir = web::normal(dir);
        let files: Vec<PathBuf> = web::with(|m| {
            m.keys()
                .filter(|p| p.parent() == Some(dir.as_path()))
                .cloned()
                .collect()
        });
        if files.is_empty() {
            return Err(Error::new(ErrorKind::NotFound, "no such folder"));
        }
        Ok(files)
    }
}

/// The page's files (compiled natively too, for its tests).
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
mod web {
    use std::collections::BTreeMap;
    use std::path::{Component, Path, PathBuf};
    use std::sync::{Arc, Mutex};

    /// The page's files by path.
    static FILES: Mutex<BTreeMap<PathBuf, Arc<[u8]>>> = Mutex::new(BTreeMap::new());

    pub(super) fn with<T>(f: impl FnOnce(&mut BTreeMap<PathBuf, Arc<[u8]>>) -> T) -> T {
        f(&mut FILES.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// `p` with its `.` and `..` resolved by the names alone (there are no links in memory), as
    /// the files are kept: a sheet names its scene as `../../scenes/…`.
    pub(super) fn normal(p: &Path) -> PathBuf {
        let mut out = PathBuf::from("/");
        for c in p.components() {
            match c {
                Component::ParentDir => {
                    out.pop();
                }
                Component::Normal(n) => out.push(n),
                Component::CurDir | Component::RootDir | Component::Prefix(_) => {}
            }
        }
        out
    }
}

/// What a non-regular file is, in words ("a FIFO (named pipe)", "a directory", …).
pub(crate) fn kind_of(ft: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if ft.is_char_device() {
            return "a character device";
        }
        if ft.is_block_device() {
            return "a block device";
        }
        if ft.is_socket() {
            return "a socket";
        }
    }
    if ft.is_dir() {
        return "a directory";
    }
    "not a regular file"
}

#[cfg(test)]
mod tests {
    use super::web;
    use std::path::{Path, PathBuf};

    #[test]
    fn the_pages_files_resolve_dots_by_name() {
        assert_eq!(
            web::normal(Path::new(
                "/raystep/b/lessons/exercises/../../scenes/./c.toml"
            )),
            PathBuf::from("/raystep/b/scenes/c.toml")
        );
        assert_eq!(web::normal(Path::new("../../x")), PathBuf::from("/x"));
        assert_eq!(web::normal(Path::new("a.json")), PathBuf::from("/a.json"));
    }
}
