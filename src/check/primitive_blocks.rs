//! The primitive blocks of a scene as the lints see them.

use crate::geometry::Aabb;
use crate::render::Renderer;
use crate::scene::Material;

/// A primitive block as the lints see it: its kind, material, the objects
/// it made and their bounds.
pub(crate) struct PrimitiveBlock {
    /// 0-based index in file order.
    pub index: u32,
    /// The kind's name (`sphere`...).
    pub kind: &'static str,
    /// Its material.
    pub material: Material,
    /// Indices of its objects in the renderer's acceleration structure.
    pub objects: Vec<u32>,
    /// The union of their bounds (`None`: unbounded, a plane).
    pub bounds: Option<Aabb>,
}

/// The primitive blocks of `renderer`'s scene that made a surface, in file order.
pub(crate) fn blocks(renderer: &Renderer) -> Vec<PrimitiveBlock> {
    let scene = renderer.scene();
    let mut out: Vec<PrimitiveBlock> = Vec::new();
    let mut at = std::collections::HashMap::new();
    for (i, o) in renderer.accel().objects().iter().enumerate() {
        let Some(b) = o.block() else { continue };
        let k = *at.entry(b).or_insert_with(|| {
            out.push(PrimitiveBlock {
                index: b,
                kind: o.shape().kind_name(),
                material: scene.material_of(o),
                objects: Vec::new(),
                bounds: Some(Aabb::EMPTY),
            });
            out.len() - 1
        });
        let block = &mut out[k];
        block.objects.push(i as u32);
        block.bounds = match (block.bounds, o.shape().bounds()) {
            (Some(a), Some(b)) => Some(a.union(&b)),
            _ => None,
        };
    }
    out.sort_by_key(|b| b.index);
    out
}

/// `kind #index`, as findings name a block.
pub(crate) fn name(block: &PrimitiveBlock) -> String {
    format!("{} #{}", block.kind, block.index)
}
