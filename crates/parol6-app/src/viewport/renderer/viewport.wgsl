// PAROL6 Studio 3D view: background, lit meshes (links, ghost, overlays, axes), grid lines
// and the fading TCP trail. One uniform block (`Globals` in renderer/frame_data.rs).
struct Globals {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light_dir: vec4<f32>,
    // x: 1 = encode linear → sRGB here (non-sRGB target); y: grid fade radius, m
    params: vec4<f32>,
    // x: newest trail slot, y: trail points, z: trail capacity
    trail: vec4<u32>,
    trail_rgba: vec4<f32>,
    // The view's background, already in the target's encoding.
    background: vec4<f32>,
};
@group(0) @binding(0) var<uniform> g: Globals;

// Background: one triangle covering the viewport, a constant colour (cheap on software
// rasterizers, unlike a textured egui rectangle).
@vertex
fn vs_background(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let x = f32(i32(vi & 1u) * 4 - 1);
    let y = f32(i32(vi >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 1.0, 1.0);
}

@fragment
fn fs_background() -> @location(0) vec4<f32> {
    return g.background;
}

// Linear → sRGB with three square roots instead of pow (within ~0.5 % of the exact curve;
// pow is expensive on software rasterizers).
fn encode(c: vec3<f32>) -> vec3<f32> {
    if (g.params.x > 0.5) {
        let s1 = sqrt(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)));
        let s2 = sqrt(s1);
        let s3 = sqrt(s2);
        return clamp(0.585122381 * s1 + 0.783140355 * s2 - 0.368262736 * s3, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    return c;
}

struct MeshIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) m0: vec4<f32>,
    @location(4) m1: vec4<f32>,
    @location(5) m2: vec4<f32>,
    @location(6) m3: vec4<f32>,
    @location(7) tint: vec4<f32>,
    @location(8) style: vec4<f32>,
};
struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_mesh(v: MeshIn) -> MeshOut {
    let m = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    let w = m * vec4<f32>(v.pos, 1.0);
    var o: MeshOut;
    o.clip = g.view_proj * w;
    o.world = w.xyz;
    o.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    o.color = vec4<f32>(mix(v.color.rgb, v.tint.rgb, v.tint.a), v.color.a * v.style.x);
    return o;
}

@fragment
fn fs_mesh(i: MeshOut) -> @location(0) vec4<f32> {
    var n = normalize(i.normal);
    let view = normalize(g.eye.xyz - i.world);
    // Two-sided lighting: mesh files do not always wind their triangles consistently.
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    let l = normalize(g.light_dir.xyz);
    let key = max(dot(n, l), 0.0);
    let rim = max(n.z, 0.0);
    let ambient = mix(0.16, 0.32, n.z * 0.5 + 0.5);
    let h = normalize(l + view);
    // Specular power 40 by squaring (x^32 · x^8).
    let x = max(dot(n, h), 0.0);
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let x32 = x8 * x8 * x8 * x8;
    let spec = x32 * x8 * 0.22;
    let c = i.color.rgb * (ambient + 0.75 * key + 0.12 * rim) + vec3<f32>(spec);
    return vec4<f32>(encode(c), i.color.a);
}

struct LineIn {
    @location(0) pos: vec3<f32>,
    @location(1) color: vec4<f32>,
};
struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) color: vec4<f32>,
};

@vertex
fn vs_line(v: LineIn) -> LineOut {
    var o: LineOut;
    o.clip = g.view_proj * vec4<f32>(v.pos, 1.0);
    o.world = v.pos;
    o.color = v.color;
    return o;
}

@fragment
fn fs_line(i: LineOut) -> @location(0) vec4<f32> {
    let r = length(i.world.xy) / max(g.params.y, 1e-3);
    let fade = clamp(1.3 - r * 1.3, 0.0, 1.0);
    return vec4<f32>(encode(i.color.rgb), i.color.a * fade);
}

@vertex
fn vs_trail(@builtin(vertex_index) vi: u32, @location(0) pos: vec3<f32>, @location(1) rgb: vec3<f32>) -> LineOut {
    let cap = max(g.trail.z, 1u);
    var slot = vi;
    if (slot >= cap) {
        slot = 0u;
    }
    let age = (g.trail.x + cap - slot) % cap;
    let t = 1.0 - f32(age) / f32(max(g.trail.y, 1u));
    var o: LineOut;
    o.clip = g.view_proj * vec4<f32>(pos, 1.0);
    o.world = pos;
    o.color = vec4<f32>(rgb, g.trail_rgba.a * t * t);
    return o;
}

@fragment
fn fs_trail(i: LineOut) -> @location(0) vec4<f32> {
    return vec4<f32>(encode(i.color.rgb), i.color.a);
}
