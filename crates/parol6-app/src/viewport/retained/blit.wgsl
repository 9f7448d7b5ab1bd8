// Copies the retained UI image into egui's render pass, pixel for pixel.

@group(0) @binding(0) var retained: texture_2d<f32>;

@vertex
fn vs_full_screen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // one triangle covering the viewport: (-1,-1), (3,-1), (-1,3)
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_copy(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(retained, vec2<i32>(p.xy), 0);
}

// The colour under the panels, set when the pipeline is made (gamma-space 0–1).
override background_r: f32 = 0.0;
override background_g: f32 = 0.0;
override background_b: f32 = 0.0;

@fragment
fn fs_fill() -> @location(0) vec4<f32> {
    return vec4<f32>(background_r, background_g, background_b, 1.0);
}
