//! The window icon, drawn in code.

use eframe::egui;

/// The window icon: a small orange arm on a dark tile, drawn in code (no asset file).
pub fn window_icon() -> egui::IconData {
    const N: usize = 64;
    let mut rgba = vec![0u8; N * N * 4];
    let mut put = |x: i32, y: i32, c: [u8; 4]| {
        if (0..N as i32).contains(&x) && (0..N as i32).contains(&y) {
            let i = (y as usize * N + x as usize) * 4;
            rgba[i..i + 4].copy_from_slice(&c);
        }
    };
    let bg = [28, 32, 40, 255];
    for y in 0..N as i32 {
        for x in 0..N as i32 {
            let (dx, dy) = ((x - 31).abs().max(0) as f32, (y - 31).abs() as f32);
            if dx < 30.0 && dy < 30.0 {
                put(x, y, bg);
            }
        }
    }
    let orange = [255, 140, 26, 255];
    let seg = |put: &mut dyn FnMut(i32, i32, [u8; 4]), a: (f32, f32), b: (f32, f32), w: f32| {
        for y in 0..N as i32 {
            for x in 0..N as i32 {
                let (px, py) = (x as f32, y as f32);
                let (vx, vy) = (b.0 - a.0, b.1 - a.1);
                let t = (((px - a.0) * vx + (py - a.1) * vy) / (vx * vx + vy * vy)).clamp(0.0, 1.0);
                let (cx, cy) = (a.0 + t * vx - px, a.1 + t * vy - py);
                if cx * cx + cy * cy <= w * w {
                    put(x, y, orange);
                }
            }
        }
    };
    seg(&mut put, (14.0, 54.0), (50.0, 54.0), 3.0); // base
    seg(&mut put, (24.0, 52.0), (24.0, 30.0), 4.0); // upper arm
    seg(&mut put, (24.0, 30.0), (46.0, 18.0), 3.5); // forearm
    seg(&mut put, (46.0, 18.0), (50.0, 28.0), 2.5); // wrist / tool
    egui::IconData { rgba, width: N as u32, height: N as u32 }
}
