//! A finding of `glint check`: its code, place, message and help, and the
//! list the lints add to.

use crate::scene::{Diagnostic, Scene, Severity};

/// What kind of problem a [`Finding`] is; its name is the JSON `code`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Code {
    /// A diagnostic of the reader (an error, or a warning such as an unused key).
    Format,
    /// `refr=` above 0 with `rindex=` below 1.
    RindexBelowOne,
    /// A material that is all zero (colour, or every one of diff, spec, refl, refr).
    ZeroMaterial,
    /// `diff + refl + refr` above 1: the surface gives back more light than it gets.
    EnergyAboveOne,
    /// A light inside a closed object that is not glass.
    LightInsideObject,
    /// A light inside glass (glass blocks shadow rays in this model).
    LightInsideGlass,
    /// The camera inside a closed object.
    CameraInsideObject,
    /// An object wholly behind the camera.
    BehindCamera,
    /// An object wholly outside the view.
    OutsideView,
    /// A lens whose aspect is not the image's: the picture is stretched.
    LensAspect,
    /// Two faces in the same plane that overlap (they flicker between each other).
    CoincidentFaces,
    /// Two squares meant to share an edge that do not meet (a crack).
    EdgeGap,
    /// A shape too small or flat to be seen (zero-area triangles).
    Degenerate,
    /// A primitive the camera sees only from its side that faces away from every light.
    FacesAway,
    /// A visible primitive that no light reaches where the camera sees it.
    Unlit,
}

impl Code {
    /// Its name, as `--json` writes it.
    pub fn name(self) -> &'static str {
        match self {
            Code::Format => "format",
            Code::RindexBelowOne => "rindex-below-one",
            Code::ZeroMaterial => "zero-material",
            Code::EnergyAboveOne => "energy-above-one",
            Code::LightInsideObject => "light-inside-object",
            Code::LightInsideGlass => "light-inside-glass",
            Code::CameraInsideObject => "camera-inside-object",
            Code::BehindCamera => "behind-camera",
            Code::OutsideView => "outside-view",
            Code::LensAspect => "lens-aspect",
            Code::CoincidentFaces => "coincident-faces",
            Code::EdgeGap => "edge-gap",
            Code::Degenerate => "degenerate",
            Code::FacesAway => "faces-away",
            Code::Unlit => "unlit",
        }
    }
}

/// One problem `check` found.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// Error (the scene cannot be read) or warning.
    pub severity: Severity,
    /// What kind of problem it is.
    pub code: Code,
    /// The scene file's name as given (`None`: parsed from text).
    pub file: Option<String>,
    /// The 1-based line of the block it is about (`None`: the file as a whole).
    pub line: Option<u32>,
    /// What is wrong, in a sentence.
    pub message: String,
    /// What to change.
    pub help: String,
}

/// Where findings go as the lints run: knows the file and each block's line.
pub(crate) struct Findings<'s> {
    /// The scene checked (for the blocks' lines).
    pub scene: &'s Scene,
    /// The scene file's name as given.
    pub file: Option<String>,
    /// The findings so far.
    pub list: Vec<Finding>,
}

impl Findings<'_> {
    /// A warning about primitive block `block`.
    pub fn block(&mut self, code: Code, block: u32, message: String, help: String) {
        let line = self.scene.block_line(block);
        self.at(code, line, message, help);
    }

    /// A warning about light `light`.
    pub fn light(&mut self, code: Code, light: u32, message: String, help: String) {
        let line = self.scene.light_line(light);
        self.at(code, line, message, help);
    }

    /// A warning at `line` (`None`: the file as a whole).
    pub fn at(&mut self, code: Code, line: Option<u32>, message: String, help: String) {
        self.list.push(Finding {
            severity: Severity::Warning,
            code,
            file: self.file.clone(),
            line,
            message,
            help,
        });
    }
}

/// A reader's diagnostic as a finding of code [`Code::Format`].
pub fn from_diagnostic(d: &Diagnostic) -> Finding {
    Finding {
        severity: d.severity,
        code: Code::Format,
        file: Some(d.file.clone()),
        line: (d.line > 0).then_some(d.line as u32),
        message: d.message.clone(),
        help: d.help.clone().unwrap_or_default(),
    }
}
