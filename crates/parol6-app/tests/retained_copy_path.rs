//! Retained painting copies its kept image into the window's pass in the one form Mesa's
//! llvmpipe runs as a plain copy instead of shading every pixel (`viewport/retained/blit.wgsl`;
//! ~0.7 ms instead of ~4.6 ms a frame at 1280×800 on lavapipe). Its checks are literal. With
//! `LP_PERF=no_shade`, llvmpipe paints every 64-pixel tile it rasterizes as rectangles plain red:
//! the whole last frame of `bench render` must be red. That guards the draw and the pass (an
//! exact rectangle alone in egui's pass, BGRA8, no depth buffer; the full-window triangle drawn
//! before left 226 496 pixels on the general path). It does not see the shader's own form (a
//! `vec4` input read as `uv.xy`): a shader that fails llvmpipe's check is still run on those
//! tiles, only slower, which `bench render`'s render-pass time shows. Checked on lavapipe
//! (Mesa 22, Vulkan), which the app takes first; on any other adapter it prints SKIPPED (and
//! fails in CI when there is none at all).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::process::Command;

#[test]
fn the_kept_image_is_copied_without_shading_on_lavapipe() {
    let dir = std::env::temp_dir().join(format!("parol6-copy-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("last.png");
    let out = Command::new(env!("CARGO_BIN_EXE_parol6"))
        .args(["bench", "render", "--seconds", "0.2", "--last-frame"])
        .arg(&png)
        .env("LP_PERF", "no_shade")
        .output()
        .expect("the parol6 binary starts");
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(1) && (stderr.contains("graphics adapter") || stderr.contains("graphics device")) {
        assert!(std::env::var_os("CI").is_none(), "no usable graphics adapter in CI: {stderr}");
        parol6_tests::skip_notice(&format!("SKIPPED retained_copy_path: {}", stderr.trim()));
        return;
    }
    assert!(out.status.success(), "bench render failed: {stderr}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("bench render prints JSON");
    let adapter = report["adapter"].as_str().unwrap_or_default().to_string();
    let lavapipe = adapter.contains("llvmpipe") && adapter.contains("Vulkan") && adapter.contains("Mesa 22.");
    if !lavapipe {
        parol6_tests::skip_notice(&format!("SKIPPED retained_copy_path: adapter {adapter} is not lavapipe (Mesa 22)"));
        return;
    }
    let img = parol6_app::viewport::read_png(&png).expect("the last frame");
    let _ = std::fs::remove_dir_all(&dir);
    let not_red = img.pixels.chunks_exact(4).filter(|p| *p != [255, 0, 0, 255]).count();
    assert_eq!(
        not_red,
        0,
        "{not_red} of {} pixels were shaded instead of copied (llvmpipe's copy path lost; adapter {adapter})",
        img.pixels.len() / 4
    );
}
