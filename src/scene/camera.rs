//! The camera block: a pinhole eye, the image size and the quality keys.

use glam::DVec3;

/// Largest image side in pixels.
pub const MAX_IMAGE_SIDE: u32 = 32768;

/// The camera block: a pinhole eye and the framework's quality knobs.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (`O=`).
    pub origin: DVec3,
    /// Unit view direction (`N=`).
    pub dir: DVec3,
    /// Full image-plane width at distance 1 (`lens_W=`).
    pub lens_w: f64,
    /// Full image-plane height at distance 1 (`lens_H=`).
    pub lens_h: f64,
    /// Output width in pixels (`image_W=`).
    pub width: u32,
    /// Output height in pixels (`image_H=`).
    pub height: u32,
    /// Area-light shadow rays per point = 16 × this (`shade_quality=`), as
    /// written: the framework's readers keep a fraction (`integrator::Model`).
    pub shade_quality: f64,
    /// Glossy-reflection rays = 16 × this (`drefl_quality=`), as written.
    pub drefl_quality: f64,
    /// Photon-mapping settings (rendered by a later feature).
    pub photons: PhotonSettings,
    /// Depth of field (variants; rendered by a later feature).
    pub dof: DepthOfField,
    /// The W lineage's right-hand direction of the image (`Dx=`), if given.
    pub right: Option<DVec3>,
    /// The V lineage's algorithm (`algorithm=`: `RC`, `RT`, `PM`, `PPM`, `SPPM`), if given.
    pub algorithm: Option<String>,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            origin: DVec3::ZERO,
            dir: DVec3::Y,
            lens_w: 0.88,
            lens_h: 0.88,
            width: 420,
            height: 420,
            shade_quality: 4.0,
            drefl_quality: 4.0,
            photons: PhotonSettings::default(),
            dof: DepthOfField::default(),
            right: None,
            algorithm: None,
        }
    }
}

/// The photon-map keys of the camera block.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonSettings {
    /// Photon map capacity (`max_photons=`).
    pub max_photons: u64,
    /// Photons emitted (`emit_photons=`).
    pub emit_photons: u64,
    /// Photons gathered per estimate (`sample_photons=`).
    pub sample_photons: u64,
    /// Gather radius (`sample_dist=`).
    pub sample_dist: f64,
    /// Progressive photon mapping hit points (`max_hitpoints=`), if given.
    pub max_hitpoints: Option<u64>,
    /// Progressive photon mapping passes (`iterations=`), if given.
    pub iterations: Option<u64>,
    /// Progressive radius reduction (`reduction=`), if given.
    pub reduction: Option<f64>,
    /// The photon keys the file sets, in the order read.
    pub keys: Vec<&'static str>,
}

impl Default for PhotonSettings {
    fn default() -> Self {
        PhotonSettings {
            max_photons: 2_000_000,
            emit_photons: 1_000_000,
            sample_photons: 100,
            sample_dist: 1.0,
            max_hitpoints: None,
            iterations: None,
            reduction: None,
            keys: Vec::new(),
        }
    }
}

/// Depth-of-field keys of the camera block (0 aperture: pinhole).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DepthOfField {
    /// Lens radius (`aperture=`).
    pub aperture: f64,
    /// Focus distance (`focalLen=`).
    pub focal_len: f64,
    /// Samples per pixel (`dofSample=`).
    pub samples: u32,
}
