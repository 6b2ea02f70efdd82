//! Outputs that would destroy an input or another output: [`check_outputs`] refuses them before
//! anything is written. Two paths are the same file when they resolve to the same place
//! (symbolic links and `..` followed, the parent's links for a file not yet there) or, on Unix,
//! when both exist and share a device and inode (a hard link).

use std::path::{Path, PathBuf};

/// Where `p` resolves: the file itself when it exists (links followed), else its resolved parent
/// joined with its name (a file not yet written).
fn resolve(p: &Path) -> PathBuf {
    if let Ok(c) = std::fs::canonicalize(p) {
        return c;
    }
    let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    match (abs.parent(), abs.file_name()) {
        (Some(dir), Some(name)) => std::fs::canonicalize(dir)
            .map(|d| d.join(name))
            .unwrap_or(abs.clone()),
        _ => abs,
    }
}

/// Whether `a` and `b` are the same file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    if resolve(a) == resolve(b) {
        return true;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    false
}

/// Refuses, before anything is written, an output that is one of the inputs or another output.
/// `inputs` and `outputs` are (how the command line names it, path): "`-o answers.csv` is the
/// submissions file the command reads: …".
pub fn check_outputs(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<(), String> {
    for (i, (oname, o)) in outputs.iter().enumerate() {
        for (iname, p) in inputs {
            if same_file(o, p) {
                return Err(format!(
                    "{oname} {} is {iname} the command reads: writing it would destroy it — give another output path",
                    o.display()
                ));
            }
        }
        for (other, q) in &outputs[..i] {
            if same_file(o, q) {
                return Err(format!(
                    "{oname} {} and {other} {} are the same file: one output would overwrite the other — give them different paths",
                    o.display(),
                    q.display()
                ));
            }
        }
    }
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn the_same_file_by_any_name() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.csv");
        std::fs::write(&a, "x").unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        // By `..`, a symbolic link and a hard link; a new file in the same folder is not.
        assert!(same_file(&a, &dir.path().join("sub/../a.csv")));
        std::os::unix::fs::symlink(&a, dir.path().join("link.csv")).unwrap();
        assert!(same_file(&a, &dir.path().join("link.csv")));
        std::fs::hard_link(&a, dir.path().join("hard.csv")).unwrap();
        assert!(same_file(&a, &dir.path().join("hard.csv")));
        assert!(!same_file(&a, &dir.path().join("b.csv")));
        // Two outputs not yet written, named two ways.
        assert!(same_file(
            &dir.path().join("x.png"),
            &dir.path().join("sub/../x.png")
        ));
        let err = check_outputs(
            &[("the scene", &a)],
            &[("--save", &dir.path().join("link.csv"))],
        )
        .unwrap_err();
        assert!(err.starts_with("--save "), "{err}");
        assert!(err.contains("is the scene the command reads"), "{err}");
        let err = check_outputs(
            &[],
            &[
                ("-o", &dir.path().join("x.png")),
                ("--heatmap", &dir.path().join("x.png")),
            ],
        )
        .unwrap_err();
        assert!(err.contains("are the same file"), "{err}");
    }
}
