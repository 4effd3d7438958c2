//! VTK XML writers: one `.vtu` per frame (gathered by [`super::frame`]) with every manifold
//! element as a polyhedral cell (VTK_POLYHEDRON, legacy `faces`/`faceoffsets` layout),
//! `blocks.vtu` with the blocks, and the `.pvd` collection. Arrays are little-endian binary in the `AppendedData` section, each block
//! (its UInt64 byte count, then the data) base64-encoded on its own, which VTK, ParaView,
//! PyVista and meshio read. (Raw appended data is smaller, but meshio 5.3 re-encodes it to
//! base64 and finds each array by its offset: when an array's new offset equals a later
//! array's raw offset it hands that later array's data to the earlier one — a contact frame of
//! 2068 points read `block_b` as garbage.)
//! Frame points are the *current* (deformed) positions; point data: displacement, velocity,
//! reference_position (= current − displacement); cell data: block id, ME id, stress (xx, yy,
//! zz, xy, yz, zx; compression negative). Contact frames hold one vertex per contact point with its normal
//! (from B to A), normal force (compression positive), shear force (vector), state (0 open,
//! 1 stick, 2 slide), gap, area, mode (0 vertex of A, 1 vertex of B, 2 edge–edge) and blocks.

use rustc_hash::FxHashMap;
use std::collections::hash_map::Entry;
use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use nmm3d_geom::{ConvexPolyhedron, Vec3};

use super::atomic;
use crate::contact::ContactRecord;
use crate::error::Result;
use crate::packed::{base64_pieces, LittleEndian};
use crate::state::Motion;
use crate::system::System;
use nmm3d_geom::contact::Mode;

const VTK_VERTEX: u8 = 1;
const VTK_LINE: u8 = 3;
const VTK_POLYHEDRON: u8 = 42;
/// Vertices of one block closer than this fraction of the cover size are one point.
pub(super) const POINT_QUANTUM: f64 = 1e-9;
/// The end of every `.vtu` file, after its appended data.
const TAIL: &[u8] = b"\n</AppendedData>\n</VTKFile>\n";

/// `values` (`comps` per cell) in the cells' write order.
pub(super) fn permute<T: Copy>(values: &[T], comps: usize, order: &[usize]) -> Vec<T> {
    order.iter().flat_map(|&i| values[comps * i..comps * (i + 1)].iter().copied()).collect()
}

pub(super) fn point_key(block: usize, x: &Vec3, quantum: f64) -> [i64; 4] {
    [block as i64, (x.x / quantum).round() as i64, (x.y / quantum).round() as i64, (x.z / quantum).round() as i64]
}

/// One polyhedral cell before its points are shared with other cells: each distinct vertex
/// (own coordinates) with its key, and the faces (count, then each face's size and indices
/// into `verts`). Made independently per cell, so in parallel.
pub(super) struct Shape {
    keys: Vec<[i64; 4]>,
    pub verts: Vec<Vec3>,
    faces: Vec<i32>,
}

impl Shape {
    pub fn of(poly: &ConvexPolyhedron, key: impl Fn(&Vec3) -> [i64; 4]) -> Self {
        let verts = poly.vertices();
        let keys = verts.iter().map(key).collect();
        let mut faces = vec![poly.faces.len() as i32];
        let tol = 1e-12 * poly.aabb().diagonal();
        for f in &poly.faces {
            faces.push(f.vertices.len() as i32);
            for v in &f.vertices {
                let k = verts.iter().position(|w| (w - v).norm() <= tol).expect("a face vertex is a vertex");
                faces.push(k as i32);
            }
        }
        Self { keys, verts, faces }
    }
}

/// Polyhedral cells being collected. Points are shared between cells through a key (block and
/// quantised reference position), so a frame stores each vertex once per block; the caller
/// places the points (`points`, in the order [`Cells::add`] creates them).
#[derive(Default)]
pub(super) struct Cells {
    pub points: Vec<Vec3>,
    keys: FxHashMap<[i64; 4], i32>,
    /// Each cell's distinct point ids, cell after cell; cell i's end at `conn_end[i]`.
    conn: Vec<i32>,
    conn_end: Vec<usize>,
    /// Each cell's faces (count, then each face's size and point ids), cell after cell.
    faces: Vec<i32>,
    faces_end: Vec<usize>,
    /// The point ids of the cell being added, vertex by vertex.
    ids: Vec<i32>,
}

/// Cell `i`'s part of `flat`, whose cells end at `ends`.
fn part<'a>(flat: &'a [i32], ends: &[usize], i: usize) -> &'a [i32] {
    &flat[if i == 0 { 0 } else { ends[i - 1] }..ends[i]]
}

impl Cells {
    /// Room for `cells` tetrahedron-like cells.
    pub fn with_capacity(cells: usize) -> Self {
        let mut c = Self::default();
        c.conn_end.reserve(cells);
        c.faces_end.reserve(cells);
        c.conn.reserve(4 * cells);
        c.faces.reserve(17 * cells);
        c
    }

    /// Add a cell; returns the indices (into `shape.verts`) of the vertices that created new
    /// points, in point order.
    pub fn add(&mut self, shape: &Shape) -> Vec<usize> {
        let mut created = Vec::new();
        self.ids.clear();
        for (k, key) in shape.keys.iter().enumerate() {
            let next = self.keys.len() as i32;
            self.ids.push(match self.keys.entry(*key) {
                Entry::Occupied(o) => *o.get(),
                Entry::Vacant(v) => {
                    created.push(k);
                    *v.insert(next)
                }
            });
        }
        // Vertices of a sliver closer than the key's quantum are one point: list it once.
        let start = self.conn.len();
        self.conn.extend(&self.ids);
        self.conn[start..].sort_unstable();
        let mut kept = start;
        for r in start..self.conn.len() {
            if r == start || self.conn[r] != self.conn[kept - 1] {
                self.conn[kept] = self.conn[r];
                kept += 1;
            }
        }
        self.conn.truncate(kept);
        self.conn_end.push(kept);
        let start = self.faces.len();
        self.faces.extend_from_slice(&shape.faces);
        let faces = &mut self.faces[start..];
        let mut i = 1;
        while i < faces.len() {
            let n = faces[i] as usize;
            for f in &mut faces[i + 1..=i + n] {
                *f = self.ids[*f as usize];
            }
            i += n + 1;
        }
        self.faces_end.push(self.faces.len());
        created
    }

    /// The order the cells are written in: by point count, stable. meshio (5.3) groups
    /// polyhedra by point count in order of first appearance but their cell data in ascending
    /// order, so any other order pairs cells with the wrong data; VTK does not care. Cell
    /// data arrays are permuted by [`permute`] with the same order.
    pub fn order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.conn_end.len()).collect();
        order.sort_by_key(|&i| part(&self.conn, &self.conn_end, i).len());
        order
    }

    /// Write the file: these cells in `order`, with the arrays already declared in the XML
    /// snippets (their values in `bin`).
    pub fn write(
        &self,
        path: &Path,
        order: &[usize],
        mut bin: Appended,
        field_data: &str,
        point_data: &str,
        cell_data: &str,
    ) -> Result<()> {
        let n = order.len();
        let (mut conn, mut faces) = (Vec::with_capacity(self.conn.len()), Vec::with_capacity(self.faces.len()));
        let (mut offsets, mut face_offsets) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for &i in order {
            conn.extend_from_slice(part(&self.conn, &self.conn_end, i));
            offsets.push(conn.len() as i32);
            faces.extend_from_slice(part(&self.faces, &self.faces_end, i));
            face_offsets.push(faces.len() as i32);
        }
        let mut s = String::new();
        s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
        let _ = writeln!(s, "<UnstructuredGrid>\n<FieldData>{field_data}</FieldData>");
        let _ = writeln!(s, "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">", self.points.len(), offsets.len());
        let _ = writeln!(s, "{point_data}{cell_data}<Points>");
        bin.vec3(&mut s, "Points", &self.points);
        s.push_str("</Points>\n<Cells>\n");
        bin.array(&mut s, "Int32", "connectivity", 1, &conn);
        bin.array(&mut s, "Int32", "offsets", 1, &offsets);
        bin.array(&mut s, "UInt8", "types", 1, &vec![VTK_POLYHEDRON; offsets.len()]);
        bin.array(&mut s, "Int32", "faces", 1, &faces);
        bin.array(&mut s, "Int32", "faceoffsets", 1, &face_offsets);
        s.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n");
        bin.write(path, &s)
    }
}

/// The blocks of the `AppendedData` section (each its UInt64 byte count, then the values),
/// and the XML that points into them (offsets in base64 characters from the `_`). Encoded
/// and streamed to the file only when it is written.
#[derive(Default)]
pub(super) struct Appended {
    blocks: Vec<Vec<u8>>,
    chars: usize,
}

impl Appended {
    /// Declare the array `name` (VTK type `ty`, `comps` components) in `s` and keep its block.
    pub fn array<T: LittleEndian>(&mut self, s: &mut String, ty: &str, name: &str, comps: usize, v: &[T]) {
        // One component is VTK's default; leaving it out keeps meshio's arrays one-dimensional
        // (it reshapes by NumberOfComponents, and a (n, 1) `faces` array breaks its reader).
        let comps = if comps == 1 { String::new() } else { format!(" NumberOfComponents=\"{comps}\"") };
        let _ = writeln!(
            s,
            "<DataArray type=\"{ty}\" Name=\"{name}\"{comps} format=\"appended\" offset=\"{}\"/>",
            self.chars
        );
        let len = std::mem::size_of_val(v);
        let mut block = Vec::with_capacity(8 + len);
        block.extend_from_slice(&(len as u64).to_le_bytes());
        v.iter().for_each(|x| x.put(&mut block));
        // Padded base64: four characters per three bytes, rounded up.
        self.chars += block.len().div_ceil(3) * 4;
        self.blocks.push(block);
    }
    pub fn f64(&mut self, s: &mut String, name: &str, comps: usize, v: &[f64]) {
        self.array(s, "Float64", name, comps, v);
    }
    pub fn i64(&mut self, s: &mut String, name: &str, comps: usize, v: &[i64]) {
        self.array(s, "Int64", name, comps, v);
    }
    pub fn vec3(&mut self, s: &mut String, name: &str, v: &[Vec3]) {
        let flat: Vec<f64> = v.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
        self.f64(s, name, 3, &flat);
    }

    /// Each block base64-encoded on its own, in pieces of a multiple of three bytes (so the
    /// pieces' encodings are the whole block's).
    fn encode(&self, w: &mut dyn Write) -> std::io::Result<()> {
        self.blocks.iter().try_for_each(|block| base64_pieces(block, |s| w.write_all(s.as_bytes())))
    }

    /// Write the file: `head` (the XML up to the appended data), then the blocks.
    fn write(&self, path: &Path, head: &str) -> Result<()> {
        atomic::write_with(path, |w| {
            w.write_all(head.as_bytes())?;
            w.write_all(b"<AppendedData encoding=\"base64\">\n_")?;
            self.encode(w)?;
            w.write_all(TAIL)
        })
    }
}

/// Write the contact points of a frame (forces on A, the block of higher index).
pub fn write_contacts(sys: &System, state: &Motion, records: &[ContactRecord], path: &Path) -> Result<()> {
    let points: Vec<Vec3> = records.iter().map(|r| r.a.position(sys, state) + sys.geometry.origin).collect();
    let normal: Vec<Vec3> = records.iter().map(|r| r.normal).collect();
    let normal_force: Vec<f64> = records.iter().map(|r| r.normal.dot(&r.force)).collect();
    let shear: Vec<Vec3> = records.iter().map(|r| r.force - r.normal * r.normal.dot(&r.force)).collect();
    let code = |m: Mode| match m {
        Mode::VertexOfA => 0,
        Mode::VertexOfB => 1,
        Mode::EdgeEdge => 2,
    };
    let mut bin = Appended::default();
    let mut point_data = String::from("<PointData Scalars=\"state\" Vectors=\"normal\">\n");
    bin.vec3(&mut point_data, "normal", &normal);
    bin.f64(&mut point_data, "normal_force", 1, &normal_force);
    bin.vec3(&mut point_data, "shear_force", &shear);
    bin.i64(&mut point_data, "state", 1, &records.iter().map(|r| r.state.code()).collect::<Vec<_>>());
    bin.f64(&mut point_data, "gap", 1, &records.iter().map(|r| r.gap).collect::<Vec<_>>());
    bin.f64(&mut point_data, "area", 1, &records.iter().map(|r| r.area).collect::<Vec<_>>());
    bin.i64(&mut point_data, "mode", 1, &records.iter().map(|r| code(r.mode)).collect::<Vec<_>>());
    bin.i64(&mut point_data, "block_a", 1, &records.iter().map(|r| r.blocks.0 as i64).collect::<Vec<_>>());
    bin.i64(&mut point_data, "block_b", 1, &records.iter().map(|r| r.blocks.1 as i64).collect::<Vec<_>>());
    point_data.push_str("</PointData>\n");
    let n = points.len();
    let simple = SimpleCells { kind: VTK_VERTEX, connectivity: (0..n as i32).collect() };
    simple.write(path, state.time, &points, bin, &point_data, "")
}

/// Write the blocks (reference geometry) as polyhedral cells with `block_id`, `body_id`, `volume`.
pub fn write_blocks(geometry: &crate::model::Geometry, path: &Path) -> Result<()> {
    let mut cells = Cells::default();
    let (mut ids, mut bodies, mut vols) = (Vec::new(), Vec::new(), Vec::new());
    for (i, b) in geometry.blocks.iter().enumerate() {
        for piece in &b.pieces {
            let quantum = POINT_QUANTUM * piece.aabb().diagonal();
            let shape = Shape::of(piece, |x| point_key(i, x, quantum));
            for k in cells.add(&shape) {
                cells.points.push(shape.verts[k] + geometry.origin);
            }
            ids.push(i as i64);
            bodies.push(b.body as i64);
            vols.push(b.volume);
        }
    }
    let order = cells.order();
    let mut bin = Appended::default();
    let mut cell_data = String::from("<CellData Scalars=\"block_id\">\n");
    bin.i64(&mut cell_data, "block_id", 1, &permute(&ids, 1, &order));
    bin.i64(&mut cell_data, "body_id", 1, &permute(&bodies, 1, &order));
    bin.f64(&mut cell_data, "volume", 1, &permute(&vols, 1, &order));
    cell_data.push_str("</CellData>\n");
    cells.write(path, &order, bin, &field_data(0.0), "", &cell_data)
}

/// Field data of every file: the time. Numbers only — meshio rejects `String` arrays (the
/// stress sign convention is in `summary.json` and the docs).
pub(super) fn field_data(time: f64) -> String {
    format!(
        "\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{time}</DataArray>\n"
    )
}

/// The bolts' file of a frame, beside its blocks' file.
pub fn bolts_file(blocks_file: &str) -> String {
    blocks_file.replacen("blocks_", "bolts_", 1)
}

/// Write the `.pvd` collection of frames: (time, blocks file, contacts file) — part 0 the
/// blocks, part 1 the contact points, part 2 the bolts (`bolts_file`, when `bolts`).
pub fn write_pvd(path: &Path, frames: &[(f64, String, Option<String>)], bolts: bool) -> Result<()> {
    let mut s = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n");
    for (t, f, c) in frames {
        let _ = writeln!(s, "<DataSet timestep=\"{t}\" part=\"0\" file=\"{f}\"/>");
        if let Some(c) = c {
            let _ = writeln!(s, "<DataSet timestep=\"{t}\" part=\"1\" file=\"{c}\"/>");
        }
        if bolts {
            let _ = writeln!(s, "<DataSet timestep=\"{t}\" part=\"2\" file=\"{}\"/>", bolts_file(f));
        }
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    atomic::write(path, s.as_bytes())
}

/// Write the bolts of a frame: each bolt a chain of lines through its nodes (an anchored bolt's
/// head and anchor; a grouted bolt's ends in rock and the joints it crosses) at their current
/// positions, with the axial force, elongation and shear force of each node's spring (0 at a
/// grouted bolt's ends), and per line its bolt's id and whether a spring of it broke. (Lines,
/// not polylines: meshio reads no VTK_POLY_LINE.)
pub fn write_bolts(sys: &System, state: &Motion, path: &Path) -> Result<()> {
    let forces = crate::time::spring_forces(sys, state);
    let (mut points, mut axial, mut elongation, mut shear) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut ids, mut broken, mut lines) = (Vec::new(), Vec::new(), Vec::new());
    for (i, path) in sys.bolt_paths.iter().enumerate() {
        let snapped = sys.bolts.iter().zip(&state.bolts).any(|(b, s)| b.bolt == i && s.broken) as i64;
        for (j, n) in path.iter().enumerate() {
            if j > 0 {
                lines.extend([points.len() as i32 - 1, points.len() as i32]);
                ids.push(i as i64);
                broken.push(snapped);
            }
            let u: Vec3 = n.covers.iter().zip(&n.weights).map(|(&c, w)| *w * state.u[c]).sum();
            points.push(n.x + u + sys.geometry.origin);
            let f = n.spring.map_or((0.0, 0.0, 0.0), |k| forces[k]);
            axial.push(f.0);
            elongation.push(f.1);
            shear.push(f.2);
        }
    }
    let mut bin = Appended::default();
    let mut point_data = String::from("<PointData Scalars=\"axial_force\">\n");
    bin.f64(&mut point_data, "axial_force", 1, &axial);
    bin.f64(&mut point_data, "elongation", 1, &elongation);
    bin.f64(&mut point_data, "shear_force", 1, &shear);
    point_data.push_str("</PointData>\n");
    let mut cell_data = String::from("<CellData Scalars=\"bolt_id\">\n");
    bin.i64(&mut cell_data, "bolt_id", 1, &ids);
    bin.i64(&mut cell_data, "broken", 1, &broken);
    cell_data.push_str("</CellData>\n");
    let simple = SimpleCells { kind: VTK_LINE, connectivity: lines };
    simple.write(path, state.time, &points, bin, &point_data, &cell_data)
}

/// Cells of one kind with the same number of points each (contact vertices, bolt lines).
struct SimpleCells {
    /// VTK cell type.
    kind: u8,
    /// Point indices, cell after cell.
    connectivity: Vec<i32>,
}

impl SimpleCells {
    /// Write the `.vtu` file of these cells on `points`, with the arrays already declared in
    /// `point_data` and `cell_data` (their values in `bin`).
    fn write(
        &self,
        path: &Path,
        time: f64,
        points: &[Vec3],
        mut bin: Appended,
        point_data: &str,
        cell_data: &str,
    ) -> Result<()> {
        let per = if self.kind == VTK_LINE { 2 } else { 1 };
        let m = self.connectivity.len() / per;
        let mut s = String::new();
        s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
        let _ = writeln!(s, "<UnstructuredGrid>\n<FieldData>{}</FieldData>", field_data(time));
        let _ = writeln!(s, "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{m}\">", points.len());
        s.push_str(point_data);
        s.push_str(cell_data);
        s.push_str("<Points>\n");
        bin.vec3(&mut s, "Points", points);
        s.push_str("</Points>\n<Cells>\n");
        bin.array(&mut s, "Int32", "connectivity", 1, &self.connectivity);
        bin.array(&mut s, "Int32", "offsets", 1, &(1..=m as i32).map(|k| per as i32 * k).collect::<Vec<_>>());
        bin.array(&mut s, "UInt8", "types", 1, &vec![self.kind; m]);
        s.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n");
        bin.write(path, &s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::engine::general_purpose::STANDARD as BASE64;
    use base64::Engine as _;

    /// Each declared array's offset points at its own base64 block: the byte count, then the
    /// values (what VTK and meshio decode from that offset).
    #[test]
    fn every_offset_starts_its_own_block() {
        let (mut bin, mut xml) = (Appended::default(), String::new());
        bin.f64(&mut xml, "gap", 1, &[1.5, -2.0, 3.25]);
        bin.i64(&mut xml, "block_b", 1, &[7, 8]);
        let offsets: Vec<usize> = xml
            .lines()
            .map(|l| l.split("offset=\"").nth(1).unwrap().trim_end_matches("\"/>").parse().unwrap())
            .collect();
        assert_eq!(offsets[0], 0);
        let mut data = Vec::new();
        bin.encode(&mut data).unwrap();
        let data = String::from_utf8(data).unwrap();
        assert_eq!(data.len(), bin.chars);
        let block = |k: usize| BASE64.decode(&data[offsets[k]..*offsets.get(k + 1).unwrap_or(&data.len())]);
        let gap = block(0).unwrap();
        assert_eq!(u64::from_le_bytes(gap[..8].try_into().unwrap()), 24);
        assert_eq!(f64::from_le_bytes(gap[16..24].try_into().unwrap()), -2.0);
        let b = block(1).unwrap();
        assert_eq!(
            (u64::from_le_bytes(b[..8].try_into().unwrap()), i64::from_le_bytes(b[16..].try_into().unwrap())),
            (16, 8)
        );
    }

    /// A block longer than one encoding piece decodes to its values (the pieces are cut at
    /// multiples of three bytes, so their concatenation is the block's encoding).
    #[test]
    fn a_long_block_is_encoded_whole() {
        let (mut bin, mut xml) = (Appended::default(), String::new());
        let v: Vec<f64> = (0..20_001).map(|i| i as f64 * 0.37 - 5.0).collect();
        bin.f64(&mut xml, "long", 1, &v);
        let mut data = Vec::new();
        bin.encode(&mut data).unwrap();
        assert_eq!(data.len(), bin.chars);
        let bytes = BASE64.decode(&data).unwrap();
        let back: Vec<f64> = bytes[8..].chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
        assert_eq!(back, v);
    }
}
