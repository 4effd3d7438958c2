//! Single-precision kernels run with subnormal numbers flushed to zero.
//!
//! A contact-coupled factor's fill decays by many orders of magnitude away from its pivots, and
//! in `f32` (smallest normal 1.2·10⁻³⁸) part of it lands among the subnormals, which x86
//! processors compute through microcode assists, tens of times slower than normal numbers.
//! Flush-to-zero and denormals-are-zero (MXCSR bits 15 and 6; Intel SDM vol. 1, §10.2.3.3–4)
//! make them zero instead: a change far below the precision the refinement restores anyway
//! (`single.rs`). Measured per single-precision factorisation (2026-11-30, back to back): the
//! thesis tunnel 16.8 → 13.3 ms, Goodman's tunnel 23.6 → 21.9 ms, the packed pile of 300 cubes
//! 52.5–53.4 → 42.4–42.5 ms (61.1 → 43.9 ms in a later run); the same refinement and Krylov
//! iteration counts. The piles of 600 and 1 000 cubes (factorised on two threads) were unchanged,
//! 150 and 273–284 ms either way: not every factor decays that far. Double-precision factors
//! measured no gain (the thesis tunnel 18.4 against 18.0 ms; their range reaches 2.2·10⁻³⁰⁸), so
//! they keep IEEE arithmetic.
//!
//! The flags are per thread: set on the calling thread and, for a parallel kernel, on every
//! thread of the current pool, and restored when the closure returns (or unwinds). Other
//! targets run the closure unchanged.

use faer::Par;

/// Run `f` with subnormal `f32`/`f64` results and operands taken as zero on the threads `par`
/// uses.
pub fn flushed<R>(par: Par, f: impl FnOnce() -> R) -> R {
    let _guard = Guard::new(matches!(par, Par::Rayon(_)) && rayon::current_num_threads() > 1);
    f()
}

/// The flags as they were before, restored on drop.
struct Guard {
    own: u32,
    pool: Option<Vec<u32>>,
}

impl Guard {
    fn new(pool: bool) -> Self {
        let own = csr::flush();
        let pool = pool.then(|| rayon::broadcast(|_| csr::flush()));
        Self { own, pool }
    }
}

impl Drop for Guard {
    fn drop(&mut self) {
        if let Some(old) = &self.pool {
            rayon::broadcast(|ctx| csr::restore(old[ctx.index()]));
        }
        csr::restore(self.own);
    }
}

#[cfg(target_arch = "x86_64")]
mod csr {
    /// MXCSR's flush-to-zero (bit 15) and denormals-are-zero (bit 6) flags.
    const FLUSH: u32 = 1 << 15 | 1 << 6;

    /// Set the flags on this thread; the register as it was.
    pub fn flush() -> u32 {
        let old = read();
        write(old | FLUSH);
        old
    }

    pub fn restore(old: u32) {
        write(old);
    }

    #[allow(unsafe_code)]
    fn read() -> u32 {
        let mut v = 0u32;
        // SAFETY: STMXCSR stores the 32-bit register into `v`, a live local.
        unsafe {
            core::arch::asm!("stmxcsr [{}]", in(reg) core::ptr::addr_of_mut!(v), options(nostack, preserves_flags))
        };
        v
    }

    #[allow(unsafe_code)]
    fn write(v: u32) {
        // SAFETY: LDMXCSR loads `v`, the register as read with only bits 15 and 6 changed (no
        // reserved bit set, exceptions masked as before); it changes only how this thread's
        // SSE/AVX arithmetic treats subnormal numbers.
        unsafe {
            core::arch::asm!("ldmxcsr [{}]", in(reg) core::ptr::addr_of!(v), options(nostack, preserves_flags, readonly))
        };
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod csr {
    pub fn flush() -> u32 {
        0
    }

    pub fn restore(_: u32) {}
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use std::hint::black_box;

    fn halved_smallest_normal() -> f32 {
        black_box(f32::MIN_POSITIVE) * black_box(0.5)
    }

    #[test]
    fn subnormals_are_zero_inside_and_kept_outside() {
        assert!(halved_smallest_normal() > 0.0, "IEEE gradual underflow before");
        assert_eq!(flushed(Par::Seq, halved_smallest_normal), 0.0);
        assert!(halved_smallest_normal() > 0.0, "restored after");
    }

    #[test]
    fn every_thread_of_the_pool_flushes_in_a_parallel_kernel_and_is_restored() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        pool.install(|| {
            let inside = flushed(Par::rayon(0), || rayon::broadcast(|_| halved_smallest_normal()));
            assert_eq!(inside, vec![0.0; 3]);
            let after = rayon::broadcast(|_| halved_smallest_normal());
            assert!(after.iter().all(|&x| x > 0.0), "{after:?}");
        });
    }
}
