//! Mesh files (STL, OBJ, DAE through `mesh-loader`), scaled per axis, with normals computed
//! where the file has none.

use std::path::Path;

use parol6_core::na::Vector3;

use super::{CpuMesh, rgba_to_linear};

/// Loads a mesh file (STL, OBJ or DAE; chosen by content and extension) scaled per axis by
/// `scale`, coloured `rgba` (linear) where the file has no colours. Files are read through
/// [`parol6_core::model::read_mesh_file`]: regular files of at most 64 MiB only.
pub fn load_mesh_file(path: &Path, scale: [f64; 3], rgba: [f32; 4]) -> Result<CpuMesh, String> {
    let loader = mesh_loader::Loader::default().custom_reader(parol6_core::model::mesh_reader).merge_meshes(true);
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
