//! Seeded property tests of the cover system.
//!
//! * Volume invariant: Σ ME volumes = block volume to 1e-12 relative, for every pattern, random
//!   cover rotations and origins, random convex bodies not aligned with the grid.
//! * Partition of unity and linear reproduction at random points: Σ w_a(x) = 1 and
//!   Σ w_a(x) X_a = x.
//! * Physical covers: a body cut into two touching boxes gives two sets of covers.
//! * Aggregation: every cover that keeps its own DOFs has an ME of at least the threshold ×
//!   its block's fullest ME (also in blocks smaller than a sub-cell), and a tied cover's
//!   masters reproduce its position (linear extrapolation).

mod common;

use common::Lcg;
use nmm3d_core::cover::{aggregation, Covers, MathMesh, PatternTable};
use nmm3d_core::model::{Block, Elastic, Geometry};
use nmm3d_core::scenario::{Material, PatternKind};
use nmm3d_geom::{ConvexPolyhedron, Plane, Vec3};

const PATTERNS: [PatternKind; 4] = [PatternKind::Tet5, PatternKind::Tet6, PatternKind::Tet24, PatternKind::Hex8];

fn random_convex(rng: &mut Lcg) -> ConvexPolyhedron {
    let centre = Vec3::new(rng.next(), rng.next(), rng.next()) * 3.0;
    let mut planes = Vec::new();
    for _ in 0..10 {
        let n = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
        planes.push(Plane::from_point_normal(centre + n * (0.6 + 0.6 * rng.next()), n).unwrap());
    }
    for n in [Vec3::x(), -Vec3::x(), Vec3::y(), -Vec3::y(), Vec3::z(), -Vec3::z()] {
        planes.push(Plane::from_point_normal(centre + n * 1.3, n).unwrap());
    }
    ConvexPolyhedron::from_planes(&planes).unwrap()
}

fn geometry(pieces: Vec<ConvexPolyhedron>) -> Geometry {
    let mat = Elastic::new(&Material { name: "r".into(), density: 2500.0, young: 1e9, poisson: 0.25 });
    Geometry {
        blocks: pieces.into_iter().map(|p| Block::new(0, 0, false, vec![p])).collect(),
        materials: vec![mat],
        features: Vec::new(),
        report: Default::default(),
        origin: Vec3::zeros(),
    }
}

fn random_mesh(rng: &mut Lcg) -> MathMesh {
    let size = 0.25 + 0.3 * rng.next();
    let origin = Vec3::new(rng.next(), rng.next(), rng.next());
    MathMesh::new(size, origin, [360.0 * rng.next(), 360.0 * rng.next(), 360.0 * rng.next()])
}

#[test]
fn manifold_element_volumes_sum_to_the_block_volume() {
    let mut rng = Lcg(0xC0FFEE);
    for case in 0..12 {
        let body = random_convex(&mut rng);
        let geo = geometry(vec![body.clone()]);
        for kind in PATTERNS {
            let covers = Covers::on_mesh(&geo, random_mesh(&mut rng), PatternTable::new(kind));
            let sum: f64 = covers.elements.iter().map(|e| e.volume).sum();
            let v = body.volume();
            assert!(((sum - v) / v).abs() < 1e-12, "case {case} {kind:?}: {sum} vs {v}");
        }
    }
}

#[test]
fn an_aligned_box_is_covered_exactly() {
    let b = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::new(2.0, 1.0, 1.0));
    for kind in PATTERNS {
        let covers = Covers::on_mesh(
            &geometry(vec![b.clone()]),
            MathMesh::new(0.5, Vec3::zeros(), [0.0; 3]),
            PatternTable::new(kind),
        );
        let sum: f64 = covers.elements.iter().map(|e| e.volume).sum();
        assert!((sum - 2.0).abs() < 1e-13);
        for e in &covers.elements {
            let whole = covers.pattern.of_cell(e.cell)[e.subcell].shape.volume() * 0.125;
            assert!((e.volume - whole).abs() < 1e-15, "{kind:?}: every sub-cell is whole");
        }
        // Cells with faces on the box's surface are taken whole without clipping; their faces
        // there must still be block boundary (contact, tractions), and only there.
        let h2 = 0.25; // cell-local areas × size²
        let boundary: f64 =
            covers.elements.iter().flat_map(|e| e.boundary_faces()).map(|f| f.area_vector().norm() * h2).sum();
        assert!((boundary - 10.0).abs() < 1e-12, "{kind:?}: boundary area {boundary} vs 10");
        let nodes = if kind == PatternKind::Tet24 {
            5 * 3 * 3 + 4 * 2 * 2 + (5 * 2 * 2 + 4 * 3 * 2 + 4 * 2 * 3)
        } else {
            5 * 3 * 3
        };
        assert_eq!(covers.covers.len(), nodes, "{kind:?}");
    }
}

#[test]
fn weights_are_a_partition_of_unity_and_reproduce_linear_fields() {
    let mut rng = Lcg(7);
    for _ in 0..6 {
        let body = random_convex(&mut rng);
        let geo = geometry(vec![body.clone()]);
        let bb = body.aabb();
        for kind in PATTERNS {
            let covers = Covers::on_mesh(&geo, random_mesh(&mut rng), PatternTable::new(kind));
            let mut tested = 0;
            while tested < 50 {
                let p = bb.min + bb.extent().component_mul(&Vec3::new(rng.next(), rng.next(), rng.next()));
                if !body.contains(&p, -1e-9) {
                    continue;
                }
                let e = covers.locate(0, &p, 1e-9).expect("a point in the block lies in an ME");
                let me = &covers.elements[e];
                let xi = covers.cell_local(me, &p);
                let w: Vec<f64> = covers.weights(me).iter().map(|w| w.eval(&xi)).collect();
                let sum: f64 = w.iter().sum();
                let x: Vec3 = me.covers.iter().zip(&w).map(|(&c, wa)| *wa * covers.covers[c].position).sum();
                assert!((sum - 1.0).abs() < 1e-12, "{kind:?}");
                assert!((x - p).norm() < 1e-11, "{kind:?}: {x} vs {p}");
                tested += 1;
            }
        }
    }
}

#[test]
fn separate_blocks_get_separate_physical_covers() {
    let a = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0));
    let b = ConvexPolyhedron::from_box(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0));
    let covers = Covers::on_mesh(
        &geometry(vec![a, b]),
        MathMesh::new(0.5, Vec3::zeros(), [0.0; 3]),
        PatternTable::new(PatternKind::Tet6),
    );
    // Each block has 3 × 3 × 3 nodes; the shared plane x = 1 is duplicated, not merged.
    assert_eq!(covers.covers.len(), 54);
    for e in &covers.elements {
        assert!(e.covers.iter().all(|&c| covers.covers[c].block == e.block));
    }
}

/// The fraction of its sub-cell that each ME fills.
fn fractions(covers: &Covers) -> Vec<f64> {
    let s3 = covers.mesh().size.powi(3);
    covers.elements.iter().map(|e| e.volume / (covers.pattern.of_cell(e.cell)[e.subcell].shape.volume() * s3)).collect()
}

#[test]
fn covers_without_a_substantial_me_are_tied_even_in_blocks_smaller_than_a_sub_cell() {
    let threshold = 0.1;
    let mut rng = Lcg(0x511CE);
    for case in 0..16 {
        // Slivers (a slab 0.02–0.1 of the cover size thick and 0.3–0.8 wide, smaller than a
        // sub-cell) and ordinary blocks, at random places and angles.
        let mesh = random_mesh(&mut rng);
        let body = if case % 2 == 0 {
            let h = mesh.size;
            let centre = Vec3::new(rng.next(), rng.next(), rng.next()) * 3.0;
            let n = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
            let (a, b) = (n.cross(&Vec3::x()).normalize(), n.cross(&n.cross(&Vec3::x())).normalize());
            let (thick, wide) = ((0.02 + 0.08 * rng.next()) * h, (0.3 + 0.5 * rng.next()) * h);
            let planes = [(n, thick), (a, wide), (b, wide)]
                .into_iter()
                .flat_map(|(d, half)| [d, -d].map(|d| Plane::from_point_normal(centre + d * (0.5 * half), d).unwrap()))
                .collect::<Vec<_>>();
            ConvexPolyhedron::from_planes(&planes).unwrap()
        } else {
            random_convex(&mut rng)
        };
        for kind in PATTERNS {
            let covers = Covers::on_mesh(&geometry(vec![body.clone()]), mesh, PatternTable::new(kind));
            let tied = aggregation::tie_ill_posed(&covers, &[false], threshold);
            let f = fractions(&covers);
            let fullest = f.iter().copied().fold(0.0, f64::max).min(1.0);
            for (c, t) in tied.iter().enumerate() {
                let best = covers
                    .elements
                    .iter()
                    .zip(&f)
                    .filter(|(e, _)| e.covers.contains(&c))
                    .map(|(_, f)| *f)
                    .fold(0.0, f64::max);
                match t {
                    None => assert!(
                        best >= threshold * fullest,
                        "case {case} {kind:?}: cover {c} keeps its DOFs on an ME of {best:.2e} (fullest {fullest:.2e})"
                    ),
                    Some(masters) => {
                        let x: Vec3 = masters.iter().map(|&(m, w)| covers.covers[m].position * w).sum();
                        let w: f64 = masters.iter().map(|m| m.1).sum();
                        assert!((w - 1.0).abs() < 1e-9, "case {case} {kind:?}: weights sum to {w}");
                        let err = (x - covers.covers[c].position).norm();
                        assert!(err < 1e-9 * covers.mesh().size, "case {case} {kind:?}: cover {c} off by {err:.2e}");
                        assert!(masters.iter().all(|&(m, _)| tied[m].is_none()), "case {case}: a master is tied");
                    }
                }
            }
            assert!(tied.iter().any(Option::is_none), "case {case} {kind:?}: the block kept no DOFs");
        }
    }
}
