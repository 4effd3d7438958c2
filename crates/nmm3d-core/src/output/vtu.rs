//! VTK XML writers: one `.vtu` per frame with every manifold element as a polyhedral cell
//! (VTK_POLYHEDRON, legacy `faces`/`faceoffsets` layout), `blocks.vtu` with the blocks, and the
//! `.pvd` collection. ASCII with round-trip number formatting. Frame point data: displacement,
//! velocity; cell data: block id, ME id, stress (xx, yy, zz, xy, yz, zx; compression negative).

use std::fmt::Write as _;
use std::path::Path;

use nmm3d_geom::{ConvexPolyhedron, Vec3};

use super::atomic;
use crate::element::kernel::stress_components;
use crate::error::Result;
use crate::state::State;
use crate::system::System;
use crate::time::corotation;

const VTK_POLYHEDRON: u8 = 42;

/// Polyhedral cells being collected.
#[derive(Default)]
struct Cells {
    points: Vec<Vec3>,
    conn: Vec<i64>,
    offsets: Vec<i64>,
    faces: Vec<i64>,
    face_offsets: Vec<i64>,
}

impl Cells {
    /// Add a polyhedron whose vertices are placed by `place`; returns its distinct vertices
    /// (in the polyhedron's own coordinates), in point order.
    fn push(&mut self, poly: &ConvexPolyhedron, place: impl Fn(&Vec3) -> Vec3) -> Vec<Vec3> {
        let verts = poly.vertices();
        let base = self.points.len();
        self.points.extend(verts.iter().map(&place));
        self.conn.extend((base..base + verts.len()).map(|i| i as i64));
        self.offsets.push(self.conn.len() as i64);
        self.faces.push(poly.faces.len() as i64);
        let tol = 1e-12 * poly.aabb().diagonal();
        for f in &poly.faces {
            self.faces.push(f.vertices.len() as i64);
            for v in &f.vertices {
                let k = verts.iter().position(|w| (w - v).norm() <= tol).expect("a face vertex is a vertex");
                self.faces.push((base + k) as i64);
            }
        }
        self.face_offsets.push(self.faces.len() as i64);
        verts
    }

    fn write(&self, s: &mut String, field_data: &str, point_data: &str, cell_data: &str) {
        s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
        let _ = writeln!(s, "<UnstructuredGrid>\n<FieldData>{field_data}</FieldData>");
        let _ = writeln!(s, "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">", self.points.len(), self.offsets.len());
        let _ = write!(s, "{point_data}{cell_data}<Points>\n");
        array_vec(s, "Points", &self.points);
        s.push_str("</Points>\n<Cells>\n");
        array(s, "Int64", "connectivity", 1, self.conn.iter());
        array(s, "Int64", "offsets", 1, self.offsets.iter());
        array(s, "UInt8", "types", 1, vec![VTK_POLYHEDRON; self.offsets.len()].iter());
        array(s, "Int64", "faces", 1, self.faces.iter());
        array(s, "Int64", "faceoffsets", 1, self.face_offsets.iter());
        s.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    }
}

/// Write one frame.
pub fn write_frame(sys: &System, state: &State, path: &Path) -> Result<()> {
    let mut cells = Cells::default();
    let (mut disp, mut vel) = (Vec::new(), Vec::new());
    let (mut block_id, mut stress) = (Vec::new(), Vec::new());
    for (e, me) in sys.covers.elements.iter().enumerate() {
        let w = sys.covers.weights(me);
        let interpolate = |xi: &Vec3, f: &dyn Fn(usize) -> Vec3| -> Vec3 { me.covers.iter().zip(w).map(|(&c, wa)| wa.eval(xi) * f(c)).sum() };
        let verts = cells.push(&me.local, |xi| interpolate(xi, &|c| state.position(sys, c)));
        for xi in &verts {
            disp.push(interpolate(xi, &|c| state.u[c]));
            vel.push(interpolate(xi, &|c| state.v[c]));
        }
        block_id.push(me.block as i64);
        stress.extend(stress_components(&corotation::element_stress(sys, state, e)));
    }
    let mut point_data = String::from("<PointData Vectors=\"displacement\">\n");
    array_vec(&mut point_data, "displacement", &disp);
    array_vec(&mut point_data, "velocity", &vel);
    point_data.push_str("</PointData>\n");
    let mut cell_data = String::from("<CellData Scalars=\"block_id\">\n");
    array(&mut cell_data, "Int64", "block_id", 1, block_id.iter());
    array(&mut cell_data, "Int64", "element_id", 1, 0..block_id.len() as i64);
    array(&mut cell_data, "Float64", "stress", 6, stress.iter());
    cell_data.push_str("</CellData>\n");
    let mut s = String::with_capacity(96 * cells.points.len());
    cells.write(&mut s, &field_data(state.time), &point_data, &cell_data);
    atomic::write(path, s.as_bytes())
}

/// Write the blocks (reference geometry) as polyhedral cells with `block_id`, `body_id`, `volume`.
pub fn write_blocks(geometry: &crate::model::Geometry, path: &Path) -> Result<()> {
    let mut cells = Cells::default();
    let (mut ids, mut bodies, mut vols) = (Vec::new(), Vec::new(), Vec::new());
    for (i, b) in geometry.blocks.iter().enumerate() {
        for piece in &b.pieces {
            let _ = cells.push(piece, |x| *x);
            ids.push(i as i64);
            bodies.push(b.body as i64);
            vols.push(b.volume);
        }
    }
    let mut cell_data = String::from("<CellData Scalars=\"block_id\">\n");
    array(&mut cell_data, "Int64", "block_id", 1, ids.iter());
    array(&mut cell_data, "Int64", "body_id", 1, bodies.iter());
    array(&mut cell_data, "Float64", "volume", 1, vols.iter());
    cell_data.push_str("</CellData>\n");
    let mut s = String::new();
    cells.write(&mut s, &field_data(0.0), "", &cell_data);
    atomic::write(path, s.as_bytes())
}

fn field_data(time: f64) -> String {
    format!(
        "\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{time}</DataArray>\n<DataArray type=\"String\" Name=\"stress_sign\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n",
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
