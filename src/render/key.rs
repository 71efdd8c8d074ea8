//! A camera key as the user wrote it, and where: what the warnings and
//! refusals name when a key drives a render's cost.

use std::fmt;

/// A camera key that drives a render's cost: its name, its value and,
/// when the scene was read from a file, where (`scene.txt:12`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CameraKey {
    /// The key's name (`shade_quality`).
    pub name: &'static str,
    /// Its value, as written back.
    pub value: String,
    /// `FILE:LINE` of the key, when the file sets it.
    pub at: Option<String>,
}

impl fmt::Display for CameraKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(at) = &self.at {
            write!(f, "{at} ")?;
        }
        write!(f, "`{}={}`", self.name, self.value)
    }
}
