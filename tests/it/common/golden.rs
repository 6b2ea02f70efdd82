//! Golden images of the diagrams: [`assert_golden`].

use raystep_diagram::Canvas;
use std::path::PathBuf;

/// The repository's root (tests/golden is there), from the root package's tests or a crate's.
fn root() -> PathBuf {
    let mut p = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    while !p.join("crates").is_dir() {
        assert!(p.pop(), "no folder above the test's crate holds crates/");
    }
    p
}

/// Compares `canvas` with tests/golden/`name`.png: at most 0.5% of the pixels may differ by more
/// than 16 in some channel (font rasterization and anti-aliasing may drift a little between
/// platforms; a moved label or a changed number does not pass). With `UPDATE_GOLDEN=1` the golden
/// is (re)written instead.
pub fn assert_golden(canvas: &Canvas, name: &str) {
    let path = root().join("tests/golden").join(format!("{name}.png"));
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, canvas.png()).unwrap();
        return;
    }
    let golden = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e} (run with UPDATE_GOLDEN=1 to create it)",
                path.display()
            )
        })
        .to_rgba8();
    let actual = canvas.to_rgba_image();
    let keep = || {
        let out = std::env::temp_dir().join(format!("raystep-{name}-actual.png"));
        std::fs::write(&out, canvas.png()).unwrap();
        out
    };
    assert_eq!(
        golden.dimensions(),
        actual.dimensions(),
        "{name}: size differs from the golden (actual kept at {})",
        keep().display()
    );
    let (differing, total) = differing(&golden, &actual, |_, _| false);
    assert!(
        differing * 200 <= total,
        "{name}: {differing} of {total} pixels differ from {} by more than 16 (actual kept at {})",
        path.display(),
        keep().display()
    );
}

/// How many pixels of two images of one size differ by more than 16 in some channel, of how
/// many compared (those `skip(x, y)` leaves out are not): the goldens' rule, at most 0.5 % of
/// them, is `differing * 200 <= compared`.
pub fn differing(
    a: &image::RgbaImage,
    b: &image::RgbaImage,
    skip: impl Fn(u32, u32) -> bool,
) -> (usize, usize) {
    let (mut differing, mut compared) = (0, 0);
    for (x, y, p) in a.enumerate_pixels() {
        if skip(x, y) {
            continue;
        }
        compared += 1;
        if p.0
            .iter()
            .zip(b.get_pixel(x, y).0.iter())
            .any(|(u, v)| u.abs_diff(*v) > 16)
        {
            differing += 1;
        }
    }
    (differing, compared)
}
