//! The built-in layouts are exactly the reference sphere lists: the copies
//! in `core/tests/data/` (and, where the project's shared folder sits beside the
//! checkout, the originals), compared bit for bit.

use std::path::Path;
use strata::trace::Sphere;
use strata_runner::scenes::{course_spheres, cover_spheres};

fn parse(csv: &str) -> Vec<[u32; 4]> {
    csv.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f32> = l
                .split(',')
                .map(|x| x.trim().parse().expect("a float"))
                .collect();
            assert_eq!(v.len(), 4, "{l}");
            [
                v[0].to_bits(),
                v[1].to_bits(),
                v[2].to_bits(),
                v[3].to_bits(),
            ]
        })
        .collect()
}

fn bits(spheres: &[Sphere]) -> Vec<[u32; 4]> {
    spheres
        .iter()
        .map(|s| [s.center.x, s.center.y, s.center.z, s.radius].map(f32::to_bits))
        .collect()
}

fn check(name: &str, built: &[Sphere]) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let copy = std::fs::read_to_string(root.join("core/tests/data").join(name)).expect("test data");
    assert_eq!(
        bits(built),
        parse(&copy),
        "{name} differs from core/tests/data/{name}"
    );
    let shared = root.join("../shared/scenes").join(name);
    if let Ok(original) = std::fs::read_to_string(&shared) {
        assert_eq!(
            copy,
            original,
            "core/tests/data/{name} is stale against {}",
            shared.display()
        );
    }
}

#[test]
fn course_layout_is_the_reference() {
    check("course.csv", &course_spheres());
}

#[test]
fn cover_layout_is_the_reference() {
    let spheres = cover_spheres();
    assert_eq!(spheres.len(), 485);
    check("cover.csv", &spheres);
}
