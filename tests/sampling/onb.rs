//! Orthonormal bases: orthonormal and of the documented handedness for 10⁵
//! random normals and for adversarial ones (±axes, the course's switch at
//! |w.x| = 0.9, Duff's sign branch near −z and at z = ±0, tiny, huge and
//! subnormal lengths); round trips through `to_world` / `to_local`.

use glam::{Vec2, Vec3};
use strata::mapping::sample_uniform_sphere;
use strata::onb::Onb;
use strata::rng::{Pcg32, STREAM, next_f32};

const TOL: f32 = 2e-6;

/// Checks orthonormality, that `w` is the normal, and the handedness
/// (`+1` right, `−1` left).
fn check(b: Onb, n: Vec3, handedness: f32, what: &str) {
    let msg = || format!("{what}: n = {n:?} gives {b:?}");
    for a in [b.u, b.v, b.w] {
        assert!((a.length() - 1.0).abs() < TOL, "not unit: {}", msg());
    }
    assert!(b.u.dot(b.v).abs() < TOL, "u·v: {}", msg());
    assert!(b.u.dot(b.w).abs() < TOL, "u·w: {}", msg());
    assert!(b.v.dot(b.w).abs() < TOL, "v·w: {}", msg());
    assert!((b.w - n).length() < TOL, "w is not the normal: {}", msg());
    assert!(
        (b.u.cross(b.v) - handedness * b.w).length() < 4.0 * TOL,
        "handedness: {}",
        msg()
    );
    let d = Vec3::new(0.3, -0.4, 0.866);
    assert!(
        (b.to_local(b.to_world(d)) - d).length() < 4.0 * TOL,
        "round trip: {}",
        msg()
    );
    // Local +z is the normal.
    assert!((b.to_world(Vec3::Z) - b.w).length() < TOL, "{}", msg());
}

fn adversarial() -> Vec<Vec3> {
    let mut v = vec![
        Vec3::X,
        -Vec3::X,
        Vec3::Y,
        -Vec3::Y,
        Vec3::Z,
        -Vec3::Z,
        Vec3::new(1.0, 0.0, -0.0),
        Vec3::new(0.0, 1.0, -0.0),
        Vec3::new(1e-4, 1e-4, -1.0),
        Vec3::new(1e-8, 0.0, -1.0),
        Vec3::new(-1e-20, 1e-20, -1.0),
        Vec3::new(3e-4, -2e-4, -1.0),
        Vec3::new(0.7, 0.7, -1e-7),
        Vec3::new(0.7, 0.7, 1e-7),
    ];
    // Around the course's switch |w.x| = 0.9, both signs, both sides.
    for x in [0.899_999, 0.9, 0.900_001, 0.95, 0.999_999] {
        for sx in [1.0, -1.0] {
            let r = (1.0f32 - x * x).sqrt();
            v.push(Vec3::new(sx * x, r * 0.6, r * 0.8));
            v.push(Vec3::new(sx * x, -r, 0.0));
        }
    }
    v.into_iter().map(|n| n.normalize()).collect()
}

fn random_normals(count: usize) -> impl Iterator<Item = Vec3> {
    let mut rng = Pcg32::new(2017, STREAM);
    (0..count).map(move |_| {
        sample_uniform_sphere(Vec2::new(next_f32(&mut rng), next_f32(&mut rng))).normalize()
    })
}

#[test]
fn duff_is_orthonormal_and_right_handed() {
    for n in adversarial().into_iter().chain(random_normals(100_000)) {
        check(Onb::from_normal(n), n, 1.0, "from_normal");
    }
}

#[test]
fn course_is_orthonormal_and_left_handed() {
    for n in adversarial().into_iter().chain(random_normals(100_000)) {
        check(
            Onb::from_normal_axis_switch(n),
            n,
            -1.0,
            "from_normal_axis_switch",
        );
    }
}

#[test]
fn any_length_normalises() {
    for n in adversarial().into_iter().chain(random_normals(1000)) {
        for scale in [1e-30f32, 1e-40, 1e-3, 7.0, 1e20, 1e30, f32::MAX / 2.0] {
            let m = n * scale;
            if m == Vec3::ZERO {
                continue; // the components underflowed entirely
            }
            // Scaling can flush tiny components to zero; compare with the
            // direction that survives.
            let unit = (m / m.abs().max_element()).normalize();
            let b = Onb::try_from_normal(m).expect("finite and non-zero");
            check(b, unit, 1.0, "try_from_normal");
            check(
                Onb::from_normal_axis_switch(m),
                unit,
                -1.0,
                "axis switch, scaled",
            );
        }
    }
}

#[test]
fn degenerate_normals_are_refused_or_nan() {
    for n in [
        Vec3::ZERO,
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
        Vec3::new(f32::NEG_INFINITY, 1.0, 1.0),
    ] {
        assert!(Onb::try_from_normal(n).is_none(), "{n}");
        let c = Onb::from_normal_axis_switch(n);
        assert!(c.u.is_nan() && c.v.is_nan() && c.w.is_nan(), "{n}: {c:?}");
    }
}

/// The course's helper axis switches at |w.x| = 0.9 exactly: below it the
/// basis is built from x, above it from y (pinned on both sides).
#[test]
fn course_switches_helper_axis_at_0_9() {
    for (wx, helper) in [
        (0.85f32, Vec3::X),
        (0.95, Vec3::Y),
        (-0.85, Vec3::X),
        (-0.95, Vec3::Y),
    ] {
        let w = Vec3::new(wx, (1.0 - wx * wx).sqrt(), 0.0);
        let b = Onb::from_normal_axis_switch(w);
        let v = w.cross(helper).normalize();
        assert!(
            (b.v - v).length() < 1e-6,
            "w.x = {wx}: v = {} want {v}",
            b.v
        );
        assert!((b.u - w.cross(v)).length() < 1e-6, "w.x = {wx}");
    }
}
