//! The lockstep path tracer gives the scalar one's film, byte for byte:
//! every built-in scene and every `examples/scenes/*.toml`, every sampler,
//! next-event estimation on and off, depths 1, 2, 5 and 50 at the golden
//! size (32×18, 4 spp); a splatted filter, an adaptive render, a
//! texture-filtered render and one 160×90 render per scene. The paths,
//! rays and shadow rays counted are equal too.

use std::path::Path;

use strata::filter::FilterKind;
use strata::render::{Adaptive, Integrator, PixelFilter, TextureFilter};
use strata_runner::golden;
use strata_runner::job::{Job, SamplerKind, run};
use strata_runner::scenes::{BUILT_IN, SceneData, built_in, file};

fn scenes() -> Vec<(String, SceneData)> {
    let mut out: Vec<(String, SceneData)> = BUILT_IN
        .iter()
        .map(|n| (n.to_string(), built_in(n).unwrap()))
        .collect();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 2, "example scenes: {files:?}");
    for p in files {
        let text = std::fs::read_to_string(&p).unwrap();
        out.push((p.display().to_string(), file::parse(&p, &text).unwrap()));
    }
    out
}

/// What a render counted: paths, rays, shadow rays.
type Counts = (u64, u64, u64);

/// The film hashes of `job` with each integrator, and what each counted.
fn both(job: &Job<'_>) -> (u64, u64, Counts, Counts) {
    let render = |integrator| {
        let done = run(
            &Job {
                integrator,
                ..job.clone()
            },
            &|_| {},
        )
        .unwrap();
        (
            golden::film_hash(&done.pixels),
            (done.stats.paths, done.stats.rays, done.stats.shadow_rays),
        )
    };
    let (a, ra) = render(Integrator::Scalar);
    let (b, rb) = render(Integrator::Lockstep);
    (a, b, ra, rb)
}

#[test]
fn lockstep_films_are_the_scalar_films() {
    let mut renders = 0;
    for (name, scene) in &scenes() {
        for sampler in SamplerKind::ALL {
            for direct_lighting in [true, false] {
                for max_depth in [1, 2, 5, 50] {
                    let job = Job {
                        max_depth,
                        direct_lighting,
                        sampler,
                        ..golden::job(scene, sampler, 2)
                    };
                    let (a, b, ra, rb) = both(&job);
                    let what = format!(
                        "{name} {} nee={direct_lighting} depth={max_depth}",
                        sampler.name()
                    );
                    assert_eq!(a, b, "{what}: film");
                    assert_eq!(ra, rb, "{what}: paths, rays, shadow rays");
                    renders += 1;
                }
            }
        }
        // A splatted filter, an adaptive render, and a larger image.
        let kind = FilterKind::Lanczos { tau: 3.0 };
        let lanczos = PixelFilter::new(kind, kind.default_radius());
        let splat = Job {
            filter: lanczos.unwrap(),
            ..golden::job(scene, SamplerKind::Sobol, 2)
        };
        let adaptive = Job {
            adaptive: Some(Adaptive::new(8, 16, 0.002).unwrap()),
            spp: 16,
            samples: 0..16,
            ..golden::job(scene, SamplerKind::Sobol, 2)
        };
        let textured = Job {
            texture_filter: TextureFilter::Box,
            ..golden::job(scene, SamplerKind::Sobol, 2)
        };
        let large = Job {
            spp: 2,
            samples: 0..2,
            ..Job::new(scene, 160, 90, 2)
        };
        let jobs = [
            ("splat", splat),
            ("adaptive", adaptive),
            ("texture box", textured),
            ("160x90", large),
        ];
        for (what, job) in jobs {
            let (a, b, ra, rb) = both(&job);
            assert_eq!(a, b, "{name} {what}: film");
            assert_eq!(ra, rb, "{name} {what}: paths, rays, shadow rays");
            renders += 1;
        }
    }
    assert!(renders >= 7 * 6 * 8 + 7 * 4, "{renders}");
}
