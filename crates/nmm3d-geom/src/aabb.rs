//! Axis-aligned bounding boxes.

use crate::math::Vec3;

/// Axis-aligned box `[min, max]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box around a set of points (`None` when empty).
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Option<Self> {
        let mut it = points.into_iter();
        let first = *it.next()?;
        Some(it.fold(Self { min: first, max: first }, |b, p| b.including(p)))
    }

    /// This box grown to include `p`.
    pub fn including(self, p: &Vec3) -> Self {
        Self { min: self.min.inf(p), max: self.max.sup(p) }
    }

    /// Union of two boxes.
    pub fn union(self, other: &Self) -> Self {
        Self { min: self.min.inf(&other.min), max: self.max.sup(&other.max) }
    }

    /// Edge lengths.
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        self.extent().norm()
    }

    /// Whether `p` lies inside the box grown by `margin`.
    pub fn contains(&self, p: &Vec3, margin: f64) -> bool {
        (0..3).all(|i| p[i] >= self.min[i] - margin && p[i] <= self.max[i] + margin)
    }

    /// Whether two boxes overlap (touching counts).
    pub fn overlaps(&self, o: &Self) -> bool {
        (0..3).all(|i| self.min[i] <= o.max[i] && o.min[i] <= self.max[i])
    }

    /// The largest gap between the two boxes along an axis (negative when they overlap): a
    /// lower bound of the distance between any two bodies inside them.
    pub fn separation(&self, o: &Self) -> f64 {
        (0..3).map(|i| (self.min[i] - o.max[i]).max(o.min[i] - self.max[i])).fold(f64::NEG_INFINITY, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separation_is_the_widest_axis_gap_and_negative_on_overlap() {
        let a = Aabb { min: Vec3::new(0.0, 0.0, 0.0), max: Vec3::new(1.0, 1.0, 1.0) };
        let b = Aabb { min: Vec3::new(1.5, 0.2, 3.0), max: Vec3::new(2.0, 0.8, 4.0) };
        assert_eq!(a.separation(&b), 2.0);
        assert_eq!(b.separation(&a), 2.0);
        let c = Aabb { min: Vec3::new(0.5, 0.5, 0.9), max: Vec3::new(2.0, 2.0, 2.0) };
        assert!((a.separation(&c) + 0.1).abs() < 1e-15);
    }
}
