//! Rock-mass modelling: blocks from joint sets, joint planes and excavations.
//!
//! * Three orthogonal sets in a box with offset origins: exact count and every volume (1e-9).
//! * Seeded random joint systems on random convex bodies: volume conserved to 1e-10, every block
//!   closed with outward faces, convex blocks with Euler characteristic 2, no sliver left; the
//!   same blocks under degenerate inputs (plane through a vertex, coplanar with a face, repeated).
//! * Tunnels through an unjointed box: excavated volume = profile area × length (1e-9), the
//!   remaining non-convex block valid; a joint through the axis splits it into two equal blocks.
//! * Covers of a non-convex block: Σ ME volumes = block volume (1e-12).

mod common;

use common::{scenario, Lcg};
use nmm3d_core::cover::{Covers, MathMesh, PatternTable};
use nmm3d_core::model::tags;
use nmm3d_core::model::tunnel::profile_area;
use nmm3d_core::model::Geometry;
use nmm3d_core::scenario::{PatternKind, Shape};
use nmm3d_geom::Vec3;

const HEAD: &str = r#"
[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25

[[joint]]
name = "j"
friction_angle = 30.0
"#;

fn geometry(extra: &str) -> Geometry {
    Geometry::from_scenario(&scenario(&format!("{HEAD}{extra}")))
}

fn total_volume(g: &Geometry) -> f64 {
    g.blocks.iter().map(|b| b.volume).sum()
}

#[test]
fn three_orthogonal_sets_give_exact_blocks() {
    let g = geometry(
        r#"
[[body]]
name = "box"
material = "rock"
shape = { box = { min = [0.0, 0.0, 0.0], max = [10.0, 8.0, 6.0] } }

[[joint_set]]
dip = 90.0
dip_direction = 90.0
spacing = 3.0
origin = [1.0, 0.0, 0.0]

[[joint_set]]
dip = 90.0
dip_direction = 0.0
spacing = 2.5
origin = [0.0, 0.5, 0.0]

[[joint_set]]
dip = 0.0
dip_direction = 0.0
spacing = 2.0
origin = [0.0, 0.0, 1.0]
"#,
    );
    let xs = [1.0, 3.0, 3.0, 3.0];
    let ys = [0.5, 2.5, 2.5, 2.5];
    let zs = [1.0, 2.0, 2.0, 1.0];
    let mut exact = Vec::new();
    for x in xs {
        for y in ys {
            for z in zs {
                exact.push(x * y * z);
            }
        }
    }
    let mut got: Vec<f64> = g.blocks.iter().map(|b| b.volume).collect();
    assert_eq!(got.len(), 64);
    exact.sort_by(f64::total_cmp);
    got.sort_by(f64::total_cmp);
    for (a, b) in got.iter().zip(&exact) {
        assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
    }
    // Ids follow centroids: x, then y, then z.
    let q = |x: f64| (x * 1e6).round() as i64;
    let c: Vec<[i64; 3]> = g.blocks.iter().map(|b| [q(b.centroid.x), q(b.centroid.y), q(b.centroid.z)]).collect();
    assert!(c.windows(2).all(|w| w[0] <= w[1]));
    // Joint faces remember their feature.
    let features: std::collections::BTreeSet<usize> = g
        .blocks
        .iter()
        .flat_map(|b| b.pieces.iter())
        .flat_map(|p| p.faces.iter())
        .filter_map(|f| tags::joint_feature(f.tag))
        .collect();
    assert_eq!(features.into_iter().collect::<Vec<_>>(), vec![0, 1, 2]);
}

fn random_body(rng: &mut Lcg) -> String {
    let mut planes = Vec::new();
    for _ in 0..9 {
        let n = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
        planes.push(format!("[{}, {}, {}, {}]", n.x, n.y, n.z, 2.0 + 2.0 * rng.next()));
    }
    for (i, s) in ["[1,0,0", "[-1,0,0", "[0,1,0", "[0,-1,0", "[0,0,1", "[0,0,-1"].iter().enumerate() {
        let _ = i;
        planes.push(format!("{s},3.5]"));
    }
    format!(
        "[[body]]\nname = \"b\"\nmaterial = \"rock\"\nshape = {{ convex = {{ planes = [{}] }} }}\n",
        planes.join(", ")
    )
}

fn random_sets(rng: &mut Lcg, n: usize) -> String {
    (0..n)
        .map(|_| {
            format!(
                "[[joint_set]]\ndip = {}\ndip_direction = {}\nspacing = {}\norigin = [{}, {}, {}]\n",
                90.0 * rng.next(),
                360.0 * rng.next(),
                0.5 + rng.next(),
                rng.next(),
                rng.next(),
                rng.next()
            )
        })
        .collect()
}

fn check_blocks(g: &Geometry, expected_volume: f64, label: &str) {
    assert!(
        (total_volume(g) - expected_volume).abs() < 1e-10 * expected_volume,
        "{label}: volume {} vs {expected_volume}",
        total_volume(g)
    );
    for (i, b) in g.blocks.iter().enumerate() {
        let closure: Vec3 = b.pieces.iter().flat_map(|p| p.faces.iter()).map(|f| f.area_vector()).sum();
        assert!(closure.norm() < 1e-9, "{label}: block {i} is not closed ({closure})");
        assert!(b.pieces.iter().all(|p| p.volume() > 0.0), "{label}: block {i} has an inward piece");
        if b.pieces.len() == 1 {
            let p = &b.pieces[0];
            let (v, f) = (p.vertices().len(), p.faces.len());
            let e: usize = p.faces.iter().map(|f| f.vertices.len()).sum::<usize>() / 2;
            assert_eq!(v + f - e, 2, "{label}: block {i} Euler characteristic");
        }
    }
    let vmax = g.blocks.iter().map(|b| b.volume).fold(0.0, f64::max);
    assert!(g.blocks.iter().all(|b| b.volume >= 1e-4 * 1e-4 * vmax), "{label}: a sliver survived");
}

#[test]
fn seeded_random_joint_systems_conserve_volume_and_stay_valid() {
    let mut rng = Lcg(0x5EED);
    for case in 0..8 {
        let body = random_body(&mut rng);
        let v0 = total_volume(&geometry(&body));
        let sets = random_sets(&mut rng, 2 + case % 2);
        let g = geometry(&format!("{body}{sets}"));
        assert!(g.blocks.len() > 3, "case {case}: {} blocks", g.blocks.len());
        assert_eq!(g.report.slivers_dropped, 0, "case {case}: {:?}", g.report);
        check_blocks(&g, v0, &format!("case {case}"));
    }
}

#[test]
fn degenerate_planes_change_nothing() {
    let body = "[[body]]\nname = \"b\"\nmaterial = \"rock\"\nshape = { box = { min = [0.0, 0.0, 0.0], max = [4.0, 4.0, 4.0] } }\n";
    let diagonal = "[[joint_plane]]\npoint = [2.0, 2.0, 2.0]\nnormal = [1.0, 1.0, 0.0]\n";
    let base = geometry(&format!("{body}{diagonal}"));
    assert_eq!(base.blocks.len(), 2);
    for (label, extra) in [
        ("through a vertex", "[[joint_plane]]\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 1.0, 1.0]\n"),
        ("coplanar with a face", "[[joint_plane]]\npoint = [0.0, 0.0, 4.0]\ndip = 0.0\ndip_direction = 0.0\n"),
        ("repeated", diagonal),
        (
            "a hair off the face",
            "[[joint_plane]]\npoint = [0.0, 0.0, 4.0000000000001]\ndip = 0.0\ndip_direction = 0.0\n",
        ),
    ] {
        let g = geometry(&format!("{body}{diagonal}{extra}"));
        assert_eq!(g.blocks.len(), 2, "{label}");
        check_blocks(&g, 64.0, label);
    }
}

fn tunnel_case(profile: &str, joint: &str) -> (Geometry, f64) {
    let text = format!(
        r#"{HEAD}
[[body]]
name = "rock"
material = "rock"
shape = {{ box = {{ min = [-10.0, -10.0, -10.0], max = [10.0, 10.0, 10.0] }} }}

[[excavation]]
shape = {{ tunnel = {{ {profile}, start = [0.0, -12.0, 0.0], end = [0.0, 12.0, 0.0] }} }}
{joint}"#
    );
    let s = scenario(&text);
    let Shape::Tunnel(t) = &s.excavation[0].shape else { unreachable!() };
    let area = profile_area(t).unwrap();
    (Geometry::from_scenario(&s), area)
}

#[test]
fn tunnels_remove_their_profile_area_times_length() {
    for profile in [
        "profile = \"horseshoe\", width = 4.0, height = 4.5",
        "profile = \"circular\", radius = 2.5",
        "profile = \"rectangular\", width = 3.0, height = 4.0",
        "profile = \"horseshoe\", width = 4.0, height = 4.5, segments = 7",
    ] {
        let (g, area) = tunnel_case(profile, "");
        let excavated = area * 20.0;
        assert!(
            (g.report.excavated_volume - excavated).abs() < 1e-9 * excavated,
            "{profile}: {} vs {excavated}",
            g.report.excavated_volume
        );
        assert_eq!(g.blocks.len(), 1, "{profile}: the ring around the tunnel stays one block");
        check_blocks(&g, 8000.0 - excavated, profile);
        let (split, _) = tunnel_case(profile, "[[joint_plane]]\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n");
        assert_eq!(split.blocks.len(), 2, "{profile}");
        let (a, b) = (split.blocks[0].volume, split.blocks[1].volume);
        assert!((a - b).abs() < 1e-9 * a, "{profile}: {a} vs {b}");
    }
}

#[test]
fn covers_of_a_non_convex_block_keep_its_volume() {
    let (g, _) = tunnel_case("profile = \"horseshoe\", width = 4.0, height = 4.5", "");
    for kind in [PatternKind::Tet6, PatternKind::Hex8] {
        let covers = Covers::on_mesh(
            &g,
            MathMesh::new(1.3, Vec3::new(0.1, 0.2, 0.3), [10.0, 20.0, 30.0]),
            PatternTable::new(kind),
        );
        let sum: f64 = covers.elements.iter().map(|e| e.volume).sum();
        let v = g.blocks[0].volume;
        assert!(((sum - v) / v).abs() < 1e-12, "{kind:?}: {sum} vs {v}");
    }
}

/// 10 000 seeded cases: a box of 1 cm to 10 m cut by one to three joint sets or planes, once
/// near the origin and once at mine or survey coordinates (up to x = 5·10⁵ m, y = 4·10⁶ m):
/// the same blocks, their volumes to 10⁻⁶ of the box (the inputs' own round-off at 4·10⁶ m is
/// ~10⁻⁹ m) and the box's volume whole.
#[test]
fn survey_coordinates_cut_as_at_the_origin() {
    let mut rng = Lcg(0x0501_27E7);
    let offsets = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [1e3, -2e3, 50.0], [512_345.6, 4_123_456.7, 1_234.5]];
    for case in 0..10_000 {
        let size = 10f64.powf(-2.0 + 3.0 * rng.next());
        let joints: String = (0..1 + case % 3)
            .map(|k| {
                let (dip, dd) = (90.0 * rng.next(), 360.0 * rng.next());
                let p = [rng.next(), rng.next(), rng.next()].map(|x| x * size);
                if k % 2 == 0 {
                    let spacing = size * (0.2 + 0.5 * rng.next());
                    format!(
                        "[[joint_set]]\ndip = {dip}\ndip_direction = {dd}\nspacing = {spacing}\norigin = {{o{k}}}\n"
                    )
                    .replace(&format!("{{o{k}}}"), &format!("[P{},{},{}]", p[0], p[1], p[2]))
                } else {
                    format!(
                        "[[joint_plane]]\ndip = {dip}\ndip_direction = {dd}\npoint = [P{},{},{}]\n",
                        p[0], p[1], p[2]
                    )
                }
            })
            .collect();
        let at = |o: [f64; 3]| {
            let body = format!(
                "[[body]]\nname = \"b\"\nmaterial = \"rock\"\nshape = {{ box = {{ min = [{}, {}, {}], max = [{}, {}, {}] }} }}\n",
                o[0], o[1], o[2], o[0] + size, o[1] + size, o[2] + size
            );
            // Joint points move with the box ("[P" marks an x to offset; y and z follow).
            let joints = shift_points(&joints, o);
            geometry(&format!("{body}{joints}"))
        };
        let base = at(offsets[0]);
        let o = offsets[1 + case % 3];
        let far = at(o);
        let label = format!("case {case}: size {size:.3e} at {o:?}");
        assert_eq!(far.blocks.len(), base.blocks.len(), "{label}");
        let v = size * size * size;
        assert!((total_volume(&far) - v).abs() < 1e-6 * v, "{label}: volume {} vs {v}", total_volume(&far));
        let volumes = |g: &Geometry| {
            let mut x: Vec<f64> = g.blocks.iter().map(|b| b.volume).collect();
            x.sort_by(f64::total_cmp);
            x
        };
        for (a, b) in volumes(&far).iter().zip(volumes(&base)) {
            assert!((a - b).abs() < 1e-6 * v, "{label}: block volume {a} vs {b}");
        }
    }
}

/// Replace each `[Px,y,z]` by `[x + o₀, y + o₁, z + o₂]`.
fn shift_points(text: &str, o: [f64; 3]) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find("[P") {
        out.push_str(&rest[..i]);
        let j = rest[i..].find(']').expect("a closing bracket") + i;
        let xyz: Vec<f64> = rest[i + 2..j].split(',').map(|x| x.trim().parse().expect("a number")).collect();
        out.push_str(&format!("[{}, {}, {}]", xyz[0] + o[0], xyz[1] + o[1], xyz[2] + o[2]));
        rest = &rest[j + 1..];
    }
    out.push_str(rest);
    out
}
