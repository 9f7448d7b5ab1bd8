//! Tessellated primitives in their own frame: boxes, cylinders, cones, spheres, capsules and
//! the axes triad drawn for the TCP and link frames.

use parol6_core::na::{Isometry3, Vector3};

use super::CpuMesh;
use crate::palette;

/// Segments around a cylinder, capsule or sphere.
const ROUND_SEGMENTS: usize = 32;
/// Rings of a sphere (and of each capsule cap: half of them).
const SPHERE_RINGS: usize = 16;

impl CpuMesh {
    /// Axis-aligned box centred on the origin with full edge lengths `size_m`.
    pub fn cuboid(size_m: [f64; 3], rgba: [f32; 4]) -> Self {
        let h = [size_m[0] * 0.5, size_m[1] * 0.5, size_m[2] * 0.5];
        let mut m = CpuMesh::default();
        // For each axis and sign: a face with normal along it.
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut n = [0.0; 3];
                n[axis] = sign;
                let corner = |su: f64, sv: f64| {
                    let mut p = [0.0; 3];
                    p[axis] = sign * h[axis];
                    p[u] = su * h[u];
                    p[v] = sv * h[v];
                    p
                };
                let a = m.push_vertex(corner(-1.0, -1.0), n, rgba);
                let b = m.push_vertex(corner(1.0, -1.0), n, rgba);
                let c = m.push_vertex(corner(1.0, 1.0), n, rgba);
                let d = m.push_vertex(corner(-1.0, 1.0), n, rgba);
                if sign > 0.0 {
                    m.indices.extend([a, b, c, a, c, d]);
                } else {
                    m.indices.extend([a, c, b, a, d, c]);
                }
            }
        }
        m
    }

    /// Cylinder along z, centred on the origin, with caps.
    pub fn cylinder(radius_m: f64, length_m: f64, rgba: [f32; 4]) -> Self {
        let mut m = CpuMesh::default();
        let hz = length_m * 0.5;
        let n = ROUND_SEGMENTS;
        let ring = |i: usize| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            (a.cos(), a.sin())
        };
        // Side.
        let side0 = m.vertices.len() as u32;
        for i in 0..=n {
            let (c, s) = ring(i);
            m.push_vertex([radius_m * c, radius_m * s, -hz], [c, s, 0.0], rgba);
            m.push_vertex([radius_m * c, radius_m * s, hz], [c, s, 0.0], rgba);
        }
        for i in 0..n as u32 {
            let (a, b, c, d) = (side0 + 2 * i, side0 + 2 * i + 1, side0 + 2 * i + 2, side0 + 2 * i + 3);
            m.indices.extend([a, c, d, a, d, b]);
        }
        // Caps.
        for (z, nz) in [(-hz, -1.0), (hz, 1.0)] {
            let centre = m.push_vertex([0.0, 0.0, z], [0.0, 0.0, nz], rgba);
            let first = m.vertices.len() as u32;
            for i in 0..=n {
                let (c, s) = ring(i);
                m.push_vertex([radius_m * c, radius_m * s, z], [0.0, 0.0, nz], rgba);
            }
            for i in 0..n as u32 {
                if nz > 0.0 {
                    m.indices.extend([centre, first + i, first + i + 1]);
                } else {
                    m.indices.extend([centre, first + i + 1, first + i]);
                }
            }
        }
        m
    }

    /// Cone along +z with its base at z = 0 and its tip at `length_m`.
    pub fn cone(radius_m: f64, length_m: f64, rgba: [f32; 4]) -> Self {
        let mut m = CpuMesh::default();
        let n = ROUND_SEGMENTS;
        let slope = radius_m / length_m.max(1e-9);
        let norm = (1.0 + slope * slope).sqrt();
        let first = m.vertices.len() as u32;
        for i in 0..=n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let (c, s) = (a.cos(), a.sin());
            let nrm = [c / norm, s / norm, slope / norm];
            m.push_vertex([radius_m * c, radius_m * s, 0.0], nrm, rgba);
            m.push_vertex([0.0, 0.0, length_m], nrm, rgba);
        }
        for i in 0..n as u32 {
            m.indices.extend([first + 2 * i, first + 2 * i + 2, first + 2 * i + 1]);
        }
        let centre = m.push_vertex([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], rgba);
        let ring0 = m.vertices.len() as u32;
        for i in 0..=n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            m.push_vertex([radius_m * a.cos(), radius_m * a.sin(), 0.0], [0.0, 0.0, -1.0], rgba);
        }
        for i in 0..n as u32 {
            m.indices.extend([centre, ring0 + i + 1, ring0 + i]);
        }
        m
    }

    /// UV sphere; with `half_gap_m` > 0 the two hemispheres are pulled apart along z (a capsule
    /// without its cylinder).
    fn sphere_split(radius_m: f64, half_gap_m: f64, rgba: [f32; 4]) -> Self {
        let mut m = CpuMesh::default();
        let rings = SPHERE_RINGS + (SPHERE_RINGS % 2);
        let segs = ROUND_SEGMENTS;
        // Duplicate the equator ring when split so each hemisphere has its own.
        let mut ring_rows: Vec<(f64, f64)> = Vec::new(); // (polar angle, z offset)
        for r in 0..=rings {
            let theta = r as f64 / rings as f64 * std::f64::consts::PI;
            if half_gap_m > 0.0 && r == rings / 2 {
                ring_rows.push((theta, half_gap_m));
                ring_rows.push((theta, -half_gap_m));
            } else {
                let off = if r < rings / 2 { half_gap_m } else { -half_gap_m };
                ring_rows.push((theta, off));
            }
        }
        let row_len = (segs + 1) as u32;
        for &(theta, off) in &ring_rows {
            let (st, ct) = theta.sin_cos();
            for s in 0..=segs {
                let phi = s as f64 / segs as f64 * std::f64::consts::TAU;
                let n = [st * phi.cos(), st * phi.sin(), ct];
                m.push_vertex([radius_m * n[0], radius_m * n[1], radius_m * n[2] + off], n, rgba);
            }
        }
        for r in 0..ring_rows.len() - 1 {
            if half_gap_m > 0.0 && r == rings / 2 {
                continue; // the gap between the hemispheres is closed by the cylinder
            }
            for s in 0..segs as u32 {
                let a = r as u32 * row_len + s;
                let b = a + row_len;
                m.indices.extend([a, b, b + 1, a, b + 1, a + 1]);
            }
        }
        m
    }

    /// Sphere centred on the origin.
    pub fn sphere(radius_m: f64, rgba: [f32; 4]) -> Self {
        Self::sphere_split(radius_m, 0.0, rgba)
    }

    /// Capsule along z: a cylinder of `length_m` with hemispherical caps.
    pub fn capsule(radius_m: f64, length_m: f64, rgba: [f32; 4]) -> Self {
        let mut m = Self::sphere_split(radius_m, length_m * 0.5, rgba);
        let mut side = CpuMesh::default();
        let n = ROUND_SEGMENTS;
        let hz = length_m * 0.5;
        for i in 0..=n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let (c, s) = (a.cos(), a.sin());
            side.push_vertex([radius_m * c, radius_m * s, -hz], [c, s, 0.0], rgba);
            side.push_vertex([radius_m * c, radius_m * s, hz], [c, s, 0.0], rgba);
        }
        for i in 0..n as u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
            side.indices.extend([a, c, d, a, d, b]);
        }
        m.append_transformed(&side, &Isometry3::identity());
        m
    }

    /// Three arrows along x (red), y (green), z (blue), each of length 1 (scale it with the
    /// instance transform).
    pub fn axes_triad() -> Self {
        let mut m = CpuMesh::default();
        let colours = [palette::VIEW_FRAME_AXIS_X, palette::VIEW_FRAME_AXIS_Y, palette::VIEW_FRAME_AXIS_Z];
        let orient = [
            Isometry3::rotation(Vector3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0)),
            Isometry3::rotation(Vector3::new(-std::f64::consts::FRAC_PI_2, 0.0, 0.0)),
            Isometry3::identity(),
        ];
        for (rgb, rot) in colours.iter().zip(orient) {
            let [r, g, b] = palette::linear_rgb(*rgb);
            let rgba = [r, g, b, 1.0];
            let shaft = CpuMesh::cylinder(0.035, 0.78, rgba);
            m.append_transformed(&shaft, &(rot * Isometry3::translation(0.0, 0.0, 0.39)));
            let tip = CpuMesh::cone(0.08, 0.22, rgba);
            m.append_transformed(&tip, &(rot * Isometry3::translation(0.0, 0.0, 0.78)));
        }
        m
    }
}
