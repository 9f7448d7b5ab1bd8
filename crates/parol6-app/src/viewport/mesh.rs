//! CPU meshes: tessellated URDF primitives, STL / OBJ / DAE files through `mesh-loader`, and
//! the per-link merge that the renderer uploads once into one static vertex and index buffer.

use std::path::Path;

use parol6_core::RobotModel;
use parol6_core::model::{Geometry, Shape};
use parol6_core::na::{Isometry3, Point3, Vector3};

/// Segments around a cylinder, capsule or sphere.
const ROUND_SEGMENTS: usize = 32;
/// Rings of a sphere (and of each capsule cap: half of them).
const SPHERE_RINGS: usize = 16;
/// Colour of geometry without a material (sRGB).
const DEFAULT_RGBA: [f32; 4] = [0.75, 0.75, 0.75, 1.0];
/// Colour of the placeholder shown for a mesh that could not be loaded (sRGB).
const PLACEHOLDER_RGBA: [f32; 4] = [1.0, 0.0, 0.85, 1.0];
/// Edge length of the placeholder cube, m.
const PLACEHOLDER_SIZE_M: f64 = 0.03;

/// One vertex: position and normal in the link frame, linear RGBA.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MeshVertex {
    /// Position, m.
    pub position_m: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Linear RGBA.
    pub rgba: [f32; 4],
}

/// An indexed triangle mesh.
#[derive(Debug, Clone, Default)]
pub struct CpuMesh {
    /// Vertices.
    pub vertices: Vec<MeshVertex>,
    /// Triangle indices into `vertices`.
    pub indices: Vec<u32>,
}

/// sRGB component → linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// sRGB RGBA (0…1) → linear RGBA (alpha unchanged).
pub fn rgba_to_linear(c: [f32; 4]) -> [f32; 4] {
    [srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2]), c[3]]
}

impl CpuMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Appends `other`, transformed by `pose`.
    pub fn append_transformed(&mut self, other: &CpuMesh, pose: &Isometry3<f64>) {
        let base = self.vertices.len() as u32;
        let rot = pose.rotation.to_rotation_matrix();
        self.vertices.extend(other.vertices.iter().map(|v| {
            let p = pose * Point3::new(v.position_m[0] as f64, v.position_m[1] as f64, v.position_m[2] as f64);
            let n = rot * Vector3::new(v.normal[0] as f64, v.normal[1] as f64, v.normal[2] as f64);
            MeshVertex {
                position_m: [p.x as f32, p.y as f32, p.z as f32],
                normal: [n.x as f32, n.y as f32, n.z as f32],
                rgba: v.rgba,
            }
        }));
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    fn push_vertex(&mut self, p: [f64; 3], n: [f64; 3], rgba: [f32; 4]) -> u32 {
        self.vertices.push(MeshVertex {
            position_m: [p[0] as f32, p[1] as f32, p[2] as f32],
            normal: [n[0] as f32, n[1] as f32, n[2] as f32],
            rgba,
        });
        (self.vertices.len() - 1) as u32
    }

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
        let colours = [[0.9, 0.1, 0.1, 1.0], [0.1, 0.8, 0.15, 1.0], [0.15, 0.3, 1.0, 1.0]];
        let orient = [
            Isometry3::rotation(Vector3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0)),
            Isometry3::rotation(Vector3::new(-std::f64::consts::FRAC_PI_2, 0.0, 0.0)),
            Isometry3::identity(),
        ];
        for (rgba, rot) in colours.iter().zip(orient) {
            let rgba = rgba_to_linear(*rgba);
            let shaft = CpuMesh::cylinder(0.035, 0.78, rgba);
            m.append_transformed(&shaft, &(rot * Isometry3::translation(0.0, 0.0, 0.39)));
            let tip = CpuMesh::cone(0.08, 0.22, rgba);
            m.append_transformed(&tip, &(rot * Isometry3::translation(0.0, 0.0, 0.78)));
        }
        m
    }
}

/// Loads a mesh file (STL, OBJ or DAE; chosen by content and extension) scaled per axis by
/// `scale`, coloured `rgba` (linear) where the file has no colours.
pub fn load_mesh_file(path: &Path, scale: [f64; 3], rgba: [f32; 4]) -> Result<CpuMesh, String> {
    let loader = mesh_loader::Loader::default().merge_meshes(true);
    let scene = loader.load(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = CpuMesh::default();
    let flip = scale[0] * scale[1] * scale[2] < 0.0;
    for mesh in &scene.meshes {
        let base = out.vertices.len() as u32;
        let has_normals = mesh.normals.len() == mesh.vertices.len();
        let colours = &mesh.colors[0];
        let has_colours = colours.len() == mesh.vertices.len();
        for (i, v) in mesh.vertices.iter().enumerate() {
            let p = [v[0] as f64 * scale[0], v[1] as f64 * scale[1], v[2] as f64 * scale[2]];
            // Normals transform with the inverse scale.
            let n = if has_normals {
                let n = mesh.normals[i];
                let n = Vector3::new(n[0] as f64 / scale[0], n[1] as f64 / scale[1], n[2] as f64 / scale[2]);
                n.try_normalize(1e-12).unwrap_or_else(Vector3::z)
            } else {
                Vector3::zeros()
            };
            let c = if has_colours { rgba_to_linear(colours[i]) } else { rgba };
            out.push_vertex(p, [n.x, n.y, n.z], c);
        }
        for f in &mesh.faces {
            if f.iter().any(|&i| i as usize >= mesh.vertices.len()) {
                continue;
            }
            if flip {
                out.indices.extend([base + f[0], base + f[2], base + f[1]]);
            } else {
                out.indices.extend([base + f[0], base + f[1], base + f[2]]);
            }
        }
        if !has_normals {
            compute_flat_normals(&mut out, base);
        }
    }
    if out.indices.is_empty() {
        return Err(format!("{}: no triangles", path.display()));
    }
    Ok(out)
}

/// Gives the vertices from `first_vertex` on the area-weighted normals of their triangles.
fn compute_flat_normals(m: &mut CpuMesh, first_vertex: u32) {
    let mut acc = vec![Vector3::<f64>::zeros(); m.vertices.len() - first_vertex as usize];
    for tri in m.indices.chunks_exact(3) {
        if tri.iter().any(|&i| i < first_vertex) {
            continue;
        }
        let p = |i: u32| {
            let v = m.vertices[i as usize].position_m;
            Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64)
        };
        let n = (p(tri[1]) - p(tri[0])).cross(&(p(tri[2]) - p(tri[0])));
        for &i in tri {
            acc[(i - first_vertex) as usize] += n;
        }
    }
    for (v, n) in m.vertices[first_vertex as usize..].iter_mut().zip(acc) {
        let n = n.try_normalize(1e-18).unwrap_or_else(Vector3::z);
        v.normal = [n.x as f32, n.y as f32, n.z as f32];
    }
}

/// The tessellated or loaded mesh of one geometry in its own frame (origin not applied).
/// Errors describe a mesh file that could not be used.
pub fn geometry_mesh(g: &Geometry, default_rgba: [f32; 4]) -> Result<CpuMesh, String> {
    let rgba = rgba_to_linear(g.rgba.unwrap_or(default_rgba));
    let positive = |v: f64| v.is_finite() && v > 0.0;
    match &g.shape {
        Shape::Box { size_m } if size_m.iter().all(|&v| positive(v)) => Ok(CpuMesh::cuboid(*size_m, rgba)),
        Shape::Cylinder { radius_m, length_m } if positive(*radius_m) && positive(*length_m) => {
            Ok(CpuMesh::cylinder(*radius_m, *length_m, rgba))
        }
        Shape::Capsule { radius_m, length_m } if positive(*radius_m) && length_m.is_finite() && *length_m >= 0.0 => {
            Ok(CpuMesh::capsule(*radius_m, *length_m, rgba))
        }
        Shape::Sphere { radius_m } if positive(*radius_m) => Ok(CpuMesh::sphere(*radius_m, rgba)),
        Shape::Mesh { path, uri, scale } => {
            if !scale.iter().all(|s| s.is_finite() && *s != 0.0) {
                return Err(format!("mesh {uri}: invalid scale {scale:?}"));
            }
            if !path.is_file() {
                return Err(format!("mesh {uri} not found (looked at {})", path.display()));
            }
            load_mesh_file(path, *scale, rgba)
        }
        other => Err(format!("degenerate primitive {other:?}")),
    }
}

/// Index and vertex range of one link's merged mesh inside the shared buffers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MeshRange {
    /// First index.
    pub first_index: u32,
    /// Number of indices (0 = nothing to draw).
    pub index_count: u32,
    /// Added to every index (first vertex of the mesh).
    pub base_vertex: i32,
}

/// All meshes of a model merged into one vertex and one index array, with the range of each
/// link's visual mesh, each link's collision mesh and the axes triad.
#[derive(Debug, Clone, Default)]
pub struct ModelMeshes {
    /// All vertices.
    pub vertices: Vec<MeshVertex>,
    /// All indices (relative to each range's `base_vertex`).
    pub indices: Vec<u32>,
    /// Visual mesh of each link (same order as `RobotModel::links`).
    pub visual: Vec<MeshRange>,
    /// Collision mesh of each link.
    pub collision: Vec<MeshRange>,
    /// The unit axes triad.
    pub triad: MeshRange,
    /// Problems found (each failed geometry is replaced by a placeholder cube).
    pub warnings: Vec<String>,
}

impl ModelMeshes {
    /// Tessellates and loads every visual and collision geometry of `model`.
    pub fn build(model: &RobotModel) -> Self {
        let mut out = ModelMeshes::default();
        for link in &model.links {
            let visual = Self::link_mesh(&link.name, "visual", &link.visuals, &mut out.warnings);
            let r = out.add(&visual);
            out.visual.push(r);
            let collision = Self::link_mesh(&link.name, "collision", &link.collisions, &mut out.warnings);
            let r = out.add(&collision);
            out.collision.push(r);
        }
        let triad = CpuMesh::axes_triad();
        out.triad = out.add(&triad);
        out
    }

    fn link_mesh(link: &str, what: &str, geoms: &[Geometry], warnings: &mut Vec<String>) -> CpuMesh {
        let mut merged = CpuMesh::default();
        for g in geoms {
            match geometry_mesh(g, DEFAULT_RGBA) {
                Ok(m) => merged.append_transformed(&m, &g.origin),
                Err(e) => {
                    warnings.push(format!("link {link} {what}: {e}; drawn as a placeholder"));
                    let cube = CpuMesh::cuboid([PLACEHOLDER_SIZE_M; 3], rgba_to_linear(PLACEHOLDER_RGBA));
                    merged.append_transformed(&cube, &g.origin);
                }
            }
        }
        merged
    }

    fn add(&mut self, m: &CpuMesh) -> MeshRange {
        let r = MeshRange {
            first_index: self.indices.len() as u32,
            index_count: m.indices.len() as u32,
            base_vertex: self.vertices.len() as i32,
        };
        self.vertices.extend_from_slice(&m.vertices);
        self.indices.extend_from_slice(&m.indices);
        r
    }

    /// Total triangles of the visual meshes.
    pub fn visual_triangle_count(&self) -> usize {
        self.visual.iter().map(|r| r.index_count as usize / 3).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds(m: &CpuMesh) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::MAX; 3];
        let mut hi = [f32::MIN; 3];
        for v in &m.vertices {
            for i in 0..3 {
                lo[i] = lo[i].min(v.position_m[i]);
                hi[i] = hi[i].max(v.position_m[i]);
            }
        }
        (lo, hi)
    }

    /// Signed volume by the divergence theorem: positive when the triangles wind outward.
    fn volume(m: &CpuMesh) -> f64 {
        m.indices
            .chunks_exact(3)
            .map(|t| {
                let p = |i: u32| {
                    let v = m.vertices[i as usize].position_m;
                    Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64)
                };
                p(t[0]).dot(&p(t[1]).cross(&p(t[2]))) / 6.0
            })
            .sum()
    }

    #[test]
    fn primitives_have_the_right_size_volume_and_winding() {
        let c = [1.0; 4];
        let b = CpuMesh::cuboid([0.2, 0.1, 0.05], c);
        assert!((volume(&b) - 0.001).abs() < 1e-9);
        let (lo, hi) = bounds(&b);
        assert!((hi[0] - lo[0] - 0.2).abs() < 1e-6);
        let cyl = CpuMesh::cylinder(0.1, 0.3, c);
        let exact = std::f64::consts::PI * 0.01 * 0.3;
        assert!((volume(&cyl) - exact).abs() / exact < 0.01, "{}", volume(&cyl));
        let s = CpuMesh::sphere(0.1, c);
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 1e-3;
        assert!((volume(&s) - exact).abs() / exact < 0.03, "{}", volume(&s));
        let cap = CpuMesh::capsule(0.1, 0.2, c);
        let exact = exact + std::f64::consts::PI * 0.01 * 0.2;
        assert!((volume(&cap) - exact).abs() / exact < 0.03, "{}", volume(&cap));
        let (lo, hi) = bounds(&cap);
        assert!((hi[2] - lo[2] - 0.4).abs() < 1e-6);
        assert!(CpuMesh::cone(0.1, 0.2, c).triangle_count() > 0);
        assert!(volume(&CpuMesh::axes_triad()) > 0.0);
    }

    #[test]
    fn embedded_parol6_meshes_build_without_warnings() {
        let model = RobotModel::parol6();
        let m = ModelMeshes::build(&model);
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        assert_eq!(m.visual.len(), model.links.len());
        assert!(m.visual.iter().all(|r| r.index_count > 0));
        let max = m.vertices.len() as i64;
        for r in m.visual.iter().chain(&m.collision).chain([&m.triad]) {
            for &i in &m.indices[r.first_index as usize..(r.first_index + r.index_count) as usize] {
                assert!((i as i64 + r.base_vertex as i64) < max);
            }
        }
    }

    #[test]
    fn missing_and_broken_meshes_become_placeholders() {
        let dir = std::env::temp_dir().join(format!("parol6-mesh-test-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        let broken = dir.join("broken.stl");
        let _ = std::fs::write(&broken, b"solid x\nfacet normal garbage\n");
        let urdf = format!(
            r#"<robot name="r">
              <link name="a"><visual><geometry><mesh filename="missing.stl"/></geometry></visual></link>
              <link name="b"><visual><geometry><mesh filename="{}"/></geometry></visual></link>
              <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
                <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
            </robot>"#,
            broken.display()
        );
        let opts = parol6_core::model::LoadOptions { base_dir: Some(dir.clone()), ..Default::default() };
        let model = RobotModel::from_urdf_str(&urdf, &opts);
        let _ = std::fs::remove_dir_all(&dir);
        let model = match model {
            Ok(m) => m,
            Err(e) => panic!("test URDF must load: {e}"),
        };
        let m = ModelMeshes::build(&model);
        assert_eq!(m.warnings.len(), 2, "{:?}", m.warnings);
        assert!(m.visual.iter().all(|r| r.index_count == 36), "placeholders are cubes");
    }

    const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    const TRIANGLE_DAE: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="tri-pos"><float_array id="tri-pos-array" count="9">0 0 0 2 0 0 0 2 0</float_array>
        <technique_common><accessor source="#tri-pos-array" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#tri"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##;

    #[test]
    fn obj_and_dae_files_load_scaled_with_normals() {
        let dir = std::env::temp_dir().join(format!("parol6-mesh-formats-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        let obj = dir.join("tetra.obj");
        let dae = dir.join("tri.dae");
        let _ = std::fs::write(&obj, TETRA_OBJ);
        let _ = std::fs::write(&dae, TRIANGLE_DAE);
        let o = load_mesh_file(&obj, [0.001, 0.002, 0.003], [1.0; 4]);
        let d = load_mesh_file(&dae, [1.0, 1.0, 1.0], [1.0; 4]);
        let _ = std::fs::remove_dir_all(&dir);
        let o = o.unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(o.triangle_count(), 4);
        let (lo, hi) = bounds(&o);
        assert!((hi[0] - 0.001).abs() < 1e-7 && (hi[1] - 0.002).abs() < 1e-7 && (hi[2] - 0.003).abs() < 1e-7);
        assert!(lo.iter().all(|v| v.abs() < 1e-9));
        for v in &o.vertices {
            let n = v.normal;
            assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-4, "{n:?}");
        }
        let d = d.unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(d.triangle_count(), 1);
        let (_, hi) = bounds(&d);
        assert!((hi[0] - 2.0).abs() < 1e-6 && (hi[1] - 2.0).abs() < 1e-6);
    }

    #[test]
    fn official_stl_urdf_loads_its_meshes_when_present() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/parol6/urdf/python-api/PAROL6.urdf");
        if !path.is_file() {
            parol6_tests::skip_notice(&format!("SKIPPED: {} not present", path.display()));
            return;
        }
        let model = match RobotModel::from_urdf_file(&path, None) {
            Ok(m) => m,
            Err(e) => panic!("official URDF must load: {e}"),
        };
        let m = ModelMeshes::build(&model);
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        assert!(m.visual_triangle_count() > 10_000, "{}", m.visual_triangle_count());
        // STL in metres: the base fits in a 0.3 m box.
        let base = model.link_index("base_link").unwrap_or_else(|| panic!("no base_link"));
        let r = m.visual[base];
        let idx = &m.indices[r.first_index as usize..(r.first_index + r.index_count) as usize];
        let span = idx
            .iter()
            .map(|&i| m.vertices[(i as i64 + r.base_vertex as i64) as usize].position_m[0])
            .fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
        assert!(span.1 - span.0 > 0.02 && span.1 - span.0 < 0.3, "{span:?}");
    }
}
