//! The instruction sets the hot loops are compiled for, picked at run time.
//!
//! The wheel is portable (no `target-cpu`): its code runs on any x86-64. The hot loops are
//! compiled a second and third time with AVX2 or AVX-512F enabled, and the widest this CPU
//! has runs ([`Isa::detect`]): the batch's SIMD lanes ([`crate::ensemble::lanes`]) for their
//! vector width, a single run's fixed-step loop ([`crate::run::fixed`]) for AVX-512's 32
//! registers. Enabling an instruction set changes how the same IEEE operations are encoded,
//! never which operations run (Rust does not contract `a * b + c` into a fused multiply-add
//! unless asked), so a step of products, sums, divisions and square roots (RK4 of every
//! model, the projection) gives the same bits in every build. A step that calls the C
//! library's `sin` and `cos` (the splittings, the exact kicks) can differ in the last bit
//! between builds of the same loop: LLVM joins the two calls into one `sincos` in one and not
//! in the other, and glibc's answers can differ by an ulp (as they can between CPUs, whose
//! glibc picks its own variant). A batch row and its single run take the same build on the
//! same machine, so they agree bit for bit either way.

/// An instruction set a kernel is compiled for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// The architecture's baseline (SSE2 on x86-64): 2 lanes per vector.
    Baseline,
    /// AVX2: 4 lanes per vector.
    Avx2,
    /// AVX-512F: 8 lanes per vector.
    Avx512,
}

impl Isa {
    /// The widest instruction set this CPU offers (the CPU's features are read once, then
    /// cached: cheap enough to ask before every stretch of steps).
    #[inline]
    pub fn detect() -> Isa {
        match (Isa::Avx512.is_supported(), Isa::Avx2.is_supported()) {
            (true, _) => Isa::Avx512,
            (false, true) => Isa::Avx2,
            (false, false) => Isa::Baseline,
        }
    }

    /// Every instruction set this CPU offers, narrowest first.
    pub fn available() -> Vec<Isa> {
        [Isa::Baseline, Isa::Avx2, Isa::Avx512]
            .into_iter()
            .filter(|isa| isa.is_supported())
            .collect()
    }

    /// Whether this CPU can run the kernel compiled for `self`.
    #[inline]
    pub fn is_supported(self) -> bool {
        match self {
            Isa::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The name used in messages and benches: `"baseline"`, `"avx2"`, `"avx512"`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }
}

impl std::str::FromStr for Isa {
    type Err = crate::Error;

    fn from_str(s: &str) -> crate::Result<Self> {
        match s {
            "baseline" => Ok(Isa::Baseline),
            "avx2" => Ok(Isa::Avx2),
            "avx512" => Ok(Isa::Avx512),
            other => Err(crate::Error::invalid(
                "isa",
                "must be one of 'baseline', 'avx2', 'avx512'",
                other,
            )),
        }
    }
}
