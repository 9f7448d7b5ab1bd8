// Copies the retained UI image into egui's render pass, pixel for pixel.

@group(0) @binding(0) var retained: texture_2d<f32>;

@vertex
fn vs_full_screen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // one triangle covering the viewport: (-1,-1), (3,-1), (-1,3)
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}

@group(0) @binding(1) var nearest: sampler;

struct Copy {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

// The viewport as two triangles (a rectangle) with texture coordinates 0–1: a software
// rasterizer recognises a textured rectangle sampled pixel for pixel as a plain copy.
@vertex
fn vs_rectangle(@builtin(vertex_index) i: u32) -> Copy {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0),
    );
    let c = corners[i];
    var out: Copy;
    out.position = vec4<f32>(c.x * 2.0 - 1.0, 1.0 - c.y * 2.0, 0.0, 1.0);
    out.uv = c;
    return out;
}

@fragment
fn fs_copy(in: Copy) -> @location(0) vec4<f32> {
    return textureSample(retained, nearest, in.uv);
}

// The colour under the panels, set when the pipeline is made (gamma-space 0–1).
override background_r: f32 = 0.0;
override background_g: f32 = 0.0;
override background_b: f32 = 0.0;

@fragment
fn fs_fill() -> @location(0) vec4<f32> {
    return vec4<f32>(background_r, background_g, background_b, 1.0);
}
