// Copies the retained UI image into egui's render pass, pixel for pixel.
//
// Drawn as a rectangle of two triangles sampled 1:1 with a nearest sampler, in the one shape
// Mesa's llvmpipe (lavapipe and llvmpipe GL) recognises as a plain copy of a texture and runs
// without shading each pixel ("linear" rasterization; on lavapipe ~0.7 ms instead of ~4.6 ms at
// 1280×800). Its checks are literal, so keep this form: the texture coordinates come from one
// vec4 input used as `uv.xy` with no arithmetic (a vec2 input, or `textureLoad` at the pixel's
// position, fails them), the corners are exact with w = 1, the texture and sampler are the only
// ones the fragment stage sees, and the pass has one colour target (BGRA8, not sRGB) and no
// depth. A render target of any other kind takes the same draw through the usual path.

@group(0) @binding(0) var retained: texture_2d<f32>;
@group(0) @binding(1) var retained_sampler: sampler;

struct Copy {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec4<f32>,
}

@vertex
fn vs_copy(@builtin(vertex_index) i: u32) -> Copy {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(-1.0, 1.0),
        vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
    );
    let c = corners[i];
    var out: Copy;
    out.position = vec4<f32>(c, 0.0, 1.0);
    out.uv = vec4<f32>(c.x * 0.5 + 0.5, 0.5 - c.y * 0.5, 0.0, 0.0);
    return out;
}

@fragment
fn fs_copy(@location(0) uv: vec4<f32>) -> @location(0) vec4<f32> {
    return textureSample(retained, retained_sampler, uv.xy);
}

// One triangle covering the viewport (the scissor picks the rectangle to fill).
@vertex
fn vs_full_screen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // (-1,-1), (3,-1), (-1,3)
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}

// The colour under the panels, set when the pipeline is made (gamma-space 0–1).
override background_r: f32 = 0.0;
override background_g: f32 = 0.0;
override background_b: f32 = 0.0;

@fragment
fn fs_fill() -> @location(0) vec4<f32> {
    return vec4<f32>(background_r, background_g, background_b, 1.0);
}
