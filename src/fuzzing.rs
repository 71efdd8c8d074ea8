//! The private readers the fuzz targets (`fuzz/`) drive; not a public API.

/// Parses OBJ text as a `primitive mesh` file would be (errors are messages).
pub fn obj(bytes: &[u8]) -> Result<usize, String> {
    crate::format::parse_obj(bytes).map(|models| models.len())
}

/// Decodes image bytes as a texture would be (errors are messages).
pub fn texture(bytes: &[u8]) -> Result<(), String> {
    crate::format::decode_texture_bytes(bytes).map(|_| ())
}

/// Parses scene text as [`Scene::parse`](crate::Scene::parse) does, but
/// finds none of the files it names, without touching the file system:
/// each is reported not found, with the places it would have been looked
/// for. A fuzz run then does not depend on its working directory (the
/// OBJ and texture readers have targets of their own).
pub fn scene(text: &str) -> Result<crate::Scene, crate::SceneError> {
    crate::format::parse_text(text, None, std::path::Path::new("scene-dir"), None, false)
}
