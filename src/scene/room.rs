//! Room made ahead in a list that a reader knows will grow.

/// Makes room in `list` for `more` entries beyond those held, if it has
/// not: a sixteenth more than asked (a reader's next, slightly larger
/// estimate then fits), and at least its length (so that estimates that
/// keep growing still double it). Room the allocator refuses is not made:
/// the list grows as it would have. On systems that commit memory when it
/// is first touched (Linux's default), room never used costs address
/// space only.
pub(crate) fn make_room<T>(list: &mut Vec<T>, more: usize) {
    if list.capacity() - list.len() < more {
        let room = more.saturating_add(more / 16).max(list.len());
        // Room not made is only the copies not saved.
        let _ = list.try_reserve_exact(room);
    }
}
