//! CPU meshes: tessellated URDF primitives, STL / OBJ / DAE files through `mesh-loader`, and
//! the per-link merge that the renderer uploads once into one static vertex and index buffer.

//!
//! Jobs: `primitives` (boxes, cylinders, capsules, spheres, cones, the axes triad), [`file`]
//! (mesh files); this file holds the mesh types, one geometry → mesh, and the per-link merge.

use parol6_core::RobotModel;
use parol6_core::model::{Geometry, Shape};
use parol6_core::na::{Isometry3, Point3, Vector3};

use crate::palette;

mod file;
mod primitives;

pub use crate::palette::srgb_to_linear;
pub use file::load_mesh_file;

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

    /// Appends one vertex and returns its index.
    pub(super) fn push_vertex(&mut self, p: [f64; 3], n: [f64; 3], rgba: [f32; 4]) -> u32 {
        self.vertices.push(MeshVertex {
            position_m: [p[0] as f32, p[1] as f32, p[2] as f32],
            normal: [n[0] as f32, n[1] as f32, n[2] as f32],
            rgba,
        });
        (self.vertices.len() - 1) as u32
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
            if !path.exists() {
                return Err(format!("mesh {uri} not found (looked at {})", path.display()));
            }
            // A FIFO or a device is refused by its type, before any read.
            if let Err(e) = parol6_core::fsio::check_regular(path) {
                return Err(format!("mesh {uri} not read: {e}"));
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
            match geometry_mesh(g, palette::srgb_rgba_unit(palette::VIEW_ROBOT_DEFAULT)) {
                Ok(m) => merged.append_transformed(&m, &g.origin),
                Err(e) => {
                    warnings.push(format!("link {link} {what}: {e}; drawn as a placeholder"));
                    let cube =
                        CpuMesh::cuboid([PLACEHOLDER_SIZE_M; 3], palette::linear_rgba(palette::VIEW_MESH_PLACEHOLDER));
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
mod tests;
