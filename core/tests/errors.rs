//! The core's errors as a caller sees them: readable on their own (an
//! inner error's text is part of the outer message, never a separate
//! `source`), and usable with `?` in any error type built on
//! `core::error::Error`.

/// Every core error reads as a sentence (`Display`) and is a
/// `core::error::Error` (so `?` lifts it into `anyhow` and `Box<dyn Error>`).
#[test]
fn core_errors_read_as_one_sentence() {
    use std::error::Error;
    use strata::render::{AdaptiveError, CameraError, MaterialError, RenderError, SceneError};
    let errors: Vec<Box<dyn Error>> = vec![
        Box::new(strata::trace::SphereSetError::StorageTooSmall {
            needed: 2,
            provided: 1,
        }),
        Box::new(strata::trace::BvhError::StorageTooSmall {
            slice: "nodes",
            needed: 3,
            provided: 0,
        }),
        Box::new(strata::trace::BvhError::SphereOutOfRange { index: 7 }),
        Box::new(strata::filter::FilterError::Radius),
        Box::new(AdaptiveError::Max),
        Box::new(RenderError::FilmSize {
            needed: 64,
            provided: 63,
        }),
        Box::new(CameraError::FieldOfView),
        Box::new(MaterialError::Energy),
        Box::new(SceneError::Material {
            material: 4,
            error: MaterialError::Colour,
        }),
        Box::new(strata::sampler::ZSobolError::IndexTooWide {
            spp: 8,
            resolution: glam::UVec2::new(1 << 31, 3),
            bits: 65,
        }),
    ];
    for e in &errors {
        let text = e.to_string();
        assert!(text.len() > 10, "{text:?}");
        assert!(!text.contains('{') && !text.contains("Error"), "{text:?}");
    }
    assert!(errors[0].to_string().contains("2 chunks needed, 1 given"));
    assert!(errors[1].to_string().contains("`nodes`"));
    assert!(errors[2].to_string().contains("sphere 7"));
    assert!(errors[5].to_string().contains("63"));
    assert!(
        errors[9]
            .to_string()
            .contains("2147483648 x 3 pixels needs a 65-bit")
    );
    // The inner error's text is in the message, and not repeated as a
    // source (a chained report prints each once).
    let scene = &errors[8];
    assert!(scene.to_string().starts_with("material 4: a colour"));
    assert!(scene.source().is_none());
}
