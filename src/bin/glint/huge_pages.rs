//! The process's allocator: the system's, asking Linux to back large blocks
//! with transparent huge pages, so a big scene's lists fault in 2 MiB at a
//! time rather than 4 KiB (a million spheres: about 13 500 page faults, not
//! 58 000). The program's only `unsafe` code (the library forbids it).

use std::alloc::{GlobalAlloc, Layout, System};

/// A huge page's size on x86-64 and aarch64 with 4 KiB pages.
const HUGE_PAGE: usize = 2 << 20;
/// Blocks from this size on are advised (smaller ones would rarely span a
/// whole aligned huge page).
const ADVISED_FROM: usize = 2 * HUGE_PAGE;

/// [`System`], with blocks of at least [`ADVISED_FROM`] bytes advised
/// `MADV_HUGEPAGE` (on Linux; elsewhere exactly [`System`]).
pub struct HugePages;

// SAFETY: every method hands its arguments to `System`'s, whose contract is
// the caller's, and returns its result unchanged; `advise` only gives the
// kernel advice on pages inside the block just returned, and changes no byte.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract for `alloc`, passed on.
        let block = unsafe { System.alloc(layout) };
        advise(block, layout.size());
        block
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract for `alloc_zeroed`, passed on.
        let block = unsafe { System.alloc_zeroed(layout) };
        advise(block, layout.size());
        block
    }

    unsafe fn dealloc(&self, block: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract for `dealloc`, passed on.
        unsafe { System.dealloc(block, layout) }
    }

    unsafe fn realloc(&self, block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller's contract for `realloc`, passed on.
        let moved = unsafe { System.realloc(block, layout, new_size) };
        advise(moved, new_size);
        moved
    }
}

/// Advises `MADV_HUGEPAGE` for the whole huge pages inside the `len` bytes
/// at `block` (null when the allocation failed), if `len` is large enough.
fn advise(block: *mut u8, len: usize) {
    if !block.is_null()
        && let Some((start, end)) = huge_range(block as usize, len)
    {
        advise_range(start, end - start);
    }
}

/// The whole huge pages inside the `len` bytes at address `block`, if `len`
/// is at least [`ADVISED_FROM`]: their first byte's address and their end's.
fn huge_range(block: usize, len: usize) -> Option<(usize, usize)> {
    let start = block.checked_next_multiple_of(HUGE_PAGE)?;
    let end = block.checked_add(len)? / HUGE_PAGE * HUGE_PAGE;
    (len >= ADVISED_FROM && start < end).then_some((start, end))
}

// Miri has no madvise: under it, the blocks pass through unadvised.
#[cfg(all(target_os = "linux", not(miri)))]
fn advise_range(start: usize, len: usize) {
    // SAFETY: `errno` is this thread's, always valid to read and write;
    // `start..start + len` lies inside a block the allocator has just
    // returned, so it is mapped, and MADV_HUGEPAGE is advice only, which
    // changes no byte of it. A kernel that refuses it (no THP, EINVAL)
    // leaves the block as it was, and `errno` is put back as it was
    // before, so an allocation never changes it.
    unsafe {
        let errno = libc::__errno_location();
        let saved = *errno;
        libc::madvise(start as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
        *errno = saved;
    }
}

#[cfg(any(not(target_os = "linux"), miri))]
fn advise_range(_start: usize, _len: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `VmFlags` line of the mapping of /proc/self/smaps that holds
    /// `address`.
    #[cfg(target_os = "linux")]
    fn flags_of(address: usize) -> Option<String> {
        let smaps = std::fs::read_to_string("/proc/self/smaps").ok()?;
        let mut inside = false;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().unwrap_or("");
            if let Some((lo, hi)) = range.split_once('-')
                && let (Ok(lo), Ok(hi)) =
                    (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16))
            {
                inside = (lo..hi).contains(&address);
            } else if inside && let Some(flags) = line.strip_prefix("VmFlags:") {
                return Some(flags.to_string());
            }
        }
        None
    }

    #[test]
    fn the_advice_covers_the_whole_huge_pages_of_large_blocks_alone() {
        const H: usize = HUGE_PAGE;
        // Unaligned: the pages between the first boundary and the last.
        assert_eq!(huge_range(3 * H + 16, 4 * H), Some((4 * H, 7 * H)));
        // Aligned: every page.
        assert_eq!(huge_range(5 * H, 2 * H), Some((5 * H, 7 * H)));
        // Just large enough: one whole page inside; past the address space.
        assert_eq!(huge_range(H + 1, 2 * H), Some((2 * H, 3 * H)));
        assert_eq!(huge_range(usize::MAX - H, 3 * H), None);
        // Below the threshold: never advised.
        assert_eq!(huge_range(4 * H, 2 * H - 1), None);
        assert_eq!(huge_range(4 * H, 4096), None);
    }

    #[test]
    fn blocks_keep_their_bytes_when_grown_past_the_threshold_and_come_zeroed() {
        // Through this allocator (the test binary's global one): a small
        // block grown by realloc into an advised one keeps its bytes ...
        let mut grown = vec![7u8; 64 << 10];
        grown[12_345] = 1;
        grown.reserve_exact(8 << 20);
        assert!(grown.capacity() >= ADVISED_FROM);
        assert_eq!((grown[0], grown[12_345], grown[(64 << 10) - 1]), (7, 1, 7));
        grown.extend([3, 3]);
        assert_eq!((grown[12_345], grown[(64 << 10) + 1]), (1, 3));
        // ... and an advised zeroed block is zero throughout (a word a page).
        let zeroed = vec![0u64; 1 << 20];
        assert!(zeroed.iter().step_by(512).all(|&w| w == 0));
    }

    #[test]
    #[cfg(target_os = "linux")]
    #[cfg_attr(miri, ignore = "Miri has no madvise")]
    fn a_large_block_is_advised_huge_pages() {
        if !std::path::Path::new("/sys/kernel/mm/transparent_hugepage/enabled").exists() {
            eprintln!("skipped: this kernel has no transparent huge pages");
            return;
        }
        // 256 MiB: above glibc's largest mmap threshold (32 MiB) and trim
        // threshold (64 MiB), so a fresh mapping, never the heap's top,
        // whose flags only this allocation's advice can set. Only address
        // space: nothing is touched.
        let layout = Layout::from_size_align(256 << 20, 64).expect("256 MiB"); // invariant: a valid size and alignment
        let hg = |flags: &Option<String>| {
            let words = flags.as_deref().unwrap_or("");
            words.split_whitespace().any(|w| w == "hg")
        };
        // SAFETY: nonzero sizes; each block is freed once, with its layout;
        // the control's madvise range lies inside its own live block.
        let (control, flags) = unsafe {
            // A control: the system's block, advised here directly, shows
            // whether this kernel (or sandbox) takes and reports the advice.
            let plain = System.alloc(layout);
            let ours = HugePages.alloc(layout);
            assert!(!plain.is_null() && !ours.is_null());
            let page = (plain as usize).next_multiple_of(HUGE_PAGE);
            let rc = libc::madvise(page as *mut libc::c_void, HUGE_PAGE, libc::MADV_HUGEPAGE);
            let control = (rc == 0).then(|| flags_of(page)).flatten();
            let flags = flags_of((ours as usize).next_multiple_of(HUGE_PAGE));
            HugePages.dealloc(ours, layout);
            System.dealloc(plain, layout);
            (control, flags)
        };
        if !hg(&control) {
            eprintln!(
                "skipped: this system takes no MADV_HUGEPAGE or shows no VmFlags ({control:?})"
            );
            return;
        }
        // "hg": the mapping was advised MADV_HUGEPAGE.
        assert!(hg(&flags), "{flags:?}");
    }
}
