//! The geometry of the built-in scenes `week09` and `cover`: their sphere
//! layouts and camera views, which the benchmark workloads
//! (`crate::workload`) trace too.

use glam::{DVec3, Vec3};
use strata::rng::{Pcg32, next_f32};
use strata::trace::Sphere;

/// The course's week-09 scene: the r = 100 ground at (0, −100.5, −1) and
/// three r = 0.5 spheres at x = −1, 0, 1 (`scenes/course.csv`).
#[must_use]
pub fn course_spheres() -> Vec<Sphere> {
    vec![
        Sphere::new(Vec3::new(0.0, -100.5, -1.0), 100.0),
        Sphere::new(Vec3::new(-1.0, 0.0, -1.0), 0.5),
        Sphere::new(Vec3::new(0.0, 0.0, -1.0), 0.5),
        Sphere::new(Vec3::new(1.0, 0.0, -1.0), 0.5),
    ]
}

/// The cover of *Ray Tracing in One Weekend*, geometry only
/// (`scenes/cover.csv`, 485 spheres): the r = 1000 ground; for `a` then
/// `b` in −11..=10, a r = 0.2 sphere at `(a + 0.9 u₁, 0.2, b + 0.9 u₂)`
/// kept if farther than 0.9 from (4, 0.2, 0), with `u₁, u₂` drawn (both,
/// before the test) from PCG32 seeded as `pcg32_srandom(42, 54)` as
/// `(next_u32 >> 8) · 2⁻²⁴`; centres in `f64`, rounded to `f32`; then the
/// three r = 1 spheres.
#[must_use]
pub fn cover_spheres() -> Vec<Sphere> {
    let mut rng = Pcg32::new(42, 54);
    let mut out = vec![Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0)];
    for a in -11..=10 {
        for b in -11..=10 {
            let u1 = next_f32(&mut rng) as f64;
            let u2 = next_f32(&mut rng) as f64;
            let c = DVec3::new(a as f64 + 0.9 * u1, 0.2, b as f64 + 0.9 * u2);
            if (c - DVec3::new(4.0, 0.2, 0.0)).length() > 0.9 {
                out.push(Sphere::new(c.as_vec3(), 0.2));
            }
        }
    }
    for x in [0.0, -4.0, 4.0] {
        out.push(Sphere::new(Vec3::new(x, 1.0, 0.0), 1.0));
    }
    out
}

/// A pinhole view: where the camera is, what it looks at, and its
/// vertical field of view in degrees.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Eye position.
    pub from: Vec3,
    /// Point looked at.
    pub at: Vec3,
    /// Vertical field of view, degrees.
    pub vfov: f32,
}

/// The course's camera: from (−2, 2, 1) to (0, 0, −1), 60°.
pub const COURSE_VIEW: View = View {
    from: Vec3::new(-2.0, 2.0, 1.0),
    at: Vec3::new(0.0, 0.0, -1.0),
    vfov: 60.0,
};

/// The cover's camera: from (13, 2, 3) to the origin, 20°.
pub const COVER_VIEW: View = View {
    from: Vec3::new(13.0, 2.0, 3.0),
    at: Vec3::ZERO,
    vfov: 20.0,
};
