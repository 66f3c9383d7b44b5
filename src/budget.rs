//! One memory budget for everything a command loads or builds: decoded textures and their
//! mips, environment images, scene meshes and the rendered frame. Each allocation site
//! computes what it will need from sizes it knows before allocating (an image header's
//! dimensions, a scene's tessellation counts, a render's size) and reserves it here first;
//! a reservation over the budget is an error naming the input, its size and the budget, so
//! a hostile input is refused in milliseconds instead of exhausting memory.
//!
//! The estimates are upper bounds of the peak each site holds (stated where each is made);
//! they are not measured, so a budget is a bound on what matgraph asks for, not on the
//! process's resident size (the executable, the GPU driver and the allocator come on top).
//! This module does no I/O.

use std::sync::atomic::{AtomicU64, Ordering};

/// The default budget of a command: 2 GiB (`--memory-budget`).
pub const DEFAULT_MEMORY_BUDGET: u64 = 2 << 30;

/// A byte count in the unit that reads best: `512 B`, `3.0 KiB`, `1.5 MiB`, `4.0 GiB`.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

/// A reservation that does not fit the budget.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{what} needs {}, over the memory budget of {}{} (raise it with --memory-budget)",
    format_bytes(*needed), format_bytes(*limit),
    if *used > 0 { format!(" ({} already in use)", format_bytes(*used)) } else { String::new() }
)]
pub struct MemoryError {
    /// The input and its size, in the user's words (`image.png: 16384×16384 texels`).
    pub what: String,
    /// Bytes it needs.
    pub needed: u64,
    /// Bytes already reserved by earlier inputs.
    pub used: u64,
    /// The budget in bytes.
    pub limit: u64,
}

/// A memory budget shared by everything one command loads and builds (see the module doc).
/// Reservations are counted atomically, so one budget may be shared across threads.
#[derive(Debug)]
pub struct MemoryBudget {
    limit: u64,
    used: AtomicU64,
}

impl Default for MemoryBudget {
    fn default() -> Self {
        MemoryBudget::new(DEFAULT_MEMORY_BUDGET)
    }
}

impl MemoryBudget {
    /// A budget of `limit` bytes, nothing reserved.
    pub fn new(limit: u64) -> MemoryBudget {
        MemoryBudget {
            limit,
            used: AtomicU64::new(0),
        }
    }

    /// The budget in bytes.
    pub fn limit(&self) -> u64 {
        self.limit
    }

    /// Bytes reserved so far.
    pub fn used(&self) -> u64 {
        self.used.load(Ordering::Relaxed)
    }

    /// Bytes still free.
    pub fn remaining(&self) -> u64 {
        self.limit.saturating_sub(self.used())
    }

    /// Reserves `bytes` for `what` (the input and its size, for the message), or refuses
    /// them, reserving nothing, when they do not fit in what is left.
    pub fn reserve(&self, what: impl FnOnce() -> String, bytes: u64) -> Result<(), MemoryError> {
        let mut used = self.used.load(Ordering::Relaxed);
        loop {
            let total = used.checked_add(bytes).filter(|&t| t <= self.limit);
            let Some(total) = total else {
                return Err(MemoryError {
                    what: what(),
                    needed: bytes,
                    used,
                    limit: self.limit,
                });
            };
            match self
                .used
                .compare_exchange_weak(used, total, Ordering::Relaxed, Ordering::Relaxed)
            {
                Ok(_) => return Ok(()),
                Err(now) => used = now,
            }
        }
    }

    /// Checks that `bytes` held for a moment (a decoder's buffer) fit in what is left,
    /// reserving nothing.
    pub fn check(&self, what: impl FnOnce() -> String, bytes: u64) -> Result<(), MemoryError> {
        self.reserve(what, bytes)?;
        self.release(bytes);
        Ok(())
    }

    /// Returns `bytes` of an earlier reservation (memory that was freed).
    pub fn release(&self, bytes: u64) {
        let _ = self
            .used
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |u| {
                Some(u.saturating_sub(bytes))
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reservations_add_up_to_the_limit_and_no_further() {
        let b = MemoryBudget::new(1000);
        b.reserve(|| "a".into(), 600).unwrap();
        let e = b.reserve(|| "b.png: 10×10 texels".into(), 401).unwrap_err();
        assert_eq!((e.needed, e.used, e.limit), (401, 600, 1000));
        assert_eq!(
            e.to_string(),
            "b.png: 10×10 texels needs 401 B, over the memory budget of 1000 B (600 B already in use) (raise it with --memory-budget)"
        );
        assert_eq!(b.used(), 600, "a refusal reserves nothing");
        b.reserve(|| "c".into(), 400).unwrap();
        assert_eq!(b.remaining(), 0);
        b.release(500);
        b.check(|| "d".into(), 500).unwrap();
        assert_eq!(b.used(), 500);
        // No overflow on absurd sizes.
        assert!(b.reserve(|| "e".into(), u64::MAX).is_err());
    }

    #[test]
    fn bytes_read_in_their_unit() {
        assert_eq!(format_bytes(0), "0 B");
        assert_eq!(format_bytes(1023), "1023 B");
        assert_eq!(format_bytes(1536), "1.5 KiB");
        assert_eq!(format_bytes(2 << 30), "2.0 GiB");
        assert_eq!(format_bytes(16384 * 16384 * 16), "4.0 GiB");
    }
}
