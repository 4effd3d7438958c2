//! VTK XML writers: one `.vtu` per frame with every manifold element as a polyhedral cell
//! (VTK_POLYHEDRON, legacy `faces`/`faceoffsets` layout), and the `.pvd` collection.
//! Point data: displacement, velocity. Cell data: block id, ME id, stress (xx, yy, zz, xy,
//! yz, zx; compression negative). ASCII with round-trip number formatting.

use std::fmt::Write as _;
use std::path::Path;

use nmm3d_geom::Vec3;

use super::atomic;
use crate::element::kernel::stress_components;
use crate::error::Result;
use crate::state::State;
use crate::system::System;
use crate::time::corotation;

const VTK_POLYHEDRON: u8 = 42;

/// Write one frame.
pub fn write_frame(sys: &System, state: &State, path: &Path) -> Result<()> {
    let mut points: Vec<Vec3> = Vec::new();
    let (mut disp, mut vel) = (Vec::new(), Vec::new());
    let (mut conn, mut offsets, mut faces, mut face_offsets) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut block_id, mut stress) = (Vec::new(), Vec::new());
    for (e, me) in sys.covers.elements.iter().enumerate() {
        let w = sys.covers.weights(me);
        let verts = me.local.vertices();
        let base = points.len();
        for xi in &verts {
            let ws: Vec<f64> = w.iter().map(|p| p.eval(xi)).collect();
            let at = |f: &dyn Fn(usize) -> Vec3| -> Vec3 { me.covers.iter().zip(&ws).map(|(&c, wa)| *wa * f(c)).sum() };
            points.push(at(&|c| state.position(sys, c)));
            disp.push(at(&|c| state.displacement(sys, c)));
            vel.push(at(&|c| state.v[c]));
        }
        conn.extend((base..base + verts.len()).map(|i| i as i64));
        offsets.push(conn.len() as i64);
        faces.push(me.local.faces.len() as i64);
        for f in &me.local.faces {
            faces.push(f.vertices.len() as i64);
            for v in &f.vertices {
                let k = verts.iter().position(|w| (w - v).norm() <= 1e-12).expect("face vertex is a vertex");
                faces.push((base + k) as i64);
            }
        }
        face_offsets.push(faces.len() as i64);
        block_id.push(me.block as i64);
        stress.extend(stress_components(&corotation::element_stress(sys, state, e)));
    }
    let mut s = String::with_capacity(64 * points.len());
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    let _ = writeln!(s, "<UnstructuredGrid>\n<FieldData>{}</FieldData>", field_data(state));
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">", points.len(), offsets.len());
    s.push_str("<PointData Vectors=\"displacement\">\n");
    array_vec(&mut s, "displacement", &disp);
    array_vec(&mut s, "velocity", &vel);
    s.push_str("</PointData>\n<CellData Scalars=\"block_id\">\n");
    array(&mut s, "Int64", "block_id", 1, block_id.iter());
    array(&mut s, "Int64", "element_id", 1, (0..offsets.len() as i64).collect::<Vec<_>>().iter());
    array(&mut s, "Float64", "stress", 6, stress.iter());
    s.push_str("</CellData>\n<Points>\n");
    array_vec(&mut s, "Points", &points);
    s.push_str("</Points>\n<Cells>\n");
    array(&mut s, "Int64", "connectivity", 1, conn.iter());
    array(&mut s, "Int64", "offsets", 1, offsets.iter());
    array(&mut s, "UInt8", "types", 1, vec![VTK_POLYHEDRON; offsets.len()].iter());
    array(&mut s, "Int64", "faces", 1, faces.iter());
    array(&mut s, "Int64", "faceoffsets", 1, face_offsets.iter());
    s.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    atomic::write(path, s.as_bytes())
}

fn field_data(state: &State) -> String {
    format!(
        "\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n<DataArray type=\"String\" Name=\"stress_sign\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n",
        state.time,
        // "compression negative" as ASCII codes, NUL-terminated (VTK's string array encoding)
        "compression negative".bytes().map(|b| b.to_string()).chain(std::iter::once("0".into())).collect::<Vec<_>>().join(" ")
    )
}

fn array<T: std::fmt::Display>(s: &mut String, ty: &str, name: &str, comps: usize, vals: impl Iterator<Item = T>) {
    let _ = write!(s, "<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">");
    for (i, v) in vals.enumerate() {
        if i > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{v}");
    }
    s.push_str("</DataArray>\n");
}

fn array_vec(s: &mut String, name: &str, vals: &[Vec3]) {
    array(s, "Float64", name, 3, vals.iter().flat_map(|v| [v.x, v.y, v.z]));
}

/// Write the `.pvd` collection of (time, relative file) frames.
pub fn write_pvd(path: &Path, frames: &[(f64, String)]) -> Result<()> {
    let mut s = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n");
    for (t, f) in frames {
        let _ = writeln!(s, "<DataSet timestep=\"{t}\" part=\"0\" file=\"{f}\"/>");
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    atomic::write(path, s.as_bytes())
}
