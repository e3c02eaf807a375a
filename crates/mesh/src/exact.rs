//! Exact signs of small determinants by floating-point expansion arithmetic (Shewchuk,
//! "Adaptive precision floating-point arithmetic and fast robust geometric predicates",
//! Discrete Comput. Geom. 18, 1997): a value is held exactly as a sum of non-overlapping
//! doubles. Used only when the plain floating-point evaluation cannot certify the sign.

use crate::v3::V3;

/// Exact `a + b = s + e`.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bv = s - a;
    let av = s - bv;
    (s, (a - av) + (b - bv))
}

/// Exact `a * b = p + e` (the fused multiply-add is correctly rounded, so `e` is exact).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// An exact value as a non-overlapping expansion, components in increasing magnitude.
#[derive(Clone, Debug, Default)]
struct Expansion(Vec<f64>);

impl Expansion {
    fn from_f64(x: f64) -> Self {
        Expansion(vec![x])
    }

    /// Exact difference of two doubles.
    fn diff(a: f64, b: f64) -> Self {
        let (s, e) = two_sum(a, -b);
        Expansion(vec![e, s])
    }

    /// Adds one double (Shewchuk's Grow-Expansion), dropping zero components.
    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut out = Vec::with_capacity(self.0.len() + 1);
        for &e in &self.0 {
            let (s, h) = two_sum(q, e);
            if h != 0.0 {
                out.push(h);
            }
            q = s;
        }
        if q != 0.0 || out.is_empty() {
            out.push(q);
        }
        self.0 = out;
    }

    fn add(&self, o: &Expansion) -> Expansion {
        let mut r = self.clone();
        for &x in &o.0 {
            r.grow(x);
        }
        r
    }

    fn neg(&self) -> Expansion {
        Expansion(self.0.iter().map(|x| -x).collect())
    }

    fn mul(&self, o: &Expansion) -> Expansion {
        let mut r = Expansion::from_f64(0.0);
        for &a in &self.0 {
            for &b in &o.0 {
                let (p, e) = two_prod(a, b);
                r.grow(e);
                r.grow(p);
            }
        }
        r
    }

    /// Sign of the exact value: that of the largest non-zero component.
    fn sign(&self) -> f64 {
        self.0
            .iter()
            .rev()
            .find(|&&x| x != 0.0)
            .map_or(0.0, |x| x.signum())
    }
}

/// Exact signs of −((b−a)×(c−a))·(p−a) and of the three components of N = (b−a)×(c−a).
pub(crate) fn orient_exact(a: &V3, b: &V3, c: &V3, p: &V3) -> (f64, V3) {
    let u: [Expansion; 3] = std::array::from_fn(|k| Expansion::diff(b[k], a[k]));
    let v: [Expansion; 3] = std::array::from_fn(|k| Expansion::diff(c[k], a[k]));
    let w: [Expansion; 3] = std::array::from_fn(|k| Expansion::diff(p[k], a[k]));
    let n = [
        u[1].mul(&v[2]).add(&u[2].mul(&v[1]).neg()),
        u[2].mul(&v[0]).add(&u[0].mul(&v[2]).neg()),
        u[0].mul(&v[1]).add(&u[1].mul(&v[0]).neg()),
    ];
    let d = n[0].mul(&w[0]).add(&n[1].mul(&w[1])).add(&n[2].mul(&w[2]));
    (-d.sign(), V3::new(n[0].sign(), n[1].sign(), n[2].sign()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expansions_are_exact_where_doubles_cancel() {
        // 1e16 + 1 − 1e16 = 1 exactly, lost in plain doubles.
        let mut e = Expansion::from_f64(1e16);
        e.grow(1.0);
        e.grow(-1e16);
        assert_eq!(e.sign(), 1.0);
        let x = Expansion::diff(1.0 + f64::EPSILON, 1.0);
        let sq = x.mul(&x);
        assert_eq!(sq.sign(), 1.0);
        assert_eq!(Expansion::diff(0.1, 0.1).sign(), 0.0);
    }

    #[test]
    fn orientation_of_nearly_coplanar_points_is_exact() {
        let a = V3::new(0.1, 0.2, 0.3);
        let b = V3::new(0.7, 0.2, 0.3);
        let c = V3::new(0.1, 0.9, 0.3);
        // Exactly in the plane z = 0.3, and one ulp above and below it.
        let up = f64::from_bits(0.3f64.to_bits() + 1);
        let down = f64::from_bits(0.3f64.to_bits() - 1);
        assert_eq!(orient_exact(&a, &b, &c, &V3::new(0.4, 0.5, 0.3)).0, 0.0);
        // N = +z: a point above the plane is on the normal's side, hence negative.
        assert_eq!(orient_exact(&a, &b, &c, &V3::new(0.4, 0.5, up)).0, -1.0);
        assert_eq!(orient_exact(&a, &b, &c, &V3::new(0.4, 0.5, down)).0, 1.0);
        assert_eq!(
            orient_exact(&a, &b, &c, &V3::new(0.4, 0.5, 0.3)).1,
            V3::new(0.0, 0.0, 1.0)
        );
    }
}
