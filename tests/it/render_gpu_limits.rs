//! `render --gpu` on an image past the adapter's limits is refused before anything is made on
//! the GPU, naming the limit and the largest image of the same shape the adapter renders (it
//! printed wgpu's bare "Validation Error"). Skipped where no GPU adapter (not even a software
//! one) can be opened.

use assert_cmd::Command;

#[test]
fn an_image_past_the_adapters_limits_is_refused_with_them() {
    let Ok(ctx) = raystep::gpu::GpuContext::headless() else {
        eprintln!("no GPU adapter here: skipped");
        return;
    };
    let lim = ctx.device.limits();
    drop(ctx);
    let side = lim.max_texture_dimension_2d;
    let bytes = lim.max_buffer_size.min(lim.max_storage_buffer_binding_size);
    // Past the largest buffer (the 16384×2441 on a 128 MiB adapter) where the scene
    // loader's 40 million pixels allow it, else wider than a texture may be.
    let (w, h) = if bytes / 16 < 39_000_000 {
        let w = side.min(8192);
        (w, ((bytes / 16) / u64::from(w) + 2) as u32)
    } else {
        (side + 1, 1)
    };
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "[camera]\nfrom = [0, 0, -5]\nat = [0, 0, 0]\nwidth = {w}\nheight = {h}\n[[sphere]]\nname = \"ball\"\ncenter = [0, 0, 0]\nradius = 1\n"
    );
    std::fs::write(dir.path().join("big.toml"), scene).unwrap();
    let out = Command::cargo_bin("raystep")
        .unwrap()
        .current_dir(dir.path())
        .args(["render", "big.toml", "--gpu", "-o", "big.png"])
        .assert()
        .failure()
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("a {w}×{h} image is past the limits of this GPU")),
        "{err}"
    );
    assert!(
        err.contains("the largest image of this shape it renders is"),
        "{err}"
    );
    assert!(!err.contains("Validation Error"), "{err}");
    assert!(!dir.path().join("big.png").exists());
}
