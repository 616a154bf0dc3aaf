//! The diffuse light: radiance `emit` on both sides and no scattering, so
//! all it has of its own is its check and its content bytes.

use glam::Vec3;

use super::{Feed, MaterialError, check, colour_ok};

/// A diffuse emitter.
#[derive(Clone, Copy)]
pub(super) struct DiffuseLight {
    pub(super) emit: Vec3,
}

impl DiffuseLight {
    /// Radiance has no upper bound, only finiteness.
    pub(super) fn validate(&self) -> Result<(), MaterialError> {
        check(colour_ok(self.emit, f32::MAX), MaterialError::Colour)
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        out.v3(self.emit);
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use crate::render::material::{HIT, Material, MaterialError};

    #[test]
    fn emission_ranges() {
        let light = Material::DiffuseLight {
            emit: Vec3::splat(40.0),
        };
        assert_eq!(light.validate(), Ok(()));
        let bad_light = Material::DiffuseLight {
            emit: Vec3::new(1.0, f32::NAN, 1.0),
        };
        assert_eq!(bad_light.validate(), Err(MaterialError::Colour));
    }

    #[test]
    fn lights_do_not_scatter() {
        let l = Material::DiffuseLight { emit: Vec3::ONE };
        assert!(l.sample(-Vec3::Y, &HIT, Vec2::splat(0.5), 0.5).is_none());
        assert_eq!(l.emitted(), Vec3::ONE);
        assert!(l.is_light() && !l.is_smooth());
    }
}
