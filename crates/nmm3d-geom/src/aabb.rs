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
}
