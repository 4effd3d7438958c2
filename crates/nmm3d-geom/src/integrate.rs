//! Exact integration of polynomials over simplices and polyhedra (simplex integration).
//!
//! For a $d$-simplex $T$ with vertices $\mathbf v_0..\mathbf v_d$ and a monomial
//! $\mathbf x^{\boldsymbol\alpha} = x^a y^b z^c$ of degree $n = a+b+c$, writing
//! $\mathbf x = \sum_j \lambda_j \mathbf v_j$ and using the Dirichlet integral
//! $\int_T \boldsymbol\lambda^{\mathbf k} = d!\,|T|\,\mathbf k!/(|\mathbf k|+d)!$ gives the closed form
//!
//! $$\int_T \mathbf x^{\boldsymbol\alpha}\,dV = \frac{d!\,|T|\,\boldsymbol\alpha!}{(n+d)!}
//!   \sum_{\boldsymbol\beta_0+\dots+\boldsymbol\beta_d=\boldsymbol\alpha}\ \prod_{j}
//!   \frac{|\boldsymbol\beta_j|!}{\boldsymbol\beta_j!}\,\mathbf v_j^{\boldsymbol\beta_j}.$$
//!
//! For degree ≤ 2 on tetrahedra this reduces to the familiar moments (Solfec `spx.h`):
//! $\int 1 = V$, $\int x_i = V\bar x_i$,
//! $\int x_i x_j = \frac{V}{20}\left[\sum_a x_{a,i}x_{a,j} + \sum_a x_{a,i}\sum_b x_{b,j}\right]$.
//! A polyhedron is integrated by the signed decomposition into tetrahedra joining a reference
//! point to a fan of every face, which is exact for any closed, outward-oriented surface.
//! Sources: Shi (1996) simplex integration; Lasserre (1998); Koziara, Solfec `spx.h`.

use crate::math::Vec3;
use crate::polyhedron::{signed_tet_volume, ConvexPolyhedron};

/// A monomial exponent `[a, b, c]` for $x^a y^b z^c$.
pub type Exponent = [u8; 3];

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// n! for n ≤ 20 (exact in f64 up to 18!).
const FACT: [f64; 21] = {
    let mut f = [1.0; 21];
    let mut i = 1;
    while i < 21 {
        f[i] = f[i - 1] * i as f64;
        i += 1;
    }
    f
};

/// All ways to write `k` as an ordered sum of `parts` non-negative integers.
fn compositions(k: u8, parts: usize) -> Vec<Vec<u8>> {
    if parts == 1 {
        return vec![vec![k]];
    }
    let mut out = Vec::new();
    for first in 0..=k {
        for mut rest in compositions(k - first, parts - 1) {
            rest.insert(0, first);
            out.push(rest);
        }
    }
    out
}

/// Largest exponent per axis with precomputed compositions (beyond it they are built on demand).
const TABLE_MAX: u8 = 6;

/// Compositions of k ≤ `TABLE_MAX` into 3 (triangles) or 4 (tetrahedra) parts, built once.
fn composition_table(k: u8, parts: usize) -> std::borrow::Cow<'static, [Vec<u8>]> {
    use std::sync::OnceLock;
    static TABLE: OnceLock<[Vec<Vec<Vec<u8>>>; 2]> = OnceLock::new();
    if k > TABLE_MAX || !(3..=4).contains(&parts) {
        return std::borrow::Cow::Owned(compositions(k, parts));
    }
    let t = TABLE.get_or_init(|| [3, 4].map(|p| (0..=TABLE_MAX).map(|k| compositions(k, p)).collect()));
    std::borrow::Cow::Borrowed(&t[parts - 3][k as usize])
}

/// $\int_T x^a y^b z^c$ over the simplex with the given vertices (3 for a triangle, 4 for a
/// tetrahedron) and measure `measure` (area or signed volume). Exact for any degree.
pub fn simplex_monomial(vertices: &[Vec3], measure: f64, e: Exponent) -> f64 {
    let d = vertices.len() - 1;
    let n = (e[0] + e[1] + e[2]) as usize;
    let cx = composition_table(e[0], d + 1);
    let cy = composition_table(e[1], d + 1);
    let cz = composition_table(e[2], d + 1);
    let mut sum = 0.0;
    for bx in cx.iter() {
        for by in cy.iter() {
            for bz in cz.iter() {
                let mut term = 1.0;
                for (j, v) in vertices.iter().enumerate() {
                    let (p, q, r) = (bx[j] as usize, by[j] as usize, bz[j] as usize);
                    let multinomial = FACT[p + q + r] / (FACT[p] * FACT[q] * FACT[r]);
                    term *= multinomial * v.x.powi(p as i32) * v.y.powi(q as i32) * v.z.powi(r as i32);
                }
                sum += term;
            }
        }
    }
    let alpha_fact = factorial(e[0] as usize) * factorial(e[1] as usize) * factorial(e[2] as usize);
    factorial(d) * measure * alpha_fact / factorial(n + d) * sum
}

/// $\int_T x^a y^b z^c\,dV$ over a tetrahedron (signed by its orientation), with the
/// closed forms for degree ≤ 2 and the general formula above.
pub fn tet_monomial(t: &[Vec3; 4], e: Exponent) -> f64 {
    let v = signed_tet_volume(t);
    let deg = e[0] + e[1] + e[2];
    let axis = |k: usize| -> usize { (0..3).find(|&i| e[i] as usize > k).unwrap_or(0) };
    match deg {
        0 => v,
        1 => {
            let i = axis(0);
            v * (t[0][i] + t[1][i] + t[2][i] + t[3][i]) / 4.0
        }
        2 => {
            let i = axis(0);
            let j = if e[i] == 2 { i } else { (i + 1..3).find(|&k| e[k] == 1).unwrap_or(i) };
            let (mut sij, mut si, mut sj) = (0.0, 0.0, 0.0);
            for p in t {
                sij += p[i] * p[j];
                si += p[i];
                sj += p[j];
            }
            v / 20.0 * (sij + si * sj)
        }
        _ => simplex_monomial(t, v, e),
    }
}

/// All moments $\int_T x^a y^b z^c\,dV$ with every exponent ≤ `m` over a tetrahedron, at once.
///
/// The sum in the closed form above is the coefficient of $\mathbf t^{\boldsymbol\alpha}$ in
/// $\prod_{j=0}^{3} (1 - \mathbf v_j\cdot\mathbf t)^{-1}$ (each factor expands to
/// $\sum_{\boldsymbol\beta} \frac{|\boldsymbol\beta|!}{\boldsymbol\beta!}\mathbf v_j^{\boldsymbol\beta}\mathbf t^{\boldsymbol\beta}$), so the whole
/// table is four products of truncated series. Index: a + (m+1) b + (m+1)² c.
pub fn tet_box_moments(t: &[Vec3; 4], m: usize) -> Vec<f64> {
    let w = m + 1;
    let len = w * w * w;
    let idx = |a: usize, b: usize, c: usize| a + w * (b + w * c);
    let mut acc = vec![0.0; len];
    acc[0] = 1.0;
    let mut factor = vec![0.0; len];
    for v in t {
        // (1 − v·t)⁻¹ truncated: coefficient |β|!/β! v^β.
        for c in 0..w {
            for b in 0..w {
                for a in 0..w {
                    factor[idx(a, b, c)] = FACT[a + b + c] / (FACT[a] * FACT[b] * FACT[c])
                        * v.x.powi(a as i32)
                        * v.y.powi(b as i32)
                        * v.z.powi(c as i32);
                }
            }
        }
        let mut next = vec![0.0; len];
        for c1 in 0..w {
            for b1 in 0..w {
                for a1 in 0..w {
                    let x = acc[idx(a1, b1, c1)];
                    if x == 0.0 {
                        continue;
                    }
                    for c2 in 0..w - c1 {
                        for b2 in 0..w - b1 {
                            for a2 in 0..w - a1 {
                                next[idx(a1 + a2, b1 + b2, c1 + c2)] += x * factor[idx(a2, b2, c2)];
                            }
                        }
                    }
                }
            }
        }
        acc = next;
    }
    let vol = signed_tet_volume(t);
    for c in 0..w {
        for b in 0..w {
            for a in 0..w {
                let n = a + b + c;
                acc[idx(a, b, c)] *= 6.0 * vol * FACT[a] * FACT[b] * FACT[c] / FACT[n + 3];
            }
        }
    }
    acc
}

/// All moments with every exponent ≤ `m` over a closed outward-oriented polyhedron
/// (index as in [`tet_box_moments`]).
pub fn polyhedron_box_moments(p: &ConvexPolyhedron, m: usize) -> Vec<f64> {
    let r = p.reference_point();
    let mut out = vec![0.0; (m + 1).pow(3)];
    for t in p.fan_tets(r) {
        for (o, x) in out.iter_mut().zip(tet_box_moments(&t, m)) {
            *o += x;
        }
    }
    out
}

/// Moments $\int_P x^a y^b z^c\,dV$ for each exponent in `exps`, over a closed
/// outward-oriented polyhedron (signed tetrahedral decomposition).
pub fn polyhedron_moments(p: &ConvexPolyhedron, exps: &[Exponent]) -> Vec<f64> {
    let r = p.reference_point();
    let mut m = vec![0.0; exps.len()];
    for t in p.fan_tets(r) {
        for (k, e) in exps.iter().enumerate() {
            m[k] += tet_monomial(&t, *e);
        }
    }
    m
}

/// Moments $\int_F x^a y^b z^c\,dA$ over a planar polygon (fan triangulation).
pub fn polygon_moments(vertices: &[Vec3], exps: &[Exponent]) -> Vec<f64> {
    let mut m = vec![0.0; exps.len()];
    for i in 1..vertices.len().saturating_sub(1) {
        let tri = [vertices[0], vertices[i], vertices[i + 1]];
        let area = 0.5 * (tri[1] - tri[0]).cross(&(tri[2] - tri[0])).norm();
        for (k, e) in exps.iter().enumerate() {
            m[k] += simplex_monomial(&tri, area, *e);
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plane::Plane;
    use crate::polyhedron::FaceTag;

    /// A tetrahedron with no symmetry, away from the origin.
    fn skewed_tet() -> [Vec3; 4] {
        [Vec3::new(0.1, 0.2, 0.3), Vec3::new(1.3, -0.2, 0.4), Vec3::new(0.2, 1.1, -0.3), Vec3::new(0.4, 0.3, 1.2)]
    }

    fn all_exponents(max_each: u8) -> Vec<Exponent> {
        let mut v = Vec::new();
        for c in 0..=max_each {
            for b in 0..=max_each {
                for a in 0..=max_each {
                    v.push([a, b, c]);
                }
            }
        }
        v
    }

    #[test]
    fn box_moments_match_closed_form() {
        let (lo, hi) = (Vec3::new(-0.5, 0.25, 1.0), Vec3::new(1.5, 2.0, 1.75));
        let b = ConvexPolyhedron::from_box(lo, hi);
        let exps = all_exponents(3);
        let m = polyhedron_moments(&b, &exps);
        for (k, e) in exps.iter().enumerate() {
            let exact: f64 = (0..3)
                .map(|i| {
                    let p = e[i] as i32 + 1;
                    (hi[i].powi(p) - lo[i].powi(p)) / p as f64
                })
                .product();
            assert!((m[k] - exact).abs() < 1e-12 * exact.abs().max(1.0), "{e:?}: {} vs {exact}", m[k]);
        }
    }

    #[test]
    fn low_degree_closed_forms_agree_with_general_formula() {
        let t = skewed_tet();
        let v = signed_tet_volume(&t);
        for e in all_exponents(2).into_iter().filter(|e| e.iter().sum::<u8>() <= 2) {
            let a = tet_monomial(&t, e);
            let b = simplex_monomial(&t, v, e);
            assert!((a - b).abs() < 1e-14, "{e:?}");
        }
    }

    #[test]
    fn unit_tet_known_values() {
        let t = [Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::z()];
        // ∫ x^a y^b z^c over the unit simplex = a! b! c! / (a+b+c+3)!
        for e in all_exponents(3) {
            let exact = factorial(e[0] as usize) * factorial(e[1] as usize) * factorial(e[2] as usize)
                / factorial((e[0] + e[1] + e[2]) as usize + 3);
            assert!((tet_monomial(&t, e) - exact).abs() < 1e-15, "{e:?}");
        }
    }

    #[test]
    fn moments_are_additive_under_splitting() {
        let cube = ConvexPolyhedron::from_box(Vec3::zeros(), Vec3::repeat(1.0));
        let p = Plane::from_point_normal(Vec3::new(0.4, 0.5, 0.6), Vec3::new(0.3, -1.0, 0.7)).unwrap();
        let (a, b) = cube.split(&p, FaceTag(1));
        let exps = all_exponents(2);
        let (ma, mb, mc) = (
            polyhedron_moments(&a.unwrap(), &exps),
            polyhedron_moments(&b.unwrap(), &exps),
            polyhedron_moments(&cube, &exps),
        );
        for k in 0..exps.len() {
            assert!((ma[k] + mb[k] - mc[k]).abs() < 1e-14);
        }
    }

    #[test]
    fn box_moment_table_matches_the_term_by_term_formula() {
        let t = skewed_tet();
        let v = signed_tet_volume(&t);
        let table = tet_box_moments(&t, 2);
        for (k, e) in all_exponents(2).into_iter().enumerate() {
            let direct = simplex_monomial(&t, v, e);
            assert!((table[k] - direct).abs() < 1e-14 * direct.abs().max(1e-3), "{e:?}: {} vs {direct}", table[k]);
        }
    }

    #[test]
    fn square_face_moments() {
        let sq = [Vec3::zeros(), Vec3::x(), Vec3::new(1.0, 1.0, 0.0), Vec3::y()];
        let m = polygon_moments(&sq, &[[0, 0, 0], [1, 0, 0], [2, 1, 0]]);
        assert!((m[0] - 1.0).abs() < 1e-15 && (m[1] - 0.5).abs() < 1e-15);
        assert!((m[2] - 1.0 / 6.0).abs() < 1e-15);
    }
}
