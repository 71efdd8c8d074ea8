//! The instruction set the ray queries run in, chosen once at run time:
//! AVX2 where the CPU has it, else x86-64's baseline (SSE2), or NEON on
//! aarch64; AVX-512 when asked for (`GLINT_SIMD`). The walks are one code,
//! compiled for each; rustc never fuses a multiply and an add on its own,
//! so every choice gives the same answers, bit for bit.

use pulp::{Arch, Simd, WithSimd};
use std::sync::OnceLock;

/// An instruction set the queries can run in.
#[derive(Clone, Copy, Debug)]
pub struct Isa(Arch);

/// The choice made for this process (see [`Isa::choose`]).
static CHOSEN: OnceLock<Isa> = OnceLock::new();

impl Isa {
    /// The names [`Isa::named`] takes besides `best`, the baseline first.
    pub const NAMES: [&str; 4] = ["baseline", "avx2", "avx512", "neon"];

    /// The fastest this CPU has for the queries: AVX2 over AVX-512 (a
    /// node's four f64 boxes fill one AVX2 register, and AVX-512 measured
    /// slower: docs/performance.md), else what pulp finds best.
    pub fn best() -> Isa {
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        if let Some(simd) = pulp::x86::V3::try_new() {
            return Isa(Arch::V3(simd));
        }
        Isa(Arch::new())
    }

    /// The architecture's baseline, which every CPU of it has.
    pub fn baseline() -> Isa {
        Isa(Arch::Scalar)
    }

    /// The one named `name` (`best`, `baseline`, or `avx2`, `avx512`,
    /// `neon`), if this CPU has it; `None` for a name it does not know.
    pub fn named(name: &str) -> Option<Result<Isa, String>> {
        let isa = match name {
            "best" => Some(Isa::best()),
            "baseline" => Some(Isa::baseline()),
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            "avx2" => pulp::x86::V3::try_new().map(|s| Isa(Arch::V3(s))),
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            "avx512" => pulp::x86::V4::try_new().map(|s| Isa(Arch::V4(s))),
            #[cfg(target_arch = "aarch64")]
            "neon" => pulp::aarch64::Neon::try_new().map(|s| Isa(Arch::Neon(s))),
            // Another architecture's: known, never found.
            #[allow(unreachable_patterns)]
            "avx2" | "avx512" | "neon" => None,
            _ => return None,
        };
        Some(isa.ok_or_else(|| format!("this CPU has no {name}")))
    }

    /// Every instruction set this CPU has, the baseline first.
    pub fn available() -> Vec<Isa> {
        Isa::NAMES
            .into_iter()
            .filter_map(|name| Isa::named(name)?.ok())
            .collect()
    }

    /// Sets the choice for this process; made before any query (a later
    /// call leaves the first choice).
    pub fn choose(self) {
        let _ = CHOSEN.set(self);
    }

    /// This process's choice: the one set by [`Isa::choose`], else the best.
    pub fn chosen() -> Isa {
        *CHOSEN.get_or_init(Isa::best)
    }

    /// Its name, as [`Isa::named`] takes it.
    pub fn name(&self) -> &'static str {
        match self.0 {
            Arch::Scalar => "baseline",
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            Arch::V3(_) => "avx2",
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            Arch::V4(_) => "avx512",
            #[cfg(target_arch = "aarch64")]
            Arch::Neon(_) => "neon",
            #[allow(unreachable_patterns)]
            _ => "other",
        }
    }

    /// Runs `f` compiled for this instruction set: what `f` inlines (the
    /// queries' walks and primitive tests) uses its instructions.
    #[inline(always)]
    pub(crate) fn run<R>(self, f: impl FnOnce() -> R) -> R {
        self.0.dispatch(Kernel(f))
    }
}

/// A closure as pulp's dispatch takes it.
struct Kernel<F>(F);

impl<R, F: FnOnce() -> R> WithSimd for Kernel<F> {
    type Output = R;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) -> R {
        (self.0)()
    }
}
